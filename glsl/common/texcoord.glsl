// Face-varying texture coordinates (OBJ `vt`; the mapping is documented in src/mesh/uv.rs) at a
// point of the surface given as the capture names it: base face, sub-face (NO_SUB_FACE: the
// face's own domain) and (u, v). The table (binding 14, SurfaceData::texcoord_words): entry f
// = (first corner entry, corner count, 0, 0) of face f; a corner entry = (s bits, t bits,
// vertex id, 0). Frame.flags.z bit 0 says whether the surface has any.
//
// Watertight: on a face edge every mapping reduces to the linear blend of the edge's two corner
// coordinates, evaluated here in the canonical frame of common/watertight.glsl (t from the
// smaller vertex id, edge_ts, precise), so two faces sharing the edge's two `vt` get the same
// bits there; inside an n-gon the edges between sub-faces blend the edge midpoint (itself the
// canonical blend at 1/2) and the centre the same way from both sides.
#ifndef TESSERA_TEXCOORD_GLSL
#define TESSERA_TEXCOORD_GLSL

#include "frame.glsl"
#include "watertight.glsl"

#ifndef NO_SUB_FACE
#define NO_SUB_FACE 0xffffffffu
#endif

layout(std430, set = 0, binding = 14) readonly buffer TexCoords {
    uvec4 texcoord_table[];
};

bool has_texcoords() {
    return (frame.flags.z & 1u) != 0u;
}

vec2 tc_value(uint entry) {
    uvec4 w = texcoord_table[entry];
    return vec2(uintBitsToFloat(w.x), uintBitsToFloat(w.y));
}

/// The blend along the face edge from corner a to corner b at x (measured from a), canonical.
vec2 tc_edge(uint first, uint a, uint b, float x) {
    bool a_lo = texcoord_table[first + a].z < texcoord_table[first + b].z;
    float t, s;
    edge_ts(x, a_lo, t, s);
    vec2 lo = tc_value(first + (a_lo ? a : b));
    vec2 hi = tc_value(first + (a_lo ? b : a));
    precise vec2 r = s * lo + t * hi;
    return r;
}

/// The blend from `from` to `to` at y, canonical in y.
vec2 tc_inner_edge(vec2 from, vec2 to, float y) {
    float t, s;
    canonical_ts(y, true, t, s);
    precise vec2 r = s * from + t * to;
    return r;
}

/// The mean of a face's n corner coordinates (its centre's).
vec2 tc_centre(uint first, uint n) {
    precise vec2 sum = vec2(0.0);
    for (uint i = 0u; i < n; ++i) {
        sum = sum + tc_value(first + i);
    }
    precise vec2 centre = sum / float(n);
    return centre;
}

vec2 tc_bilinear(vec2 c0, vec2 c1, vec2 c2, vec2 c3, vec2 uv) {
    precise vec2 r = ((1.0 - uv.x) * (1.0 - uv.y)) * c0 + (uv.x * (1.0 - uv.y)) * c1
                   + (uv.x * uv.y) * c2 + ((1.0 - uv.x) * uv.y) * c3;
    return r;
}

/// Texture coordinate of (face, sub_face, uv) (quads: bilinear; a triangle drawn whole:
/// barycentric, (u, v) the weights of corners 1 and 2; sub-face k of any other face: bilinear
/// over corner k, the midpoint of edge k -> k+1, the centre, the midpoint of edge k-1 -> k).
vec2 surface_texcoord(uint face, uint sub_face, vec2 uv) {
    uvec4 fe = texcoord_table[face];
    uint first = fe.x;
    uint n = fe.y;
    float u = uv.x;
    float v = uv.y;
    if (sub_face == NO_SUB_FACE && n == 4u) {
        if (v == 0.0) return tc_edge(first, 0u, 1u, u);
        if (u == 1.0) return tc_edge(first, 1u, 2u, v);
        if (v == 1.0) return tc_edge(first, 3u, 2u, u);
        if (u == 0.0) return tc_edge(first, 0u, 3u, v);
        return tc_bilinear(tc_value(first), tc_value(first + 1u), tc_value(first + 2u),
                           tc_value(first + 3u), uv);
    }
    if (sub_face == NO_SUB_FACE) {
        // A triangle drawn as one patch: barycentric; the edge opposite corner 0 is where the
        // weights of corners 1 and 2 sum to 1 (up to the tessellator's rounding).
        if (v == 0.0) return tc_edge(first, 0u, 1u, u);
        if (u == 0.0) return tc_edge(first, 0u, 2u, v);
        if (u + v >= 1.0 - 1e-6) return tc_edge(first, 1u, 2u, v);
        precise vec2 r = ((1.0 - u - v) * tc_value(first) + u * tc_value(first + 1u))
                       + v * tc_value(first + 2u);
        return r;
    }
    uint k = sub_face;
    uint next = (k + 1u) % n;
    uint prev = (k + n - 1u) % n;
    if (v == 0.0) return tc_edge(first, k, next, 0.5 * u);
    if (u == 0.0) return tc_edge(first, k, prev, 0.5 * v);
    vec2 centre = tc_centre(first, n);
    vec2 mid_next = tc_edge(first, k, next, 0.5);
    vec2 mid_prev = tc_edge(first, k, prev, 0.5);
    if (u == 1.0) return tc_inner_edge(mid_next, centre, v);
    if (v == 1.0) return tc_inner_edge(mid_prev, centre, u);
    return tc_bilinear(tc_value(first + k), mid_next, centre, mid_prev, uv);
}

