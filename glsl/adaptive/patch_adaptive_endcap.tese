#version 450
// End cap evaluation: the quad Gregory TES (gregory/gregory_quad_tes.glsl), an edge on a
// one-level-coarser patch evaluated from its coarse-edge record (adaptive.glsl), points captured
// in base-face parameters with kind and level.
// Defines: SPACING, CAPTURE.
#include "frame.glsl"
#include "adaptive.glsl"
#include "endcap.glsl"
// End-cap points are absolute (endcap_points.comp sums refined points; the corners are limit
// slots, not control points): every corner's origin is zero.
#define GREGORY_CORNER_ORIGIN(info, k) vec3(0.0)
#include "gregory/gregory.glsl"

/// Per canonical edge end: the g_eout slot of the continuation beyond the crease the edge
/// crosses there (-1: none) and the corner it belongs to; quad_edge sets edge_fillet_beyond.
int edge_fillet_beyond_slot[2] = int[2](-1, -1);
int edge_fillet_beyond_corner[2] = int[2](0, 0);

/// The residual sharpness of edge k when it is a promoted crease between two end caps (flag bit
/// 28 + k), 0 elsewhere: its 24-bit code in the record's fillet_fine words (upper 16 bits in
/// word k / 2 at bit 16 (k mod 2), lower 8 in word 2 at bit 8k), 2^20 s
/// (`patch::adaptive::promoted::fillet_fine_code`; exact in a float).
float fillet_fine_sharpness(GregoryPatchInfo info, int k) {
    if ((info.flags & (1u << uint(28 + k))) == 0u) {
        return 0.0;
    }
    uint hi = (apatches[info.pad0].fillet_fine[k >> 1] >> uint(16 * (k & 1))) & 0xffffu;
    uint lo = (apatches[info.pad0].fillet_fine[2] >> uint(8 * k)) & 0xffu;
    return float((hi << 8u) | lo) / 1048576.0;
}

/// Edge k (corner k -> k + 1) at x measured from corner `from_corner`, when it lies on a coarser
/// patch.
bool end_cap_edge(GregoryPatchInfo info, int k, float x, int from_corner, inout vec3 pos,
                  inout vec3 nrm) {
    // Every edge point passes here first: its lattice for edge_ts and fine_edge_point (the
    // draw's split is this level's, frame.glsl's sub_domain).
    edge_lattice_override = split_lattice(apatches[info.pad0].level, chunk.split);
    // The fillet sharpness at the edge's ends (bits 8k..8k+8 of the record's fillet word, an
    // edge that is no promoted crease: flag bit 28 + k off) in canonical order, with the
    // corners' normals (as drawn there): gregory_edge bends the edge's tangent with them.
    uint code = (apatches[info.pad0].fillet >> uint(8 * k)) & 0xffu;
    // A promoted crease (flag bit 28 + k): its sharpness (fillet_fine_sharpness) for the band
    // offset (canonical_edge's edge_band_tangent), no fillet ends.
    bool band = (info.flags & (1u << uint(28 + k))) != 0u;
    edge_band_sharpness = fillet_fine_sharpness(info, k);
    bool a_is_lo = info.corners[k] < info.corners[(k + 1) & 3];
    for (int side = 0; side < 2; ++side) {
        int corner = (k + side) & 3;
        uint c = (code >> uint(4 * side)) & 0xfu;
        int end = ((side == 0) == a_is_lo) ? 0 : 1;
        edge_fillet_sharpness[end] = float(c) * 0.5;
        // The crease there is not regular: the normal turns (record's transition bit 8 + corner).
        uint bits = apatches[info.pad0].transition;
        edge_fillet_rotate[end] = c != 0u && (bits & (1u << uint(8 + corner))) != 0u;
        // Three or more creases meet there: from the normal at the point (bit 12 + corner).
        edge_fillet_many[end] = c != 0u && (bits & (1u << uint(12 + corner))) != 0u;
        // A promoted crease from an irregular crease vertex (bit 16 + corner): its shared
        // normal turns towards that vertex's.
        edge_crease_turn[end] = band && (bits & (1u << uint(16 + corner))) != 0u;
        vec3 n = vec3(0.0);
        if (c != 0u || edge_crease_turn[end]) {
            vec3 unused = vec3(0.0);
            shared_corner(info.corners[corner], info.face, unused, n);
            sector_normal(apatches[info.pad0].corner_frame[corner], n);
        }
        edge_fillet_normal[end] = n;
        // This patch's other edge at that corner: the promoted crease the edge crosses, between
        // two end caps (flag bit 28 + crease); the continuation's edge point beyond it is the
        // neighbour's other edge point there (g_eout, read in quad_edge).
        int crease = (side == 0) ? ((k + 3) & 3) : ((k + 1) & 3);
        bool beyond = c != 0u && !edge_fillet_rotate[end]
            && (info.flags & (1u << uint(28 + crease))) != 0u;
        edge_fillet_beyond_slot[end] = beyond ? ((side == 0) ? 2 * crease + 1 : 2 * crease) : -1;
        edge_fillet_beyond_corner[end] = corner;
        // The positional fillet reaches that end whole (transition bit 20 + corner): on a
        // promoted crease no fade there; on an edge crossing the crease there, the crease's
        // residual sharpness (fillet_fine_sharpness) for its offset.
        bool positional = (bits & (1u << uint(20 + corner))) != 0u;
        edge_fillet_positional[end] = band && positional;
        edge_fillet_position_sharpness[end] =
            (positional && beyond) ? fillet_fine_sharpness(info, crease) : 0.0;
    }
    uint c = apatches[info.pad0].coarse[k];
    if (c == NO_ENTRY) {
        return false;
    }
    int other = (from_corner == k) ? ((k + 1) & 3) : k;
    fine_edge_point(c, info.corners[from_corner], info.corners[other], x, pos, nrm);
    return true;
}

