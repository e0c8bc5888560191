#version 450
// Core test: bilinear quad; every invocation appends (u, v, patch id) and its position to an SSBO.
#include "core_test_common.glsl"
layout(quads, equal_spacing, ccw) in;
layout(location = 0) in vec3 c_pos[];
struct CoreTestRecord {
    vec4 uvp; // u, v, gl_PrimitiveID
    vec4 pos; // evaluated position
};
layout(std430, set = 0, binding = 0) buffer Capture {
    uint count;
    uint capacity;
    CoreTestRecord rec[];
} cap;
void main() {
    vec2 t = gl_TessCoord.xy;
    vec3 a = mix(c_pos[0], c_pos[1], t.x);
    vec3 b = mix(c_pos[3], c_pos[2], t.x);
    vec3 p = mix(a, b, t.y);
    gl_Position = vec4(p, 1.0);
    uint slot = atomicAdd(cap.count, 1u);
    if (slot < cap.capacity) {
        cap.rec[slot].uvp = vec4(t, float(gl_PrimitiveID), 0.0);
        cap.rec[slot].pos = vec4(p, 0.0);
    }
}
