#version 450
// Lit material: key light + head light diffuse, Blinn specular, optional colour by patch type
// (regular gold, irregular purple, triangle green, as in Fig. 1 of the Gregory-patch paper;
// single-crease patches teal).
// Normals come from the surface; back faces (the inside of open surfaces) use the flipped normal.
#include "frame.glsl"
layout(location = 0) in vec3 t_world;
layout(location = 1) in vec3 t_normal;
layout(location = 2) flat in uint t_class;
layout(location = 0) out vec4 out_color;

// Blue -> cyan -> green -> yellow -> red for t in [0, 1].
vec3 heat_ramp(float t) {
    vec3 c = vec3(clamp(1.5 - abs(4.0 * t - 3.0), 0.0, 1.0),
                  clamp(1.5 - abs(4.0 * t - 2.0), 0.0, 1.0),
                  clamp(1.5 - abs(4.0 * t - 1.0), 0.0, 1.0));
    return c;
}

// Adaptive patch kinds (adaptive/adaptive.glsl): regular, boundary, crease, end cap,
// single-crease, transition.
const vec3 KIND_COLORS[6] = vec3[6](vec3(0.90, 0.68, 0.20), vec3(0.95, 0.50, 0.15),
                                   vec3(0.85, 0.25, 0.25), vec3(0.58, 0.38, 0.80),
                                   vec3(0.20, 0.70, 0.70), vec3(0.30, 0.50, 0.90));

// Adaptive patch levels 0..8 (the thesis' Fig. 5.1 colours each level apart).
const vec3 LEVEL_COLORS[9] = vec3[9](vec3(0.25, 0.40, 0.90), vec3(0.20, 0.75, 0.85),
                                    vec3(0.30, 0.80, 0.35), vec3(0.95, 0.85, 0.25),
                                    vec3(0.95, 0.55, 0.15), vec3(0.90, 0.25, 0.25),
                                    vec3(0.80, 0.30, 0.75), vec3(0.55, 0.35, 0.85),
                                    vec3(0.95, 0.95, 0.95));

// Pm patch types (pm/pm.glsl): ordinary gold, polar blue, m = 3 green, 4 purple, 5 red.
const vec3 PM_COLORS[5] = vec3[5](vec3(0.90, 0.68, 0.20), vec3(0.25, 0.45, 0.90),
                                 vec3(0.30, 0.72, 0.35), vec3(0.58, 0.38, 0.80),
                                 vec3(0.85, 0.25, 0.25));

vec3 base_color() {
    if (t_class >= CLASS_PM) {
        if (frame.flags.x == COLOR_PATCH_TYPE) return PM_COLORS[min(t_class - CLASS_PM, 4u)];
        return vec3(0.72, 0.74, 0.78);
    }
    if (t_class >= CLASS_ADAPTIVE) {
        uint kind = min((t_class - CLASS_ADAPTIVE) / 16u, 5u);
        uint level = (t_class - CLASS_ADAPTIVE) % 16u;
        if (frame.flags.x == COLOR_LEVEL) return LEVEL_COLORS[min(level, 8u)];
        if (frame.flags.x == COLOR_PATCH_TYPE) return KIND_COLORS[kind];
        return vec3(0.72, 0.74, 0.78);
    }
    if (frame.flags.x == COLOR_ERROR) {
        if (t_class >= CLASS_HEAT_BASE) return heat_ramp(float(t_class - CLASS_HEAT_BASE) / 1023.0);
        if (t_class == CLASS_REGULAR) return heat_ramp(0.0);
        return vec3(0.72, 0.74, 0.78);
    }
    if (frame.flags.x != COLOR_PATCH_TYPE) return vec3(0.72, 0.74, 0.78);
    if (t_class == CLASS_REGULAR) return vec3(0.90, 0.68, 0.20);
    if (t_class == CLASS_TRIANGLE) return vec3(0.30, 0.72, 0.35);
    if (t_class == CLASS_SINGLE_CREASE) return vec3(0.15, 0.62, 0.70);
    return vec3(0.58, 0.38, 0.80);
}

void main() {
    vec3 n = normalize(t_normal);
    vec3 to_eye = normalize(frame.eye.xyz - t_world);
    if (!gl_FrontFacing) n = -n;
    vec3 l = normalize(frame.light_dir.xyz);
    vec3 h = normalize(l + to_eye);
    vec3 albedo = base_color();
    float key = max(dot(n, l), 0.0);
    float head = max(dot(n, to_eye), 0.0);
    float spec = pow(max(dot(n, h), 0.0), 48.0);
    vec3 c = albedo * (0.12 + 0.68 * key + 0.25 * head) + vec3(0.22 * spec);
    out_color = vec4(c, 1.0);
}
