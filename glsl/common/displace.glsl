// Displacement along the normal (`--displacement procedural --displacement-scale S`), applied by
// every evaluation stage after the watertight position and normal, and by the CPU-path vertex
// stage. Rust mirrors it in src/render/displace.rs. Needs the Frame block (frame.glsl).
//
// Watertight: the inputs (position, normal) are bitwise equal on both sides of a shared smooth
// edge, and this is one function of them in precise arithmetic, so the displaced points are too.
// Across an infinitely sharp crease the normals differ, and so do the displaced points.
#ifndef TESSERA_DISPLACE_GLSL
#define TESSERA_DISPLACE_GLSL

/// d(p) = (sin(5x + 1) + sin(5y + 2) + sin(5z + 3)) / 3, in [-1, 1], and its gradient.
float procedural_displacement(vec3 p, out vec3 grad) {
    precise vec3 a = 5.0 * p + vec3(1.0, 2.0, 3.0);
    precise vec3 g = (5.0 / 3.0) * cos(a);
    precise float d = (sin(a.x) + sin(a.y) + sin(a.z)) / 3.0;
    grad = g;
    return d;
}

/// p + s d(p) n with s = Frame.displace.x; the shading normal tilted by the tangential part of
/// s grad d (first order: the surface's own curvature term is left out).
void displace_point(inout vec3 p, inout vec3 n) {
    float s = frame.displace.x;
    if (s == 0.0) {
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

#endif
