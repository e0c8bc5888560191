// Sub-triangles of a triangle domain split n x n, for schemes that draw a triangle patch as n^2
// sub-patches (gregory/gregory.glsl's TRI_SUB_MODE, adaptive/transition.glsl's split fans).
#ifndef TESSERA_TRI_SUB_GLSL
#define TESSERA_TRI_SUB_GLSL

/// Corners, as (b1, b2) in units of 1/n, of sub-triangle `idx` of the n x n grid of the
/// barycentric domain: per row j first the n - j upright ones, then the n - 1 - j inverted ones
/// (upright rotated by 180 degrees: the orientation is kept). In both kinds the edge opposite
/// c0 keeps b0 constant, the one opposite c1 keeps b1, the one opposite c2 keeps b2.
void tri_sub_corners(uint idx, uint n, out ivec2 c0, out ivec2 c1, out ivec2 c2) {
    uint rem = idx;
    c0 = ivec2(0);
    c1 = ivec2(0);
    c2 = ivec2(0);
    for (uint j = 0u; j < n; ++j) {
        uint up = n - j;
        if (rem < up) {
            c0 = ivec2(int(rem), int(j));
            c1 = ivec2(int(rem) + 1, int(j));
            c2 = ivec2(int(rem), int(j) + 1);
            return;
        }
        rem -= up;
        uint down = n - 1u - j;
        if (rem < down) {
            c0 = ivec2(int(rem) + 1, int(j) + 1);
            c1 = ivec2(int(rem), int(j) + 1);
            c2 = ivec2(int(rem) + 1, int(j));
            return;
        }
        rem -= down;
    }
}

#endif
