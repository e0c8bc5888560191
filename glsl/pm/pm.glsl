// Pm-patches (Myles, Ni, Peters 2008), stencil variant: the word buffer the CPU writes
// (src/render/schemes/pm/tables.rs mirrors it), stencil rows over the control positions, and
// the watertight evaluation of edges (outer edges and inner spokes alike) and corners.
//
// Buffer (set 0 binding 4, uint words): header [0] patch records, [1] edge records, [2] centre
// records, [3] rows, [4] terms (word offsets). Patch record (PM_RECORD_WORDS): face, kind word
// (kind | sector << 8 | m << 16 | pole << 24), flags (bit k: domain edge k starts at its
// canonical start), centre record, corner vertex ids [4..8), edge record ids [8..12),
// coefficient rows [12..28). Edge record (PM_EDGE_WORDS): degree, curve rows [1..6) from the
// canonical start (smaller vertex id; a spoke's corner), cross-derivative rows of the patch on
// the left [6..10) and on the right [10..14). Centre record: rows of b_004, b^0_103, b^1_103.
// Row: first term, term count; term: vertex id, f32 weight bits (terms sorted by vertex id).
//
// Watertight: both patches of an edge evaluate the same edge record at the same canonical
// parameter (canonical_ts, common/watertight.glsl) with `precise` arithmetic: positions and
// normals are bitwise equal. Normal on an edge: cross(tangent, d_left - d_right), the two
// patches' inward cross derivatives (G1: both lie in the tangent plane, on opposite sides).
// Needs frame.glsl first.
#ifndef TESSERA_PM_GLSL
#define TESSERA_PM_GLSL

#include "control_points.glsl"
#include "watertight.glsl"

layout(std430, set = 0, binding = 4) readonly buffer PmWords {
    uint pm_words[];
};

#define PM_RECORD_WORDS 32u
#define PM_EDGE_WORDS 16u
#define PM_CENTRE_WORDS 4u

#define PM_KIND_BICUBIC 0u
#define PM_KIND_POLAR 1u
#define PM_KIND_SECTOR 2u

/// Word offset of patch `patch_index`'s record.
uint pm_record(uint patch_index) {
    return pm_words[0] + patch_index * PM_RECORD_WORDS;
}

/// Stencil row `row` applied to the control positions relative to `origin`,
/// sum w_i (p_i - origin): terms in ascending vertex id, no fused multiply-add, so equal rows
/// and origins give equal bits in every shader. Relative sums keep the differences that
/// derivatives are made of free of the cancellation of large coordinates.
vec3 pm_row(uint row, vec3 origin) {
    uint r = pm_words[3] + 2u * row;
    uint first = pm_words[4] + 2u * pm_words[r];
    uint count = pm_words[r + 1u];
    precise vec3 acc = vec3(0.0);
    for (uint i = 0u; i < count; ++i) {
        uint t = first + 2u * i;
        precise vec3 rel = control_point(pm_words[t]) - origin;
        precise vec3 term = uintBitsToFloat(pm_words[t + 1u]) * rel;
        acc = acc + term;
    }
    return acc;
}

/// The origin of a patch's coefficients: the control position of its record's corner 0.
vec3 pm_origin(uint rec) {
    return control_point(pm_words[rec + 4u]);
}

/// Coefficient `k` of the patch whose record starts at `rec`, relative to pm_origin(rec).
vec3 pm_coefficient(uint rec, uint k) {
    return pm_row(pm_words[rec + 12u + k], pm_origin(rec));
}

/// Colour class of the patch (CLASS_PM + ordinary 0, polar 1, m = 3, 4, 5 as 2, 3, 4).
uint pm_class(uint kind_word) {
    uint kind = kind_word & 0xffu;
    uint m = (kind_word >> 16) & 0xffu;
    return CLASS_PM + (kind == PM_KIND_SECTOR ? m - 1u : kind);
}

/// Edge record `edge` at coordinate x measured from one end (`from_lo`: that end is the
/// canonical start): the curve point and the shared normal.
void pm_edge(uint edge, float x, bool from_lo, out vec3 pos, out vec3 nrm) {
    uint e = pm_words[1] + edge * PM_EDGE_WORDS;
    uint degree = pm_words[e];
    vec3 origin = control_point(pm_words[e + 14u]);
    float t, s;
    canonical_ts(x, from_lo, t, s);
    vec3 c[5];
    for (uint i = 0u; i <= degree; ++i) {
        c[i] = pm_row(pm_words[e + 1u + i], origin);
    }
    vec3 dl[4];
    vec3 dr[4];
    for (uint i = 0u; i < 4u; ++i) {
        dl[i] = pm_row(pm_words[e + 6u + i], origin);
        dr[i] = pm_row(pm_words[e + 10u + i], origin);
    }
    precise vec4 b3 = vec4(s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t);
    precise vec3 p;
    precise vec3 tangent;
    if (degree == 3u) {
        p = ((b3.x * c[0] + b3.y * c[1]) + b3.z * c[2]) + b3.w * c[3];
        tangent = ((s * s) * (c[1] - c[0]) + (2.0 * t * s) * (c[2] - c[1])) + (t * t) * (c[3] - c[2]);
    } else {
        precise float s2 = s * s;
        precise float t2 = t * t;
        p = (((s2 * s2) * c[0] + (4.0 * t * s2 * s) * c[1]) + (6.0 * t2 * s2) * c[2])
            + (4.0 * t2 * t * s) * c[3] + (t2 * t2) * c[4];
        tangent = ((b3.x * (c[1] - c[0]) + b3.y * (c[2] - c[1])) + b3.z * (c[3] - c[2]))
                  + b3.w * (c[4] - c[3]);
    }
    precise vec3 d_left = ((b3.x * dl[0] + b3.y * dl[1]) + b3.z * dl[2]) + b3.w * dl[3];
    precise vec3 d_right = ((b3.x * dr[0] + b3.y * dr[1]) + b3.z * dr[2]) + b3.w * dr[3];
    precise vec3 nn = normalize(cross(tangent, d_left - d_right));
    precise vec3 world = origin + p;
    pos = world;
    nrm = nn;
}

/// The centre of a Pm-patch (centre record `centre`, rows relative to its word 3): b_004 and the normal of the plane of the
/// spoke points next to it, cross(b^0_103 - b_004, b^1_103 - b_004), the same for every sector.
void pm_centre(uint centre, out vec3 pos, out vec3 nrm) {
    uint c = pm_words[2] + centre * PM_CENTRE_WORDS;
    vec3 origin = control_point(pm_words[c + 3u]);
    precise vec3 p = pm_row(pm_words[c], origin);
    precise vec3 a = pm_row(pm_words[c + 1u], origin) - p;
    precise vec3 b = pm_row(pm_words[c + 2u], origin) - p;
    precise vec3 nn = normalize(cross(a, b));
    precise vec3 world = origin + p;
    pos = world;
    nrm = nn;
}

/// Domain edge k of the patch at record `rec`, at coordinate x measured from its start corner
/// (`from_start`) or from its end corner.
void pm_domain_edge(uint rec, uint k, float x, bool from_start, out vec3 pos, out vec3 nrm) {
    bool start_lo = ((pm_words[rec + 2u] >> k) & 1u) != 0u;
    pm_edge(pm_words[rec + 8u + k], x, start_lo == from_start, pos, nrm);
}

/// Unit normal of derivatives, +z if degenerate.
vec3 pm_normal(vec3 du, vec3 dv) {
    vec3 n = cross(du, dv);
    float len = length(n);
    return len > 0.0 ? n / len : vec3(0.0, 0.0, 1.0);
}

#endif
