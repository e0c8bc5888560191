#version 450
// QAS triangle and n-gon fan triangle (glsl/qas/qas.glsl): the paper's quadratic triangles for
// position and normal; corners and edges by the shared watertight rules. gl_TessCoord =
// barycentric weights of corners 0, 1, 2. A triangle's captured (u, v) are the weights of
// corners 1 and 2. A fan triangle (centre, V_k, V_{k+1}) is captured in sub-face k where
// w1 >= w2, as (w0 + 2 w2, w0), else in sub-face k + 1 as (w0, w0 + 2 w1) (the piecewise linear
// map of src/patch/qas, fan_to_sub_face); on its edges the weights are the canonical (t, s) of
// the edge first, so both triangles of a spoke name its points alike (texture coordinates).
// Defines: SPACING, CAPTURE.
#include "qas_tes_io.glsl"

layout(triangles, SPACING, cw) in;

void main() {
    float w0 = gl_TessCoord.x;
    float w1 = gl_TessCoord.y;
    float w2 = gl_TessCoord.z;
    uint pi = chunk.patch_base + uint(gl_PrimitiveID);
    uvec4 c = qas[pi].corners;
    float b[6] = float[6](w0 * w0, w1 * w1, w2 * w2, 2.0 * w0 * w1, 2.0 * w1 * w2, 2.0 * w2 * w0);
    // d/dw1 and d/dw2 of the weights with w0 = 1 - w1 - w2.
    float d1[6] = float[6](-2.0 * w0, 2.0 * w1, 0.0, 2.0 * (w0 - w1), 2.0 * w2, -2.0 * w2);
    float d2[6] = float[6](-2.0 * w0, 0.0, 2.0 * w2, -2.0 * w1, 2.0 * w1, 2.0 * (w0 - w2));
    vec3 p = vec3(0.0);
    vec3 n = vec3(0.0);
    vec3 du = vec3(0.0);
    vec3 dv = vec3(0.0);
    for (int k = 0; k < 6; ++k) {
        vec3 c = qas[pi].p[k].xyz;
        p += b[k] * c;
        n += b[k] * qas[pi].n[k].xyz;
        du += d1[k] * c;
        dv += d2[k] * c;
    }
    vec3 nrm = normalize(n);
    bool fan = qas[pi].kind == QAS_FAN;
    int zeros = int(w0 == 0.0) + int(w1 == 0.0) + int(w2 == 0.0);
    if (zeros >= 2) {
        int k = (w0 != 0.0) ? 0 : (w1 != 0.0 ? 1 : 2);
        qas_corner(pi, k, p, nrm);
        w0 = float(k == 0);
        w1 = float(k == 1);
        w2 = float(k == 2);
    } else if (w2 == 0.0) {
        // Edge 0-1 (a fan's spoke centre - V_k: the centre is the larger id, weight t).
        vec2 ts = qas_edge(pi, 0, 3, 1, c.x, c.y, w1, p, nrm);
        if (fan) {
            w0 = ts.x;
            w1 = ts.y;
        }
    } else if (w0 == 0.0) {
        // Edge 1-2 (a fan's outer edge V_k V_{k+1}).
        vec2 ts = qas_edge(pi, 1, 4, 2, c.y, c.z, w2, p, nrm);
        if (fan) {
            w1 = c.y < c.z ? ts.y : ts.x;
            w2 = c.y < c.z ? ts.x : ts.y;
        }
    } else if (w1 == 0.0) {
        // Edge 2-0 (a fan's spoke V_{k+1} - centre).
        vec2 ts = qas_edge(pi, 2, 5, 0, c.z, c.x, w0, p, nrm);
        if (fan) {
            w0 = ts.x;
            w2 = ts.y;
        }
    }
    SurfaceTangents tg = uv_tangents(du, dv);
    if (!fan) {
        qas_emit(qas[pi].face, NO_SUB_FACE, vec2(w1, w2), tg, p, nrm, CLASS_TRIANGLE);
        return;
    }
    // The captured sub-face (u, v) of each half as a linear map of (w1, w2), w0 = 1 - w1 - w2
    // (columns: d(u, v)/dw1, d(u, v)/dw2).
    bool near_k = w1 >= w2;
    precise vec2 uv = near_k ? vec2(w0 + 2.0 * w2, w0) : vec2(w0, w0 + 2.0 * w1);
    uint sub = near_k ? qas[pi].sub : qas[pi].sub_next;
    tg.uv_jac = near_k ? mat2(-1.0, -1.0, 1.0, -1.0) : mat2(-1.0, 1.0, -1.0, -1.0);
    qas_emit(qas[pi].face, sub, min(uv, vec2(1.0)), tg, p, nrm, CLASS_TRIANGLE);
}
