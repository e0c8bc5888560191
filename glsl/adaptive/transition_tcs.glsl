// The TCS body of a transition triangle (transition.glsl): the control points of its patch and
// levels shared with the neighbours: the outer segment takes the level of the patch edge, or of
// the finer patch along a half edge (level + 1); both spokes take the patch's largest edge level,
// which every triangle of the fan computes alike. The stage file defines, before including this:
//   PATCH_CONTROL_POINTS(info)  writes this invocation's outputs for PatchInfo `info`.
#ifndef TESSERA_TRANSITION_TCS_GLSL
#define TESSERA_TRANSITION_TCS_GLSL

void main() {
    TransitionTri tt = ttris[chunk.patch_base + uint(gl_PrimitiveID)];
    PatchInfo info = patches[tt.patch_index];
    PATCH_CONTROL_POINTS(info);
    if (gl_InvocationID == 0) {
        AdaptivePatch ap = apatches[info.pad0];
        int e = int(tt.edge);
        vec4 o = patch_edge_levels(info.corners, ap.level);
        // Where the patches of a level are drawn split (push constant `split`: the level-0
        // patches' split), the fan is drawn whole with that level's full lattice on its edges.
        float lattice = split_lattice(ap.level, fan_level_split(ap.level));
        if (lattice > 0.0) {
            o = vec4(lattice);
        }
        float half_lattice = split_lattice(ap.level + 1u, fan_level_split(ap.level + 1u));
        ivec2 se = bspline_edge_corners(e);
        float segment = o[e];
        if (tt.half_edge != 0u && half_lattice > 0.0) {
            segment = half_lattice;
        } else if (tt.half_edge == 1u) {
            segment = level_edge_tess(info.corners[se.x], ap.mid[e], ap.level + 1u);
        } else if (tt.half_edge == 2u) {
            segment = level_edge_tess(ap.mid[e], info.corners[se.y], ap.level + 1u);
        }
        float spoke = max(max(o.x, o.y), max(o.z, o.w));
        // Triangle domain: outer[i] is the edge where gl_TessCoord[i] == 0; vertex 0 is the
        // centre, so outer[0] is the segment on the patch edge.
        gl_TessLevelOuter[0] = segment;
        gl_TessLevelOuter[1] = spoke;
        gl_TessLevelOuter[2] = spoke;
        gl_TessLevelInner[0] = max(segment, spoke);
    }
    CULL_PATCH(c_bspline, 16);
}

#endif
