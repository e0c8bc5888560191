// What the patches of the adaptive scheme share (Köbler 2013, ch. 3): per-patch records and
// coarse-edge records (src/patch/adaptive/draw.rs writes them byte for byte), tessellation
// levels by patch level, the evaluation of an edge lying on a one-level-coarser patch (the
// transition edges of §3.4, split in two halves as OpenSubdiv does) and the capture in base-face
// parameters. Every vertex id here is a frame SLOT: the index of a limit point in vertex_limit /
// vertex_normal (bindings 2 and 9, written by limit_frames.comp), the same for a vertex and its
// vertex-point children at finer levels, so corners and canonical edge directions agree across
// levels. Needs frame.glsl first.
#ifndef TESSERA_ADAPTIVE_GLSL
#define TESSERA_ADAPTIVE_GLSL

#include "bspline.glsl"
#include "watertight.glsl"
#include "control_points.glsl"
#include "single_crease/single_crease.glsl"
#ifdef CAPTURE
#include "capture.glsl"
#endif

const uint NO_ENTRY = 0xffffffffu;

/// Patch kinds as captured (subdiv::adaptive::PatchType 0-4; transition patches are B-spline
/// patches drawn as a triangle fan; single-crease patches keep their kind when drawn as one).
#define KIND_END_CAP 3u
#define KIND_SINGLE_CREASE 4u
#define KIND_TRANSITION 5u

/// One drawn patch (144 bytes): base face and sub-face (NO_ENTRY for quads), level, kind, the map
/// of the patch domain into the base face (origin + s axis_u + t axis_v), transition mask (bit
/// e: the neighbour across edge e is one level finer), the slot of each transition edge's
/// midpoint, per edge the coarse-edge record it lies on (NO_ENTRY: none), and the sector frame
/// each corner and transition midpoint takes its normal from (NO_ENTRY: none;
/// src/patch/adaptive/sector_frames.rs); quad end caps: per corner the frame of the exact limit
/// position the corner offset reaches (NO_ENTRY: none; src/patch/adaptive/exact_corners.rs) and
/// the offsets' width codes (bits 8k..8k+8, 16 s).
struct AdaptivePatch {
    uint base_face;
    uint sub_face;
    uint level;
    uint kind;
    vec2 origin;
    vec2 axis_u;
    vec2 axis_v;
    uint transition;
    uint fillet;
    uvec4 mid;
    uvec4 coarse;
    uvec4 corner_frame;
    uvec4 mid_frame;
    uvec4 corner_exact;
    uint corner_fade;
    uint fillet_fine[3];
};

layout(std430, set = 0, binding = 10) readonly buffer AdaptivePatches {
    AdaptivePatch apatches[];
};

/// The normal of sector frame `f` (a frame index like a slot; NO_ENTRY: keep `nrm`): where sharp
/// edges split a point's faces, every patch of one sector reads one normal there.
void sector_normal(uint f, inout vec3 nrm) {
    if (f != NO_ENTRY) {
        vec3 n = vertex_normal[f].xyz;
        if (dot(n, n) > 0.0) {
            nrm = n;
        }
    }
}

/// An edge of a coarse patch with finer patches along it (64 bytes): its 12 B-spline grid points
/// (refined-buffer ids; rows left of / on / right of the direction from the smaller slot lo to
/// hi, each from the lo end), the end and midpoint slots, flags (bit 0: boundary or infinitely
/// sharp; bits 1, 2: the first / last point along the edge is a phantom, mirrored 2 x1 - x2 as
/// the coarse patch's TCS does; bits 3-4: the curve of a single-crease coarse patch, 0 the grid
/// curve, 1 its crease edge, 2 an edge across its crease line with bit 5 set when the crease end
/// is lo; bit 6: a whole edge shared at one level (mid unused); bits 8-31: that patch's record, whose crease_sharpness the curve reads).
struct CoarseEdge {
    uint rows[12];
    uint lo;
    uint hi;
    uint mid;
    uint flags;
};

layout(std430, set = 0, binding = 11) readonly buffer CoarseEdges {
    CoarseEdge coarse_edges[];
};

/// The full edge lattice of a level-`level` patch drawn as s x s sub-patches (uniform mode,
/// s > 1; src/render/schemes/adaptive/pass.rs draws level k with s = split / 2^k, split the
/// level-0 patches' TessSettings::split): s times the sub-patch level, rounded up as the
/// equal-spacing tessellator does, so the split patch, the split transition triangle beside it
/// and the coarse side of its half edges place the same points. 0 when the level is drawn whole.
float split_lattice(uint level, uint s) {
    if (s <= 1u || frame.tess.y != TESS_MODE_UNIFORM) {
        return 0.0;
    }
    return ceil(clamp(frame.tess.x / float(s << level), 1.0, frame.tess.w)) * float(s);
}

/// `x` on the lattice edge_lattice_override when it is set (the parameter edge_ts snaps an edge
/// point to, so its captured and displaced (u, v) is that point's too).
float lattice_x(float x) {
    float n = edge_lattice_override;
    return n > 0.0 ? round(x * n) / n : x;
}

