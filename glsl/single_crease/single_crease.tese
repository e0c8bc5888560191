#version 450
// Single-crease patch evaluation of the single-crease pass (single_crease_tes.glsl): surface,
// shared corners (vertex limit frames) and shared edges, capture in the face's own (u, v).
// Defines: SPACING (equal_spacing | fractional_odd_spacing | fractional_even_spacing), CAPTURE.
#include "frame.glsl"
#include "bspline.glsl"
#include "watertight.glsl"
#include "single_crease.glsl"
#ifdef CAPTURE
#include "capture.glsl"
#endif

#ifndef SPACING
#define SPACING equal_spacing
#endif

// As bspline/patch_bspline.tese: `cw` in Vulkan's upper-left domain is counter-clockwise in (u right, v up).
layout(quads, SPACING, cw) in;
layout(location = 0) out vec3 t_world;
layout(location = 1) out vec3 t_normal;
layout(location = 2) flat out uint t_class;

#include "single_crease_tes.glsl"

/// The face's own (u, v) of the rotated patch's (u, v): flags bits 8-9 (the crease side,
/// patch::single_crease::Rotation).
vec2 face_uv(uint flags, float u, float v) {
    uint rot = (flags >> 8) & 3u;
    return rot == 0u ? vec2(u, v) : (rot == 1u ? vec2(1.0 - u, 1.0 - v)
                                   : (rot == 2u ? vec2(1.0 - v, u) : vec2(v, 1.0 - u)));
}

/// d(face_uv)/d(u, v) (columns: by u, by v).
mat2 face_uv_jacobian(uint flags) {
    uint rot = (flags >> 8) & 3u;
    return rot == 0u ? mat2(1.0) : (rot == 1u ? mat2(-1.0)
                                  : (rot == 2u ? mat2(0.0, 1.0, -1.0, 0.0)
                                               : mat2(0.0, -1.0, 1.0, 0.0)));
}

void main() {
    vec3 sd = sub_domain();
    float u = sd.x + gl_TessCoord.x * sd.z;
    float v = sd.y + gl_TessCoord.y * sd.z;
    uint patch_index = chunk.patch_base + uint(gl_PrimitiveID);
    PatchInfo info = patches[patch_index];
    float sharpness = crease_sharpness[patch_index];
    vec3 p;
    vec3 nrm;
    vec3 du, dv;
    single_crease_surface(sharpness, u, v, p, nrm, du, dv);

    bool u_edge = (u == 0.0 || u == 1.0);
    bool v_edge = (v == 0.0 || v == 1.0);
    if (u_edge && v_edge) {
        quad_corner_point(info.corners, info.face, u, v, p, nrm);
    } else if (u_edge || v_edge) {
        single_crease_edge_point(info.flags, sharpness, bspline_edge(u, v), v_edge ? u : v, p, nrm);
    }

    SurfaceTangents tg = SurfaceTangents(du, dv, face_uv_jacobian(info.flags));
    displace_point(info.face, NO_SUB_FACE, face_uv(info.flags, u, v), tg, p, nrm);
    t_world = p;
    t_normal = nrm;
    t_class = CLASS_SINGLE_CREASE;
    gl_Position = frame.view_proj * vec4(p, 1.0);
#ifdef CAPTURE
    capture_point(info.face, face_uv(info.flags, u, v), p, nrm);
#endif
}
