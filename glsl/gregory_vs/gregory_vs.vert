#version 450
// Two-stage Gregory construction, stage 1 (§4.1): per control vertex, from its one-ring in the
// connectivity buffer and the dynamic positions buffer, the limit position p (§3.2), one edge
// point per ring edge (§3.3) and the transversal vectors r (§3.4); at boundary, crease and
// corner vertices the sector-wise rules of §4.6 (as patch::gregory::GregoryVertex::sectored).
// Edge tangents 2/3 s lambda q and transversal vectors rho r with the factors s, rho the table
// stores per smooth vertex; crease sectors' cross-boundary tangents T/3 times the factor s(k) it
// stores per face of a crease vertex.
// Points relative to the vertex's control position (corner frames, gregory/gregory.glsl).
// Packed into the varyings as documented in gregory_vs/gregory_vs.glsl. Vertices beyond the
// varyings budget are never drawn by this variant (the host falls back).
#include "gregory/gregory.glsl"
#include "gregory_vs.glsl"

layout(location = 0) out vec4 v_data[GVS_SLOTS];

#define MAXE GVS_MAX_VALENCE

void put(int f, float x) {
    v_data[1 + f / 4][f % 4] = x;
}

void put3(int f, vec3 x) {
    put(f, x.x);
    put(f + 1, x.y);
    put(f + 2, x.z);
}

vec3 m[MAXE];
vec3 c[MAXE];
vec3 e[MAXE];
vec3 rp[MAXE];
vec3 rm[MAXE];
bool sharp[MAXE];

/// Cross-boundary tangent T of a crease sector with k faces from edge s (the sine mode of the
/// sector's subdivision matrix; weights as patch::gregory::crease_tangent_weights).
vec3 crease_tangent(vec3 v, int s, int k, int ne) {
    float th = GVS_PI / float(k);
    float cth = cos(th);
    float x = (4.0 * (1.0 + cth) + sqrt(16.0 * (1.0 + cth) * (1.0 + cth) + 128.0 * (1.0 + cth))) / 64.0;
    float mu = 0.25 + x;
    float bb = 1.0 / (16.0 * x);
    float sum_s = 1.0 / tan(0.5 * th);
    float gamma = (sin(th) * (1.0 / 16.0 + bb / 4.0) - (1.0 + 2.0 * bb) * sum_s / 8.0) / x;
    float scale = 8.0 * mu / (3.0 * float(k));
    vec3 t = vec3(0.0);
    float wsum = 0.0;
    for (int i = 0; i <= k; ++i) {
        float a = (i == 0 || i == k) ? scale * gamma : scale * sin(float(i) * th);
        float bp = i > 0 ? scale * bb * (sin(float(i - 1) * th) + sin(float(i) * th)) : 0.0;
        float bn = i < k ? scale * bb * (sin(float(i) * th) + sin(float(i + 1) * th)) : 0.0;
        float wm = 2.0 * (a - bp - bn);
        t += wm * m[(s + i) % ne];
        wsum += wm;
        if (i < k) {
            float wc = 4.0 * bn;
            t += wc * c[(s + i) % ne];
            wsum += wc;
        }
    }
    return t - wsum * v;
}

