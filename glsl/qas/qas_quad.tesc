#version 450
// QAS quad: levels from the corner vertices both neighbours share (common/tess_factors.glsl).
#include "frame.glsl"
#include "tess_factors.glsl"
#include "qas.glsl"

layout(vertices = 1) out;

void main() {
    if (gl_InvocationID == 0) {
        set_quad_tess_levels(qas[chunk.patch_base + uint(gl_PrimitiveID)].corners);
    }
    CULL_PATCH(qas[chunk.patch_base + uint(gl_PrimitiveID)].p, 9);
}
