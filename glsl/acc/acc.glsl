// ACC geometry patches (Loop, Schaefer 2008 §3; CPU construction src/patch/acc.rs): per patch
// the 16 bicubic Bézier points (4 j + i, i along u) and, per edge k (corner k to k + 1), the row
// of the neighbouring patch beside the edge, from corner k. Watertight: corners and the edge's
// Bézier row hold the same bits in both faces' records; an edge is evaluated in the canonical
// frame (common/watertight.glsl), its normal from the edge curve and the difference of the rows
// left and right of it, which both faces hold.
#ifndef TESSERA_ACC_GLSL
#define TESSERA_ACC_GLSL

struct AccPatchRecord {
    uint face;      // base-mesh face id
    uint cls;       // colour class (CLASS_REGULAR: valence-4 corners, else CLASS_IRREGULAR)
    uint pad0;
    uint pad1;
    uvec4 corners;  // base vertex ids of the corners
    vec4 b[16];     // Bézier points (xyz)
    vec4 nbr[16];   // per edge k, the neighbour's row beside it, from corner k (xyz)
};

layout(std430, set = 0, binding = 4) readonly buffer AccPatches {
    AccPatchRecord acc[];
};

#endif
