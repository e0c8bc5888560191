#version 450
// Triangular Gregory patch, stencil variant (paper §4.3): 15 control points from the face's one-ring.
#define GREGORY_TRI
#include "common/frame.glsl"
#include "common/tess_factors.glsl"
#include "common/gregory.glsl"
#include "common/gregory_stencil.glsl"
