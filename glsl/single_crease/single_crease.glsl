// Single-crease patches (Nießner, Loop, Greiner 2012): a regular quad whose only feature is one
// semi-sharp crease line of sharpness s, 0 < s < 10 (src/patch/single_crease.rs has the CPU
// construction and the derivations). The CPU rotates the 16 control vertices so that the crease
// runs along u = 1: row j of the net, P_k = cvs[4j + k], is the curve case of §3 with the crease
// vertex at k = 2 and the curve parameter t = u.
//
// Pieces across the crease (§3, §3.1), with lo = floor(s), hi = ceil(s), f = s - lo,
// a = 1 - 2^-lo, b = 1 - 2^-hi:
//   set 0, u in [0, a]: M_inf;
//   set 1, u in [a, b] (f > 0): (1 - f) M_lo + f M_inf;
//   set 2, u in [b, 1]: M_lo (f = 0, then b = a) or (1 - f) M_lo + f M_hi.
// M_n has entries ~ 2^(2n), which f32 cannot carry; restricted to its own piece [1 - 2^-n, 1]
// it is the uniform segment of the crease-refined polygon (§3: N(t) M_n = N(2^n (t - 1) + 1)
// R_p^n), and R_p^n has entries in [0, 1]. So every set is built as Bezier points over its
// own u-range from M_inf, R_p^lo and R_p^hi, restricted by blossoming: the same sets as
// SingleCreasePatch::bezier_sets, well conditioned.
#ifndef TESSERA_SINGLE_CREASE_GLSL
#define TESSERA_SINGLE_CREASE_GLSL
// Needs frame.glsl first (edge parameters, vertex limits).

#include "watertight.glsl"

/// Per-patch sharpness along the crease line (binding 4), indexed like `patches` (binding 1) in the
/// single-crease pass, by patch record (PatchInfo.pad0, 0 for other kinds) in the adaptive scheme.
layout(std430, set = 0, binding = 4) readonly buffer CreaseSharpness {
    float crease_sharpness[];
};

/// Rows of a 4x4 matrix acting on P0..P3: M[i] are the weights of output point i.
struct CurveMatrix {
    vec4 r[4];
};

/// M_inf: P3 -> 2 P2 - P1, the infinitely sharp end condition (§3).
CurveMatrix m_inf() {
    return CurveMatrix(vec4[4](vec4(1.0, 0.0, 0.0, 0.0), vec4(0.0, 1.0, 0.0, 0.0),
                               vec4(0.0, 0.0, 1.0, 0.0), vec4(0.0, -1.0, 2.0, 0.0)));
}

/// R_p^n, n crease steps (§3) in closed form with y = 2^-n, x = y^3 (eigenvalues 1/8, 1/2,
/// 1/2, 1 of R_p).
CurveMatrix crease_power(float n) {
    precise float y = exp2(-n);
    precise float x = y * y * y;
    precise float a = 2.0 * (y - x);
    precise float b = (1.0 - 2.0 * y) + x;
    precise float c = 1.0 - y;
    return CurveMatrix(vec4[4](vec4(x, a, b, 0.0), vec4(0.0, y, c, 0.0), vec4(0.0, 0.0, 1.0, 0.0),
                               vec4(0.0, 0.0, c, y)));
}

/// Weights of the Bezier points of a cubic at the blossom arguments (x1, x2, x3).
vec4 blossom(float x1, float x2, float x3) {
    precise float y1 = 1.0 - x1;
    precise float y2 = 1.0 - x2;
    precise float y3 = 1.0 - x3;
    precise vec4 w = vec4(y1 * y2 * y3, (x1 * y2 * y3 + y1 * x2 * y3) + y1 * y2 * x3,
                          (x1 * x2 * y3 + x1 * y2 * x3) + y1 * x2 * x3, x1 * x2 * x3);
    return w;
}

/// Weights over P0..P3 of Bezier point i of the curve N(t) M P restricted to t in [t0, t1]
/// (blossom (t0, t0, t0), (t0, t0, t1), (t0, t1, t1), (t1, t1, t1)).
vec4 piece_row(CurveMatrix m, float t0, float t1, int i) {
    precise vec4 w = blossom(i >= 3 ? t1 : t0, i >= 2 ? t1 : t0, i >= 1 ? t1 : t0);
    precise vec4 row = vec4(0.0);
    for (int e = 0; e < 4; ++e) {
        vec4 b = bspline_to_bezier_row(e);
        precise vec4 me = ((b.x * m.r[0] + b.y * m.r[1]) + b.z * m.r[2]) + b.w * m.r[3];
        row += w[e] * me;
    }
    return row;
}

/// The split of the sharpness: (lo, hi, f) and the piece boundaries (a, b) in u.
struct CreaseSplit {
    float lo;
    float hi;
    float f;
    float a;
    float b;
};

CreaseSplit crease_split(float sharpness) {
    float lo = floor(sharpness);
    float hi = ceil(sharpness);
    return CreaseSplit(lo, hi, sharpness - lo, 1.0 - exp2(-lo), 1.0 - exp2(-hi));
}

/// The u-range of set g (0, 1, 2); empty ranges (t0 == t1) are never selected.
vec2 set_range(CreaseSplit c, int g) {
    return g == 0 ? vec2(0.0, c.a) : (g == 1 ? vec2(c.a, c.b) : vec2(c.b, 1.0));
}

