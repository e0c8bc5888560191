// Watertight shared edges and corners (Loop, Schaefer, Ni, Castano 2009, §4.5): the rules every
// patch type follows so that two patches meeting at a corner or an edge compute bitwise-equal
// positions and normals there, whichever of them evaluates it.
// * Corners: position vertex_limit[id] (frame.glsl) and normal vertex_normal[id], per-vertex data
//   every patch type reads (a zero normal: the vertex has several sectors, the patch keeps its own).
// * Edges: evaluated from data both neighbours hold bitwise equal, in the canonical frame: the
//   parameter runs from the end with the smaller vertex id and is derived from max(x, 1 - x)
//   (canonical_ts), or snapped to the full edge level's lattice for equal-spaced sub-patches
//   (edge_ts, needs frame.glsl first).
// * An edge with a regular (B-spline) patch on either side: the edge's limit curve and the
//   symmetric cross-derivative normal from the 12 B-spline points of its grid (grid_edge_rows).
//   Gregory/Gregory edges: gregory/gregory.glsl.
// The edge arithmetic is `precise` (no contraction into fused multiply-adds), so every shader
// that inlines it computes the same bits.
#ifndef TESSERA_WATERTIGHT_GLSL
#define TESSERA_WATERTIGHT_GLSL

#include "bspline.glsl"

/// Unit limit normal per vertex (xyz), read at patch corners; zero at vertices with several
/// sectors, whose w bits then index their sector normals (sector_corner_normal).
layout(std430, set = 0, binding = 9) readonly buffer VertexNormals {
    vec4 vertex_normal[];
};

/// Canonical edge parameters (t, s = 1 - t), t measured from the edge end with the smaller id,
/// from a coordinate x measured from one end (`from_lo`: that end is the smaller id). Derived
/// from max(x, 1 - x) only, so both sides agree when the tessellator gives them x and 1 - x.
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

#ifdef TESSERA_FRAME_GLSL
/// Uniform mode with sub-patches (chunk.split > 1): the full edge level, the same for a split
/// quad (split x the sub-patch level) and an unsplit triangle (whose TCS uses
/// gregory_tri_edge_level).
float split_edge_level() {
    float sub = ceil(clamp(frame.tess.x / float(chunk.split), 1.0, frame.tess.w));
    return sub * float(chunk.split);
}

/// The full edge level edge_ts snaps to when a stage sets it (0: none), for patches that split
/// per patch level (adaptive/adaptive.glsl); negative (never set): split_edge_level's rule.
float edge_lattice_override = -1.0;

/// Edge parameters in the canonical frame as canonical_ts, except with sub-patches and equal
/// spacing: the tessellator's fixed-point coordinates of a sub-patch edge (origin + x * size)
/// and of a whole triangle edge need not agree bitwise, so both snap to the lattice point k / L
/// of the full edge level L (or edge_lattice_override) and derive (t, s) from the integer k.
void edge_ts(float x, bool from_lo, out float t, out float s) {
#ifdef SPACING_EQUAL
    float level = edge_lattice_override >= 0.0 ? edge_lattice_override
                  : ((chunk.split > 1u) ? split_edge_level() : 0.0);
    if (level > 0.0) {
        float k = round(x * level);
        float k_lo = from_lo ? k : level - k;
        t = k_lo / level;
        s = (level - k_lo) / level;
        return;
    }
#endif
    canonical_ts(x, from_lo, t, s);
}

/// The normal of face `face`'s sector at vertex `id` into nrm, if a pass wrote one: where the
/// vertex has several sectors its normal is zero and the bits of w index a list after the
/// vertices (render/pass/frames.rs, VertexFrames::normal_bytes): a header whose w bits are the
/// count, then (normal, face bits) per face.
void sector_corner_normal(uint id, uint face, inout vec3 nrm) {
    uint list = floatBitsToUint(vertex_normal[id].w);
    if (list == 0u) {
        return;
    }
    uint count = floatBitsToUint(vertex_normal[list].w);
    for (uint k = 1u; k <= count; ++k) {
        vec4 entry = vertex_normal[list + k];
        if (floatBitsToUint(entry.w) == face) {
            nrm = entry.xyz;
            return;
        }
    }
}

