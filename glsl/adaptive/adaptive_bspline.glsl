// What the adaptive scheme's B-spline stages share: the corners at the ends of a B-spline patch
// edge and the domain points of the corners.
#ifndef TESSERA_ADAPTIVE_BSPLINE_GLSL
#define TESSERA_ADAPTIVE_BSPLINE_GLSL

/// Start and end corner (0..3 = (0,0), (1,0), (1,1), (0,1)) of B-spline edge e (0: v=0, 1: u=1,
/// 2: v=1, 3: u=0; src/render/schemes/bspline PATCH_EDGES): the edge parameter runs start -> end.
ivec2 bspline_edge_corners(int e) {
    return e == 0 ? ivec2(0, 1) : e == 1 ? ivec2(1, 2) : e == 2 ? ivec2(3, 2) : ivec2(0, 3);
}

/// Domain point of corner k.
vec2 corner_uv(int k) {
    return vec2((k == 1 || k == 2) ? 1.0 : 0.0, (k >= 2) ? 1.0 : 0.0);
}

#endif