/// Parameters (t, s) on a coarse edge of the point at x on one of its halves: the half's own
/// canonical parameters (edge_ts: on the lattice edge_lattice_override where it is set; x
/// measured from the half's lo end when `x_from_lo`), then halved onto the coarse edge (`first_half`: the half [lo, mid]). The coarse patch and the
/// finer patch along the half call this with x and 1 - x and get the same bits.
void coarse_half_ts(bool first_half, bool x_from_lo, float x, out float t, out float s) {
    float th;
    float sh;
    edge_ts(x, x_from_lo, th, sh);
    precise float ht = 0.5 * th;
    precise float hs = 0.5 * sh;
    precise float tc = first_half ? ht : 0.5 + ht;
    precise float sc = first_half ? 0.5 + hs : hs;
    t = tc;
    s = sc;
}

/// Point and normal of coarse edge `ce` at (t, s), from its record: the grid_edge_rows the coarse
/// patch evaluates from its own (phantom-mirrored) B-spline points.
void coarse_edge_point(CoarseEdge ce, float t, float s, out vec3 pos, out vec3 nrm) {
    vec3 l[4];
    vec3 m[4];
    vec3 r[4];
    for (int k = 0; k < 4; ++k) {
        l[k] = control_point(ce.rows[k]);
        m[k] = control_point(ce.rows[4 + k]);
        r[k] = control_point(ce.rows[8 + k]);
    }
    if ((ce.flags & 2u) != 0u) {
        l[0] = 2.0 * l[1] - l[2];
        m[0] = 2.0 * m[1] - m[2];
        r[0] = 2.0 * r[1] - r[2];
    }
    if ((ce.flags & 4u) != 0u) {
        l[3] = 2.0 * l[2] - l[1];
        m[3] = 2.0 * m[2] - m[1];
        r[3] = 2.0 * r[2] - r[1];
    }
    uint curve = (ce.flags >> 3) & 3u;
    if (curve == 0u) {
        grid_edge_rows(l, m, r, (ce.flags & 1u) != 0u, t, s, pos, nrm);
    } else {
        // The coarse single-crease patch's own edge curve (single_crease_tes.glsl, e = 1 or 0/2).
        float sharpness = crease_sharpness[ce.flags >> 8];
        if (curve == 1u) {
            crease_edge_rows(l, m, r, sharpness, t, s, pos, nrm);
        } else {
            crease_across_edge(l, m, r, (ce.flags & 32u) != 0u, sharpness, t, s, pos, nrm);
        }
    }
}

/// The finer patch's side of a transition edge: edge from slot a to slot b (one of them the
/// coarse edge's midpoint) at x measured from a, evaluated from the coarse record `index`; with
/// flags bit 6 (an end cap next to a single-crease patch's crease-aware edge) the whole edge a-b.
/// Position always from the coarse edge; the normal too unless the edge is sharp (a crease:
/// each side keeps its own).
void fine_edge_point(uint index, uint a, uint b, float x, inout vec3 pos, inout vec3 nrm) {
    CoarseEdge ce = coarse_edges[index];
    float t;
    float s;
    if ((ce.flags & 64u) != 0u) {
        // A whole edge shared at one level: the canonical parameters of the other patch's own rule.
        edge_ts(x, a == ce.lo, t, s);
    } else {
        bool first_half = (a == ce.lo || b == ce.lo);
        bool x_from_lo = first_half ? (a == ce.lo) : (a == ce.mid);
        coarse_half_ts(first_half, x_from_lo, x, t, s);
    }
    vec3 n;
    coarse_edge_point(ce, t, s, pos, n);
    if ((ce.flags & 1u) == 0u) {
        nrm = n;
    }
}

/// The colour class of a patch (shade.frag): kind and level.
uint adaptive_class(uint kind, uint level) {
    return CLASS_ADAPTIVE + kind * 16u + min(level, 15u);
}

/// The base face's (u, v) (or its sub-face's) of patch `ap`'s own (s, t).
vec2 adaptive_face_uv(AdaptivePatch ap, vec2 st) {
    return ap.origin + st.x * ap.axis_u + st.y * ap.axis_v;
}

/// Displaces a point of patch `ap` at its own (s, t) (displace.glsl), `tg` the tangents in
/// the patch's own (s, t).
void displace_adaptive(AdaptivePatch ap, vec2 st, SurfaceTangents tg, inout vec3 p,
                       inout vec3 n) {
    displace_point(ap.base_face, ap.sub_face, adaptive_face_uv(ap, st),
                   mapped_tangents(tg, mat2(ap.axis_u, ap.axis_v)), p, n);
}

#ifdef CAPTURE
/// Captures a point of patch `ap` at its own (s, t) in its base face's (u, v) (or its sub-face's),
/// tagged with the kind and level.
void capture_adaptive(AdaptivePatch ap, uint kind, vec2 st, vec3 p, vec3 n) {
    vec2 uv = adaptive_face_uv(ap, st);
    capture_tagged(ap.base_face, ap.sub_face, uv, p, n, CAPTURE_TAGGED | (ap.level << 8u) | kind);
}
#endif

#endif
