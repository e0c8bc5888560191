#version 450
// Single-crease patch evaluation (Nießner, Loop, Greiner 2012, §4): the TES picks the Bezier set
// of the piece across the crease that holds u (splits at 1 - 2^-floor(s) and 1 - 2^-ceil(s),
// single_crease.glsl) and evaluates position and normal there. Shared corners and edges follow
// common/watertight.glsl: corners read the vertex limit frames; the edge away from the crease
// (u = 0) is the B-spline grid curve of the unmodified points (M_inf and every blend keep P0..P2,
// so it is the neighbour's, B-spline or Gregory, grid_edge_rows); the crease edge (u = 1) and
// the two edges across the crease (v = 0, 1) are crease-aware curves from the 12 grid points and
// the sharpness, which the single-crease patch on the other side computes alike.
// Defines: SPACING (equal_spacing | fractional_odd_spacing | fractional_even_spacing), CAPTURE.
#include "frame.glsl"
#include "bspline.glsl"
#include "watertight.glsl"
#include "single_crease.glsl"
#ifdef CAPTURE
#include "capture.glsl"
#endif

#ifndef SPACING
#define SPACING equal_spacing
#endif

// As bspline/patch_bspline.tese: `cw` in Vulkan's upper-left domain is counter-clockwise in (u right, v up).
layout(quads, SPACING, cw) in;
layout(location = 0) in vec3 c_bspline[];
layout(location = 1) in vec3 c_set0[];
layout(location = 2) in vec3 c_set1[];
layout(location = 3) in vec3 c_set2[];
layout(location = 0) out vec3 t_world;
layout(location = 1) out vec3 t_normal;
layout(location = 2) flat out uint t_class;

#include "patch_edge_grid.glsl"

/// Bezier point k of set g.
vec3 set_point(int g, int k) {
    return g == 0 ? c_set0[k] : (g == 1 ? c_set1[k] : c_set2[k]);
}

/// Limit point and normal on patch edge e (0: v=0, 1: u=1, 2: v=1, 3: u=0) at local parameter x.
void edge_point(uint flags, float sharpness, int e, float x, out vec3 pos, out vec3 nrm) {
    vec3 l[4];
    vec3 m[4];
    vec3 r[4];
    float t, s;
    patch_edge_grid(flags, e, x, l, m, r, t, s);
    if (e == 3) {
        grid_edge_rows(l, m, r, false, t, s, pos, nrm);
    } else if (e == 1) {
        crease_edge_rows(l, m, r, sharpness, t, s, pos, nrm);
    } else {
        // Along u from u = 0 (away) to u = 1 (crease) in face order; bit 4+e: that runs from the
        // larger id, so the canonical (smaller-id) end is the crease end.
        bool crease_at_lo = ((flags >> (4 + e)) & 1u) != 0u;
        crease_across_edge(l, m, r, crease_at_lo, sharpness, t, s, pos, nrm);
    }
}

/// The face's own (u, v) of the rotated patch's (u, v): flags bits 8-9 (the crease side,
/// render::schemes::single_crease::Rotation).
vec2 face_uv(uint flags, float u, float v) {
    uint rot = (flags >> 8) & 3u;
    return rot == 0u ? vec2(u, v) : (rot == 1u ? vec2(1.0 - u, 1.0 - v)
                                   : (rot == 2u ? vec2(1.0 - v, u) : vec2(v, 1.0 - u)));
}

void main() {
    vec3 sd = sub_domain();
    float u = sd.x + gl_TessCoord.x * sd.z;
    float v = sd.y + gl_TessCoord.y * sd.z;
    uint patch_index = chunk.patch_base + uint(gl_PrimitiveID);
    PatchInfo info = patches[patch_index];
    float sharpness = crease_sharpness[patch_index];
    CreaseSplit cs = crease_split(sharpness);
    int g = set_at(cs, u);
    vec2 range = set_range(cs, g);
    float x = (u - range.x) / (range.y - range.x);
    vec4 bx, dbx, bv, dbv;
    bernstein3(x, 1.0 - x, bx, dbx);
    bernstein3(v, 1.0 - v, bv, dbv);
    vec3 p = vec3(0.0);
    vec3 du = vec3(0.0);
    vec3 dv = vec3(0.0);
    for (int j = 0; j < 4; ++j) {
        for (int i = 0; i < 4; ++i) {
            vec3 cp = set_point(g, 4 * j + i);
            p += (bx[i] * bv[j]) * cp;
            du += (dbx[i] * bv[j]) * cp;
            dv += (bx[i] * dbv[j]) * cp;
        }
    }
    // du is d/dx = (range width) d/du: the same direction.
    vec3 nrm = cross(du, dv);
    float len = length(nrm);
    nrm = len > 0.0 ? nrm / len : vec3(0.0, 0.0, 1.0);

    bool u_edge = (u == 0.0 || u == 1.0);
    bool v_edge = (v == 0.0 || v == 1.0);
    if (u_edge && v_edge) {
        quad_corner_point(info.corners, u, v, p, nrm);
    } else if (u_edge || v_edge) {
        int e = (v == 0.0) ? 0 : (u == 1.0) ? 1 : (v == 1.0) ? 2 : 3;
        edge_point(info.flags, sharpness, e, v_edge ? u : v, p, nrm);
    }

    t_world = p;
    t_normal = nrm;
    t_class = CLASS_SINGLE_CREASE;
    gl_Position = frame.view_proj * vec4(p, 1.0);
#ifdef CAPTURE
    capture_point(info.face, face_uv(info.flags, u, v), p, nrm);
#endif
}
