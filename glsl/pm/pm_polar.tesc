#version 450
// Polar Pm facet: the singular bicubic (16 points, row 3 the pole) from its stencil rows on the
// triangle domain (corners: facet corners pole + 1, pole + 2, pole; levels: pm_levels.glsl).
#include "frame.glsl"
#include "tess_factors.glsl"
#include "pm.glsl"
#include "pm_levels.glsl"

#define PM_POINTS 16
#define PM_SET_LEVELS(rec) pm_polar_levels(rec)
#include "pm_tcs.glsl"
