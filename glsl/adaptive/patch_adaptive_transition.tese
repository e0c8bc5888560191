#version 450
// Transition triangle of a B-spline patch (transition_tes.glsl), captured as `transition`.
// Defines: SPACING, CAPTURE.
#include "frame.glsl"
#include "adaptive.glsl"
#include "adaptive_bspline.glsl"
#include "transition.glsl"
#include "bspline/bspline_tes.glsl"

#define PATCH_SURFACE(info, u, v, p, nrm, du, dv) bspline_surface(u, v, p, nrm, du, dv)
#define PATCH_EDGE(info, e, x, p, nrm) edge_point(info.flags, e, x, p, nrm)
#define PATCH_EDGE_TS(info, e, t, s, p, nrm) edge_point_ts(info.flags, e, t, s, p, nrm)
#define FAN_KIND(ap) KIND_TRANSITION
#include "transition_tes.glsl"
