#version 450
// Pm-patches, vertex-stage variant, stage 1 (paper §5.1, Fig. 9): per control vertex p of
// valence n, from its one-ring in the connectivity buffer and the dynamic control positions, the
// face points f_j (eq. 13 generalised by the crease scalars of eq. 14), the vertex point
// v = sum_j (9 f_j + (n - 4) p) / (n (n + 5)) and the tangent vectors
// t_1 = kappa_n sum_j cos(2 pi j / n) e_j, t_2 likewise with sin, e_j = (f_j + f_{j-1}) / 2
// (eq. 15), as patch::pm::pm_vertex; all relative to p (layout: pm_vs.glsl).
#include "control_points.glsl"
#include "pm_vs.glsl"

layout(location = 0) out vec4 v_data[PMVS_SLOTS];

void put3(int f, vec3 x) {
    for (int i = 0; i < 3; ++i) {
        v_data[(f + i) / 4][(f + i) % 4] = x[i];
    }
}

void main() {
    uint v = uint(gl_VertexIndex);
    uint off = pmvs_conn[4u * v];
    int n = min(int(pmvs_conn[4u * v + 1u]), PMVS_MAX_VALENCE);
    float kappa = uintBitsToFloat(pmvs_conn[4u * v + 2u]);
    vec3 p = control_point(v);
    for (int s = 0; s < PMVS_SLOTS; ++s) {
        v_data[s] = vec4(0.0);
    }
    vec3 sum_f = vec3(0.0);
    vec3 t1 = vec3(0.0);
    vec3 t2 = vec3(0.0);
    for (int j = 0; j < n; ++j) {
        uint w = off + 4u * uint(j);
        uint w1 = off + 4u * uint((j + 1) % n);
        vec3 pa = control_point(pmvs_conn[w]) - p;
        vec3 pb = control_point(pmvs_conn[w1]) - p;
        // p̄_j: the mean of the facet's vertices other than p and the spoke ends, or of the
        // two spoke ends for a triangle.
        uint far_first = pmvs_conn[w + 1u];
        uint far_count = pmvs_conn[w + 2u];
        vec3 pbar = 0.5 * (pa + pb);
        if (far_count > 0u) {
            pbar = vec3(0.0);
            for (uint i = 0u; i < far_count; ++i) {
                pbar += control_point(pmvs_conn[far_first + i]) - p;
            }
            pbar /= float(far_count);
        }
        float aj = uintBitsToFloat(pmvs_conn[w + 3u]);
        float aj1 = uintBitsToFloat(pmvs_conn[w1 + 3u]);
        // Eq. (14) relative to p (the weights sum to 1, so p's own term drops out).
        float wa = (1.0 - aj) * aj1 / 2.0;
        float wb = aj * (1.0 - aj1) / 2.0;
        float wq = aj * aj1 / 4.0;
        vec3 f = (wa + wq) * pa + (wb + wq) * pb + wq * pbar;
        put3(10 + 3 * j, f);
        sum_f += f;
        // e_j = (f_j + f_{j-1}) / 2, so sum_j c_j e_j = sum_j f_j (c_j + c_{j+1}) / 2.
        t1 += (kappa * (pmvs_cos(j, n) + pmvs_cos(j + 1, n)) / 2.0) * f;
        t2 += (kappa * (pmvs_sin(j, n) + pmvs_sin(j + 1, n)) / 2.0) * f;
    }
    float nf = float(max(n, 1));
    put3(4, t1);
    put3(7, t2);
    v_data[0] = vec4((9.0 / (nf * (nf + 5.0))) * sum_f, float(n));
}
