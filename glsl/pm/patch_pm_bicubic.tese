#version 450
// Ordinary Pm facet: the bicubic Bézier patch at gl_TessCoord = (u, v) of the face (corner 0
// at (0, 0), 1 at (1, 0), 2 at (1, 1)); corners and edges by the shared watertight rules
// (pm.glsl). Defines: SPACING, CAPTURE.
#include "pm_tes.glsl"

// As bspline/patch_bspline.tese: `cw` in Vulkan's upper-left domain is counter-clockwise in (u right, v up).
layout(quads, SPACING, cw) in;

void main() {
    float u = gl_TessCoord.x;
    float v = gl_TessCoord.y;
    vec3 cp[16];
    for (int i = 0; i < 16; ++i) {
        cp[i] = g_cp[i];
    }
    vec3 p, nrm, du, dv;
    bezier_surface_frame(cp, u, v, p, nrm, du, dv);
    uint rec = pm_record(chunk.patch_base + uint(gl_PrimitiveID));
    p += pm_origin(rec);
    bool u_edge = (u == 0.0 || u == 1.0);
    bool v_edge = (v == 0.0 || v == 1.0);
    if (u_edge && v_edge) {
        uvec4 c = uvec4(pm_words[rec + 4u], pm_words[rec + 5u], pm_words[rec + 6u],
                        pm_words[rec + 7u]);
        quad_corner_point(c, pm_words[rec], u, v, p, nrm);
    } else if (v == 0.0) {
        pm_domain_edge(rec, 0u, u, true, p, nrm);
    } else if (u == 1.0) {
        pm_domain_edge(rec, 1u, v, true, p, nrm);
    } else if (v == 1.0) {
        pm_domain_edge(rec, 2u, u, false, p, nrm);
    } else if (u == 0.0) {
        pm_domain_edge(rec, 3u, v, false, p, nrm);
    }
    pm_emit(rec, PM_NO_SUB_FACE, vec2(u, v), vec3(0.0), uv_tangents(du, dv), p, nrm);
}
