// Transition patches (Köbler 2013 §3.4; the edge split of OpenSubdiv): a B-spline patch with a
// one-level-finer neighbour across some edges is drawn as a fan of triangles around its domain
// centre, one per edge, two per transition edge (one per half), so each half of a transition
// edge is a whole primitive edge tessellated exactly as the finer patch's edge. Record per
// triangle (16 bytes): the patch (index into the PatchInfo records), B-spline edge e, half (0:
// the whole edge, 1: the half at the edge's start corner, 2: the half at its end), pad.
// Needs frame.glsl and adaptive.glsl first.
#ifndef TESSERA_TRANSITION_GLSL
#define TESSERA_TRANSITION_GLSL

#include "tri_sub.glsl"

struct TransitionTri {
    uint patch_index;
    uint edge;
    uint half_edge;
    uint pad;
};

layout(std430, set = 0, binding = 12) readonly buffer TransitionTris {
    TransitionTri ttris[];
};

/// How a fan triangle is drawn split. Push constant `split` > 1 (uniform levels above the patch
/// limit; src/render/schemes/adaptive/pass.rs): the split s of the fan's own patch level, and the
/// triangle is cut into n x n sub-triangles (tri_sub_corners, one draw per `sub_index`), n = s
/// for a whole edge and s / 2 (at least 1) for a half edge, whose finer owner splits half as
/// often. Sub-triangle levels: `outer` on the edges parallel to the patch edge, `spoke` on the
/// other two, so the patch edge carries n * outer = its owner's lattice (split_lattice: s * sub or
/// s / 2 * sub, sub the sub-patch level) and both spokes s * ceil(sub / 2) points in every
/// triangle of the fan. n = 0: the fan is drawn whole.
struct FanSplit {
    uint n;
    float outer;
    float spoke;
};

FanSplit fan_split(uint level, uint half_edge) {
    FanSplit f;
    f.n = 0u;
    f.outer = 0.0;
    f.spoke = 0.0;
    uint s = chunk.split;
    if (s > 1u) {
        float sub = split_lattice(level, s) / float(s);
        float q = ceil(0.5 * sub);
        f.n = (half_edge == 0u) ? s : (s >> 1);
        f.outer = sub;
        f.spoke = (half_edge == 0u) ? q : 2.0 * q;
    }
    return f;
}

/// Tessellation coordinates in the whole fan triangle (centre, start, end weights) of the point
/// `tc` of sub-triangle `chunk.sub_index` of a split triangle. On sub-triangle edges from
/// integer lattice indices over the denominator n * outer * spoke (s * sub * ceil(sub / 2) in
/// every triangle of the fan), so neighbouring sub-triangles and the two triangles at a spoke
/// compute the same bits and a patch-edge point is exactly k / (n * outer); inside, affine.
vec3 fan_domain_point(FanSplit f, vec3 tc) {
    ivec2 c0;
    ivec2 c1;
    ivec2 c2;
    tri_sub_corners(chunk.sub_index, f.n, c0, c1, c2);
    if (tc.x == 0.0 || tc.y == 0.0 || tc.z == 0.0) {
        int mo = int(f.outer);
        int ms = int(f.spoke);
        ivec2 b;
        if (tc.x == 0.0) {
            // Edge opposite c0: parallel to the patch edge, level `outer`.
            int k1 = int(round(tc.y * f.outer));
            b = (c1 * k1 + c2 * (mo - k1)) * ms;
        } else {
            // Edge opposite c1 or c2: parallel to a spoke, level `spoke`.
            int k0 = int(round(tc.x * f.spoke));
            ivec2 other = (tc.y == 0.0) ? c2 : c1;
            b = (c0 * k0 + other * (ms - k0)) * mo;
        }
        int total = int(f.n) * mo * ms;
        float d = float(total);
        return vec3(float(total - b.x - b.y) / d, float(b.x) / d, float(b.y) / d);
    }
    vec2 b = (vec2(c0) * tc.x + vec2(c1) * tc.y + vec2(c2) * tc.z) / float(f.n);
    return vec3(1.0 - b.x - b.y, b.x, b.y);
}

#endif
