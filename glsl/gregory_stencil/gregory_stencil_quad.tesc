#version 450
// Quad Gregory patch, stencil variant (paper §4.3): 20 control points from the face's one-ring.
#include "frame.glsl"
#include "tess_factors.glsl"
#include "gregory_stencil.glsl"
