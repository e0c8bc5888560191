// Gregory patch evaluation shared by both GPU construction variants (Loop, Schaefer, Ni, Castano
// 2009, §3.1, §4.4, §4.5). The TES also includes common/frame.glsl (push constants, vertex_limit).
//
// TCS -> TES contract (both variants):
//   quads:     layout(vertices = 20) out vec3 g_cp[] at location 0: p0..3, e_plus0..3, e_minus0..3,
//              f_plus0..3, f_minus0..3 (src/patch/gregory/eval.rs GregoryQuad fields; corner i =
//              face corner i);
//              layout(location = 1) patch out vec3 g_eout[8];
//              layout(location = 9) patch out vec3 g_nbr[8].
//   triangles: layout(vertices = 15), same order with 3 per kind; g_eout[6] at location 1,
//              g_nbr[6] at location 7.
//   g_eout[2k]   : at corner k, the edge point of corner k's vertex on the ring edge beyond patch edge k
//                  (k -> k+1), i.e. the neighbour face's other edge point there (own one: e_minus[k]);
//   g_eout[2k+1] : at corner k+1, the neighbour's other edge point there (own one: e_plus[k+1]);
//   g_nbr[2k], g_nbr[2k+1]: the neighbour patch's face points next to edge k at corner k and at
//                  corner k+1 (eq. 6 with the neighbour's face size, flags bit 8+k), computed with
//                  the same arithmetic as the neighbour computes them for itself.
// Per-patch record (binding 6), indexed by chunk.patch_base + gl_PrimitiveID.
//
// Corner frames: every point above belongs to one face corner (p, e, f of corner i; g_eout[2k]
// and g_nbr[2k] to corner k, g_eout[2k+1] and g_nbr[2k+1] to corner k+1) and is passed relative
// to that corner's origin GREGORY_CORNER_ORIGIN(info, i): the control position of the corner's
// vertex for the Gregory schemes, zero (absolute points) where a stage defines it so. Points a
// few hundredths of the model apart then keep their digits in f32 however far the model lies
// from the coordinate origin (the car's normals: 2.6e-4 rad from the f64 construction with
// absolute points). Every patch at a vertex uses the same origin, so shared points keep equal
// bits; an edge is evaluated in the frame of its smaller-id end (shared_edge).
//
// Watertightness (§4.5): corners and the canonical edge parameter follow common/watertight.glsl;
// an edge shared with a regular B-spline patch is its grid_edge_rows on the edge's 12 grid points
// (binding 7, grid_edge), exactly as bspline/patch_bspline.tese evaluates it. Gregory/Gregory
// edges (shared_edge): the boundary cubic (p, e, e, p) with normal cross(tangent, d_left -
// d_right), d = both patches' cross-edge derivatives (each side computes both), `precise` as well.
#ifndef TESSERA_GREGORY_GLSL
#define TESSERA_GREGORY_GLSL

/// One Gregory patch. flags bit 4+k: patch edge k is a boundary or infinitely sharp edge shared with
/// a regular patch (its curve is the cubic B-spline of the crease polygon, see grid_edge_rows).
/// flags bit k (0..3): patch edge k (corner k -> k+1) is shared with a regular
/// B-spline patch (evaluate it from the grid in binding 7); bit 8+k: the face across edge k is a
/// triangle (else a quad); bit 12+k: edge k is a boundary or infinitely sharp edge (no
/// neighbour term in its normal); bit 16+k: corner k's vertex has several sectors (crease or
/// corner rule, §4.6), so the corner keeps this patch's own normal (its position is still
/// vertex_limit).
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

#include "control_points.glsl"

#include "watertight.glsl"
#include "tri_sub.glsl"

#ifndef GREGORY_CORNER_ORIGIN
/// Origin of corner k's points (the contract above): the control position of its vertex.
#define GREGORY_CORNER_ORIGIN(info, k) control_point((info).corners[(k)])
#endif

