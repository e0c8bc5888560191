#version 450
// Single-crease patch of the single-crease pass: reads the patch's sharpness (binding 4), builds
// its Bezier control sets (single_crease_tcs.glsl) and sets the tessellation levels as the
// B-spline TCS does (common/tess_factors.glsl).
#include "frame.glsl"
#include "bspline.glsl"
#include "tess_factors.glsl"
#include "single_crease.glsl"
#include "single_crease_tcs.glsl"

void main() {
    uint patch_index = chunk.patch_base + uint(gl_PrimitiveID);
    single_crease_control_points(crease_sharpness[patch_index]);
    if (gl_InvocationID == 0) {
        uvec4 c = patches[patch_index].corners;
        set_quad_tess_levels(c);
    }
    CULL_PATCH(c_bspline, 16);
}
