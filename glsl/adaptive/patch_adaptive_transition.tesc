#version 450
// Transition triangle of a B-spline patch: control points by bspline_tcs.glsl, levels by
// transition_tcs.glsl.
#include "frame.glsl"
#include "adaptive.glsl"
#include "adaptive_levels.glsl"
#include "adaptive_bspline.glsl"
#include "transition.glsl"
#include "bspline/bspline_tcs.glsl"

#define PATCH_CONTROL_POINTS(info) bspline_control_points(info.flags)
#include "transition_tcs.glsl"
