#version 450
// Regular bicubic B-spline patch evaluation. Interior points: Bezier form (from the TCS) with
// derivatives for the normal n = normalize(dP/du x dP/dv). Points on the patch boundary are made
// bitwise identical to the neighbour's: corners read the shared vertex limit position; edge points
// evaluate the edge's limit curve from the 12 B-spline points both patches hold, in canonical order
// (parameter running from the end vertex with the smaller id, rows combined symmetrically).
// Defines: SPACING (equal_spacing | fractional_odd_spacing | fractional_even_spacing), CAPTURE.
#include "common/frame.glsl"
#include "common/bspline.glsl"
#ifdef CAPTURE
#include "common/capture.glsl"
#endif

#ifndef SPACING
#define SPACING equal_spacing
#endif

// Vulkan's default upper-left domain origin mirrors GL's: `cw` here gives triangles that are
// counter-clockwise in the (u right, v up) parameter plane, i.e. seen from outside.
layout(quads, SPACING, cw) in;
layout(location = 0) in vec3 c_bspline[];
layout(location = 1) in vec3 c_bezier[];
layout(location = 0) out vec3 t_world;
layout(location = 1) out vec3 t_normal;
layout(location = 2) flat out uint t_class;

/// Limit point on patch edge e (0: v=0, 1: u=1, 2: v=1, 3: u=0) at local parameter x, computed from
/// data and in an order that do not depend on which of the two patches evaluates it.
vec3 edge_point(uint flags, int e, float x) {
    bool along_u = (e == 0 || e == 2);
    int off = (e == 1 || e == 2) ? 1 : 0;
    bool reversed = ((flags >> (4 + e)) & 1u) != 0u;
    // Edge curve B-spline points c_k = (r0 + r2 + 4 r1)/6: the v (or u) = 0 B-spline weights.
    vec3 c[4];
    for (int k = 0; k < 4; ++k) {
        int kk = reversed ? 3 - k : k;
        vec3 r[3];
        for (int m = 0; m < 3; ++m) {
            int idx = along_u ? (m + off) * 4 + kk : kk * 4 + m + off;
            r[m] = c_bspline[idx];
        }
        c[k] = ((r[0] + r[2]) + 4.0 * r[1]) * (1.0 / 6.0);
    }
    // Canonical (t, s = 1 - t): derived from w = max(x, 1 - x) only, which both sides agree on
    // whenever the tessellator generates mirrored coordinates as exact 1 - a.
    float w = max(x, 1.0 - x);
    float l = 1.0 - w;
    float t = (x >= 0.5) ? w : l;
    float s = (x >= 0.5) ? l : w;
    if (reversed) {
        float tmp = t;
        t = s;
        s = tmp;
    }
    vec4 n = bspline3(t, s);
    return ((n.x * c[0] + n.y * c[1]) + n.z * c[2]) + n.w * c[3];
}

void main() {
    // Face (u, v) of this domain point: sub-patch origin + local coordinate * size (exact, as
    // every term is dyadic, so neighbours across a face edge still get exactly 1 - x).
    vec3 sd = sub_domain();
    float u = sd.x + gl_TessCoord.x * sd.z;
    float v = sd.y + gl_TessCoord.y * sd.z;
    vec4 bu, dbu, bv, dbv;
    bernstein3(u, 1.0 - u, bu, dbu);
    bernstein3(v, 1.0 - v, bv, dbv);
    vec3 p = vec3(0.0);
    vec3 du = vec3(0.0);
    vec3 dv = vec3(0.0);
    for (int j = 0; j < 4; ++j) {
        for (int i = 0; i < 4; ++i) {
            vec3 cp = c_bezier[4 * j + i];
            p += (bu[i] * bv[j]) * cp;
            du += (dbu[i] * bv[j]) * cp;
            dv += (bu[i] * dbv[j]) * cp;
        }
    }
    vec3 nrm = cross(du, dv);
    float len = length(nrm);
    nrm = len > 0.0 ? nrm / len : vec3(0.0, 0.0, 1.0);

    PatchInfo info = patches[chunk.patch_base + uint(gl_PrimitiveID)];
    bool u_edge = (u == 0.0 || u == 1.0);
    bool v_edge = (v == 0.0 || v == 1.0);
    if (u_edge && v_edge) {
        int k = (u == 0.0) ? (v == 0.0 ? 0 : 3) : (v == 0.0 ? 1 : 2);
        p = vertex_limit[info.corners[k]].xyz;
    } else if (u_edge || v_edge) {
        int e = (v == 0.0) ? 0 : (u == 1.0) ? 1 : (v == 1.0) ? 2 : 3;
        float x = v_edge ? u : v;
        p = edge_point(info.flags, e, x);
    }

    t_world = p;
    t_normal = nrm;
    t_class = CLASS_REGULAR;
    gl_Position = frame.view_proj * vec4(p, 1.0);
#ifdef CAPTURE
    capture_point(info.face, vec2(u, v), p, nrm);
#endif
}
