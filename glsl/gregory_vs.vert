#version 450
// Two-stage Gregory construction, stage 1 (§4.1): per control vertex, from its one-ring in the
// connectivity buffer and the dynamic positions buffer, the limit position p (§3.2), the edge
// points e_j = p + 2/3 lambda q_j (§3.3) and the transversal vectors r_j (§3.4), one per ring
// edge. Packed into the varyings as documented in common/gregory_vs.glsl. Vertices of larger
// valence than GVS_MAX_VALENCE are never drawn by this variant (the host falls back).
#include "common/gregory.glsl"
#include "common/gregory_vs.glsl"

layout(location = 0) out vec4 v_data[GVS_SLOTS];

void put(int f, float x) {
    v_data[1 + f / 4][f % 4] = x;
}

void put3(int f, vec3 x) {
    put(f, x.x);
    put(f + 1, x.y);
    put(f + 2, x.z);
}

void main() {
    uint v = uint(gl_VertexIndex);
    uint off = conn[2u * v];
    int n = min(int(conn[2u * v + 1u]), GVS_MAX_VALENCE);
    vec3 pv = control_point(v);
    vec3 m[GVS_MAX_VALENCE];
    vec3 c[GVS_MAX_VALENCE];
    vec3 sum = vec3(0.0);
    for (int i = 0; i < n; ++i) {
        uint rec = off + 2u * uint(i);
        m[i] = 0.5 * (pv + control_point(conn[rec]));
        uint fr = conn[rec + 1u];
        uint size = conn[fr];
        vec3 acc = vec3(0.0);
        for (uint k = 0u; k < size; ++k) {
            acc += control_point(conn[fr + 1u + k]);
        }
        c[i] = acc / float(size);
        sum += m[i] + c[i];
    }
    float nf = float(n);
    vec3 p = (nf - 3.0) / (nf + 5.0) * pv + 4.0 / (nf * (nf + 5.0)) * sum;
    float cos_pi_n = cos(GVS_PI / nf);
    float sigma = inversesqrt(4.0 + cos_pi_n * cos_pi_n);
    float c2 = cos(2.0 * GVS_PI / nf);
    float lambda = (5.0 + c2 + cos_pi_n * sqrt(18.0 + 2.0 * c2)) / 16.0;
    for (int j = 0; j < n; ++j) {
        vec3 q = vec3(0.0);
        for (int i = 0; i < n; ++i) {
            float k = float((i + n - j) % n);
            float wm = (1.0 - sigma * cos_pi_n) * cos(2.0 * GVS_PI * k / nf);
            float wc = 2.0 * sigma * cos((2.0 * GVS_PI * k + GVS_PI) / nf);
            q += wm * m[i] + wc * c[i];
        }
        q *= 2.0 / nf;
        put3(6 * j, p + (2.0 / 3.0) * lambda * q);
        int nx = (j + 1) % n;
        int pr = (j + n - 1) % n;
        put3(6 * j + 3, (m[nx] - m[pr]) * (1.0 / 3.0) + (2.0 / 3.0) * (c[j] - c[pr]));
    }
    v_data[0] = vec4(p, nf);
}
