#version 450
// QAS triangle (glsl/qas/qas.glsl): the paper's quadratic triangles for position and normal;
// corners and edges by the shared watertight rules. gl_TessCoord = barycentric weights of face
// corners 0, 1, 2; the captured (u, v) are the weights of corners 1 and 2.
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
    int zeros = int(w0 == 0.0) + int(w1 == 0.0) + int(w2 == 0.0);
    if (zeros >= 2) {
        qas_corner(pi, (w0 != 0.0) ? 0 : (w1 != 0.0 ? 1 : 2), p, nrm);
    } else if (w2 == 0.0) {
        qas_edge(pi, 0, 3, 1, c.x, c.y, w1, p, nrm);
    } else if (w0 == 0.0) {
        qas_edge(pi, 1, 4, 2, c.y, c.z, w2, p, nrm);
    } else if (w1 == 0.0) {
        qas_edge(pi, 2, 5, 0, c.z, c.x, w0, p, nrm);
    }
    qas_emit(qas[pi].face, vec2(w1, w2), uv_tangents(du, dv), p, nrm, CLASS_TRIANGLE);
}