/// d(s, t)/d(u, v) of the bilinear blend of c0..c3 (columns: by u, by v).
mat2 tc_bilinear_jacobian(vec2 c0, vec2 c1, vec2 c2, vec2 c3, vec2 uv) {
    return mat2((1.0 - uv.y) * (c1 - c0) + uv.y * (c2 - c3),
                (1.0 - uv.x) * (c3 - c0) + uv.x * (c2 - c1));
}

/// d(s, t)/d(u, v) of surface_texcoord at (face, sub_face, uv) (columns: by u, by v): each
/// mapping's own derivative (bilinear, barycentric, the sub-face's bilinear), the same on its
/// edges as inside (the edges' canonical evaluation only reorders the same blend).
mat2 surface_texcoord_jacobian(uint face, uint sub_face, vec2 uv) {
    uvec4 fe = texcoord_table[face];
    uint first = fe.x;
    uint n = fe.y;
    if (sub_face == NO_SUB_FACE && n == 4u) {
        return tc_bilinear_jacobian(tc_value(first), tc_value(first + 1u), tc_value(first + 2u),
                                    tc_value(first + 3u), uv);
    }
    if (sub_face == NO_SUB_FACE) {
        vec2 c0 = tc_value(first);
        return mat2(tc_value(first + 1u) - c0, tc_value(first + 2u) - c0);
    }
    uint k = sub_face;
    uint next = (k + 1u) % n;
    uint prev = (k + n - 1u) % n;
    return tc_bilinear_jacobian(tc_value(first + k), tc_edge(first, k, next, 0.5),
                                tc_centre(first, n), tc_edge(first, k, prev, 0.5), uv);
}

/// Texture coordinate of a point of sector k of a Pm facet (pm/patch_pm_sector.tese) at
/// barycentric w over (corner k, corner k + 1, centre): linear over the sector triangle, the
/// centre's value the mean of the corners'. Facet edges as every face (tc_edge); a spoke is
/// blended from its corner to the centre by the centre's weight, canonical in it (the sector on
/// the other side reads that weight as 1 - its corner's weight), so both sectors of a spoke
/// get the same bits.
vec2 pm_sector_texcoord(uint face, uint k, vec3 w) {
    uvec4 fe = texcoord_table[face];
    uint first = fe.x;
    uint n = fe.y;
    uint next = (k + 1u) % n;
    vec2 centre = tc_centre(first, n);
    vec2 ck = tc_value(first + k);
    vec2 cn = tc_value(first + next);
    int zeros = int(w.x == 0.0) + int(w.y == 0.0) + int(w.z == 0.0);
    if (zeros >= 2) {
        return w.z != 0.0 ? centre : (w.x != 0.0 ? ck : cn);
    }
    if (w.z == 0.0) return tc_edge(first, k, next, w.y);
    if (w.x == 0.0) return tc_inner_edge(cn, centre, w.z);
    if (w.y == 0.0) return tc_inner_edge(centre, ck, w.x);
    precise vec2 r = (w.x * ck + w.y * cn) + w.z * centre;
    return r;
}

/// d(s, t)/d(w.y, w.z) of pm_sector_texcoord in sector k (w.x = 1 - w.y - w.z; columns: by
/// w.y, by w.z): linear over the sector triangle.
mat2 pm_sector_texcoord_jacobian(uint face, uint k) {
    uvec4 fe = texcoord_table[face];
    uint first = fe.x;
    uint n = fe.y;
    vec2 ck = tc_value(first + k);
    return mat2(tc_value(first + (k + 1u) % n) - ck, tc_centre(first, n) - ck);
}

#endif
