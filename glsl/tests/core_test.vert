#version 450
// Core test: passes the control point through (object space = clip space).
layout(location = 0) in vec3 in_pos;
layout(location = 0) out vec3 v_pos;
void main() {
    v_pos = in_pos;
}
