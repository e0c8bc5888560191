// The TES body of a regular bicubic B-spline patch (inputs from bspline_tcs.glsl), shared by the
// B-spline pass and the adaptive scheme: the interior from the Bezier points with derivatives for
// the normal n = normalize(dP/du x dP/dv), and the shared-edge evaluation. Points on the patch
// boundary are bitwise identical (position and normal) to the neighbour's, B-spline or Gregory:
// corners read the shared vertex limit position and normal (bindings 2, 9); edge points
// evaluate the edge's limit curve and normal from the 12 B-spline points both patches hold, in
// canonical order (parameter running from the end vertex with the smaller id, rows combined
// symmetrically, precise arithmetic: common/watertight.glsl). Needs frame.glsl first.
#ifndef TESSERA_BSPLINE_TES_GLSL
#define TESSERA_BSPLINE_TES_GLSL

#include "bspline.glsl"
#include "watertight.glsl"

layout(location = 0) in vec3 c_bspline[];
layout(location = 1) in vec3 c_bezier[];

#include "patch_edge_grid.glsl"

/// Limit point and normal on patch edge e (0: v=0, 1: u=1, 2: v=1, 3: u=0) at the canonical
/// parameters (t, s = 1 - t) measured from the edge end with the smaller id, computed from data
/// and in an order that do not depend on which of the two patches (B-spline, single-crease or
/// Gregory) evaluates it: grid_edge_rows (common/watertight.glsl) on patch_edge_rows.
void edge_point_ts(uint flags, int e, float t, float s, out vec3 pos, out vec3 nrm) {
    vec3 l[4];
    vec3 m[4];
    vec3 r[4];
    patch_edge_rows(flags, e, l, m, r);
    // Boundary mask bit e: the row beyond edge e is this patch's own phantom (boundary or
    // infinitely sharp crease).
    bool sharp = ((flags >> uint(e)) & 1u) != 0u;
    grid_edge_rows(l, m, r, sharp, t, s, pos, nrm);
}

/// edge_point_ts at local parameter x of edge e (measured from its start corner: u on edges 0
/// and 2, v on edges 1 and 3).
void edge_point(uint flags, int e, float x, out vec3 pos, out vec3 nrm) {
    bool reversed = ((flags >> (4 + e)) & 1u) != 0u;
    float t, s;
    edge_ts(x, !reversed, t, s);
    edge_point_ts(flags, e, t, s, pos, nrm);
}

/// The patch's own surface point, unit normal and partials dP/du, dP/dv at (u, v) from the
/// Bezier points (relative to the origin c_bspline[5], bspline_tcs.glsl).
void bspline_surface(float u, float v, out vec3 pos, out vec3 nrm, out vec3 du, out vec3 dv) {
    vec3 cp[16];
    for (int k = 0; k < 16; ++k) {
        cp[k] = c_bezier[k];
    }
    vec3 rel;
    bezier_surface_frame(cp, u, v, rel, nrm, du, dv);
    pos = c_bspline[5] + rel;
}

#endif
