#version 450
// Ordinary Pm facet: the 16 bicubic Bézier points from their stencil rows; levels from the
// facet's corner vertices (pm_levels.glsl).
#include "frame.glsl"
#include "tess_factors.glsl"
#include "pm.glsl"
#include "pm_levels.glsl"

#define PM_POINTS 16
#define PM_SET_LEVELS(rec) pm_bicubic_levels(rec)
#include "pm_tcs.glsl"