/// The shared limit position of vertex `id` and its shared normal; where the vertex has
/// several sectors, the normal of face `face`'s sector, or the patch's own if no pass wrote one.
void shared_corner(uint id, uint face, inout vec3 pos, inout vec3 nrm) {
    pos = vertex_limit[id].xyz;
    vec3 vn = vertex_normal[id].xyz;
    if (dot(vn, vn) > 0.0) {
        nrm = vn;
    } else {
        sector_corner_normal(id, face, nrm);
    }
}

/// The quad corner k (0: (0,0), 1: (1,0), 2: (1,1), 3: (0,1)) at a domain corner (u, v).
int quad_corner_index(float u, float v) {
    return (u == 0.0) ? (v == 0.0 ? 0 : 3) : (v == 0.0 ? 1 : 2);
}

/// A quad patch's corner at (u, v) on a corner: shared_corner of its vertex for face `face`.
void quad_corner_point(uvec4 corners, uint face, float u, float v, inout vec3 pos, inout vec3 nrm) {
    shared_corner(corners[quad_corner_index(u, v)], face, pos, nrm);
}
#endif

/// Derivative of bspline3(t, s) with respect to t.
vec4 bspline3_deriv(float t, float s) {
    float d1t = (-12.0 * t + 9.0 * t * t) * (1.0 / 6.0);
    float d1s = (-12.0 * s + 9.0 * s * s) * (1.0 / 6.0);
    return vec4(-0.5 * s * s, d1t, -d1s, 0.5 * t * t);
}

/// Edge limit curve and normal from its B-spline points c (from the smaller-id end), the same
/// points relative to an origin both sides share, c_rel (built from grid points minus that
/// origin, so the tangent keeps the digits of small patches far from the coordinate origin: the
/// derivative does not depend on the origin), and the cross-edge differences d (left minus right
/// row, per point): position sum N_i c_i, normal cross(dC/dt, sum N_i d_i). The tail of
/// grid_edge_rows and single_crease/single_crease.glsl's crease edge.
void edge_curve(vec3 c[4], vec3 c_rel[4], vec3 d[4], float t, float s, out vec3 pos,
                out vec3 nrm) {
    precise vec4 n = bspline3(t, s);
    precise vec3 p = ((n.x * c[0] + n.y * c[1]) + n.z * c[2]) + n.w * c[3];
    precise vec4 dn = bspline3_deriv(t, s);
    precise vec3 tangent =
        ((dn.x * c_rel[0] + dn.y * c_rel[1]) + dn.z * c_rel[2]) + dn.w * c_rel[3];
    precise vec3 cross_dir = ((n.x * d[0] + n.y * d[1]) + n.z * d[2]) + n.w * d[3];
    precise vec3 nn = normalize(cross(tangent, cross_dir));
    pos = p;
    nrm = nn;
}

/// Limit curve and normal of an edge of a regular (B-spline) patch from its 12-point grid in the
/// canonical frame: rows l (left of the direction from the smaller id), m (on the edge), r, each
/// from the smaller-id end. Position: the edge-curve B-spline points ((l + r) + 4 m) / 6;
/// normal: cross(dC/dt, sum N_i (l_i - r_i)), the exact cross derivative of both patches. Used
/// by the B-spline TES for all its edges and by the Gregory TES for edges it shares with one.
void grid_edge_rows(vec3 l[4], vec3 m[4], vec3 r[4], bool sharp, float t, float s, out vec3 pos,
                    out vec3 nrm) {
    precise vec3 c[4];
    precise vec3 c_rel[4];
    precise vec3 d[4];
    precise vec3 o = m[0];
    for (int i = 0; i < 4; ++i) {
        // On a boundary or infinitely sharp edge one outer row is a side's own mirrored phantom
        // (2a - b), which makes (l + r + 4m)/6 equal m only in exact arithmetic: use m itself, the
        // crease polygon both sides share, so both sides get the same bits.
        c[i] = sharp ? m[i] : ((l[i] + r[i]) + 4.0 * m[i]) * (1.0 / 6.0);
        c_rel[i] = sharp ? m[i] - o : (((l[i] - o) + (r[i] - o)) + 4.0 * (m[i] - o)) * (1.0 / 6.0);
        d[i] = l[i] - r[i];
    }
    edge_curve(c, c_rel, d, t, s, pos, nrm);
}

#endif
