// The TCS body of a transition triangle (transition.glsl): the control points of its patch and
// levels shared with the neighbours: the outer segment takes the level of the patch edge, or of
// the finer patch along a half edge (level + 1); both spokes take the patch's largest edge level,
// which every triangle of the fan computes alike. A fan drawn split (fan_split) gets the levels
// of one sub-triangle instead. The stage file defines, before including this:
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
        ivec2 se = bspline_edge_corners(e);
        vec4 o = patch_edge_levels(info.corners, ap.level);
        float segment = o[e];
        if (tt.half_edge == 1u) {
            segment = level_edge_tess(info.corners[se.x], ap.mid[e], ap.level + 1u);
        } else if (tt.half_edge == 2u) {
            segment = level_edge_tess(ap.mid[e], info.corners[se.y], ap.level + 1u);
        }
        float spoke = max(max(o.x, o.y), max(o.z, o.w));
        // Drawn split (transition.glsl, fan_split): the levels of one sub-triangle; a half
        // edge whose finer owner is drawn whole keeps that owner's level (the same points).
        FanSplit fs = fan_split(ap.level, tt.half_edge);
        if (fs.n > 0u) {
            segment = (fs.n == 1u && tt.half_edge != 0u) ? segment : fs.outer;
            spoke = fs.spoke;
        }
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
