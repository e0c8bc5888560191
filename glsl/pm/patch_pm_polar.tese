#version 450
// Polar Pm facet: the singular bicubic (row 3 the pole) on the triangle domain with corners
// (facet corner pole + 1, pole + 2, pole) at barycentric gl_TessCoord = (w0, w1, w2), at the
// patch's (u, v) = (w1 / (w0 + w1), w2); the pole is a corner (shared vertex frame). Captured
// (u, v): the barycentric weights of face corners 1 and 2. Defines: SPACING, CAPTURE.
#include "pm_tes.glsl"

layout(triangles, SPACING, cw) in;

void main() {
    vec3 w = gl_TessCoord;
    uint rec = pm_record(chunk.patch_base + uint(gl_PrimitiveID));
    float u = (w.x + w.y > 0.0) ? w.y / (w.x + w.y) : 0.0;
    float v = w.z;
    vec4 bu, dbu, bv, dbv;
    bernstein3(u, 1.0 - u, bu, dbu);
    bernstein3(v, 1.0 - v, bv, dbv);
    vec3 p = vec3(0.0);
    vec3 du = vec3(0.0);
    vec3 dv = vec3(0.0);
    for (int j = 0; j < 4; ++j) {
        for (int i = 0; i < 4; ++i) {
            vec3 c = g_cp[4 * j + i];
            p += (bu[i] * bv[j]) * c;
            du += (dbu[i] * bv[j]) * c;
            dv += (bu[i] * dbv[j]) * c;
        }
    }
    vec3 nrm = pm_normal(du, dv);
    p += pm_origin(rec);
    int zeros = int(w.x == 0.0) + int(w.y == 0.0) + int(w.z == 0.0);
    if (zeros >= 2) {
        uint k = (w.x != 0.0) ? 0u : (w.y != 0.0 ? 1u : 2u);
        shared_corner(pm_words[rec + 4u + k], pm_words[rec], p, nrm);
    } else if (w.z == 0.0) {
        pm_domain_edge(rec, 0u, w.y, true, p, nrm);
    } else if (w.x == 0.0) {
        pm_domain_edge(rec, 1u, w.z, true, p, nrm);
    } else if (w.y == 0.0) {
        pm_domain_edge(rec, 2u, w.x, true, p, nrm);
    }
    // Face-corner weights: domain corners are facet corners pole + 1, pole + 2, pole.
    uint pole = pm_words[rec + 1u] >> 24;
    float fw[3];
    fw[(pole + 1u) % 3u] = w.x;
    fw[(pole + 2u) % 3u] = w.y;
    fw[pole] = w.z;
    // Their derivatives by the patch's (u, v): w = ((1 - u)(1 - v), u (1 - v), v).
    vec3 fu, fv;
    fu[(pole + 1u) % 3u] = -(1.0 - v);
    fu[(pole + 2u) % 3u] = 1.0 - v;
    fu[pole] = 0.0;
    fv[(pole + 1u) % 3u] = -(1.0 - u);
    fv[(pole + 2u) % 3u] = -u;
    fv[pole] = 1.0;
    SurfaceTangents tg = SurfaceTangents(du, dv, mat2(fu.y, fu.z, fv.y, fv.z));
    pm_emit(rec, PM_NO_SUB_FACE, vec2(fw[1], fw[2]), vec3(0.0), tg, p, nrm);
}