#ifdef TESSERA_FRAME_GLSL
/// Bit of chunk.sub_index: the triangle draw is split into chunk.split^2 sub-triangles (the
/// sub-triangle index in the low bits); without it a split-level triangle is drawn whole.
#define TRI_SUB_MODE 0x80000000u

bool tri_sub_mode() {
    return chunk.split > 1u && (chunk.sub_index & TRI_SUB_MODE) != 0u;
}

/// Barycentric weights (of face corners 0, 1, 2) of this TES invocation's domain point. In
/// sub-triangle mode, points on a sub-triangle edge are put on the lattice k / L of the full
/// edge level L with integer arithmetic, so both sub-triangles (and a split quad across an outer
/// edge) agree bitwise; inner points map affinely.
vec3 tri_domain_point(vec3 tc) {
    if (!tri_sub_mode()) {
        return tc;
    }
    uint n = chunk.split;
    float sub = ceil(clamp(frame.tess.x / float(n), 1.0, frame.tess.w));
    ivec2 c0, c1, c2;
    tri_sub_corners(chunk.sub_index & ~TRI_SUB_MODE, n, c0, c1, c2);
    if (tc.x == 0.0 || tc.y == 0.0 || tc.z == 0.0) {
        int ks = int(sub);
        int k0 = int(round(tc.x * sub));
        int k1 = int(round(tc.y * sub));
        int k2 = ks - k0 - k1;
        ivec2 b = c0 * k0 + c1 * k1 + c2 * k2;
        int total = ks * int(n);
        float l = float(total);
        return vec3(float(total - b.x - b.y) / l, float(b.x) / l, float(b.y) / l);
    }
    vec2 b = (vec2(c0) * tc.x + vec2(c1) * tc.y + vec2(c2) * tc.z) / float(n);
    return vec3(1.0 - b.x - b.y, b.x, b.y);
}

#ifdef TESSERA_TESS_FACTORS_GLSL
/// Outer level of a triangle edge. Sub-triangle mode: the sub-level (as the quads' sub-patches).
/// Whole triangles with the quads' split in chunk.split: the split quads' full edge level.
float gregory_tri_edge_level(uint a, uint b) {
    float l = edge_tess_level(a, b);
    return (chunk.split > 1u && !tri_sub_mode()) ? split_edge_level() : l;
}

/// Levels of the triangle patch with corner vertex ids c.xyz. Triangle domain: outer[i] is the
/// edge where gl_TessCoord[i] == 0 (the barycentric weight of corner i), so outer[0] is edge 1-2,
/// [1] edge 2-0, [2] edge 0-1. Triangles are drawn whole; with split quads their edges take the
/// quads' full level (gregory_tri_edge_level).
void set_gregory_tri_tess_levels(uvec4 c) {
    float o0 = gregory_tri_edge_level(c.y, c.z);
    float o1 = gregory_tri_edge_level(c.z, c.x);
    float o2 = gregory_tri_edge_level(c.x, c.y);
    gl_TessLevelOuter[0] = o0;
    gl_TessLevelOuter[1] = o1;
    gl_TessLevelOuter[2] = o2;
    gl_TessLevelInner[0] = max(o0, max(o1, o2));
}
#endif
#endif

