#version 450
// End cap evaluation: the quad Gregory TES (gregory/gregory_quad_tes.glsl), an edge on a
// one-level-coarser patch evaluated from its coarse-edge record (adaptive.glsl), points captured
// in base-face parameters with kind and level.
// Defines: SPACING, CAPTURE.
#include "frame.glsl"
#include "adaptive.glsl"
// End-cap points are absolute (endcap_points.comp sums refined points; the corners are limit
// slots, not control points): every corner's origin is zero.
#define GREGORY_CORNER_ORIGIN(info, k) vec3(0.0)
#include "gregory/gregory.glsl"

/// Edge k (corner k -> k + 1) at x measured from corner `from_corner`, when it lies on a coarser
/// patch.
bool end_cap_edge(GregoryPatchInfo info, int k, float x, int from_corner, inout vec3 pos,
                  inout vec3 nrm) {
    // Every edge point passes here first: its lattice for edge_ts and fine_edge_point (the
    // draw's split is this level's, frame.glsl's sub_domain).
    edge_lattice_override = split_lattice(apatches[info.pad0].level, chunk.split);
    uint c = apatches[info.pad0].coarse[k];
    if (c == NO_ENTRY) {
        return false;
    }
    int other = (from_corner == k) ? ((k + 1) & 3) : k;
    fine_edge_point(c, info.corners[from_corner], info.corners[other], x, pos, nrm);
    return true;
}

#define GREGORY_EDGE_OVERRIDE end_cap_edge
#define GREGORY_CORNER_NORMAL(info, k, nrm) \
    sector_normal(apatches[info.pad0].corner_frame[k], nrm)
#define GREGORY_CLASS(info) adaptive_class(KIND_END_CAP, apatches[info.pad0].level)
#define GREGORY_DISPLACE(info, u, v, tg, p, n) \
    displace_adaptive(apatches[info.pad0], vec2(u, v), tg, p, n)
#define GREGORY_CAPTURE(info, u, v, p, n) \
    capture_adaptive(apatches[info.pad0], KIND_END_CAP, vec2(u, v), p, n)
#include "gregory/gregory_quad_tes.glsl"
