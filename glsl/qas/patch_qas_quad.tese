#version 450
// QAS quad (glsl/qas/qas.glsl): biquadratic position and normal patches; corners and edges by
// the shared watertight rules. Drawn whole (the pass is not split into sub-patches).
// Defines: SPACING, CAPTURE.
#include "qas_tes_io.glsl"

layout(quads, SPACING, cw) in;

/// Biquadratic Bernstein weights at t.
vec3 bern2(float t) {
    float s = 1.0 - t;
    return vec3(s * s, 2.0 * t * s, t * t);
}

/// Their derivatives at t.
vec3 dbern2(float t) {
    float s = 1.0 - t;
    return vec3(-2.0 * s, 2.0 * (s - t), 2.0 * t);
}

void main() {
    float u = gl_TessCoord.x;
    float v = gl_TessCoord.y;
    uint pi = chunk.patch_base + uint(gl_PrimitiveID);
    uvec4 c = qas[pi].corners;
    vec3 bu = bern2(u);
    vec3 bv = bern2(v);
    vec3 dbu = dbern2(u);
    vec3 dbv = dbern2(v);
    vec3 p = vec3(0.0);
    vec3 n = vec3(0.0);
    vec3 du = vec3(0.0);
    vec3 dv = vec3(0.0);
    for (int j = 0; j < 3; ++j) {
        for (int i = 0; i < 3; ++i) {
            float w = bu[i] * bv[j];
            vec3 c = qas[pi].p[3 * j + i].xyz;
            p += w * c;
            n += w * qas[pi].n[3 * j + i].xyz;
            du += (dbu[i] * bv[j]) * c;
            dv += (bu[i] * dbv[j]) * c;
        }
    }
    vec3 nrm = normalize(n);
    bool u_edge = (u == 0.0 || u == 1.0);
    bool v_edge = (v == 0.0 || v == 1.0);
    if (u_edge && v_edge) {
        qas_corner(pi, int(2.0 * u + 6.0 * v), p, nrm);
    } else if (v == 0.0) {
        qas_edge(pi, 0, 1, 2, c.x, c.y, u, p, nrm);
    } else if (v == 1.0) {
        qas_edge(pi, 6, 7, 8, c.w, c.z, u, p, nrm);
    } else if (u == 0.0) {
        qas_edge(pi, 0, 3, 6, c.x, c.w, v, p, nrm);
    } else if (u == 1.0) {
        qas_edge(pi, 2, 5, 8, c.y, c.z, v, p, nrm);
    }
    qas_emit(qas[pi].face, NO_SUB_FACE, vec2(u, v), uv_tangents(du, dv), p, nrm, CLASS_IRREGULAR);
}
