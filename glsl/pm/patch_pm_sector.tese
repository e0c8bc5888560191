#version 450
// One quartic sector of a Pm-patch on the triangle domain with corners (v^i, v^{i+1}, centre)
// at barycentric gl_TessCoord = (a, b, c); coefficients g_cp[quartic_index] (row c = 0 first,
// b along each row: src/patch/pm/construct.rs). Corners: the shared vertex frames and the
// centre record; edges: the facet edge and both spokes from their edge records (pm.glsl).
// Captured as sub-face i with (u, v) = (b, c). Defines: SPACING, CAPTURE.
#include "pm_tes.glsl"

layout(triangles, SPACING, cw) in;

const int ROW_START[5] = int[5](0, 5, 9, 12, 14);
const float FACT[5] = float[5](1.0, 1.0, 2.0, 6.0, 24.0);

vec3 q(int a, int b) {
    return g_cp[ROW_START[4 - a - b] + b];
}

void main() {
    vec3 w = gl_TessCoord;
    float pa[5], pb[5], pc[5];
    pa[0] = 1.0;
    pb[0] = 1.0;
    pc[0] = 1.0;
    for (int k = 1; k < 5; ++k) {
        pa[k] = pa[k - 1] * w.x;
        pb[k] = pb[k - 1] * w.y;
        pc[k] = pc[k - 1] * w.z;
    }
    vec3 p = vec3(0.0);
    vec3 db = vec3(0.0);
    vec3 dc = vec3(0.0);
    for (int c = 0; c <= 4; ++c) {
        for (int b = 0; b <= 4 - c; ++b) {
            int a = 4 - b - c;
            p += (24.0 / (FACT[a] * FACT[b] * FACT[c]) * pa[a] * pb[b] * pc[c]) * q(a, b);
        }
    }
    // d/db and d/dc with a = 1 - b - c: 4 sum B3_ijk (Q_{i,j+1,k} - Q_{i+1,j,k}), and with k + 1.
    for (int k = 0; k <= 3; ++k) {
        for (int j = 0; j <= 3 - k; ++j) {
            int i = 3 - j - k;
            float b3 = 24.0 / (FACT[i] * FACT[j] * FACT[k]) * pa[i] * pb[j] * pc[k];
            vec3 base = q(i + 1, j);
            db += b3 * (q(i, j + 1) - base);
            dc += b3 * (g_cp[ROW_START[k + 1] + j] - base);
        }
    }
    vec3 nrm = pm_normal(db, dc);
    uint rec = pm_record(chunk.patch_base + uint(gl_PrimitiveID));
    p += pm_origin(rec);
    int zeros = int(w.x == 0.0) + int(w.y == 0.0) + int(w.z == 0.0);
    if (zeros >= 2) {
        if (w.z != 0.0) {
            pm_centre(pm_words[rec + 3u], p, nrm);
        } else {
            shared_corner(pm_words[rec + 4u + (w.x != 0.0 ? 0u : 1u)], pm_words[rec], p, nrm);
        }
    } else if (w.z == 0.0) {
        pm_domain_edge(rec, 0u, w.y, true, p, nrm);
    } else if (w.x == 0.0) {
        pm_domain_edge(rec, 1u, w.z, true, p, nrm);
    } else if (w.y == 0.0) {
        pm_domain_edge(rec, 2u, w.x, true, p, nrm);
    }
    uint sector = (pm_words[rec + 1u] >> 8) & 0xffu;
    pm_emit(rec, sector, vec2(w.y, w.z), w, uv_tangents(db, dc), p, nrm);
}