/// Edge k of Gregory patch `patch_index` shared with a regular patch: [`grid_edge_rows`] on the
/// grid ids of binding 7.
void grid_edge(uint patch_index, uint flags, int k, float t, float s, out vec3 pos,
               out vec3 nrm) {
    uint base = patch_index * 48u + uint(k) * 12u;
    vec3 l[4];
    vec3 m[4];
    vec3 r[4];
    for (int i = 0; i < 4; ++i) {
        l[i] = control_point(grid_ids[base + uint(i)]);
        m[i] = control_point(grid_ids[base + 4u + uint(i)]);
        r[i] = control_point(grid_ids[base + 8u + uint(i)]);
    }
    // Phantom points of a boundary-regular neighbour, mirrored as bspline/patch_bspline.tesc does
    // (2 a - b: the doubling is exact, so the result does not depend on contraction).
    if ((flags & (1u << uint(20 + 2 * k))) != 0u) {
        l[0] = 2.0 * l[1] - l[2];
        m[0] = 2.0 * m[1] - m[2];
        r[0] = 2.0 * r[1] - r[2];
    }
    if ((flags & (1u << uint(21 + 2 * k))) != 0u) {
        l[3] = 2.0 * l[2] - l[1];
        m[3] = 2.0 * m[2] - m[1];
        r[3] = 2.0 * r[2] - r[1];
    }
    bool sharp = (flags & (1u << uint(4 + k))) != 0u;
    grid_edge_rows(l, m, r, sharp, t, s, pos, nrm);
}

/// Cross-edge derivative of a quad Gregory patch along one of its edges, pointing into the
/// patch, in the canonical frame (t from the smaller-id end "0"): the edge row (p0, e0, e1, p1)
/// and the next row (eo0, f0, f1, eo1) of the Bezier net, eo = the patch's other edge point at
/// that end, f = its face point there next to this edge (at the edge F_i equals that f, §4.4).
vec3 cross_quad(vec3 p0, vec3 e0, vec3 e1, vec3 p1, vec3 eo0, vec3 f0, vec3 f1, vec3 eo1,
                float t, float s) {
    precise vec4 b = vec4(s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t);
    precise vec3 d = 3.0 * (((b.x * (eo0 - p0) + b.y * (f0 - e0)) + b.z * (f1 - e1))
                            + b.w * (eo1 - p1));
    return d;
}

/// Derivative along the edge (by t) of cross_quad (same arguments): the quadratic of the
/// differences of its cubic's coefficients, exact on the edge where the face points are frozen.
vec3 cross_quad_slope(vec3 p0, vec3 e0, vec3 e1, vec3 p1, vec3 eo0, vec3 f0, vec3 f1, vec3 eo1,
                      float t, float s) {
    precise vec3 r0 = eo0 - p0;
    precise vec3 r1 = f0 - e0;
    precise vec3 r2 = f1 - e1;
    precise vec3 r3 = eo1 - p1;
    precise vec3 d = 9.0 * (((s * s) * (r1 - r0) + (2.0 * t * s) * (r2 - r1)) + (t * t) * (r3 - r2));
    return d;
}

/// Cross-edge derivative of a triangular Gregory patch along an edge (same arguments as
/// cross_quad): d/dw - (d/du + d/dv) / 2 at w = 0, with u = s, v = t the weights of the edge's
/// ends and w that of the opposite corner (§3.1 with the F points frozen); symmetric in the ends.
vec3 cross_tri(vec3 p0, vec3 e0, vec3 e1, vec3 p1, vec3 eo0, vec3 f0, vec3 f1, vec3 eo1,
               float t, float s) {
    precise vec3 m = s * e0 + t * e1;
    precise vec3 tw = ((3.0 * s * s * s) * eo0 + (3.0 * t * t * t) * eo1)
                    + (12.0 * s * t) * (s * f0 + t * f1);
    precise vec3 tu = (3.0 * s * s) * p0 + (3.0 * t) * ((2.0 * s + t) * m + (s * (s + t)) * e0);
    precise vec3 tv = (3.0 * t * t) * p1 + (3.0 * s) * ((s + 2.0 * t) * m + (t * (s + t)) * e1);
    precise vec3 d = tw - 0.5 * (tu + tv);
    return d;
}

