#version 450
// Edge points (Köbler 2013, section 4.3): s * midpoint + (1 - s) * (a + b + f0 + f1) / 4, with s the
// crease blend weight (1 on sharp and boundary edges, whose face points are not read).
// Record: dst, a, b, f0, f1, s.
#include "refine.glsl"

void main() {
    uint r = record(6u);
    if (r == NO_POINT) {
        return;
    }
    vec3 a = load(tables[r + 1u]);
    vec3 b = load(tables[r + 2u]);
    float s = uintBitsToFloat(tables[r + 5u]);
    vec3 p = 0.5 * (a + b);
    if (s < 1.0) {
        vec3 smooth_point = 0.25 * (a + b + load(tables[r + 3u]) + load(tables[r + 4u]));
        p = s * p + (1.0 - s) * smooth_point;
    }
    store(tables[r], p);
}
