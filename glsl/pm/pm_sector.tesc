#version 450
// One quartic sector of a Pm-patch: its 15 coefficients from their stencil rows, on the
// triangle domain (corners v^i, v^{i+1}, centre; levels: pm_levels.glsl).
#include "frame.glsl"
#include "tess_factors.glsl"
#include "pm.glsl"
#include "pm_levels.glsl"

#define PM_POINTS 15
#define PM_SET_LEVELS(rec) pm_sector_levels(rec)
#include "pm_tcs.glsl"
