#version 450
// Regular B-spline patches: passes each control vertex (world space) to the TCS.
layout(location = 0) in vec3 in_pos;
layout(location = 0) out vec3 v_pos;
void main() {
    v_pos = in_pos;
}