/// Gregory/Gregory edge in canonical order: the boundary cubic (p0, e0, e1, p1) from the
/// smaller-id end, relative to `origin`, normal cross(tangent, d_left - d_right) with d_* the
/// two patches' cross-edge derivatives (into each patch). The construction is tangent-plane
/// continuous across the edge (§3.4), so this is the normal of both patches; both compute the
/// same bits.
/// Set by a stage before an edge (the adaptive end caps, glsl/adaptive/endcap.glsl), per
/// canonical end (0: the smaller id): the residual sharpness of a promoted crease's fillet there
/// (0: none), the limit normal there and, where the edge crosses that crease between two end
/// caps, the derivative of its continuation beyond the crease (`edge_fillet_has_beyond`).
/// gregory_edge bends its tangent with that fillet, as `AdaptiveSurface::normal`
/// (`patch::adaptive::promoted::fillet_cross_derivative` of the two derivatives' sum, else
/// `fillet_bend`): both sides set the same values.
/// Where the crease there is not regular (`edge_fillet_rotate`), the normal turns instead
/// (`patch::adaptive::promoted::fillet_rotation`) from the edge's own normal at that end
/// (`edge_fillet_own`, set by canonical_edge) towards the limit normal.
float edge_fillet_sharpness[2] = float[2](0.0, 0.0);
vec3 edge_fillet_normal[2] = vec3[2](vec3(0.0), vec3(0.0));
bool edge_fillet_has_beyond[2] = bool[2](false, false);
vec3 edge_fillet_beyond[2] = vec3[2](vec3(0.0), vec3(0.0));
bool edge_fillet_rotate[2] = bool[2](false, false);
vec3 edge_fillet_own[2] = vec3[2](vec3(0.0), vec3(0.0));
/// Where three or more promoted creases meet at that end (with edge_fillet_rotate): the normal
/// turns from the one at the point instead (`patch::adaptive::promoted::turn_towards` by
/// `fillet_many_share`).
bool edge_fillet_many[2] = bool[2](false, false);
/// On a promoted crease (edge_band_sharpness > 0), per canonical end: that end is an irregular
/// crease vertex (`patch::adaptive::promoted::irregular_crease_vertex`) whose limit normal is
/// edge_fillet_normal; the shared normal turns towards it (`crease_turn_share`).
bool edge_crease_turn[2] = bool[2](false, false);
/// `patch::adaptive::promoted::FILLET_TURN_GAIN`.
const float FILLET_TURN_GAIN = 0.75;
/// Set by a stage before an edge that is a promoted crease between two quad end caps: its
/// residual sharpness (0: none). canonical_edge then turns the edge's tangent by the band offset
/// `h (d_own + d_nbr) / 6` of its fillet (`patch::adaptive::promoted::band_offset_factor`):
/// `edge_band_tangent`, a third of that offset's derivative along the edge, from both sides'
/// cross_quad_slope in canonical order (both sides compute the same bits).
float edge_band_sharpness = 0.0;
vec3 edge_band_tangent = vec3(0.0);
/// The positional fillet (`patch::adaptive::promoted::fillet_offset`). Per canonical end, set
/// by a stage before an edge: on a promoted crease, whether the fillet reaches that end whole
/// (`positional_fillet_end`; else it fades there, `fillet_end_fade`); on an edge crossing a
/// crease at a positional end (with `edge_fillet_has_beyond`), that crease's residual sharpness
/// (0: none). canonical_edge sets edge_band_offset, the promoted crease's offset
/// `fillet_offset(s, 0) (d_own + d_nbr)` with the ends' fades (both sides compute the same bits).
bool edge_fillet_positional[2] = bool[2](false, false);
float edge_fillet_position_sharpness[2] = float[2](0.0, 0.0);
vec3 edge_band_offset = vec3(0.0);

/// The fillet's change of a cross-crease derivative at distance w from the crease, `d_sum` the
/// sum of both sides' derivatives there (`patch::adaptive::promoted::fillet_cross_derivative`).
vec3 fillet_change(float sharp, float w, vec3 d_sum) {
    precise float lo = floor(sharp);
    precise float frac = sharp - lo;
    precise float r0 = max(1.0 - w * exp2(lo), 0.0);
    precise float r1 = max(1.0 - w * exp2(lo + 1.0), 0.0);
    precise float k = (1.0 - frac) * (-0.5 * r0 * r0) + frac * (-0.5 * r1 * r1);
    precise vec3 d = k * d_sum;
    return d;
}