void main() {
    uint v = uint(gl_VertexIndex);
    uint off = conn[4u * v];
    int ne = min(int(conn[4u * v + 1u]), MAXE);
    int nf = min(int(conn[4u * v + 2u]), ne);
    uint kind = conn[4u * v + 3u];
    // Everything relative to the vertex's control position (the origin of its corner's points,
    // gregory/gregory.glsl): the ring differences keep their digits far from the coordinate
    // origin.
    vec3 origin = control_point(v);
    vec3 pv = vec3(0.0);
    for (int j = 0; j < ne; ++j) {
        m[j] = 0.5 * (control_point(conn[off + uint(j)]) - origin);
    }
    uint fo = off + uint(ne + nf);
    for (int i = 0; i < nf; ++i) {
        uint size = conn[fo];
        vec3 acc = (control_point(conn[off + uint(i)]) - origin)
                 + (control_point(conn[off + uint((i + 1) % ne)]) - origin);
        for (uint s = 0u; s + 3u < size; ++s) {
            acc += control_point(conn[fo + 1u + s]) - origin;
        }
        c[i] = acc / float(size);
        fo += size - 2u;
    }
    if (kind != GVS_KIND_CREASE && kind != GVS_KIND_CORNER) {
        // Smooth interior vertex (§3.2-3.4).
        int n = nf;
        float nf_ = float(n);
        vec3 sum = vec3(0.0);
        for (int i = 0; i < n; ++i) {
            sum += m[i] + c[i];
        }
        vec3 p = (nf_ - 3.0) / (nf_ + 5.0) * pv + 4.0 / (nf_ * (nf_ + 5.0)) * sum;
        float cos_pi_n = cos(GVS_PI / nf_);
        float sigma = inversesqrt(4.0 + cos_pi_n * cos_pi_n);
        float c2 = cos(2.0 * GVS_PI / nf_);
        float lambda = (5.0 + c2 + cos_pi_n * sqrt(18.0 + 2.0 * c2)) / 16.0;
        // The edge-tangent factor s(n) after the face records (GregoryTangents::scale; 1.0 for
        // the paper's construction, which leaves lambda's bits unchanged).
        lambda *= uintBitsToFloat(conn[fo]);
        // The transversal factor rho (patch::gregory::tangents_tri; 1.0 leaves r's bits).
        float rho = uintBitsToFloat(conn[fo + 1u]);
        for (int j = 0; j < n; ++j) {
            vec3 q = vec3(0.0);
            for (int i = 0; i < n; ++i) {
                float k = float((i + n - j) % n);
                float wm = (1.0 - sigma * cos_pi_n) * cos(2.0 * GVS_PI * k / nf_);
                float wc = 2.0 * sigma * cos((2.0 * GVS_PI * k + GVS_PI) / nf_);
                q += wm * m[i] + wc * c[i];
            }
            q *= 2.0 / nf_;
            put3(6 * j, p + (2.0 / 3.0) * lambda * q);
            int nx = (j + 1) % n;
            int pr = (j + n - 1) % n;
            put3(6 * j + 3, rho * ((m[nx] - m[pr]) * (1.0 / 3.0) + (2.0 / 3.0) * (c[j] - c[pr])));
        }
        v_data[0] = vec4(p, nf_);
        return;
    }
    // Boundary / crease / corner vertex (§4.6), sector by sector.
    for (int j = 0; j < ne; ++j) {
        sharp[j] = false;
    }
    for (int i = 0; i < nf; ++i) {
        uint w = conn[off + uint(ne + i)];
        int s = int(w & 0xffffu);
        int k = int(w >> 16);
        sharp[s % ne] = true;
        sharp[(s + k) % ne] = true;
    }
    vec3 p = pv;
    if (kind == GVS_KIND_CREASE) {
        vec3 acc = pv;
        for (int j = 0; j < ne; ++j) {
            if (sharp[j]) {
                acc += m[j];
            }
        }
        p = acc / 3.0;
    }
    for (int j = 0; j < ne; ++j) {
        e[j] = sharp[j] ? (pv + 2.0 * m[j]) / 3.0 : p;
    }
    for (int i = 0; i < nf; ++i) {
        uint w = conn[off + uint(ne + i)];
        int s = int(w & 0xffffu);
        int k = int(w >> 16);
        if (s != i) {
            continue; // not the first face of its sector
        }
        int t = (s + k) % ne;
        float alpha;
        vec3 second;
        vec3 ds = e[s] - p;
        if (kind == GVS_KIND_CORNER) {
            alpha = GVS_PI / (2.0 * float(k));
            second = e[t] - p;
        } else {
            alpha = GVS_PI / float(k);
            // The sector's cross-boundary factor s(k) after the face records, one word per
            // face (GregoryTangents::crease_scale; 1.0 keeps the paper's bits).
            second = crease_tangent(pv, s, k, ne) / 3.0 * uintBitsToFloat(conn[fo + uint(s)]);
        }
        for (int q = 1; q < k; ++q) {
            float a = float(q) * alpha;
            e[(s + q) % ne] = p + cos(a) * ds + sin(a) * second;
        }
        for (int q = 1; q < k; ++q) {
            int eq = (s + q) % ne;
            vec3 r = (m[(s + q + 1) % ne] - m[(s + q - 1) % ne]) * (1.0 / 3.0)
                   + (2.0 / 3.0) * (c[eq] - c[(s + q - 1) % ne]);
            rm[(s + q - 1) % ne] = -r;
            rp[eq] = r;
        }
        rp[s] = (2.0 / 3.0) * (m[(s + 1) % ne] - pv) + (4.0 / 3.0) * (c[s] - m[s]);
        int last = (s + k - 1) % ne;
        rm[last] = (2.0 / 3.0) * (m[(s + k - 1) % ne] - pv) + (4.0 / 3.0) * (c[last] - m[t]);
    }
    for (int j = 0; j < ne; ++j) {
        put3(9 * j, e[j]);
        if (j < nf) {
            put3(9 * j + 3, rp[j]);
            put3(9 * j + 6, rm[j]);
        }
    }
    // One-sided face points beside sharp edges (GregoryVertex::one_sided): the word after the
    // crease words, passed to the TCS as the sign of slot 0's w.
    uint one_sided = conn[kind == GVS_KIND_CREASE ? fo + uint(nf) : fo];
    v_data[0] = vec4(p, one_sided != 0u ? -float(nf) : float(nf));
}
