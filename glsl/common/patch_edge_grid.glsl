// The 12 grid points of an edge of a 16-point patch (cvs order, corners 5, 6, 10, 9) in the
// canonical frame of common/watertight.glsl. Needs frame.glsl, watertight.glsl and the TES input
// `c_bspline[]` (the patch's B-spline points) declared before the include. Used by the B-spline
// TES for every edge and by the single-crease TES for its edges.
#ifndef TESSERA_PATCH_EDGE_GRID_GLSL
#define TESSERA_PATCH_EDGE_GRID_GLSL

/// Rows l (left of the direction from the smaller vertex id), m (on the edge), r of patch edge e
/// (0: v=0, 1: u=1, 2: v=1, 3: u=0), each from the smaller-id end. flags bit 4+e: edge e runs
/// from the larger vertex id.
void patch_edge_rows(uint flags, int e, out vec3 l[4], out vec3 m[4], out vec3 r[4]) {
    bool along_u = (e == 0 || e == 2);
    int off = (e == 1 || e == 2) ? 1 : 0;
    bool reversed = ((flags >> (4 + e)) & 1u) != 0u;
    // The face lies left of its edge in face order (corners 0->1, 1->2, 2->3, 3->0); the
    // parameter runs with face order on edges 0 and 1. Left of the canonical direction (from the
    // smaller id) is this patch's inner row exactly when the two directions agree.
    bool face_order = (e == 0 || e == 1);
    bool own_left = face_order != reversed;
    int inner = (off == 0) ? 2 : 0;
    int ml = own_left ? inner : 2 - inner;
    int mr = 2 - ml;
    for (int k = 0; k < 4; ++k) {
        int kk = reversed ? 3 - k : k;
        int il = along_u ? (ml + off) * 4 + kk : kk * 4 + ml + off;
        int im = along_u ? (1 + off) * 4 + kk : kk * 4 + 1 + off;
        int ir = along_u ? (mr + off) * 4 + kk : kk * 4 + mr + off;
        l[k] = c_bspline[il];
        m[k] = c_bspline[im];
        r[k] = c_bspline[ir];
    }
}

/// patch_edge_rows and the canonical parameters (t, s) of the local coordinate x (measured from
/// the edge's start corner).
void patch_edge_grid(uint flags, int e, float x, out vec3 l[4], out vec3 m[4], out vec3 r[4],
                     out float t, out float s) {
    patch_edge_rows(flags, e, l, m, r);
    bool reversed = ((flags >> (4 + e)) & 1u) != 0u;
    edge_ts(x, !reversed, t, s);
}

#endif
