#version 450
// Pm-patches, vertex-stage variant: one quartic sector of a Pm-patch: its 15 coefficients assembled from
// the corners' per-vertex data (pm_vs_assembly.glsl); levels and culling as the stencil variant.
#include "frame.glsl"
#include "tess_factors.glsl"
#include "pm/pm.glsl"
#include "pm/pm_levels.glsl"
#include "pm_vs.glsl"
#include "pm_vs_assembly.glsl"

#define PM_POINTS 15
#define PM_SET_LEVELS(rec) pm_sector_levels(rec)
#define PM_COEFFICIENT(rec, k) pmvs_sector(rec, k)
#include "pm/pm_tcs.glsl"
