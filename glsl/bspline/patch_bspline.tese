#version 450
// Regular bicubic B-spline patch evaluation (bspline_tes.glsl): interior from the Bezier points,
// corners and edges by the shared watertight rules.
// Defines: SPACING (equal_spacing | fractional_odd_spacing | fractional_even_spacing), CAPTURE.
#include "frame.glsl"
#include "bspline_tes.glsl"
#ifdef CAPTURE
#include "capture.glsl"
#endif

#ifndef SPACING
#define SPACING equal_spacing
#endif

// Vulkan's default upper-left domain origin mirrors GL's: `cw` here gives triangles that are
// counter-clockwise in the (u right, v up) parameter plane, i.e. seen from outside.
layout(quads, SPACING, cw) in;
layout(location = 0) out vec3 t_world;
layout(location = 1) out vec3 t_normal;
layout(location = 2) flat out uint t_class;

void main() {
    // Face (u, v) of this domain point: sub-patch origin + local coordinate * size (exact, as
    // every term is dyadic, so neighbours across a face edge still get exactly 1 - x).
    vec3 sd = sub_domain();
    float u = sd.x + gl_TessCoord.x * sd.z;
    float v = sd.y + gl_TessCoord.y * sd.z;
    vec3 p;
    vec3 nrm;
    vec3 du, dv;
    bspline_surface(u, v, p, nrm, du, dv);

    PatchInfo info = patches[chunk.patch_base + uint(gl_PrimitiveID)];
    bool u_edge = (u == 0.0 || u == 1.0);
    bool v_edge = (v == 0.0 || v == 1.0);
    if (u_edge && v_edge) {
        quad_corner_point(info.corners, info.face, u, v, p, nrm);
    } else if (u_edge || v_edge) {
        edge_point(info.flags, bspline_edge(u, v), v_edge ? u : v, p, nrm);
    }

    displace_point(info.face, NO_SUB_FACE, vec2(u, v), uv_tangents(du, dv), p, nrm);
    t_world = p;
    t_normal = nrm;
    t_class = CLASS_REGULAR;
    gl_Position = frame.view_proj * vec4(p, 1.0);
#ifdef CAPTURE
    capture_point(info.face, vec2(u, v), p, nrm);
#endif
}
