// Gregory patch evaluation shared by both GPU construction variants (Loop, Schaefer, Ni, Castano
// 2009, §3.1, §4.4, §4.5). The TES also includes common/frame.glsl (push constants, vertex_limit).
//
// TCS -> TES contract (both variants):
//   quads:     layout(vertices = 20) out vec3 g_cp[] at location 0: p0..3, e_plus0..3, e_minus0..3,
//              f_plus0..3, f_minus0..3 (src/patch/gregory GregoryQuad fields, corner i = face corner i);
//              layout(location = 1) patch out vec3 g_eout[8].
//   triangles: layout(vertices = 15), same order with 3 per kind; patch out vec3 g_eout[6].
//   g_eout[2k]   : at corner k, the edge point of corner k's vertex on the ring edge beyond patch edge k
//                  (k -> k+1), i.e. the neighbour face's other edge point there (own one: e_minus[k]);
//   g_eout[2k+1] : at corner k+1, the neighbour's other edge point there (own one: e_plus[k+1]).
// Per-patch record (binding 6), indexed by chunk.patch_base + gl_PrimitiveID.
//
// Watertightness (§4.5): a patch corner is put at vertex_limit[id] with normal vertex_normal[id]
// (per-vertex data every patch type reads). A patch edge is evaluated from data both neighbours
// hold bitwise equal, with the parameter running from the end with the smaller vertex id:
// Gregory/Gregory edges as the boundary cubic (p, e, e, p) with normal cross(tangent, cross-edge
// vector) where the cross-edge vector blends (e_left - e_right) of both end vertices; edges shared
// with a regular B-spline patch from the 12 B-spline points of the edge's grid, exactly as
// glsl/patch_bspline.tese evaluates them. The edge arithmetic is `precise` (no contraction into
// fused multiply-adds), so every shader that inlines it computes the same bits.
#ifndef TESSERA_GREGORY_GLSL
#define TESSERA_GREGORY_GLSL

#include "common/bspline.glsl"

/// One Gregory patch. flags bit k (0..3): patch edge k (corner k -> k+1) is shared with a regular
/// B-spline patch (evaluate it from the grid in binding 7).
struct GregoryPatchInfo {
    uint face;
    uint flags;
    uint pad0;
    uint pad1;
    uvec4 corners; // vertex ids of the face corners (w unused for triangles)
};

layout(std430, set = 0, binding = 6) readonly buffer GregoryPatches {
    GregoryPatchInfo gpatches[];
};

/// Per patch 4 edges x 12 vertex ids: grid_ids[patch * 48 + k * 12 + row * 4 + i], i along the
/// edge from its smaller-id end, row 0 = left of that direction, 1 = on the edge, 2 = right.
layout(std430, set = 0, binding = 7) readonly buffer GregoryGrids {
    uint grid_ids[];
};

/// Control-vertex positions, xyz per vertex (the values the B-spline path reads as vertices).
layout(std430, set = 0, binding = 8) readonly buffer ControlPositions {
    float control_pos[];
};

/// Unit limit normal per vertex (xyz), read at patch corners.
layout(std430, set = 0, binding = 9) readonly buffer VertexNormals {
    vec4 vertex_normal[];
};

vec3 control_point(uint v) {
    return vec3(control_pos[3u * v], control_pos[3u * v + 1u], control_pos[3u * v + 2u]);
}

/// Canonical edge parameters (t, s = 1 - t), t measured from the edge end with the smaller id,
/// from a coordinate x measured from one end (`from_lo`: that end is the smaller id). Derived
/// from max(x, 1 - x) only, as patch_bspline.tese does, so both sides agree when the tessellator
/// gives them x and 1 - x.
void canonical_ts(float x, bool from_lo, out float t, out float s) {
    precise float w = max(x, 1.0 - x);
    precise float l = 1.0 - w;
    t = (x >= 0.5) ? w : l;
    s = (x >= 0.5) ? l : w;
    if (!from_lo) {
        float tmp = t;
        t = s;
        s = tmp;
    }
}

/// Derivative of bspline3(t, s) with respect to t.
vec4 bspline3_deriv(float t, float s) {
    float d1t = (-12.0 * t + 9.0 * t * t) * (1.0 / 6.0);
    float d1s = (-12.0 * s + 9.0 * s * s) * (1.0 / 6.0);
    return vec4(-0.5 * s * s, d1t, -d1s, 0.5 * t * t);
}

/// Edge shared with a regular patch: the limit curve of the 12-point grid (position as
/// patch_bspline.tese's edge_point) and the normal cross(dC/dt, sum N_i (left_i - right_i)).
void grid_edge(uint patch_index, int k, float t, float s, out vec3 pos, out vec3 nrm) {
    uint base = patch_index * 48u + uint(k) * 12u;
    precise vec3 c[4];
    precise vec3 d[4];
    for (int i = 0; i < 4; ++i) {
        vec3 l = control_point(grid_ids[base + uint(i)]);
        vec3 m = control_point(grid_ids[base + 4u + uint(i)]);
        vec3 r = control_point(grid_ids[base + 8u + uint(i)]);
        c[i] = ((l + r) + 4.0 * m) * (1.0 / 6.0);
        d[i] = l - r;
    }
    precise vec4 n = bspline3(t, s);
    precise vec3 p = ((n.x * c[0] + n.y * c[1]) + n.z * c[2]) + n.w * c[3];
    precise vec4 dn = bspline3_deriv(t, s);
    precise vec3 tangent = ((dn.x * c[0] + dn.y * c[1]) + dn.z * c[2]) + dn.w * c[3];
    precise vec3 cross_dir = ((n.x * d[0] + n.y * d[1]) + n.z * d[2]) + n.w * d[3];
    precise vec3 nn = normalize(cross(tangent, cross_dir));
    pos = p;
    nrm = nn;
}

/// Gregory/Gregory edge in canonical order: boundary cubic (p0, e0, e1, p1) from the smaller-id
/// end, normal cross(tangent, s d0 + t d1) with d the (left - right) edge-point differences at
/// both ends (tangent-plane vectors across the edge, §3.3).
void gregory_edge(vec3 p0, vec3 e0, vec3 e1, vec3 p1, vec3 d0, vec3 d1, float t, float s,
                  out vec3 pos, out vec3 nrm) {
    precise vec4 b = vec4(s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t);
    precise vec3 p = ((b.x * p0 + b.y * e0) + b.z * e1) + b.w * p1;
    precise vec3 tangent = ((s * s) * (e0 - p0) + (2.0 * t * s) * (e1 - e0)) + (t * t) * (p1 - e1);
    precise vec3 cross_dir = s * d0 + t * d1;
    precise vec3 nn = normalize(cross(tangent, cross_dir));
    pos = p;
    nrm = nn;
}

/// `(a x + b y) / (a + b)`, the mean where a + b == 0 (the patch corner, §4.4).
vec3 gregory_blend(float a, vec3 x, float b, vec3 y) {
    float sum = a + b;
    return sum > 0.0 ? (a * x + b * y) / sum : 0.5 * (x + y);
}

/// Unit normal of derivatives, +z if degenerate.
vec3 safe_normal(vec3 du, vec3 dv) {
    vec3 n = cross(du, dv);
    float len = length(n);
    return len > 0.0 ? n / len : vec3(0.0, 0.0, 1.0);
}

#endif
