// What the Pm evaluation shaders share: includes, inputs, outputs and the emit step
// (displacement after the watertight evaluation, capture tagged with the patch type).
#ifndef TESSERA_PM_TES_GLSL
#define TESSERA_PM_TES_GLSL

#include "frame.glsl"
#include "pm.glsl"
#include "displace.glsl"
#ifdef CAPTURE
#include "capture.glsl"
#endif
#include "tes_outputs.glsl"

/// Sub-face word of a record in the face's own domain (capture.glsl NO_SUB_FACE).
#define PM_NO_SUB_FACE 0xffffffffu

layout(location = 0) in vec3 g_cp[];

/// Writes the outputs (and the capture record, `sub` the sector or NO_SUB_FACE) of point uv;
/// `w` the sector's barycentric point (texture coordinates; unused without a sector); `tg` the
/// patch's tangents (a sector's in its captured (u, v) = (w.y, w.z)).
void pm_emit(uint rec, uint sub, vec2 uv, vec3 w, SurfaceTangents tg, vec3 p, vec3 nrm) {
    uint face = pm_words[rec];
    vec2 st = vec2(0.0);
    mat2 st_jac = mat2(0.0);
    if (has_texcoords()) {
        bool whole = sub == PM_NO_SUB_FACE;
        st = whole ? surface_texcoord(face, NO_SUB_FACE, uv) : pm_sector_texcoord(face, sub, w);
        st_jac = whole ? surface_texcoord_jacobian(face, NO_SUB_FACE, uv)
                       : pm_sector_texcoord_jacobian(face, sub);
    }
    displace_with_texcoord(st, st_jac, tg, p, nrm);
    uint cls = pm_class(pm_words[rec + 1u]);
    t_world = p;
    t_normal = nrm;
    t_class = cls;
    gl_Position = frame.view_proj * vec4(p, 1.0);
#ifdef CAPTURE
    // Tag: the Pm capture kinds (16 + class, render::schemes::pm::kind_name), level 0.
    capture_with_texcoord(face, sub, uv, p, nrm, CAPTURE_TAGGED | (16u + cls - CLASS_PM), st);
#endif
}

#endif
