#version 450
// Core test: one bilinear quad patch with every tessellation level set to pc.level.
#include "core_test_common.glsl"
layout(vertices = 4) out;
layout(location = 0) in vec3 v_pos[];
layout(location = 0) out vec3 c_pos[];
void main() {
    c_pos[gl_InvocationID] = v_pos[gl_InvocationID];
    if (gl_InvocationID == 0) {
        gl_TessLevelOuter[0] = pc.level;
        gl_TessLevelOuter[1] = pc.level;
        gl_TessLevelOuter[2] = pc.level;
        gl_TessLevelOuter[3] = pc.level;
        gl_TessLevelInner[0] = pc.level;
        gl_TessLevelInner[1] = pc.level;
    }
}