/// The positional fillet's factor at distance w from a promoted crease of residual sharpness
/// `sharp`: `h (1 - w/h)^3 / 6`, blended by the fraction of sharp
/// (`patch::adaptive::promoted::fillet_offset`).
float fillet_offset(float sharp, float w) {
    precise float lo = floor(sharp);
    precise float frac = sharp - lo;
    precise float r0 = max(1.0 - w * exp2(lo), 0.0);
    precise float r1 = max(1.0 - w * exp2(lo + 1.0), 0.0);
    precise float k = (1.0 - frac) * (exp2(-lo) * (r0 * r0 * r0))
                    + frac * (exp2(-lo - 1.0) * (r1 * r1 * r1));
    precise float f = k * (1.0 / 6.0);
    return f;
}

/// `(1 - w/h)`, squared if `square`, h = 2^-floor(sharp), blended with the next step by the
/// fraction of sharp (`patch::adaptive::promoted::fillet_fade`).
float fillet_fade(float sharp, float w, bool square) {
    precise float lo = floor(sharp);
    precise float frac = sharp - lo;
    precise float r0 = max(1.0 - w * exp2(lo), 0.0);
    precise float r1 = max(1.0 - w * exp2(lo + 1.0), 0.0);
    if (square) {
        r0 = r0 * r0;
        r1 = r1 * r1;
    }
    precise float f = (1.0 - frac) * r0 + frac * r1;
    return f;
}

/// The positional fillet's share at distance x along a promoted crease from an end it does not
/// reach whole, `1 - (1 - x/h)^2` (`patch::adaptive::promoted::fillet_end_fade`); 1 at an end it
/// reaches (`positional`).
float fillet_end_share(bool positional, float sharp, float x) {
    return positional ? 1.0 : 1.0 - fillet_fade(sharp, x, true);
}

/// Rodrigues' rotation of `n` about the unit `axis` by `angle`
/// (`patch::adaptive::promoted::rotate`).
vec3 rotate_about(vec3 n, vec3 axis, float angle) {
    precise float c = cos(angle);
    precise vec3 r = (n * c + cross(axis, n) * sin(angle)) + axis * (dot(axis, n) * (1.0 - c));
    return r;
}

/// `n` turned about `own x limit` by the turn's weight at w (`fillet_fade`, linear) times the
/// angle between them (`patch::adaptive::promoted::fillet_rotation`).
vec3 fillet_rotation(float sharp, float w, vec3 own, vec3 limit, vec3 n) {
    precise vec3 a = normalize(own);
    precise vec3 b = normalize(limit);
    precise vec3 axis = cross(a, b);
    precise float sn = length(axis);
    if (!(sn > 1e-7)) {
        return n;
    }
    precise float angle = atan(sn, dot(a, b)) * fillet_fade(sharp, w, false);
    return rotate_about(n, axis / sn, angle);
}

/// `n` turned towards `limit` by `share` of the angle between them
/// (`patch::adaptive::promoted::turn_towards`).
vec3 turn_towards(vec3 n, vec3 limit, float share) {
    precise vec3 b = normalize(limit);
    precise vec3 axis = cross(n, b);
    precise float sn = length(axis);
    if (!(sn > 1e-7) || share == 0.0) {
        return n;
    }
    precise float angle = atan(sn, dot(n, b)) * share;
    return rotate_about(n, axis / sn, angle);
}

