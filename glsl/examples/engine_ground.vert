#version 450
// examples/engine.rs: the engine's own ground quad (no vertex buffer), drawn in the same pass
// as tessera's surface. Set 0 is the engine's camera; tessera's sets start at set 1.
layout(set = 0, binding = 0) uniform Camera {
    mat4 view_proj;
    vec4 ground; // xyz centre, w half extent
} cam;
layout(location = 0) out vec2 v_xz;
const vec2 CORNERS[6] = vec2[](vec2(-1, -1), vec2(1, -1), vec2(1, 1),
                               vec2(-1, -1), vec2(1, 1), vec2(-1, 1));
void main() {
    vec2 c = CORNERS[gl_VertexIndex] * cam.ground.w;
    vec3 p = cam.ground.xyz + vec3(c.x, 0.0, c.y);
    v_xz = c;
    gl_Position = cam.view_proj * vec4(p, 1.0);
}
