#version 450
// Core test: bilinear quad; every invocation appends its domain (u,v) to an SSBO.
#include "core_test_common.glsl"
layout(quads, equal_spacing, ccw) in;
layout(location = 0) in vec3 c_pos[];
layout(std430, set = 0, binding = 0) buffer Capture {
    uint count;
    uint capacity;
    vec2 uv[];
} cap;
void main() {
    vec2 t = gl_TessCoord.xy;
    vec3 a = mix(c_pos[0], c_pos[1], t.x);
    vec3 b = mix(c_pos[3], c_pos[2], t.x);
    gl_Position = vec4(mix(a, b, t.y), 1.0);
    uint slot = atomicAdd(cap.count, 1u);
    if (slot < cap.capacity) {
        cap.uv[slot] = t;
    }
}
