// The TES body of a single-crease patch (inputs from single_crease_tcs.glsl), shared by the
// single-crease pass and the adaptive scheme (Nießner, Loop, Greiner 2012, §4): the surface from
// the Bezier set of the piece across the crease that holds u (splits at 1 - 2^-floor(s) and
// 1 - 2^-ceil(s), single_crease.glsl), and the shared edges of common/watertight.glsl: the edge
// away from the crease (u = 0) is the B-spline grid curve of the unmodified points (M_inf and
// every blend keep P0..P2, so it is the neighbour's, B-spline or Gregory, grid_edge_rows); the
// crease edge (u = 1) and the two edges across the crease (v = 0, 1) are crease-aware curves from
// the 12 grid points and the sharpness, which the single-crease patch on the other side (or a
// finer patch reading a coarse-edge record, adaptive/adaptive.glsl) computes alike.
// Needs frame.glsl, bspline.glsl, watertight.glsl and single_crease.glsl first.
#ifndef TESSERA_SINGLE_CREASE_TES_GLSL
#define TESSERA_SINGLE_CREASE_TES_GLSL

layout(location = 0) in vec3 c_bspline[];
layout(location = 1) in vec3 c_set0[];
layout(location = 2) in vec3 c_set1[];
layout(location = 3) in vec3 c_set2[];

#include "patch_edge_grid.glsl"

/// Bezier point k of set g.
vec3 set_point(int g, int k) {
    return g == 0 ? c_set0[k] : (g == 1 ? c_set1[k] : c_set2[k]);
}

/// The curve of patch edge e (0: v=0, 1: u=1 the crease, 2: v=1, 3: u=0) from its grid rows in the
/// canonical frame at the canonical parameters (t, s): the B-spline grid curve (e = 3), the crease
/// edge (e = 1) or the curve across the crease (e = 0, 2; `crease_at_lo`: the crease end is the
/// smaller id).
void single_crease_edge_curve(int e, bool crease_at_lo, float sharpness, vec3 l[4], vec3 m[4],
                              vec3 r[4], float t, float s, out vec3 pos, out vec3 nrm) {
    if (e == 3) {
        grid_edge_rows(l, m, r, false, t, s, pos, nrm);
    } else if (e == 1) {
        crease_edge_rows(l, m, r, sharpness, t, s, pos, nrm);
    } else {
        crease_across_edge(l, m, r, crease_at_lo, sharpness, t, s, pos, nrm);
    }
}

/// Limit point and normal on patch edge e at the canonical parameters (t, s).
void single_crease_edge_ts(uint flags, float sharpness, int e, float t, float s, out vec3 pos,
                           out vec3 nrm) {
    vec3 l[4];
    vec3 m[4];
    vec3 r[4];
    patch_edge_rows(flags, e, l, m, r);
    // Edges 0 and 2 run along u from u = 0 (away) to u = 1 (crease); bit 4+e: that runs from the
    // larger id, so the canonical (smaller-id) end is the crease end.
    bool crease_at_lo = ((flags >> (4 + e)) & 1u) != 0u;
    single_crease_edge_curve(e, crease_at_lo, sharpness, l, m, r, t, s, pos, nrm);
}

/// single_crease_edge_ts at local parameter x of edge e (measured from its start corner).
void single_crease_edge_point(uint flags, float sharpness, int e, float x, out vec3 pos,
                              out vec3 nrm) {
    bool reversed = ((flags >> (4 + e)) & 1u) != 0u;
    float t, s;
    edge_ts(x, !reversed, t, s);
    single_crease_edge_ts(flags, sharpness, e, t, s, pos, nrm);
}

/// The patch's own surface point, unit normal and partials dP/du, dP/dv at (u, v) (rotated
/// frame) from the Bezier set of the piece holding u.
void single_crease_surface(float sharpness, float u, float v, out vec3 pos, out vec3 nrm,
                           out vec3 du, out vec3 dv) {
    CreaseSplit cs = crease_split(sharpness);
    int g = set_at(cs, u);
    vec2 range = set_range(cs, g);
    float x = (u - range.x) / (range.y - range.x);
    vec3 cp[16];
    for (int k = 0; k < 16; ++k) {
        cp[k] = set_point(g, k);
    }
    // d/dx = (range width) d/du: the same normal. The sets are relative to c_bspline[5].
    vec3 rel;
    vec3 dx;
    bezier_surface_frame(cp, x, v, rel, nrm, dx, dv);
    du = dx / (range.y - range.x);
    pos = c_bspline[5] + rel;
}

#endif
