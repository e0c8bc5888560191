#version 450
// Quad Gregory patch, stencil variant (paper §4.3): 20 control points from the face's one-ring.
#include "common/frame.glsl"
#include "common/tess_factors.glsl"
#include "common/gregory_stencil.glsl"
