#version 450
// Ordinary Pm facet: the 16 bicubic Bézier points from their stencil rows; levels from the
// facet's corner vertices (common/tess_factors.glsl).
#include "frame.glsl"
#include "tess_factors.glsl"
#include "pm.glsl"

#define PM_POINTS 16
#define PM_SET_LEVELS(rec) set_quad_tess_levels(uvec4(pm_words[rec + 4u], pm_words[rec + 5u], \
                                                      pm_words[rec + 6u], pm_words[rec + 7u]))
#include "pm_tcs.glsl"
