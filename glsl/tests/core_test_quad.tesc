#version 450
// Core test: one bilinear quad patch (4 points; 16 with PATCH16; NPOINTS >= 16 with PATCH16 and
// NPOINTS=n, the first 16 forming the grid) with every tessellation level set to pc.level.
#include "core_test_common.glsl"
#if defined(NPOINTS)
layout(vertices = NPOINTS) out;
#elif defined(PATCH16)
layout(vertices = 16) out;
#else
layout(vertices = 4) out;
#endif
layout(location = 0) in vec3 v_pos[];
layout(location = 0) out vec3 c_pos[];
#ifdef PATCH16
layout(location = 1) out vec3 c_twice[]; // second per-vertex output: 2 * position
#endif
layout(location = 2) patch out float c_prim; // gl_PrimitiveID as the TCS sees it
layout(location = 3) patch out float c_mean_x; // mean x of all input points (reads every input)
void main() {
    c_pos[gl_InvocationID] = v_pos[gl_InvocationID];
#ifdef PATCH16
    c_twice[gl_InvocationID] = 2.0 * v_pos[gl_InvocationID];
#endif
    if (gl_InvocationID == 0) {
        c_prim = pc.first_patch + float(gl_PrimitiveID);
        float sx = 0.0;
        for (int k = 0; k < gl_PatchVerticesIn; ++k) {
            sx += v_pos[k].x;
        }
        c_mean_x = sx / float(gl_PatchVerticesIn);
        gl_TessLevelOuter[0] = pc.level;
        gl_TessLevelOuter[1] = pc.level;
        gl_TessLevelOuter[2] = pc.level;
        gl_TessLevelOuter[3] = pc.level;
        gl_TessLevelInner[0] = pc.level;
        gl_TessLevelInner[1] = pc.level;
    }
}
