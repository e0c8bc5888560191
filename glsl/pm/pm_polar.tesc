#version 450
// Polar Pm facet: the singular bicubic (16 points, row 3 the pole) from its stencil rows on the
// triangle domain (corners: facet corners pole + 1, pole + 2, pole). gl_TessCoord[i] is the
// weight of domain corner i, so outer[0] is edge 1-2, [1] edge 2-0, [2] edge 0-1.
#include "frame.glsl"
#include "tess_factors.glsl"
#include "pm.glsl"

void pm_polar_levels(uint rec) {
    uint c0 = pm_words[rec + 4u];
    uint c1 = pm_words[rec + 5u];
    uint c2 = pm_words[rec + 6u];
    float o0 = edge_tess_level(c1, c2);
    float o1 = edge_tess_level(c2, c0);
    float o2 = edge_tess_level(c0, c1);
    gl_TessLevelOuter[0] = o0;
    gl_TessLevelOuter[1] = o1;
    gl_TessLevelOuter[2] = o2;
    gl_TessLevelInner[0] = max(o0, max(o1, o2));
}

#define PM_POINTS 16
#define PM_SET_LEVELS(rec) pm_polar_levels(rec)
#include "pm_tcs.glsl"
