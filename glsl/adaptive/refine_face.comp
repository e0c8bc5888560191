#version 450
// Face points (Köbler 2013, section 4.3): the centroid of the parent face's vertices.
// Record: dst, offset, count.
#include "refine.glsl"

void main() {
    uint r = record(3u);
    if (r == NO_POINT) {
        return;
    }
    uint offset = tables[r + 1u];
    uint n = tables[r + 2u];
    vec3 sum = vec3(0.0);
    for (uint k = 0u; k < n; ++k) {
        sum += load(tables[offset + k]);
    }
    store(tables[r], sum / float(n));
}
