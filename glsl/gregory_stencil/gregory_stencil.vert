#version 450
// Gregory patches, stencil variant: passes each one-ring vertex (world space) to the TCS.
layout(location = 0) in vec3 in_pos;
layout(location = 0) out vec3 v_pos;
void main() {
    v_pos = in_pos;
}
