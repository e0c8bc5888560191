#version 450
// ACC patch: levels from the corner vertices both neighbours share (common/tess_factors.glsl).
#include "frame.glsl"
#include "tess_factors.glsl"
#include "acc.glsl"

layout(vertices = 1) out;

void main() {
    if (gl_InvocationID == 0) {
        set_quad_tess_levels(acc[chunk.patch_base + uint(gl_PrimitiveID)].corners);
    }
    CULL_PATCH(acc[chunk.patch_base + uint(gl_PrimitiveID)].b, 16);
}