/// The fillet's change of the derivative `along` (from edge end `end`, unit parameter) at
/// distance w from that end: of `along` plus the continuation beyond the crease where it is
/// known, else (`patch::adaptive::promoted::fillet_bend`) with the sum's normal part
/// `2 (along . n) n`, n the limit normal there.
vec3 edge_fillet_change(int end, float w, vec3 along) {
    vec3 n = edge_fillet_normal[end];
    precise vec3 sum = edge_fillet_has_beyond[end] ? along + edge_fillet_beyond[end]
                                                   : (2.0 * dot(along, n)) * n;
    return fillet_change(edge_fillet_sharpness[end], w, sum);
}

void gregory_edge(vec3 origin, vec3 p0, vec3 e0, vec3 e1, vec3 p1, vec3 d_left, vec3 d_right,
                  float t, float s, out vec3 pos, out vec3 nrm) {
    precise vec4 b = vec4(s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t);
    precise vec3 p = (((b.x * p0 + b.y * e0) + b.z * e1) + b.w * p1) + origin;
    // The positional fillet: a promoted crease's own offset (canonical_edge), on an edge
    // crossing a crease at a positional end that crease's, of the edge's derivative from that
    // end plus its continuation's beyond the crease (`AdaptiveSurface::fillet_position`).
    if (edge_band_sharpness > 0.0) {
        p = p + edge_band_offset;
    }
    if (edge_fillet_position_sharpness[0] > 0.0 && edge_fillet_has_beyond[0]) {
        precise vec3 sum = 3.0 * (e0 - p0) + edge_fillet_beyond[0];
        p = p + sum * fillet_offset(edge_fillet_position_sharpness[0], t);
    }
    if (edge_fillet_position_sharpness[1] > 0.0 && edge_fillet_has_beyond[1]) {
        precise vec3 sum = 3.0 * (e1 - p1) + edge_fillet_beyond[1];
        p = p + sum * fillet_offset(edge_fillet_position_sharpness[1], s);
    }
    precise vec3 tangent = ((s * s) * (e0 - p0) + (2.0 * t * s) * (e1 - e0)) + (t * t) * (p1 - e1);
    if (edge_band_sharpness > 0.0) {
        tangent = tangent + edge_band_tangent;
    }
    // (tangent is a third of d/dt; the derivative from end 0 is 3 (e0 - p0), from end 1
    // 3 (e1 - p1) along -t.)
    if (edge_fillet_sharpness[0] > 0.0 && !edge_fillet_rotate[0]) {
        precise vec3 d = edge_fillet_change(0, t, 3.0 * (e0 - p0));
        tangent = tangent + d * (1.0 / 3.0);
    }
    if (edge_fillet_sharpness[1] > 0.0 && !edge_fillet_rotate[1]) {
        precise vec3 d = edge_fillet_change(1, s, 3.0 * (e1 - p1));
        tangent = tangent - d * (1.0 / 3.0);
    }
    precise vec3 cross_dir = d_left - d_right;
    precise vec3 nn = normalize(cross(tangent, cross_dir));
    if (edge_fillet_sharpness[0] > 0.0 && edge_fillet_rotate[0]) {
        nn = edge_fillet_many[0]
            ? turn_towards(nn, edge_fillet_normal[0],
                           FILLET_TURN_GAIN * fillet_fade(edge_fillet_sharpness[0], t, true))
            : fillet_rotation(edge_fillet_sharpness[0], t, edge_fillet_own[0],
                              edge_fillet_normal[0], nn);
    }
    if (edge_fillet_sharpness[1] > 0.0 && edge_fillet_rotate[1]) {
        nn = edge_fillet_many[1]
            ? turn_towards(nn, edge_fillet_normal[1],
                           FILLET_TURN_GAIN * fillet_fade(edge_fillet_sharpness[1], s, true))
            : fillet_rotation(edge_fillet_sharpness[1], s, edge_fillet_own[1],
                              edge_fillet_normal[1], nn);
    }
    // A promoted crease within the fillet of an irregular crease vertex at an end.
    if (edge_band_sharpness > 0.0 && edge_crease_turn[0]) {
        nn = turn_towards(nn, edge_fillet_normal[0],
                          FILLET_TURN_GAIN * fillet_fade(edge_band_sharpness, t, false));
    }
    if (edge_band_sharpness > 0.0 && edge_crease_turn[1]) {
        nn = turn_towards(nn, edge_fillet_normal[1],
                          FILLET_TURN_GAIN * fillet_fade(edge_band_sharpness, s, false));
    }
    pos = p;
    nrm = nn;
}

