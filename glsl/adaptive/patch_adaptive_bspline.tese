#version 450
// B-spline patch of the adaptive scheme: as bspline/patch_bspline.tese, with the adaptive edges
// and capture of adaptive_patch_tes.glsl.
// Defines: SPACING, CAPTURE.
#include "frame.glsl"
#include "adaptive.glsl"
#include "adaptive_bspline.glsl"
#include "bspline/bspline_tes.glsl"

#define PATCH_SURFACE(info, u, v, p, nrm, du, dv) bspline_surface(u, v, p, nrm, du, dv)
#define PATCH_EDGE(info, e, x, p, nrm) edge_point(info.flags, e, x, p, nrm)
#include "adaptive_patch_tes.glsl"
