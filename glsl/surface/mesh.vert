#version 450
// Triangles evaluated on the CPU (faces without a GPU patch scheme yet): world position, normal
// and colour class per vertex, and the domain point it lies at with the limit surface's partials
// there (texture coordinates and tangents for a displacement map).
#include "frame.glsl"
layout(location = 0) in vec3 in_pos;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in uint in_class;
layout(location = 3) in uvec2 in_face;  // base face (0xffffffff: none), sub-face
layout(location = 4) in vec2 in_uv;     // (u, v) in that domain
layout(location = 5) in vec3 in_du;     // dP/du there
layout(location = 6) in vec3 in_dv;     // dP/dv there
layout(location = 0) out vec3 t_world;
layout(location = 1) out vec3 t_normal;
layout(location = 2) flat out uint t_class;
void main() {
    vec3 p = in_pos;
    vec3 n = in_normal;
    if (in_face.x != 0xffffffffu || !displacing_by_map()) {
        displace_point(in_face.x, in_face.y, in_uv, uv_tangents(in_du, in_dv), p, n);
    }
    t_world = p;
    t_normal = n;
    t_class = in_class;
    gl_Position = frame.view_proj * vec4(p, 1.0);
}