/// Cross-edge derivative of a patch with `corners` corners (4: quad, else triangle).
vec3 cross_any(bool quad, vec3 p0, vec3 e0, vec3 e1, vec3 p1, vec3 eo0, vec3 f0, vec3 f1,
               vec3 eo1, float t, float s) {
    return quad ? cross_quad(p0, e0, e1, p1, eo0, f0, f1, eo1, t, s)
                : cross_tri(p0, e0, e1, p1, eo0, f0, f1, eo1, t, s);
}

/// An edge in canonical order, from its smaller-id end 0 (points relative to origin o0) to end 1
/// (points relative to o1), for the patch on its left (`own_left`) or right: the end-1 points
/// are moved into the frame of end 0 by the same `precise` shift on both sides.
void canonical_edge(bool own_quad, bool nbr_quad, bool sharp, bool own_left, float t, float s,
                    vec3 o0, vec3 o1, vec3 p0, vec3 e0, vec3 e1, vec3 p1,
                    vec3 own_eo0, vec3 own_f0, vec3 own_f1, vec3 own_eo1,
                    vec3 nbr_eo0, vec3 nbr_f0, vec3 nbr_f1, vec3 nbr_eo1,
                    out vec3 pos, out vec3 nrm) {
    precise vec3 shift = o1 - o0;
    precise vec3 q1 = p1 + shift;
    precise vec3 g1 = e1 + shift;
    precise vec3 own_g1 = own_f1 + shift;
    precise vec3 own_h1 = own_eo1 + shift;
    vec3 d_own = cross_any(own_quad, p0, e0, g1, q1, own_eo0, own_f0, own_g1, own_h1, t, s);
    // A boundary or infinitely sharp edge: no neighbour term (each side keeps its own normal).
    vec3 d_nbr = vec3(0.0);
    precise vec3 nbr_g1 = nbr_f1 + shift;
    precise vec3 nbr_h1 = nbr_eo1 + shift;
    if (!sharp) {
        d_nbr = cross_any(nbr_quad, p0, e0, g1, q1, nbr_eo0, nbr_f0, nbr_g1, nbr_h1, t, s);
    }
    // A promoted crease between two quad end caps: the band offset's derivative along the edge
    // (a third of it, as gregory_edge's tangent), the sum of the two slopes commutative.
    if (edge_band_sharpness > 0.0 && !sharp && own_quad && nbr_quad) {
        precise vec3 slope_own = cross_quad_slope(p0, e0, g1, q1, own_eo0, own_f0, own_g1,
                                                  own_h1, t, s);
        precise vec3 slope_nbr = cross_quad_slope(p0, e0, g1, q1, nbr_eo0, nbr_f0, nbr_g1,
                                                  nbr_h1, t, s);
        precise float lo = floor(edge_band_sharpness);
        precise float frac = edge_band_sharpness - lo;
        precise float h = (1.0 - frac) * exp2(-lo) + frac * exp2(-lo - 1.0);
        precise vec3 band = (slope_own + slope_nbr) * (h * (1.0 / 18.0));
        edge_band_tangent = band;
        // The positional fillet on the crease, faded towards an end it does not reach whole.
        precise float share = fillet_end_share(edge_fillet_positional[0], edge_band_sharpness, t)
                            * fillet_end_share(edge_fillet_positional[1], edge_band_sharpness, s);
        precise vec3 offset = (d_own + d_nbr) * (fillet_offset(edge_band_sharpness, 0.0) * share);
        edge_band_offset = offset;
    } else {
        edge_band_tangent = vec3(0.0);
        edge_band_offset = vec3(0.0);
    }
    // The edge's own normal at an end where the fillet turns it (edge_fillet_rotate): the
    // same cross(tangent, d_left - d_right) there, from the data both sides share.
    for (int end = 0; end < 2; ++end) {
        if (edge_fillet_sharpness[end] > 0.0 && edge_fillet_rotate[end] && !sharp) {
            float te = float(end);
            float se = 1.0 - te;
            precise vec3 a = cross_any(own_quad, p0, e0, g1, q1, own_eo0, own_f0, own_g1, own_h1,
                                       te, se);
            precise vec3 b = cross_any(nbr_quad, p0, e0, g1, q1, nbr_eo0, nbr_f0, nbr_g1, nbr_h1,
                                       te, se);
            precise vec3 cross_end = own_left ? a - b : b - a;
            precise vec3 tangent_end = (end == 0) ? e0 - p0 : q1 - g1;
            edge_fillet_own[end] = cross(tangent_end, cross_end);
        }
    }
    if (own_left) {
        gregory_edge(o0, p0, e0, g1, q1, d_own, d_nbr, t, s, pos, nrm);
    } else {
        gregory_edge(o0, p0, e0, g1, q1, d_nbr, d_own, t, s, pos, nrm);
    }
}

