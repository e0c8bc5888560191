#version 450
// Two-stage Gregory construction, stage 2 (§4.2) for a triangle (15 control points).
#define NC 3
#define D_OWN 4.0
#include "gregory_vs_tcs.glsl"