/// Corner k's offset to the exact limit position (`AdaptiveSurface::fillet_position`'s corner
/// offsets): that position's frame minus the corner's slot, the same bits in every end cap there.
vec3 corner_delta(GregoryPatchInfo info, int k) {
    precise vec3 d = vertex_limit[apatches[info.pad0].corner_exact[k]].xyz
                   - vertex_limit[info.corners[k]].xyz;
    return d;
}

/// Corner k's offset at own distance x along one of its edges and w along the other,
/// `(1 - x/h)^2 (1 - w/h)^2` (`patch::adaptive::promoted::corner_offset_share`).
vec3 corner_offset(GregoryPatchInfo info, int k, float x, float w) {
    float sharp = float((apatches[info.pad0].corner_fade >> uint(8 * k)) & 0xffu) / 16.0;
    precise float share = fillet_fade(sharp, x, true) * fillet_fade(sharp, w, true);
    precise vec3 d = corner_delta(info, k) * share;
    return d;
}

/// Adds the corner offsets (record's corner_exact) at own (u, v): whole at a corner; on an edge
/// both ends' in canonical order from canonical parameters (the neighbour's bits).
void exact_corner_offsets(GregoryPatchInfo info, float u, float v, inout vec3 p) {
    uvec4 frames = apatches[info.pad0].corner_exact;
    if (all(equal(frames, uvec4(NO_ENTRY)))) {
        return;
    }
    bool u_edge = (u == 0.0 || u == 1.0);
    bool v_edge = (v == 0.0 || v == 1.0);
    if (u_edge && v_edge) {
        int k = quad_corner_index(u, v);
        if (frames[k] != NO_ENTRY) {
            precise vec3 q = p + corner_delta(info, k);
            p = q;
        }
        return;
    }
    if (u_edge || v_edge) {
        // Edge k at x from corner `from` (as main's quad_edge calls).
        int k = (v == 0.0) ? 0 : (u == 1.0) ? 1 : (v == 1.0) ? 2 : 3;
        float x = v_edge ? u : v;
        int from = (k == 2) ? 3 : (k == 3) ? 0 : k;
        int a = k;
        int b = (k + 1) & 3;
        bool a_is_lo = info.corners[a] < info.corners[b];
        float t, s;
        edge_ts(x, (from == a) == a_is_lo, t, s);
        int lo = a_is_lo ? a : b;
        int hi = a_is_lo ? b : a;
        precise vec3 offset = vec3(0.0);
        if (frames[lo] != NO_ENTRY) {
            offset += corner_offset(info, lo, t, 0.0);
        }
        if (frames[hi] != NO_ENTRY) {
            offset += corner_offset(info, hi, s, 0.0);
        }
        precise vec3 q = p + offset;
        p = q;
        return;
    }
    // Inside: each corner's distances along its two edges.
    vec2 d[4] = vec2[4](vec2(u, v), vec2(1.0 - u, v), vec2(1.0 - u, 1.0 - v), vec2(u, 1.0 - v));
    for (int k = 0; k < 4; ++k) {
        if (frames[k] != NO_ENTRY) {
            p += corner_offset(info, k, d[k].x, d[k].y);
        }
    }
}

/// Node (a, b)'s value in a lattice region whose node frames start at `table` (`cells` per
/// side): the frame's exact limit normal, `drawn` on the border (a or b == cells) or where the
/// node has no frame (`patch::adaptive::lattice_frames::lattice_normal`).
vec3 lattice_node(uint table, uint cells, uint a, uint b, vec3 drawn) {
    if (a >= cells || b >= cells) {
        return drawn;
    }
    uint f = lattice[table + a + cells * b];
    if (f == NO_ENTRY) {
        return drawn;
    }
    return vertex_normal[f].xyz;
}

