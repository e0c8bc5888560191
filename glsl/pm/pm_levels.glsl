// Tessellation levels of the Pm patch types, shared by the stencil (pm_*.tesc) and vertex-stage
// (pm_vs_*.tesc) variants: a bicubic's from its four corner vertices; a polar patch's from its
// three (gl_TessCoord[i] is the weight of domain corner i, so outer[0] is edge 1-2, [1] edge 2-0,
// [2] edge 0-1); a sector's [2] from the facet edge's corner vertices, [0] and [1] from the spokes
// from v^{i+1} and v^i to the centre (tess_factors.glsl's spoke_tess_level: the chord from the
// corner's limit point to the centre, which both sectors of a spoke compute alike). Needs frame.glsl,
// tess_factors.glsl and pm.glsl first.
#ifndef TESSERA_PM_LEVELS_GLSL
#define TESSERA_PM_LEVELS_GLSL

void pm_bicubic_levels(uint rec) {
    set_quad_tess_levels(uvec4(pm_words[rec + 4u], pm_words[rec + 5u], pm_words[rec + 6u],
                               pm_words[rec + 7u]));
}

/// Triangle-domain levels from the three outer ones, the inner their largest.
void pm_tri_levels(float o0, float o1, float o2) {
    gl_TessLevelOuter[0] = o0;
    gl_TessLevelOuter[1] = o1;
    gl_TessLevelOuter[2] = o2;
    gl_TessLevelInner[0] = max(o0, max(o1, o2));
}

void pm_polar_levels(uint rec) {
    uint c0 = pm_words[rec + 4u];
    uint c1 = pm_words[rec + 5u];
    uint c2 = pm_words[rec + 6u];
    pm_tri_levels(edge_tess_level(c1, c2), edge_tess_level(c2, c0), edge_tess_level(c0, c1));
}

void pm_sector_levels(uint rec) {
    uint c0 = pm_words[rec + 4u];
    uint c1 = pm_words[rec + 5u];
    vec3 n_unused;
    vec3 centre;
    pm_centre(pm_words[rec + 3u], centre, n_unused);
    pm_tri_levels(spoke_tess_level(c1, centre), spoke_tess_level(c0, centre), edge_tess_level(c0, c1));
}

#endif
