#version 450
// Triangular Gregory patch evaluation (15 control points, layout in gregory/gregory.glsl): the
// cubic-boundary quartic of §3.1 with the face points blended (§4.4), position and derivatives
// (F frozen) for the normal; corners and edges by the shared watertight rules (§4.5).
// Domain: gl_TessCoord = barycentric weights (b0, b1, b2) of face corners 0, 1, 2; the captured
// (u, v) are (b1, b2), the (s, t) of patch::gregory::GregoryTriangle::eval.
// Defines: SPACING, CAPTURE.
#include "frame.glsl"
#include "bspline.glsl"
#include "gregory.glsl"
#ifdef CAPTURE
#include "capture.glsl"
#endif

#ifndef SPACING
#define SPACING equal_spacing
#endif

layout(triangles, SPACING, cw) in;
layout(location = 0) in vec3 g_cp[];
layout(location = 1) patch in vec3 g_eout[6];
layout(location = 7) patch in vec3 g_nbr[6];
layout(location = 0) out vec3 t_world;
layout(location = 1) out vec3 t_normal;
layout(location = 2) flat out uint t_class;

#define P(i) g_cp[(i)]
#define EP(i) g_cp[3 + (i)]
#define EM(i) g_cp[6 + (i)]
#define FP(i) g_cp[9 + (i)]
#define FM(i) g_cp[12 + (i)]

/// Face edge k (corner k -> k+1) at coordinate x measured from corner k.
void tri_edge(GregoryPatchInfo info, int k, float x, out vec3 pos, out vec3 nrm) {
    int a = k;
    int b = (k + 1) % 3;
    bool a_is_lo = info.corners[a] < info.corners[b];
    float t, s;
    edge_ts(x, a_is_lo, t, s);
    bool nbr_quad = (info.flags & (1u << uint(8 + k))) == 0u;
    bool sharp = (info.flags & (1u << uint(12 + k))) != 0u;
    shared_edge(false, nbr_quad, sharp, a_is_lo, t, s, GREGORY_CORNER_ORIGIN(info, a),
                GREGORY_CORNER_ORIGIN(info, b), P(a), EP(a), EM(b), P(b),
                EM(a), FP(a), FM(b), EP(b),
                g_eout[2 * k], g_nbr[2 * k], g_nbr[2 * k + 1], g_eout[2 * k + 1], pos, nrm);
}

/// One edge term 3ab(a+b)(aX + bY) and its partials in a and b.
void edge_term(float a, float b, vec3 x, vec3 y, out vec3 val, out vec3 da, out vec3 db) {
    vec3 m = a * x + b * y;
    val = 3.0 * a * b * (a + b) * m;
    da = 3.0 * b * ((2.0 * a + b) * m + a * (a + b) * x);
    db = 3.0 * a * ((a + 2.0 * b) * m + b * (a + b) * y);
}

void main() {
    uint patch_index = chunk.patch_base + uint(gl_PrimitiveID);
    GregoryPatchInfo info = gpatches[patch_index];
    vec3 bary = tri_domain_point(gl_TessCoord);
    float w0 = bary.x;
    float w1 = bary.y;
    float w2 = bary.z;
    // Every corner's points in the frame of corner 0 (o1, o2: the other corners' origins
    // relative to it).
    vec3 o0 = GREGORY_CORNER_ORIGIN(info, 0);
    vec3 o1 = GREGORY_CORNER_ORIGIN(info, 1) - o0;
    vec3 o2 = GREGORY_CORNER_ORIGIN(info, 2) - o0;
    vec3 f0 = gregory_blend(w2, FM(0), w1, FP(0));
    vec3 f1 = gregory_blend(w0, FM(1), w2, FP(1)) + o1;
    vec3 f2 = gregory_blend(w1, FM(2), w0, FP(2)) + o2;
    vec3 e01, e01_0, e01_1, e12, e12_1, e12_2, e20, e20_2, e20_0;
    edge_term(w0, w1, EP(0), EM(1) + o1, e01, e01_0, e01_1);
    edge_term(w1, w2, EP(1) + o1, EM(2) + o2, e12, e12_1, e12_2);
    edge_term(w2, w0, EP(2) + o2, EM(0), e20, e20_2, e20_0);
    vec3 inner = w0 * f0 + w1 * f1 + w2 * f2;
    vec3 p1 = P(1) + o1;
    vec3 p2 = P(2) + o2;
    vec3 p = w0 * w0 * w0 * P(0) + w1 * w1 * w1 * p1 + w2 * w2 * w2 * p2 + e01 + e12 + e20
           + 12.0 * w0 * w1 * w2 * inner + o0;
    vec3 t0 = 3.0 * w0 * w0 * P(0) + e01_0 + e20_0 + 12.0 * (w1 * w2 * inner + w0 * w1 * w2 * f0);
    vec3 t1 = 3.0 * w1 * w1 * p1 + e01_1 + e12_1 + 12.0 * (w0 * w2 * inner + w0 * w1 * w2 * f1);
    vec3 t2 = 3.0 * w2 * w2 * p2 + e12_2 + e20_2 + 12.0 * (w0 * w1 * inner + w0 * w1 * w2 * f2);
    vec3 nrm = safe_normal(t1 - t0, t2 - t0);

    int zeros = int(w0 == 0.0) + int(w1 == 0.0) + int(w2 == 0.0);
    if (zeros >= 2) {
        int k = (w0 != 0.0) ? 0 : (w1 != 0.0 ? 1 : 2);
        nrm = gregory_corner_normal(P(k), EP(k), EM(k), FP(k), FM(k));
        shared_corner(info.corners[k], info.face, p, nrm);
    } else if (w2 == 0.0) {
        tri_edge(info, 0, w1, p, nrm);
    } else if (w0 == 0.0) {
        tri_edge(info, 1, w2, p, nrm);
    } else if (w1 == 0.0) {
        tri_edge(info, 2, w0, p, nrm);
    }

    displace_point(info.face, NO_SUB_FACE, vec2(w1, w2), uv_tangents(t1 - t0, t2 - t0), p, nrm);
    t_world = p;
    t_normal = nrm;
    t_class = CLASS_TRIANGLE;
    gl_Position = frame.view_proj * vec4(p, 1.0);
#ifdef CAPTURE
    capture_point(info.face, vec2(w1, w2), p, nrm);
#endif
}
