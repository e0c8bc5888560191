#version 450
// Limit frames of the adaptive scheme's patch corners: per slot s, rows first + 3s .. + 2 are the
// limit position and two tangents (stencil_rows.glsl); writes vertex_limit[s] (out_a) and
// vertex_normal[s] (out_b): normalize(du x dv) where the vertex has one sector (flags[s] bit 0),
// zero otherwise (each patch keeps its own normal there, common/watertight.glsl).
#include "stencil_rows.glsl"

void main() {
    uint s = item();
    if (s == NO_ROW) {
        return;
    }
    uint r = range.first + 3u * s;
    vec3 p = row_sum(r);
    vec3 du = row_sum(r + 1u);
    vec3 dv = row_sum(r + 2u);
    vec3 n = cross(du, dv);
    float len = length(n);
    bool shared_normal = (flags[s] & 1u) != 0u && len > 0.0;
    out_a[s] = vec4(p, 1.0);
    out_b[s] = shared_normal ? vec4(n / len, 0.0) : vec4(0.0);
}
