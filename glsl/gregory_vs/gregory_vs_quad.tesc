#version 450
// Two-stage Gregory construction, stage 2 (§4.2) for a quad (20 control points).
#define NC 4
#define D_OWN 3.0
#include "gregory_vs_tcs.glsl"
