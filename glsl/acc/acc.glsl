// ACC patches (Loop, Schaefer 2008; CPU construction src/patch/acc): per patch the 16 bicubic
// Bézier points of the geometry patch (4 j + i, i along u), the tangent patches (u: 3 j + i, i
// along u of 3, j along v of 4; v: 4 j + i, i along u of 4, j along v of 3) and, per edge k
// (corner k to k + 1), its frame in the edge's canonical direction (from the smaller vertex id):
// the versal derivative (3 quadratic coefficients) and the difference of the cross derivatives
// left and right of it (4 cubic coefficients), the same bits in both faces' records.
// Watertight: corners and the edge's Bézier row hold the same bits in both faces' records; an
// edge is evaluated in the canonical frame (common/watertight.glsl), its normal from its frame.
#ifndef TESSERA_ACC_GLSL
#define TESSERA_ACC_GLSL

struct AccPatchRecord {
    uint face;      // base-mesh face id
    uint cls;       // colour class (CLASS_REGULAR: valence-4 corners, else CLASS_IRREGULAR)
    uint pad0;
    uint pad1;
    uvec4 corners;  // base vertex ids of the corners
    vec4 b[16];     // Bézier points (xyz)
    vec4 tu[12];    // u-tangent patch (xyz)
    vec4 tv[12];    // v-tangent patch (xyz)
    vec4 edge[28];  // per edge k: 3 versal then 4 cross coefficients at 7 k (xyz)
};

layout(std430, set = 0, binding = 4) readonly buffer AccPatches {
    AccPatchRecord acc[];
};

#endif
