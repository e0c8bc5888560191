#version 450
// Transition triangle of a single-crease patch (transition_tes.glsl) with the surface and edges of
// single_crease_tes.glsl for the sharpness of its record, captured as `single-crease`.
// Defines: SPACING, CAPTURE.
#include "frame.glsl"
#include "adaptive.glsl"
#include "adaptive_bspline.glsl"
#include "transition.glsl"
#include "single_crease/single_crease_tes.glsl"

#define PATCH_SURFACE(info, u, v, p, nrm, du, dv) \
    single_crease_surface(crease_sharpness[info.pad0], u, v, p, nrm, du, dv)
#define PATCH_EDGE(info, e, x, p, nrm) \
    single_crease_edge_point(info.flags, crease_sharpness[info.pad0], e, x, p, nrm)
#define PATCH_EDGE_TS(info, e, t, s, p, nrm) \
    single_crease_edge_ts(info.flags, crease_sharpness[info.pad0], e, t, s, p, nrm)
#define FAN_KIND(ap) KIND_SINGLE_CREASE
#include "transition_tes.glsl"
