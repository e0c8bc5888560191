#version 450
// examples/engine.rs: a checkerboard in two colours from the engine's push constants.
layout(push_constant) uniform Ground {
    vec4 light;
    vec4 dark;
    float cell;
} pc;
layout(location = 0) in vec2 v_xz;
layout(location = 0) out vec4 out_color;
void main() {
    ivec2 k = ivec2(floor(v_xz / pc.cell));
    out_color = ((k.x + k.y) & 1) == 0 ? pc.light : pc.dark;
}
