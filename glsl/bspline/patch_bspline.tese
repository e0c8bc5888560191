#version 450
// Regular bicubic B-spline patch evaluation. Interior points: Bezier form (from the TCS) with
// derivatives for the normal n = normalize(dP/du x dP/dv). Points on the patch boundary are made
// bitwise identical (position and normal) to the neighbour's, B-spline or Gregory: corners read the
// shared vertex limit position and normal (bindings 2, 9); edge points evaluate the edge's limit
// curve and normal from the 12 B-spline points both patches hold, in canonical order (parameter
// running from the end vertex with the smaller id, rows combined symmetrically, precise
// arithmetic: common/watertight.glsl).
// Defines: SPACING (equal_spacing | fractional_odd_spacing | fractional_even_spacing), CAPTURE.
#include "frame.glsl"
#include "bspline.glsl"
#include "watertight.glsl"
#ifdef CAPTURE
#include "capture.glsl"
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

#include "patch_edge_grid.glsl"

/// Limit point and normal on patch edge e (0: v=0, 1: u=1, 2: v=1, 3: u=0) at local parameter x,
/// computed from data and in an order that do not depend on which of the two patches (B-spline
/// or Gregory) evaluates it: grid_edge_rows (common/watertight.glsl) in the canonical frame.
void edge_point(uint flags, int e, float x, out vec3 pos, out vec3 nrm) {
    vec3 l[4];
    vec3 m[4];
    vec3 r[4];
    float t, s;
    patch_edge_grid(flags, e, x, l, m, r, t, s);
    // Boundary mask bit e: the row beyond edge e is this patch's own phantom (boundary or
    // infinitely sharp crease).
    bool sharp = ((flags >> uint(e)) & 1u) != 0u;
    grid_edge_rows(l, m, r, sharp, t, s, pos, nrm);
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
        quad_corner_point(info.corners, u, v, p, nrm);
    } else if (u_edge || v_edge) {
        int e = (v == 0.0) ? 0 : (u == 1.0) ? 1 : (v == 1.0) ? 2 : 3;
        float x = v_edge ? u : v;
        edge_point(info.flags, e, x, p, nrm);
    }

    t_world = p;
    t_normal = nrm;
    t_class = CLASS_REGULAR;
    gl_Position = frame.view_proj * vec4(p, 1.0);
#ifdef CAPTURE
    capture_point(info.face, vec2(u, v), p, nrm);
#endif
}
