// Displacement along the normal, applied by every evaluation stage after the watertight position
// and normal, and by the CPU-path vertex stage. Rust mirrors it in src/render/displace.rs.
// Frame.displace: x the scale s (0: off), y the mode (DISPLACE_PROCEDURAL, DISPLACE_MAP).
// * Procedural (`--displacement procedural`): d(p) of the undisplaced limit position.
// * Map (`--displacement FILE.png`): d = value - 0.5 of the displacement map (binding 15, a
//   combined image sampler: linear filtering, repeat addressing) at the point's face-varying
//   texture coordinate (texcoord.glsl), read with textureLod(.., 0) (evaluation stages have no
//   implicit derivatives).
// The point moves to p + s d n. The shading normal, both modes, is n tilted by the surface
// gradient of d: normalize(n - s grad_surf d), the exact normal of p + s d n when the surface's
// own curvature term s d dn is left out (first order). Procedural: grad_surf d is the tangential
// part of grad d. Map: the chain rule through the caller's tangents (SurfaceTangents: dp/da,
// dp/db of the undisplaced surface in the stage's own parameters and d(u, v)/d(a, b) to the
// capture's (u, v)), the texture-coordinate Jacobian d(s, t)/d(u, v) (texcoord.glsl) and the
// map's (s, t)-gradient: the analytic derivative of the bilinear filter from the four texels
// (texelFetch, wrapped), map_gradient; DisplacementMap::sample mirrors it on the CPU. Where the
// tangents degenerate (|n . ta x tb| <= 1e-6 |ta| |tb|: a polar pole, a crease sector's
// collinear corner tangents) the normal is kept.
//
// Watertight: the inputs (position, normal, and for the map the texture coordinate where the
// faces share their `vt`) are bitwise equal on both sides of a shared smooth edge, and the
// displaced point is one function of them in precise arithmetic (it never reads the tangents or
// the tilted normal), so the displaced points are too. Across an infinitely sharp crease the
// normals differ, and so do the displaced points. The tilted normals agree across edges only
// to a tolerance: each side's tangents and texture-coordinate Jacobian are its own.
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

/// Tangents of the undisplaced surface at a point: ta = dp/da, tb = dp/db in the evaluating
/// stage's own parameters (a, b), and uv_jac = d(u, v)/d(a, b) (columns: by a, by b) of the
/// capture's (u, v) the texture coordinate is looked up at (mat2(1.0): the same parameters).
struct SurfaceTangents {
    vec3 ta;
    vec3 tb;
    mat2 uv_jac;
};

/// Tangents in the capture's own (u, v).
SurfaceTangents uv_tangents(vec3 du, vec3 dv) {
    return SurfaceTangents(du, dv, mat2(1.0));
}

/// The same tangents with the stage's parameters mapped to the capture's (u, v) by a further
/// linear map `jac` = d(u, v)/d(stage's (u, v)) (e.g. a sub-patch's axes in its base face).
SurfaceTangents mapped_tangents(SurfaceTangents tg, mat2 jac) {
    return SurfaceTangents(tg.ta, tg.tb, jac * tg.uv_jac);
}

/// (s, t)-gradient of the map's value: the derivative of the bilinear filter between the four
/// texel centres around st (texel (i, j) at ((i + 0.5) / w, (j + 0.5) / h), wrapped as repeat
/// addressing wraps), from the texels themselves (texelFetch): the piece holding st.
vec2 map_gradient(vec2 st) {
    ivec2 size = textureSize(displacement_map, 0);
    vec2 x = st * vec2(size) - 0.5;
    vec2 x0 = floor(x);
    vec2 f = x - x0;
    ivec2 i0 = ivec2(mod(x0, vec2(size)));
    ivec2 i1 = ivec2(mod(x0 + 1.0, vec2(size)));
    i0 = clamp(i0, ivec2(0), size - 1);
    i1 = clamp(i1, ivec2(0), size - 1);
    float v00 = texelFetch(displacement_map, ivec2(i0.x, i0.y), 0).r;
    float v10 = texelFetch(displacement_map, ivec2(i1.x, i0.y), 0).r;
    float v01 = texelFetch(displacement_map, ivec2(i0.x, i1.y), 0).r;
    float v11 = texelFetch(displacement_map, ivec2(i1.x, i1.y), 0).r;
    float ds = ((1.0 - f.y) * (v10 - v00) + f.y * (v11 - v01)) * float(size.x);
    float dt = ((1.0 - f.x) * (v01 - v00) + f.x * (v11 - v10)) * float(size.y);
    return vec2(ds, dt);
}

/// The surface gradient of d at a point with unit normal n: the vector g perpendicular to n
/// with g . ta = dd/da and g . tb = dd/db, for dd = (dd/da, dd/db); zero where the tangents
/// degenerate.
vec3 surface_gradient(vec3 n, vec3 ta, vec3 tb, vec2 dd) {
    float det = dot(n, cross(ta, tb));
    if (!(abs(det) > 1e-6 * length(ta) * length(tb))) {
        return vec3(0.0);
    }
    return (cross(tb, n) * dd.x + cross(n, ta) * dd.y) / det;
}

/// Displaces (p, n) by the current mode; `st` is the point's texture coordinate and `st_jac`
/// its Jacobian d(s, t)/d(u, v) in the capture's (u, v) (columns: by u, by v), read by the map
/// mode only, as are the tangents `tg`. Both modes tilt the shading normal (file docs).
void displace_with_texcoord(vec2 st, mat2 st_jac, SurfaceTangents tg, inout vec3 p,
                            inout vec3 n) {
    float s = frame.displace.x;
    if (s == 0.0) {
        return;
    }
    if (frame.displace.y == DISPLACE_MAP) {
        precise float d = textureLod(displacement_map, st, 0.0).r - 0.5;
        precise vec3 moved = p + (s * d) * n;
        // dd/d(a, b) = grad_st(d) . d(s, t)/d(a, b), d(s, t)/d(a, b) = st_jac * uv_jac.
        vec2 dd = map_gradient(st) * (st_jac * tg.uv_jac);
        vec3 g = surface_gradient(n, tg.ta, tg.tb, dd);
        p = moved;
        n = normalize(n - s * g);
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
/// (sub_face NO_SUB_FACE: the face's own domain), with the undisplaced surface's tangents
/// there; the texture coordinate and its Jacobian are looked up only for the map mode.
void displace_point(uint face, uint sub_face, vec2 uv, SurfaceTangents tg, inout vec3 p,
                    inout vec3 n) {
    bool map = displacing_by_map();
    vec2 st = map ? surface_texcoord(face, sub_face, uv) : vec2(0.0);
    mat2 st_jac = map ? surface_texcoord_jacobian(face, sub_face, uv) : mat2(0.0);
    displace_with_texcoord(st, st_jac, tg, p, n);
}

#endif
