#version 450
// B-spline patch of the adaptive scheme: as bspline/patch_bspline.tese, except that an edge lying
// on a one-level-coarser patch is evaluated from that patch's coarse-edge record, and points are
// captured in base-face parameters with kind and level.
// Defines: SPACING, CAPTURE.
#include "frame.glsl"
#include "adaptive.glsl"
#include "adaptive_bspline.glsl"
#include "bspline/bspline_tes.glsl"

#ifndef SPACING
#define SPACING equal_spacing
#endif

layout(quads, SPACING, cw) in;
layout(location = 0) out vec3 t_world;
layout(location = 1) out vec3 t_normal;
layout(location = 2) flat out uint t_class;

void main() {
    float u = gl_TessCoord.x;
    float v = gl_TessCoord.y;
    vec3 p;
    vec3 nrm;
    bspline_surface(u, v, p, nrm);

    PatchInfo info = patches[chunk.patch_base + uint(gl_PrimitiveID)];
    AdaptivePatch ap = apatches[info.pad0];
    bool u_edge = (u == 0.0 || u == 1.0);
    bool v_edge = (v == 0.0 || v == 1.0);
    if (u_edge && v_edge) {
        quad_corner_point(info.corners, u, v, p, nrm);
    } else if (u_edge || v_edge) {
        int e = bspline_edge(u, v);
        float x = v_edge ? u : v;
        if (ap.coarse[e] != NO_ENTRY) {
            ivec2 se = bspline_edge_corners(e);
            fine_edge_point(ap.coarse[e], info.corners[se.x], info.corners[se.y], x, p, nrm);
        } else {
            edge_point(info.flags, e, x, p, nrm);
        }
    }

    t_world = p;
    t_normal = nrm;
    t_class = adaptive_class(ap.kind, ap.level);
    gl_Position = frame.view_proj * vec4(p, 1.0);
#ifdef CAPTURE
    capture_adaptive(ap, ap.kind, vec2(u, v), p, nrm);
#endif
}