/// Evaluates patch edge k (corner a -> b, this patch on its left) from this patch's data
/// (p, e along the edge, other edge points eo and face points f at both ends, each relative to
/// its corner's origin oa, ob) and the neighbour's (g_eout / g_nbr of the TCS contract), in the
/// canonical frame.
void shared_edge(bool own_quad, bool nbr_quad, bool sharp, bool a_is_lo, float t, float s,
                 vec3 oa, vec3 ob, vec3 pa, vec3 ea, vec3 eb, vec3 pb,
                 vec3 own_eo_a, vec3 own_f_a, vec3 own_f_b, vec3 own_eo_b,
                 vec3 nbr_eo_a, vec3 nbr_f_a, vec3 nbr_f_b, vec3 nbr_eo_b,
                 out vec3 pos, out vec3 nrm) {
    if (a_is_lo) {
        canonical_edge(own_quad, nbr_quad, sharp, true, t, s, oa, ob, pa, ea, eb, pb,
                       own_eo_a, own_f_a, own_f_b, own_eo_b,
                       nbr_eo_a, nbr_f_a, nbr_f_b, nbr_eo_b, pos, nrm);
    } else {
        canonical_edge(own_quad, nbr_quad, sharp, false, t, s, ob, oa, pb, eb, ea, pa,
                       own_eo_b, own_f_b, own_f_a, own_eo_a,
                       nbr_eo_b, nbr_f_b, nbr_f_a, nbr_eo_a, pos, nrm);
    }
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

/// A patch's own normal at its corner from the corner's point p and its edge points towards the
/// next corner (e_next) and the previous one (e_prev), all in the corner's frame: the direction
/// of the Bézier net's corner derivatives, kept where the vertex has several sectors
/// (shared_corner). Computed in the corner's own frame, every patch at the vertex works on the
/// same operands. Where the two edge tangents are collinear (a crease sector of one face, whose
/// edges both follow the crease curve), the corner's face points f_plus, f_minus span the
/// tangent plane with the edge instead (src/patch/gregory/vertex.rs puts them in it).
vec3 gregory_corner_normal(vec3 p, vec3 e_next, vec3 e_prev, vec3 f_plus, vec3 f_minus) {
    vec3 a = e_next - p;
    vec3 b = e_prev - p;
    vec3 n = cross(a, b);
    if (length(n) > 1e-5 * length(a) * length(b)) {
        return normalize(n);
    }
    return safe_normal(a, 0.5 * (f_plus + f_minus) - p);
}

#endif
