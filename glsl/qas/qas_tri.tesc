#version 450
// QAS triangle and n-gon fan triangle: levels from data both neighbours share. The barycentric
// weight of corner i is gl_TessCoord[i], so outer[0] is edge 1-2, [1] edge 2-0, [2] edge 0-1.
// A triangle's edges from their corner vertices; a fan triangle's outer edge 1-2 (the coarse
// edge V_k V_{k+1}) likewise, its spokes 2-0 and 0-1 from the spoke's vertex and the face
// centre (corner 0's limit point, the same bits in every fan triangle of the face).
#include "frame.glsl"
#include "tess_factors.glsl"
#include "qas.glsl"

layout(vertices = 1) out;

void main() {
    if (gl_InvocationID == 0) {
        uint pi = chunk.patch_base + uint(gl_PrimitiveID);
        uvec4 c = qas[pi].corners;
        float o0 = edge_tess_level(c.y, c.z);
        float o1;
        float o2;
        if (qas[pi].kind == QAS_FAN) {
            vec3 centre = qas[pi].p[0].xyz;
            o1 = spoke_tess_level(c.z, centre);
            o2 = spoke_tess_level(c.y, centre);
        } else {
            o1 = edge_tess_level(c.z, c.x);
            o2 = edge_tess_level(c.x, c.y);
        }
        gl_TessLevelOuter[0] = o0;
        gl_TessLevelOuter[1] = o1;
        gl_TessLevelOuter[2] = o2;
        gl_TessLevelInner[0] = max(o0, max(o1, o2));
    }
    CULL_PATCH(qas[chunk.patch_base + uint(gl_PrimitiveID)].p, 6);
}
