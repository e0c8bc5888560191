#version 450
// Single-crease patch of the adaptive scheme (any level, no finer neighbour; Nießner, Loop,
// Greiner 2012): the Bezier sets of single_crease_tcs.glsl for the sharpness of its record,
// levels by patch level (adaptive_patch_tcs.glsl).
#include "frame.glsl"
#include "adaptive.glsl"
#include "adaptive_levels.glsl"
#include "single_crease/single_crease_tcs.glsl"

#define PATCH_CONTROL_POINTS(info) single_crease_control_points(crease_sharpness[info.pad0])
#include "adaptive_patch_tcs.glsl"
