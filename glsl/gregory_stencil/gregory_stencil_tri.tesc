#version 450
// Triangular Gregory patch, stencil variant (paper §4.3): 15 control points from the face's one-ring.
#define GREGORY_TRI
#include "frame.glsl"
#include "tess_factors.glsl"
#include "gregory/gregory.glsl"
#include "gregory_stencil.glsl"