/// Linear along a region's edge from its vertex at d (in cells): the nearer node first.
vec3 lattice_along(uint table, uint cells, bool along_x, float d, vec3 drawn) {
    float a0 = floor(d);
    precise float ta = d - a0;
    uint a = uint(a0);
    vec3 n0 = along_x ? lattice_node(table, cells, a, 0u, drawn)
                      : lattice_node(table, cells, 0u, a, drawn);
    vec3 n1 = along_x ? lattice_node(table, cells, a + 1u, 0u, drawn)
                      : lattice_node(table, cells, 0u, a + 1u, drawn);
    precise vec3 n = n0 * (1.0 - ta) + n1 * ta;
    return n;
}

/// The normal within a lattice region of end cap `cap` (`AdaptiveSurface::normal`'s lattice,
/// `patch::adaptive::lattice_frames::lattice_normal`): bilinear in the lattice cell over the
/// nodes' exact limit normals, border nodes taking the drawn normal `nrm`; on an edge from the
/// region's vertex linear from canonical parameters (edge_ts), so both end caps there get the same
/// bits. Corners keep theirs.
void lattice_normals(GregoryPatchInfo info, uint cap, float u, float v, inout vec3 nrm) {
    uint at = lattice[cap];
    if (at == NO_ENTRY) {
        return;
    }
    bool u_edge = (u == 0.0 || u == 1.0);
    bool v_edge = (v == 0.0 || v == 1.0);
    if (u_edge && v_edge) {
        return;
    }
    uint head = lattice[at];
    vec3 drawn = normalize(nrm);
    for (int c = 0; c < 4; ++c) {
        uint bits = (head >> uint(8 * c)) & 0xffu;
        uint cells = bits >> 4u;
        if (cells == 0u) {
            continue;
        }
        float scale = exp2(float(bits & 0xfu));
        uint table = lattice[at + 1u + uint(c)];
        if (u_edge || v_edge) {
            // Edge k at x from corner `from` (as main's quad_edge calls); the region's edges are
            // k = c (its x axis) and k = c - 1 (its w axis).
            int k = (v == 0.0) ? 0 : (u == 1.0) ? 1 : (v == 1.0) ? 2 : 3;
            if (k != c && k != ((c + 3) & 3)) {
                continue;
            }
            float x = v_edge ? u : v;
            int from = (k == 2) ? 3 : (k == 3) ? 0 : k;
            bool a_is_lo = info.corners[k] < info.corners[(k + 1) & 3];
            float t, s;
            edge_ts(x, (from == k) == a_is_lo, t, s);
            // Corner c is edge k's start (k == c) or end; its distance from it canonically.
            bool c_is_lo = (k == c) == a_is_lo;
            precise float d = (c_is_lo ? t : s) * scale;
            if (d >= float(cells)) {
                continue;
            }
            nrm = normalize(lattice_along(table, cells, k == c, d, drawn));
            return;
        }
        // (x, w): along edge c from corner c, distance from edge c.
        float x = (c == 0) ? u : (c == 1) ? v : (c == 2) ? 1.0 - u : 1.0 - v;
        float w = (c == 0) ? v : (c == 1) ? 1.0 - u : (c == 2) ? 1.0 - v : u;
        precise float fx = x * scale;
        precise float fw = w * scale;
        if (fx >= float(cells) || fw >= float(cells)) {
            continue;
        }
        float a0 = floor(fx);
        float b0 = floor(fw);
        precise float ta = fx - a0;
        precise float tb = fw - b0;
        uint a = uint(a0);
        uint b = uint(b0);
        precise vec3 n = lattice_node(table, cells, a, b, drawn) * ((1.0 - ta) * (1.0 - tb))
                       + lattice_node(table, cells, a + 1u, b, drawn) * (ta * (1.0 - tb))
                       + lattice_node(table, cells, a, b + 1u, drawn) * ((1.0 - ta) * tb)
                       + lattice_node(table, cells, a + 1u, b + 1u, drawn) * (ta * tb);
        nrm = normalize(n);
        return;
    }
}

#define GREGORY_NORMAL_OVERRIDE(info, cap, u, v, nrm) lattice_normals(info, cap, u, v, nrm)
#define GREGORY_EDGE_OVERRIDE end_cap_edge
#define GREGORY_CORNER_NORMAL(info, k, nrm) \
    sector_normal(apatches[info.pad0].corner_frame[k], nrm)
#define GREGORY_FILLET fillet_fine_sharpness
#define GREGORY_FILLET_BEYOND
#define GREGORY_POSITION_OFFSET exact_corner_offsets
#define GREGORY_FILLET_END(info, k) \
    ((apatches[info.pad0].transition & (1u << uint(20 + (k)))) != 0u)
#define GREGORY_CLASS(info) adaptive_class(KIND_END_CAP, apatches[info.pad0].level)
#define GREGORY_DISPLACE(info, u, v, tg, p, n) \
    displace_adaptive(apatches[info.pad0], vec2(u, v), tg, p, n)
#define GREGORY_CAPTURE(info, u, v, p, n) \
    capture_adaptive(apatches[info.pad0], KIND_END_CAP, vec2(u, v), p, n)
#include "gregory/gregory_quad_tes.glsl"
