// Cubic B-spline and Bernstein bases with derivatives, and the B-spline -> Bezier change of basis.
// Uniform cubic B-spline: N0 = s^3/6, N1 = (4 - 6t^2 + 3t^3)/6, N2 = N1(s), N3 = t^3/6 with s = 1 - t
// (de Boor; the regular Catmull-Clark patch of Stam 1998, sec. 2).
#ifndef TESSERA_BSPLINE_GLSL
#define TESSERA_BSPLINE_GLSL

/// Cubic Bernstein basis and its derivative at t (s = 1 - t given by the caller).
void bernstein3(float t, float s, out vec4 b, out vec4 db) {
    b = vec4(s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t);
    db = vec4(-3.0 * s * s, 3.0 * s * s - 6.0 * t * s, 6.0 * t * s - 3.0 * t * t, 3.0 * t * t);
}

/// Inner cubic B-spline basis function N1 at x (N2(t) = N1(1 - t)).
float bspline3_inner(float x) {
    return (4.0 - 6.0 * x * x + 3.0 * x * x * x) * (1.0 / 6.0);
}

/// Cubic B-spline basis at the pair (t, s = 1 - t): symmetric in (t, s) swapped with index reversal.
vec4 bspline3(float t, float s) {
    return vec4(s * s * s * (1.0 / 6.0), bspline3_inner(t), bspline3_inner(s), t * t * t * (1.0 / 6.0));
}

/// Bezier control point k (0..3) of the cubic segment with B-spline points b0..b3:
/// e0 = (b0 + 4 b1 + b2)/6, e1 = (2 b1 + b2)/3, e2 = (b1 + 2 b2)/3, e3 = (b1 + 4 b2 + b3)/6.
vec4 bspline_to_bezier_row(int k) {
    if (k == 0) return vec4(1.0, 4.0, 1.0, 0.0) * (1.0 / 6.0);
    if (k == 1) return vec4(0.0, 2.0, 1.0, 0.0) * (1.0 / 3.0);
    if (k == 2) return vec4(0.0, 1.0, 2.0, 0.0) * (1.0 / 3.0);
    return vec4(0.0, 1.0, 4.0, 1.0) * (1.0 / 6.0);
}

/// Patch edge (0: v=0, 1: u=1, 2: v=1, 3: u=0) of (u, v) on exactly one domain edge.
int bspline_edge(float u, float v) {
    return (v == 0.0) ? 0 : (u == 1.0) ? 1 : (v == 1.0) ? 2 : 3;
}

/// Point, unit normal (cross(dP/du, dP/dv), +z where it vanishes) and the partials dP/du,
/// dP/dv of the bicubic Bezier patch cp[4*j + i] (i along u) at (u, v).
void bezier_surface_frame(vec3 cp[16], float u, float v, out vec3 pos, out vec3 nrm,
                          out vec3 du, out vec3 dv) {
    vec4 bu, dbu, bv, dbv;
    bernstein3(u, 1.0 - u, bu, dbu);
    bernstein3(v, 1.0 - v, bv, dbv);
    vec3 p = vec3(0.0);
    du = vec3(0.0);
    dv = vec3(0.0);
    for (int j = 0; j < 4; ++j) {
        for (int i = 0; i < 4; ++i) {
            vec3 c = cp[4 * j + i];
            p += (bu[i] * bv[j]) * c;
            du += (dbu[i] * bv[j]) * c;
            dv += (bu[i] * dbv[j]) * c;
        }
    }
    vec3 n = cross(du, dv);
    float len = length(n);
    pos = p;
    nrm = len > 0.0 ? n / len : vec3(0.0, 0.0, 1.0);
}

#endif
