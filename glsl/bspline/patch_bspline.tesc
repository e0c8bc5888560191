#version 450
// Regular bicubic B-spline patch: control points by bspline_tcs.glsl, tessellation levels from
// data the neighbouring patch shares (common/tess_factors.glsl).
#include "frame.glsl"
#include "tess_factors.glsl"
#include "bspline_tcs.glsl"

void main() {
    PatchInfo info = patches[chunk.patch_base + uint(gl_PrimitiveID)];
    bspline_control_points(info.flags);
    if (gl_InvocationID == 0) {
        set_quad_tess_levels(info.corners);
    }
    // The Bezier points (relative to c_bspline[5], bspline_tcs.glsl) bound the patch tighter
    // than the B-spline points.
    CULL_PATCH_AT(c_bezier, 16, c_bspline[5]);
}
