// Transition patches (Köbler 2013 §3.4; the edge split of OpenSubdiv): a B-spline patch with a
// one-level-finer neighbour across some edges is drawn as a fan of triangles around its domain
// centre, one per edge, two per transition edge (one per half), so each half of a transition
// edge is a whole primitive edge tessellated exactly as the finer patch's edge. Record per
// triangle (16 bytes): the patch (index into the PatchInfo records), B-spline edge e, half (0:
// the whole edge, 1: the half at the edge's start corner, 2: the half at its end), pad.
#ifndef TESSERA_TRANSITION_GLSL
#define TESSERA_TRANSITION_GLSL

struct TransitionTri {
    uint patch_index;
    uint edge;
    uint half_edge;
    uint pad;
};

layout(std430, set = 0, binding = 12) readonly buffer TransitionTris {
    TransitionTri ttris[];
};

#endif
