// The TCS body of a single-crease patch (16 control vertices rotated so the crease runs along
// u = 1, single_crease.glsl), shared by the single-crease pass and the adaptive scheme: passes the
// B-spline points on for the TES's shared edges and builds, for this invocation, the Bezier point
// of each of the two or three control sets of the pieces across the crease (Nießner, Loop,
// Greiner 2012, §4; the fractional blend of §3.1). Needs frame.glsl and single_crease.glsl first.
#ifndef TESSERA_SINGLE_CREASE_TCS_GLSL
#define TESSERA_SINGLE_CREASE_TCS_GLSL

layout(vertices = 16) out;
layout(location = 0) in vec3 v_pos[];
layout(location = 0) out vec3 c_bspline[];
layout(location = 1) out vec3 c_set0[];
layout(location = 2) out vec3 c_set1[];
layout(location = 3) out vec3 c_set2[];

/// Writes c_bspline and c_set0..2 of this invocation for crease sharpness `sharpness`.
void single_crease_control_points(float sharpness) {
    CreaseSplit cs = crease_split(sharpness);
    int id = gl_InvocationID;
    int i = id % 4;
    int j = id / 4;
    c_bspline[gl_InvocationID] = v_pos[id];
    // Along the crease (v) every piece is the smooth cubic: Bezier row j of each column, relative
    // to the origin v_pos[5] (as bspline_tcs.glsl; the TES adds c_bspline[5] back).
    vec4 wj = bspline_to_bezier_row(j);
    vec3 o = v_pos[5];
    vec3 col[4];
    for (int k = 0; k < 4; ++k) {
        col[k] = ((wj.x * (v_pos[k] - o) + wj.y * (v_pos[4 + k] - o)) + wj.z * (v_pos[8 + k] - o))
            + wj.w * (v_pos[12 + k] - o);
    }
    // Across it (u) Bezier point i of each piece over its own u-range. Empty pieces are never read.
    vec4 w0 = set_row(cs, 0, i);
    vec4 w1 = set_row(cs, 1, i);
    vec4 w2 = set_row(cs, 2, i);
    c_set0[gl_InvocationID] = ((w0.x * col[0] + w0.y * col[1]) + w0.z * col[2]) + w0.w * col[3];
    c_set1[gl_InvocationID] = ((w1.x * col[0] + w1.y * col[1]) + w1.z * col[2]) + w1.w * col[3];
    c_set2[gl_InvocationID] = ((w2.x * col[0] + w2.y * col[1]) + w2.z * col[2]) + w2.w * col[3];
}

#endif
