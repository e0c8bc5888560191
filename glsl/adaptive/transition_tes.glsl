// The TES body of a transition triangle (Köbler 2013 §3.4): the patch's own surface at the mapped
// domain point; on the outer segment the shared edge rules (a half edge at the coarse parameter of
// coarse_half_ts, the same bits as the finer patch's fine_edge_point; a whole edge on a coarser
// patch by fine_edge_point itself), at segment ends the shared corner or midpoint slot, on the
// spokes a parameter canonical from the centre, so the two triangles of a spoke evaluate the same
// domain points. The stage file includes what its patch type needs and defines, before including
// this:
//   PATCH_SURFACE(info, u, v, p, nrm, du, dv)  the patch's own point, unit normal, partials;
//   PATCH_EDGE(info, e, x, p, nrm)        its shared-edge rule on B-spline edge e at local x;
//   PATCH_EDGE_TS(info, e, t, s, p, nrm)  the same at canonical parameters (t, s);
//   FAN_KIND(ap)                          the kind captured and coloured.
// Defines: SPACING, CAPTURE.
#ifndef TESSERA_TRANSITION_TES_GLSL
#define TESSERA_TRANSITION_TES_GLSL

#include "adaptive_tes_io.glsl"

// Vertex 0 the centre, 1 and 2 the segment ends counter-clockwise in (u, v) (see `flip`).
layout(triangles, SPACING, cw) in;

void main() {
    TransitionTri tt = ttris[chunk.patch_base + uint(gl_PrimitiveID)];
    PatchInfo info = patches[tt.patch_index];
    AdaptivePatch ap = apatches[info.pad0];
    int e = int(tt.edge);
    uint h = tt.half_edge;
    // The outer segment's points on the lattice of the patches that own it: this patch's level
    // for a whole edge, the finer one (split half as often) for a half (split_lattice; 0 where
    // they are drawn whole).
    uint owner = ap.level + (h == 0u ? 0u : 1u);
    edge_lattice_override = split_lattice(owner, (h == 0u) ? chunk.split : (chunk.split >> 1));
    ivec2 se = bspline_edge_corners(e);
    vec2 start = corner_uv(se.x);
    vec2 end = corner_uv(se.y);
    vec2 mid = 0.5 * (start + end);
    // Segment A -> B runs with the edge parameter.
    vec2 a = (h == 2u) ? mid : start;
    vec2 b = (h == 1u) ? mid : end;
    uint slot_a = (h == 2u) ? ap.mid[e] : info.corners[se.x];
    uint slot_b = (h == 1u) ? ap.mid[e] : info.corners[se.y];
    // Edges 2 and 3 run against face order: B is vertex 1 there, keeping the fan counter-clockwise.
    bool flip = e >= 2;
    // A split fan: the point in the whole triangle (fan_domain_point), except on the segment of
    // a half edge whose finer owner is drawn whole: the tessellator's own coordinates there, as
    // that patch's.
    vec3 tc = gl_TessCoord;
    FanSplit fs = fan_split(ap.level, h);
    if (fs.n > 0u && !(fs.n == 1u && h != 0u && tc.x == 0.0)) {
        tc = fan_domain_point(fs, tc);
    }
    float wc = tc.x;
    float wa = flip ? tc.z : tc.y;
    float wb = flip ? tc.y : tc.z;

    vec3 p;
    vec3 nrm;
    vec3 du, dv;
    vec2 uv;
    if (wc == 0.0 && (wa == 0.0 || wb == 0.0)) {
        bool at_a = (wb == 0.0);
        uv = at_a ? a : b;
        PATCH_SURFACE(info, uv.x, uv.y, p, nrm, du, dv);
        shared_corner(at_a ? slot_a : slot_b, info.face, p, nrm);
        uint frame_a = (h == 2u) ? ap.mid_frame[e] : ap.corner_frame[se.x];
        uint frame_b = (h == 1u) ? ap.mid_frame[e] : ap.corner_frame[se.y];
        sector_normal(at_a ? frame_a : frame_b, nrm);
    } else if (wc == 0.0) {
        float x = lattice_x(wb);
        uv = a + x * (b - a);
        PATCH_SURFACE(info, uv.x, uv.y, p, nrm, du, dv);
        if (h == 0u && ap.coarse[e] != NO_ENTRY) {
            // A whole edge lying on a coarser patch (this patch is the finer side there).
            fine_edge_point(ap.coarse[e], slot_a, slot_b, x, p, nrm);
        } else if (h == 0u) {
            PATCH_EDGE(info, e, x, p, nrm);
        } else {
            bool forward = ((info.flags >> (4 + e)) & 1u) == 0u;
            float t;
            float s;
            coarse_half_ts((h == 1u) == forward, forward, x, t, s);
            PATCH_EDGE_TS(info, e, t, s, p, nrm);
        }
    } else if (wa == 0.0 || wb == 0.0) {
        // Spoke from the centre to B (wa == 0) or A (wb == 0).
        float y = (wa == 0.0) ? wb : wa;
        vec2 q = (wa == 0.0) ? b : a;
        float ty;
        float sy;
        canonical_ts(y, true, ty, sy);
        precise vec2 spoke_uv = sy * vec2(0.5) + ty * q;
        uv = spoke_uv;
        PATCH_SURFACE(info, uv.x, uv.y, p, nrm, du, dv);
    } else {
        uv = wc * vec2(0.5) + wa * a + wb * b;
        PATCH_SURFACE(info, uv.x, uv.y, p, nrm, du, dv);
    }

    displace_adaptive(ap, uv, uv_tangents(du, dv), p, nrm);
    t_world = p;
    t_normal = nrm;
    t_class = adaptive_class(FAN_KIND(ap), ap.level);
    gl_Position = frame.view_proj * vec4(p, 1.0);
#ifdef CAPTURE
    capture_adaptive(ap, FAN_KIND(ap), uv, p, nrm);
#endif
}

#endif
