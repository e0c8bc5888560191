#version 450
// Single-crease patch of the adaptive scheme (rotated: crease along u = 1, its record in the same
// frame): as single_crease/single_crease.tese, with the adaptive edges and capture of
// adaptive_patch_tes.glsl and the sharpness of its record.
// Defines: SPACING, CAPTURE.
#include "frame.glsl"
#include "adaptive.glsl"
#include "adaptive_bspline.glsl"
#include "single_crease/single_crease_tes.glsl"

#define PATCH_SURFACE(info, u, v, p, nrm, du, dv) \
    single_crease_surface(crease_sharpness[info.pad0], u, v, p, nrm, du, dv)
#define PATCH_EDGE(info, e, x, p, nrm) \
    single_crease_edge_point(info.flags, crease_sharpness[info.pad0], e, x, p, nrm)
#include "adaptive_patch_tes.glsl"
