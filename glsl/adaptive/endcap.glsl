// End caps of the adaptive scheme (Köbler 2013 §3.5; Gregory patches over the isolation level's
// points, Loop et al. 2009): control points precomputed per frame by endcap_points.comp, 36 per
// patch from GregoryPatchInfo.pad1 (20 points, 8 neighbour edge points, 8 neighbour face points);
// GregoryPatchInfo.pad0 is the patch's AdaptivePatch record.
#ifndef TESSERA_ENDCAP_GLSL
#define TESSERA_ENDCAP_GLSL

layout(std430, set = 0, binding = 13) readonly buffer EndCapPoints {
    vec4 endcap_points[];
};

/// The end caps' lattice regions near irregular crease vertices
/// (src/patch/adaptive/lattice_frames.rs `LatticeFrames::table_words`): word e per end cap (its
/// GregoryPatchInfo index) the index of its block, NO_ENTRY for none; a block is a head word
/// (bits 8c..8c+8 per corner c: bits 0-3 its region's steps, bits 4-7 its cells, 0 for none),
/// then per corner the index of its cells^2 node frames (node (a, b) at a + cells b).
layout(std430, set = 0, binding = 16) readonly buffer EndCapLattice {
    uint lattice[];
};

#endif
