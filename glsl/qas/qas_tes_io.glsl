// What both QAS evaluation shaders share: includes, spacing, outputs, and the watertight
// corner and edge evaluation (module docs of qas.glsl).
#ifndef TESSERA_QAS_TES_IO_GLSL
#define TESSERA_QAS_TES_IO_GLSL

#include "frame.glsl"
#include "watertight.glsl"
#include "qas.glsl"
#include "displace.glsl"
#ifdef CAPTURE
#include "capture.glsl"
#endif

#include "tes_outputs.glsl"

/// The quadratic Bézier (lo, mid, hi) at canonical (t, s = 1 - t) measured from lo.
vec3 qas_curve(vec3 lo, vec3 mid, vec3 hi, float t, float s) {
    precise float w0 = s * s;
    precise float w1 = 2.0 * t * s;
    precise float w2 = t * t;
    precise vec3 r = (w0 * lo + w1 * mid) + w2 * hi;
    return r;
}

/// Patch `pi`'s edge from coefficient slot a (corner vertex ia, x = 0) over slot m to slot b
/// (corner vertex ib, x = 1) at x: position and unit normal, in the canonical frame. Returns
/// that frame's (t, s): the weights of the end with the larger and the smaller id.
vec2 qas_edge(uint pi, int a, int m, int b, uint ia, uint ib, float x, out vec3 pos,
              out vec3 nrm) {
    bool from_lo = ia < ib;
    float t, s;
    edge_ts(x, from_lo, t, s);
    int lo = from_lo ? a : b;
    int hi = from_lo ? b : a;
    pos = qas_curve(qas[pi].p[lo].xyz, qas[pi].p[m].xyz, qas[pi].p[hi].xyz, t, s);
    precise vec3 nn = normalize(qas_curve(qas[pi].n[lo].xyz, qas[pi].n[m].xyz,
                                          qas[pi].n[hi].xyz, t, s));
    nrm = nn;
    return vec2(t, s);
}

/// Patch `pi`'s corner coefficient slot k: the limit point and its unit normal.
void qas_corner(uint pi, int k, out vec3 pos, out vec3 nrm) {
    pos = qas[pi].p[k].xyz;
    precise vec3 nn = normalize(qas[pi].n[k].xyz);
    nrm = nn;
}

/// Writes the outputs (and the capture record) of point (u, v) of face `face` (sub-face `sub`,
/// NO_SUB_FACE: the face's own domain), displaced (`displace.glsl`, `tg` the position patch's
/// tangents in that (u, v)) after the watertight evaluation.
void qas_emit(uint face, uint sub, vec2 uv, SurfaceTangents tg, vec3 p, vec3 nrm, uint cls) {
    displace_point(face, sub, uv, tg, p, nrm);
    t_world = p;
    t_normal = nrm;
    t_class = cls;
    gl_Position = frame.view_proj * vec4(p, 1.0);
#ifdef CAPTURE
    capture_tagged(face, sub, uv, p, nrm, 0u);
#endif
}

#endif
