#version 450
// Quad Gregory patch evaluation (gregory_quad_tes.glsl) for the Gregory schemes.
// Defines: SPACING (equal_spacing | fractional_odd_spacing | fractional_even_spacing), CAPTURE.
#include "frame.glsl"

#define GREGORY_CLASS(info) CLASS_IRREGULAR
#define GREGORY_DISPLACE(info, u, v, tg, p, n) \
    displace_point(info.face, NO_SUB_FACE, vec2(u, v), tg, p, n)
#define GREGORY_CAPTURE(info, u, v, p, n) capture_point(info.face, vec2(u, v), p, n)
#include "gregory_quad_tes.glsl"
