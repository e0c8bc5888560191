// The TES body of the quad Gregory patch (20 control points from either construction variant,
// layout in gregory/gregory.glsl), shared by the Gregory schemes and the adaptive scheme's end
// caps. Interior: the bicubic Bezier net with the face points blended at (u, v) (§3.1, §4.4),
// position and derivatives (F frozen) for the normal. Corners and edges: the watertight shared
// evaluation of common/watertight.glsl and gregory/gregory.glsl (§4.5).
// Hooks the stage file defines before including: GREGORY_CLASS(info) (colour class),
// GREGORY_DISPLACE(info, u, v, tg, p, n) (displace.glsl's displace_point at the face point,
// tg the patch's SurfaceTangents in its own (u, v)),
// GREGORY_CAPTURE(info, u, v, p, n) (with CAPTURE), and optionally
// GREGORY_EDGE_OVERRIDE(info, k, x, from_corner, pos, nrm) (true: edge k evaluated elsewhere) and
// GREGORY_CORNER_NORMAL(info, k, nrm) (after the shared corner: a normal read elsewhere) and
// GREGORY_FILLET(info, k) (edge k's residual sharpness of a fillet the interior normal follows,
// 0: none)
// and GREGORY_FILLET_BEYOND (the stage sets edge_fillet_beyond_slot / _corner per edge end)
// and, with GREGORY_FILLET, GREGORY_FILLET_END(info, k) (the positional fillet reaches corner k
// whole, `patch::adaptive::promoted::positional_fillet_end`) and
// GREGORY_POSITION_OFFSET(info, u, v, p) (after the shared corners and edges: adds to p) and
// GREGORY_NORMAL_OVERRIDE(info, patch_index, u, v, nrm) (after the shared corners and edges:
// replaces nrm).
// Needs frame.glsl first; defines SPACING, CAPTURE as the stage file's.
#ifndef TESSERA_GREGORY_QUAD_TES_GLSL
#define TESSERA_GREGORY_QUAD_TES_GLSL

#include "bspline.glsl"
#include "gregory.glsl"
#ifdef CAPTURE
#include "capture.glsl"
#endif

#ifndef SPACING
#define SPACING equal_spacing
#endif
#ifndef GREGORY_CORNER_NORMAL
#define GREGORY_CORNER_NORMAL(info, k, nrm)
#endif

// As bspline/patch_bspline.tese: `cw` in Vulkan's upper-left domain is counter-clockwise in (u right, v up).
layout(quads, SPACING, cw) in;
layout(location = 0) in vec3 g_cp[];
layout(location = 1) patch in vec3 g_eout[8];
layout(location = 9) patch in vec3 g_nbr[8];
layout(location = 0) out vec3 t_world;
layout(location = 1) out vec3 t_normal;
layout(location = 2) flat out uint t_class;

#define P(i) g_cp[(i)]
#define EP(i) g_cp[4 + (i)]
#define EM(i) g_cp[8 + (i)]
#define FP(i) g_cp[12 + (i)]
#define FM(i) g_cp[16 + (i)]

/// Face edge k (corner k -> k+1) at coordinate x measured from corner `from_corner`.
void quad_edge(uint patch_index, GregoryPatchInfo info, int k, float x, int from_corner,
               inout vec3 pos, inout vec3 nrm) {
#ifdef GREGORY_EDGE_OVERRIDE
    if (GREGORY_EDGE_OVERRIDE(info, k, x, from_corner, pos, nrm)) {
        return;
    }
#endif
    int a = k;
    int b = (k + 1) & 3;
    bool a_is_lo = info.corners[a] < info.corners[b];
    bool from_lo = (from_corner == a) == a_is_lo;
    float t, s;
    edge_ts(x, from_lo, t, s);
    // An edge shared with a B-spline patch: its grid's limit curve and normal; across a sharp
    // edge (bit 4+k) only the curve, the crease polygon's, which the B-spline side evaluates
    // alike, while the normal is this patch's own one-sided one (shared_edge below).
    bool grid = (info.flags & (1u << uint(k))) != 0u;
    vec3 grid_pos = vec3(0.0);
    if (grid) {
        grid_edge(patch_index, info.flags, k, t, s, pos, nrm);
        if ((info.flags & (1u << uint(4 + k))) == 0u) {
            return;
        }
        grid_pos = pos;
    }
#ifdef GREGORY_FILLET_BEYOND
    // The continuation beyond a crease this edge crosses (the stage's end_cap_edge named its
    // slot): its derivative from the corner, 3 (eo - p), as the neighbour's own.
    for (int end = 0; end < 2; ++end) {
        int slot = edge_fillet_beyond_slot[end];
        edge_fillet_has_beyond[end] = slot >= 0;
        if (slot >= 0) {
            precise vec3 d = 3.0 * (g_eout[slot] - P(edge_fillet_beyond_corner[end]));
            edge_fillet_beyond[end] = d;
        }
    }
#endif
    bool nbr_quad = (info.flags & (1u << uint(8 + k))) == 0u;
    bool sharp = (info.flags & (1u << uint(12 + k))) != 0u;
    shared_edge(true, nbr_quad, sharp, a_is_lo, t, s, GREGORY_CORNER_ORIGIN(info, a),
                GREGORY_CORNER_ORIGIN(info, b), P(a), EP(a), EM(b), P(b),
                EM(a), FP(a), FM(b), EP(b),
                g_eout[2 * k], g_nbr[2 * k], g_nbr[2 * k + 1], g_eout[2 * k + 1], pos, nrm);
    if (grid) {
        pos = grid_pos;
    }
}

