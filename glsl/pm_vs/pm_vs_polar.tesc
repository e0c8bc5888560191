#version 450
// Pm-patches, vertex-stage variant: polar facet: the singular bicubic (16 points, row 3 the pole) assembled from
// the corners' per-vertex data (pm_vs_assembly.glsl); levels and culling as the stencil variant.
#include "frame.glsl"
#include "tess_factors.glsl"
#include "pm/pm.glsl"
#include "pm/pm_levels.glsl"
#include "pm_vs.glsl"
#include "pm_vs_assembly.glsl"

#define PM_POINTS 16
#define PM_SET_LEVELS(rec) pm_polar_levels(rec)
#define PM_COEFFICIENT(rec, k) pmvs_polar(rec, k)
#include "pm/pm_tcs.glsl"
