// The TES body of a whole patch of the adaptive scheme with a quad domain (or of one of its
// split x split sub-patches, frame.glsl's sub_domain): the patch type's
// surface, the shared corners (slot frames; sector frames for the normal where sharp edges split
// the point), its own edge rule, except that an edge lying on a
// one-level-coarser patch is evaluated from that patch's coarse-edge record (fine_edge_point), and
// the capture in base-face parameters with kind and level. The stage file includes what its type
// needs and defines, before including this:
//   PATCH_SURFACE(info, u, v, p, nrm, du, dv)  the patch's own point, unit normal, partials;
//   PATCH_EDGE(info, e, x, p, nrm)     its shared-edge rule on B-spline edge e at local x.
// Defines: SPACING, CAPTURE.
#ifndef TESSERA_ADAPTIVE_PATCH_TES_GLSL
#define TESSERA_ADAPTIVE_PATCH_TES_GLSL

#include "adaptive_tes_io.glsl"

layout(quads, SPACING, cw) in;

void main() {
    // A sub-patch of a split patch covers part of the domain (frame.glsl's sub_domain; the
    // whole domain when the draw does not split); its edge points snap to the whole patch's
    // lattice, where its neighbours place theirs.
    vec3 sd = sub_domain();
    float u = sd.x + gl_TessCoord.x * sd.z;
    float v = sd.y + gl_TessCoord.y * sd.z;
    PatchInfo info = patches[chunk.patch_base + uint(gl_PrimitiveID)];
    AdaptivePatch ap = apatches[info.pad0];
    edge_lattice_override = split_lattice(ap.level, chunk.split);
    bool u_edge = (u == 0.0 || u == 1.0);
    bool v_edge = (v == 0.0 || v == 1.0);
    if (u_edge || v_edge) {
        u = lattice_x(u);
        v = lattice_x(v);
    }
    vec3 p;
    vec3 nrm;
    vec3 du, dv;
    PATCH_SURFACE(info, u, v, p, nrm, du, dv);

    if (u_edge && v_edge) {
        quad_corner_point(info.corners, info.face, u, v, p, nrm);
        sector_normal(ap.corner_frame[quad_corner_index(u, v)], nrm);
    } else if (u_edge || v_edge) {
        int e = bspline_edge(u, v);
        float x = v_edge ? u : v;
        if (ap.coarse[e] != NO_ENTRY) {
            ivec2 se = bspline_edge_corners(e);
            fine_edge_point(ap.coarse[e], info.corners[se.x], info.corners[se.y], x, p, nrm);
        } else {
            PATCH_EDGE(info, e, x, p, nrm);
        }
    }

    displace_adaptive(ap, vec2(u, v), uv_tangents(du, dv), p, nrm);
    t_world = p;
    t_normal = nrm;
    t_class = adaptive_class(ap.kind, ap.level);
    gl_Position = frame.view_proj * vec4(p, 1.0);
#ifdef CAPTURE
    capture_adaptive(ap, ap.kind, vec2(u, v), p, nrm);
#endif
}

#endif