#ifdef GREGORY_FILLET
/// Inside the patch: du, dv with the cross-edge derivative of every edge k whose residual
/// sharpness GREGORY_FILLET(info, k) is non-zero changed within its fillet, as
/// `patch::adaptive::promoted::fillet_cross_derivative`: -(d_own + d_nbr) (1 - w/h)^2 / 2 at
/// distance w < h = 2^-floor(s) from the edge (blended with h / 2 by the fraction of s), d_* both
/// sides' cross-edge derivatives at the edge point (into each patch); between two quads the
/// derivative along the edge also follows the fillet's offset (`fillet_offset_factor`). `p`
/// gains that offset there, `fillet_offset(s, w) (d_own + d_nbr)` faded towards an end it does
/// not reach whole (`AdaptiveSurface::fillet_position`).
void fillet_derivatives(GregoryPatchInfo info, float u, float v, inout vec3 du, inout vec3 dv,
                        inout vec3 p) {
    for (int k = 0; k < 4; ++k) {
        float sharp = GREGORY_FILLET(info, k);
        if (sharp == 0.0) {
            continue;
        }
        float n = floor(sharp);
        float frac = sharp - n;
        // (distance from edge k, position along it from corner k).
        float w = (k == 0) ? v : (k == 1) ? 1.0 - u : (k == 2) ? 1.0 - v : u;
        float x = (k == 0) ? u : (k == 1) ? v : (k == 2) ? 1.0 - u : 1.0 - v;
        float r0 = max(1.0 - w * exp2(n), 0.0);
        float r1 = max(1.0 - w * exp2(n + 1.0), 0.0);
        if (r0 == 0.0) {
            continue;
        }
        int a = k;
        int b = (k + 1) & 3;
        bool nbr_quad = (info.flags & (1u << uint(8 + k))) == 0u;
        vec3 d_own = cross_quad(P(a), EP(a), EM(b), P(b), EM(a), FP(a), FM(b), EP(b), x, 1.0 - x);
        vec3 d_nbr = cross_any(nbr_quad, P(a), EP(a), EM(b), P(b), g_eout[2 * k], g_nbr[2 * k],
                               g_nbr[2 * k + 1], g_eout[2 * k + 1], x, 1.0 - x);
        vec3 d = (d_own + d_nbr) * ((1.0 - frac) * (-0.5 * r0 * r0) + frac * (-0.5 * r1 * r1));
        float share = fillet_end_share(GREGORY_FILLET_END(info, a), sharp, x)
                    * fillet_end_share(GREGORY_FILLET_END(info, b), sharp, 1.0 - x);
        float offset = fillet_offset(sharp, w);
        p += (d_own + d_nbr) * (offset * share);
        // Between two quads the derivative along the edge gains the fillet's offset factor
        // `h (1 - w/h)^3 / 6` (`fillet_offset_factor`) times the slope of d_own + d_nbr there.
        vec3 along = vec3(0.0);
        if (nbr_quad) {
            vec3 slope = cross_quad_slope(P(a), EP(a), EM(b), P(b), EM(a), FP(a), FM(b), EP(b),
                                          x, 1.0 - x)
                       + cross_quad_slope(P(a), EP(a), EM(b), P(b), g_eout[2 * k], g_nbr[2 * k],
                                          g_nbr[2 * k + 1], g_eout[2 * k + 1], x, 1.0 - x);
            along = slope * offset;
        }
        if (k == 0) {
            dv += d;
            du += along;
        } else if (k == 1) {
            du -= d;
            dv += along;
        } else if (k == 2) {
            dv -= d;
            du -= along;
        } else {
            du += d;
            dv -= along;
        }
    }
}

