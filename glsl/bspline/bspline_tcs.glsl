// The TCS body of a regular bicubic B-spline patch (16 control vertices cvs[4*j + i], as
// patch::RegularPatch), shared by the B-spline pass and the adaptive scheme's B-spline and
// transition patches: mirrors phantom points (columns first, then rows: 2a - b) and writes, for
// this invocation, the mirrored B-spline point (the TES's shared-edge evaluation) and the Bezier
// point (the interior) relative to the patch origin P[5] (a corner vertex, never a phantom; the
// TES adds it back): differences of nearby points keep their digits where absolute coordinates
// would not, so the normals of small patches far from the coordinate origin stay accurate.
#ifndef TESSERA_BSPLINE_TCS_GLSL
#define TESSERA_BSPLINE_TCS_GLSL

#include "bspline.glsl"

layout(vertices = 16) out;
layout(location = 0) in vec3 v_pos[];
layout(location = 0) out vec3 c_bspline[];
layout(location = 1) out vec3 c_bezier[];

/// Writes c_bspline and c_bezier of this invocation; `flags` bits 0-3 are the boundary mask
/// (bit 0: v=0 row, 1: u=1 column, 2: v=1 row, 3: u=0 column are phantoms).
void bspline_control_points(uint flags) {
    vec3 P[16];
    for (int k = 0; k < 16; ++k) {
        P[k] = v_pos[k];
    }
    // Phantom columns: bit 3 = u=0 side (column 0), bit 1 = u=1 side (column 3).
    for (int j = 0; j < 4; ++j) {
        if ((flags & 8u) != 0u) P[4 * j + 0] = 2.0 * P[4 * j + 1] - P[4 * j + 2];
        if ((flags & 2u) != 0u) P[4 * j + 3] = 2.0 * P[4 * j + 2] - P[4 * j + 1];
    }
    // Phantom rows: bit 0 = v=0 side (row 0), bit 2 = v=1 side (row 3).
    for (int i = 0; i < 4; ++i) {
        if ((flags & 1u) != 0u) P[i] = 2.0 * P[4 + i] - P[8 + i];
        if ((flags & 4u) != 0u) P[12 + i] = 2.0 * P[8 + i] - P[4 + i];
    }

    int id = gl_InvocationID;
    int i = id % 4;
    int j = id / 4;
    c_bspline[gl_InvocationID] = P[id];
    // Bezier point (i, j) = sum_b wj[b] * sum_a wi[a] * P[4b + a] (tensor-product change of basis).
    vec4 wi = bspline_to_bezier_row(i);
    vec4 wj = bspline_to_bezier_row(j);
    vec3 o = P[5];
    vec3 acc = vec3(0.0);
    for (int b = 0; b < 4; ++b) {
        vec3 row = wi.x * (P[4 * b] - o) + wi.y * (P[4 * b + 1] - o) + wi.z * (P[4 * b + 2] - o)
            + wi.w * (P[4 * b + 3] - o);
        acc += wj[b] * row;
    }
    c_bezier[gl_InvocationID] = acc;
}

#endif
