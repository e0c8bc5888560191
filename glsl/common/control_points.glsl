// Control-vertex positions as a storage buffer, xyz per vertex tightly packed (the values the
// B-spline path reads as vertices; in the adaptive scheme the refined points of every level).
#ifndef TESSERA_CONTROL_POINTS_GLSL
#define TESSERA_CONTROL_POINTS_GLSL

layout(std430, set = 0, binding = 8) readonly buffer ControlPositions {
    float control_pos[];
};

vec3 control_point(uint v) {
    return vec3(control_pos[3u * v], control_pos[3u * v + 1u], control_pos[3u * v + 2u]);
}

#endif
