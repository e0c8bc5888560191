#version 450
// Core test: bilinear quad; every invocation appends (u, v, patch id) and its position to an SSBO.
#include "core_test_common.glsl"
layout(quads, equal_spacing, ccw) in;
layout(location = 0) in vec3 c_pos[];
#ifdef PATCH16
layout(location = 1) in vec3 c_twice[];
#endif
layout(location = 2) patch in float c_prim;
layout(location = 3) patch in float c_mean_x;
struct CoreTestRecord {
    vec4 uvp; // u, v, patch (first_patch + gl_PrimitiveID), the same as seen by the TCS
    vec4 pos; // evaluated position, mean x of the TCS inputs
};
layout(std430, set = 0, binding = 0) buffer Capture {
    uint count;
    uint capacity;
    CoreTestRecord rec[];
} cap;
void main() {
    vec2 t = gl_TessCoord.xy;
#ifdef PATCH16
    // 4x4 row-major grid of points: corners are 0, 3, 15, 12.
    // Rows from the first output, columns checked through the second one (2 * position).
    vec3 a = mix(c_pos[0], 0.5 * c_twice[3], t.x);
    vec3 b = mix(0.5 * c_twice[12], c_pos[15], t.x);
#else
    vec3 a = mix(c_pos[0], c_pos[1], t.x);
    vec3 b = mix(c_pos[3], c_pos[2], t.x);
#endif
    vec3 p = mix(a, b, t.y);
    gl_Position = vec4(p, 1.0);
    uint slot = atomicAdd(cap.count, 1u);
    if (slot < cap.capacity) {
        cap.rec[slot].uvp = vec4(t, pc.first_patch + float(gl_PrimitiveID), c_prim);
        cap.rec[slot].pos = vec4(p, c_mean_x);
    }
}
