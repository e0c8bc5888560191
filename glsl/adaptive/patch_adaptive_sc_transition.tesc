#version 450
// Transition triangle of a single-crease patch: the Bezier sets of single_crease_tcs.glsl for the
// sharpness of its record, levels by transition_tcs.glsl.
#include "frame.glsl"
#include "adaptive.glsl"
#include "adaptive_levels.glsl"
#include "adaptive_bspline.glsl"
#include "transition.glsl"
#include "single_crease/single_crease_tcs.glsl"

#define PATCH_CONTROL_POINTS(info) single_crease_control_points(crease_sharpness[info.pad0])
#include "transition_tcs.glsl"
