#version 450
// Pm-patches, vertex-stage variant: ordinary facet: the 16 bicubic points assembled from
// the corners' per-vertex data (pm_vs_assembly.glsl); levels and culling as the stencil variant.
#include "frame.glsl"
#include "tess_factors.glsl"
#include "pm/pm.glsl"
#include "pm/pm_levels.glsl"
#include "pm_vs.glsl"
#include "pm_vs_assembly.glsl"

#define PM_POINTS 16
#define PM_SET_LEVELS(rec) pm_bicubic_levels(rec)
#define PM_COEFFICIENT(rec, k) pmvs_bicubic(rec, k)
#include "pm/pm_tcs.glsl"
