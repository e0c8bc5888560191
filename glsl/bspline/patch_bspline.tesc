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
    CULL_PATCH(c_bezier, 16);
}
