#version 450
// QAS triangle: levels from the corner vertices both neighbours share. The barycentric weight
// of corner i is gl_TessCoord[i], so outer[0] is edge 1-2, [1] edge 2-0, [2] edge 0-1.
#include "frame.glsl"
#include "tess_factors.glsl"
#include "qas.glsl"

layout(vertices = 1) out;

void main() {
    if (gl_InvocationID == 0) {
        uvec4 c = qas[chunk.patch_base + uint(gl_PrimitiveID)].corners;
        float o0 = edge_tess_level(c.y, c.z);
        float o1 = edge_tess_level(c.z, c.x);
        float o2 = edge_tess_level(c.x, c.y);
        gl_TessLevelOuter[0] = o0;
        gl_TessLevelOuter[1] = o1;
        gl_TessLevelOuter[2] = o2;
        gl_TessLevelInner[0] = max(o0, max(o1, o2));
    }
    CULL_PATCH(qas[chunk.patch_base + uint(gl_PrimitiveID)].p, 6);
}