/// At corner k, where the positional fillet reaches it whole: the offset of the promoted crease
/// there (edge k or k - 1), `fillet_offset(s, 0)` times the derivative along the corner's other
/// edge plus its continuation's beyond the crease (the neighbour's other edge point there), the
/// sum every patch at the vertex forms from the same two derivatives.
vec3 fillet_corner_offset(GregoryPatchInfo info, int k) {
    if (!GREGORY_FILLET_END(info, k)) {
        return vec3(0.0);
    }
    int prev = (k + 3) & 3;
    bool from_k = GREGORY_FILLET(info, k) != 0.0;
    float sharp = from_k ? GREGORY_FILLET(info, k) : GREGORY_FILLET(info, prev);
    if (sharp == 0.0) {
        return vec3(0.0);
    }
    precise vec3 along = 3.0 * ((from_k ? EM(k) : EP(k)) - P(k));
    precise vec3 beyond = 3.0 * (g_eout[from_k ? 2 * k : 2 * prev + 1] - P(k));
    precise vec3 offset = (along + beyond) * fillet_offset(sharp, 0.0);
    return offset;
}
#endif

void main() {
    uint patch_index = chunk.patch_base + uint(gl_PrimitiveID);
    GregoryPatchInfo info = gpatches[patch_index];
    vec3 sd = sub_domain();
    float u = sd.x + gl_TessCoord.x * sd.z;
    float v = sd.y + gl_TessCoord.y * sd.z;
    float su = 1.0 - u;
    float sv = 1.0 - v;
    // Every corner's points in the frame of corner 0 (o[k]: corner k's origin relative to it).
    vec3 o0 = GREGORY_CORNER_ORIGIN(info, 0);
    vec3 o[4] = vec3[4](vec3(0.0), GREGORY_CORNER_ORIGIN(info, 1) - o0,
                        GREGORY_CORNER_ORIGIN(info, 2) - o0, GREGORY_CORNER_ORIGIN(info, 3) - o0);
    vec3 f0 = gregory_blend(u, FP(0), v, FM(0));
    vec3 f1 = gregory_blend(su, FM(1), v, FP(1)) + o[1];
    vec3 f2 = gregory_blend(su, FP(2), sv, FM(2)) + o[2];
    vec3 f3 = gregory_blend(u, FM(3), sv, FP(3)) + o[3];
    // Bezier net b[4j + i], i along u (the paper's matrix G with the F points blended).
    vec3 b[16] = vec3[16](P(0), EP(0), EM(1) + o[1], P(1) + o[1],
                          EM(0), f0, f1, EP(1) + o[1],
                          EP(3) + o[3], f3, f2, EM(2) + o[2],
                          P(3) + o[3], EM(3) + o[3], EP(2) + o[2], P(2) + o[2]);
    vec4 bu, dbu, bv, dbv;
    bernstein3(u, su, bu, dbu);
    bernstein3(v, sv, bv, dbv);
    vec3 p = vec3(0.0);
    vec3 du = vec3(0.0);
    vec3 dv = vec3(0.0);
    for (int j = 0; j < 4; ++j) {
        for (int i = 0; i < 4; ++i) {
            vec3 cp = b[4 * j + i];
            p += (bu[i] * bv[j]) * cp;
            du += (dbu[i] * bv[j]) * cp;
            dv += (bu[i] * dbv[j]) * cp;
        }
    }
    p += o0;
    vec3 nrm = safe_normal(du, dv);
#ifdef GREGORY_FILLET
    {
        vec3 fu = du;
        vec3 fv = dv;
        fillet_derivatives(info, u, v, fu, fv, p);
        nrm = safe_normal(fu, fv);
    }
#endif

    bool u_edge = (u == 0.0 || u == 1.0);
    bool v_edge = (v == 0.0 || v == 1.0);
    if (u_edge && v_edge) {
        int k = quad_corner_index(u, v);
        nrm = gregory_corner_normal(P(k), EP(k), EM(k), FP(k), FM(k));
        quad_corner_point(info.corners, info.face, u, v, p, nrm);
        GREGORY_CORNER_NORMAL(info, k, nrm);
#ifdef GREGORY_FILLET
        {
            // Every patch at the vertex adds the same bits.
            precise vec3 q = p + fillet_corner_offset(info, k);
            p = q;
        }
#endif
    } else if (v == 0.0) {
        quad_edge(patch_index, info, 0, u, 0, p, nrm);
    } else if (u == 1.0) {
        quad_edge(patch_index, info, 1, v, 1, p, nrm);
    } else if (v == 1.0) {
        quad_edge(patch_index, info, 2, u, 3, p, nrm);
    } else if (u == 0.0) {
        quad_edge(patch_index, info, 3, v, 0, p, nrm);
    }

#ifdef GREGORY_NORMAL_OVERRIDE
    GREGORY_NORMAL_OVERRIDE(info, patch_index, u, v, nrm);
#endif
#ifdef GREGORY_POSITION_OFFSET
    GREGORY_POSITION_OFFSET(info, u, v, p);
#endif
    GREGORY_DISPLACE(info, u, v, uv_tangents(du, dv), p, nrm);
    t_world = p;
    t_normal = nrm;
    t_class = GREGORY_CLASS(info);
    gl_Position = frame.view_proj * vec4(p, 1.0);
#ifdef CAPTURE
    GREGORY_CAPTURE(info, u, v, p, nrm);
#endif
}

#endif
