#version 450
// One quartic sector of a Pm-patch: its 15 coefficients from their stencil rows, on the
// triangle domain (corners v^i, v^{i+1}, centre). Outer levels: [2] the facet edge (its corner
// vertices), [0] and [1] the spokes from v^{i+1} and v^i to the centre (in screen-space mode the
// chord from the corner's limit point to the centre, which both sectors of a spoke compute
// alike).
#include "frame.glsl"
#include "tess_factors.glsl"
#include "pm.glsl"

float pm_spoke_level(uint corner, vec3 centre) {
    if (frame.tess.y != TESS_MODE_ADAPTIVE) {
        return edge_tess_level(corner, corner);
    }
    float len = length(to_pixels(centre) - to_pixels(vertex_limit[corner].xyz));
    return clamp(len / max(frame.tess.z, 1e-3), 1.0, frame.tess.w);
}

void pm_sector_levels(uint rec) {
    uint c0 = pm_words[rec + 4u];
    uint c1 = pm_words[rec + 5u];
    vec3 n_unused;
    vec3 centre;
    pm_centre(pm_words[rec + 3u], centre, n_unused);
    float o0 = pm_spoke_level(c1, centre);
    float o1 = pm_spoke_level(c0, centre);
    float o2 = edge_tess_level(c0, c1);
    gl_TessLevelOuter[0] = o0;
    gl_TessLevelOuter[1] = o1;
    gl_TessLevelOuter[2] = o2;
    gl_TessLevelInner[0] = max(o0, max(o1, o2));
}

#define PM_POINTS 15
#define PM_SET_LEVELS(rec) pm_sector_levels(rec)
#include "pm_tcs.glsl"
