// Displacement along the normal, applied by every evaluation stage after the watertight position
// and normal, and by the CPU-path vertex stage. Rust mirrors it in src/render/displace.rs.
// Frame.displace: x the scale s (0: off), y the mode (DISPLACE_PROCEDURAL, DISPLACE_MAP).
// * Procedural (`--displacement procedural`): d(p) of the undisplaced limit position.
// * Map (`--displacement FILE.png`): d = value - 0.5 of the displacement map (binding 15, a
//   combined image sampler: linear filtering, repeat addressing) at the point's face-varying
//   texture coordinate (texcoord.glsl), read with textureLod(.., 0) (evaluation stages have no
//   implicit derivatives). The normal is kept.
// The point moves to p + s d n.
//
// Watertight: the inputs (position, normal, and for the map the texture coordinate where the
// faces share their `vt`) are bitwise equal on both sides of a shared smooth edge, and this is
// one function of them in precise arithmetic, so the displaced points are too. Across an
// infinitely sharp crease the normals differ, and so do the displaced points.
#ifndef TESSERA_DISPLACE_GLSL
#define TESSERA_DISPLACE_GLSL

#include "texcoord.glsl"

#define DISPLACE_PROCEDURAL 0.0
#define DISPLACE_MAP 1.0

layout(set = 0, binding = 15) uniform sampler2D displacement_map;

/// d(p) = (sin(5x + 1) + sin(5y + 2) + sin(5z + 3)) / 3, in [-1, 1], and its gradient.
float procedural_displacement(vec3 p, out vec3 grad) {
    precise vec3 a = 5.0 * p + vec3(1.0, 2.0, 3.0);
    precise vec3 g = (5.0 / 3.0) * cos(a);
    precise float d = (sin(a.x) + sin(a.y) + sin(a.z)) / 3.0;
    grad = g;
    return d;
}

/// Whether the displacement reads the map (the caller then needs the texture coordinate).
bool displacing_by_map() {
    return frame.displace.x != 0.0 && frame.displace.y == DISPLACE_MAP;
}

/// Displaces (p, n) by the current mode; `st` is the point's texture coordinate, read by the
/// map mode only. Procedural: the shading normal tilted by the tangential part of s grad d
/// (first order: the surface's own curvature term is left out).
void displace_with_texcoord(vec2 st, inout vec3 p, inout vec3 n) {
    float s = frame.displace.x;
    if (s == 0.0) {
        return;
    }
    if (frame.displace.y == DISPLACE_MAP) {
        precise float d = textureLod(displacement_map, st, 0.0).r - 0.5;
        precise vec3 moved = p + (s * d) * n;
        p = moved;
        return;
    }
    vec3 g;
    precise float d = procedural_displacement(p, g);
    precise vec3 tangential = g - dot(g, n) * n;
    precise vec3 moved = p + (s * d) * n;
    precise vec3 tilted = normalize(n - s * tangential);
    p = moved;
    n = tilted;
}

/// Displaces the point (face, sub_face, uv) of the surface, named as the capture names it
/// (sub_face NO_SUB_FACE: the face's own domain); the texture coordinate is looked up only
/// for the map mode.
void displace_point(uint face, uint sub_face, vec2 uv, inout vec3 p, inout vec3 n) {
    vec2 st = displacing_by_map() ? surface_texcoord(face, sub_face, uv) : vec2(0.0);
    displace_with_texcoord(st, p, n);
}

#endif
