#version 450
// Vertex points (Köbler 2013, section 4.3): the parent rule with weight w blended with the child
// rule (1 - w), each smooth/dart, crease or corner; the masks of `subdiv::rules::VertexMask`.
// Record: dst, src, edge_count, face_count, offset (ring: edge neighbours then face points),
// rules (rule0 | rule1 << 8; 0 smooth, 1 crease, 2 corner), w, crease0, crease1 (ring positions).
#include "refine.glsl"

// Mask weights: the vertex, each ring edge neighbour, each ring face point, each crease neighbour.
struct Mask {
    float v;
    float e;
    float f;
    float c;
};

void add_rule(inout Mask m, uint rule, float w, uint ne, uint nf, bool has_crease) {
    if (rule == 1u && !has_crease) {
        rule = 2u;
    }
    if (rule == 0u) {
        if (ne < 2u || nf == 0u) {
            m.v += w;
            return;
        }
        float n = float(ne);
        float inv = 1.0 / (n * n);
        float scale = ne == nf ? w : w / ((n - 2.0) / n + inv * float(ne + nf));
        m.v += scale * (n - 2.0) / n;
        m.e += scale * inv;
        m.f += scale * inv;
    } else if (rule == 1u) {
        m.v += 0.75 * w;
        m.c += 0.125 * w;
    } else {
        m.v += w;
    }
}

void main() {
    uint r = record(9u);
    if (r == NO_POINT) {
        return;
    }
    uint ne = tables[r + 2u];
    uint nf = tables[r + 3u];
    uint ring = tables[r + 4u];
    uint rules = tables[r + 5u];
    float w = uintBitsToFloat(tables[r + 6u]);
    uint c0 = tables[r + 7u];
    uint c1 = tables[r + 8u];
    bool has_crease = c0 != NO_POINT;
    Mask m = Mask(0.0, 0.0, 0.0, 0.0);
    add_rule(m, rules & 0xffu, w, ne, nf, has_crease);
    if (w < 1.0) {
        add_rule(m, rules >> 8u, 1.0 - w, ne, nf, has_crease);
    }
    vec3 p = m.v * load(tables[r + 1u]);
    if (m.e != 0.0) {
        vec3 edges = vec3(0.0);
        for (uint k = 0u; k < ne; ++k) {
            edges += load(tables[ring + k]);
        }
        vec3 faces = vec3(0.0);
        for (uint k = 0u; k < nf; ++k) {
            faces += load(tables[ring + ne + k]);
        }
        p += m.e * edges + m.f * faces;
    }
    if (m.c != 0.0) {
        p += m.c * (load(tables[ring + c0]) + load(tables[ring + c1]));
    }
    store(tables[r], p);
}
