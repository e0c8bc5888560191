#version 450
// B-spline patch of the adaptive scheme (any level, no finer neighbour): control points by
// bspline_tcs.glsl from the refined buffer, levels by patch level (adaptive_patch_tcs.glsl).
#include "frame.glsl"
#include "adaptive.glsl"
#include "adaptive_levels.glsl"
#include "bspline/bspline_tcs.glsl"

#define PATCH_CONTROL_POINTS(info) bspline_control_points(info.flags)
#include "adaptive_patch_tcs.glsl"
