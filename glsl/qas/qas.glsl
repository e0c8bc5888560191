// QAS patches (Boubekeur, Schlick 2007; CPU construction and fit: src/patch/qas): per patch the
// Bézier coefficients of a quadratic position patch and a quadratic normal patch (a quad's 9 in
// slots 3j + i, i along u; a triangle's 3 corners then edges 0-2), fitted on the CPU to one
// Catmull-Clark step's limit points. The records are rewritten per animation frame.
// Watertight: a patch corner is its limit point (one f32 value per vertex, the same in every
// record); an edge is the quadratic through the two corner coefficients and the edge
// coefficient (4 e - (a + b)) / 2, the same bits in both faces' records, evaluated in the
// canonical frame (common/watertight.glsl: t from the smaller vertex id, precise arithmetic), so
// quads and triangles meeting on an edge agree bitwise (positions, and normals on smooth edges,
// whose normal coefficients also come from shared rows).
#ifndef TESSERA_QAS_GLSL
#define TESSERA_QAS_GLSL

/// Patch kinds (`QasPatchRecord.kind`, src/render/schemes/qas).
#define QAS_QUAD 0u
#define QAS_TRIANGLE 1u

struct QasPatchRecord {
    uint face;      // base-mesh face id
    uint kind;      // QAS_QUAD | QAS_TRIANGLE
    uint pad0;
    uint pad1;
    uvec4 corners;  // base vertex ids of the corners (a triangle repeats corner 0)
    vec4 p[9];      // position coefficients (xyz)
    vec4 n[9];      // normal coefficients (xyz)
};

layout(std430, set = 0, binding = 4) readonly buffer QasPatches {
    QasPatchRecord qas[];
};

#endif