/// The set covering u (pieces join C2, so either choice at a split is the same surface).
int set_at(CreaseSplit c, float u) {
    return u < c.a ? 0 : (u < c.b ? 1 : 2);
}

/// Weights over P0..P3 of Bezier point i (across the crease) of set g over its own u-range.
vec4 set_row(CreaseSplit c, int g, int i) {
    if (g == 0) {
        return piece_row(m_inf(), 0.0, c.a, i);
    }
    CurveMatrix lo = crease_power(c.lo);
    precise vec4 w;
    if (g == 1) {
        // In the frame of R_p^lo (u in [a, 1] -> [0, 1]) the range [a, b] is [0, 1/2].
        w = (1.0 - c.f) * piece_row(lo, 0.0, 0.5, i) + c.f * piece_row(m_inf(), c.a, c.b, i);
    } else if (c.f == 0.0) {
        w = piece_row(lo, 0.0, 1.0, i);
    } else {
        w = (1.0 - c.f) * piece_row(lo, 0.5, 1.0, i) + c.f * piece_row(crease_power(c.hi), 0.0, 1.0, i);
    }
    return w;
}

/// Weight alpha of the crease-edge curve's B-spline points alpha (l + r) + (1 - 2 alpha) m, the
/// limit of u = 1 of the last set: 2^-s / 6 for integer s, blended linearly in f (§3.1).
float crease_edge_alpha(CreaseSplit c) {
    return ((1.0 - c.f) * exp2(-c.lo) + c.f * exp2(-c.hi)) * (1.0 / 6.0);
}

/// The crease edge (u = 1): grid rows l, m, r across it in the canonical frame (as
/// grid_edge_rows); its curve has the B-spline points alpha (l + r) + (1 - 2 alpha) m and the
/// cross derivative of l - r, both symmetric in l and r, so both patches of the crease compute it
/// alike.
void crease_edge_rows(vec3 l[4], vec3 m[4], vec3 r[4], float sharpness, float t, float s,
                      out vec3 pos, out vec3 nrm) {
    precise float alpha = crease_edge_alpha(crease_split(sharpness));
    precise float beta = 1.0 - 2.0 * alpha;
    precise vec3 c[4];
    precise vec3 c_rel[4];
    precise vec3 d[4];
    precise vec3 o = m[0];
    for (int i = 0; i < 4; ++i) {
        c[i] = alpha * (l[i] + r[i]) + beta * m[i];
        c_rel[i] = alpha * ((l[i] - o) + (r[i] - o)) + beta * (m[i] - o);
        d[i] = l[i] - r[i];
    }
    edge_curve(c, c_rel, d, t, s, pos, nrm);
}

/// An edge across the crease (v = 0 or v = 1): rows l, m, r along it in the canonical frame,
/// (t, s) from the smaller-id end; `crease_at_lo`: the crease end is the smaller id. The curve is
/// the curve case of the smooth edge rows ((l + r) + 4 m) / 6 (its B-spline points across the
/// crease), evaluated in the direction away -> crease on its piece's Bezier points; the normal
/// crosses the tangent (towards the larger id) with the same transform of l - r. Both patches
/// of the edge (the single-crease patches on either side, same sharpness) compute the same bits.
void crease_across_edge(vec3 l[4], vec3 m[4], vec3 r[4], bool crease_at_lo, float sharpness,
                        float t, float s, out vec3 pos, out vec3 nrm) {
    precise vec3 c[4];
    precise vec3 c_rel[4];
    precise vec3 d[4];
    precise vec3 o = m[0];
    for (int k = 0; k < 4; ++k) {
        int kk = crease_at_lo ? 3 - k : k;
        c[k] = ((l[kk] + r[kk]) + 4.0 * m[kk]) * (1.0 / 6.0);
        // The tangent from points relative to o (as edge_curve in common/watertight.glsl).
        c_rel[k] = (((l[kk] - o) + (r[kk] - o)) + 4.0 * (m[kk] - o)) * (1.0 / 6.0);
        d[k] = l[kk] - r[kk];
    }
    // Curve parameter from the away end.
    float tau = crease_at_lo ? s : t;
    CreaseSplit cs = crease_split(sharpness);
    int g = set_at(cs, tau);
    vec2 range = set_range(cs, g);
    precise float x = (tau - range.x) / (range.y - range.x);
    precise float y = 1.0 - x;
    vec4 b, db;
    bernstein3(x, y, b, db);
    precise vec3 p = vec3(0.0);
    precise vec3 tangent = vec3(0.0);
    precise vec3 cross_dir = vec3(0.0);
    for (int i = 0; i < 4; ++i) {
        precise vec4 w = set_row(cs, g, i);
        precise vec3 e = ((w.x * c[0] + w.y * c[1]) + w.z * c[2]) + w.w * c[3];
        precise vec3 e_rel = ((w.x * c_rel[0] + w.y * c_rel[1]) + w.z * c_rel[2]) + w.w * c_rel[3];
        precise vec3 f = ((w.x * d[0] + w.y * d[1]) + w.z * d[2]) + w.w * d[3];
        p += b[i] * e;
        tangent += db[i] * e_rel;
        cross_dir += b[i] * f;
    }
    if (crease_at_lo) {
        tangent = -tangent;
    }
    precise vec3 nn = normalize(cross(tangent, cross_dir));
    pos = p;
    nrm = nn;
}

#endif
