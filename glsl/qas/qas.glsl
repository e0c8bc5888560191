// QAS patches (Boubekeur, Schlick 2007; CPU construction and fit: src/patch/qas): per patch the
// Bézier coefficients of a quadratic position patch and a quadratic normal patch (a quad's 9 in
// slots 3j + i, i along u; a triangle's 3 corners then edges 0-2; a fan triangle of an n-gon
// laid out as a triangle with corners (centre, V_k, V_{k+1})), fitted on the CPU to one
// Catmull-Clark step's limit points. The records are rewritten per animation frame.
// Watertight: a patch corner is its limit point (one f32 value per vertex, the same in every
// record); an edge is the quadratic through the two corner coefficients and the edge
// coefficient (4 e - (a + b)) / 2, the same bits in both faces' records, evaluated in the
// canonical frame (common/watertight.glsl: t from the smaller vertex id, precise arithmetic), so
// quads and triangles meeting on an edge agree bitwise (positions, and normals on smooth edges,
// whose normal coefficients also come from shared rows). A fan's spokes (centre to V_k) are
// shared by the two fan triangles at V_k the same way: the centre's corner id QAS_FAN_CENTRE is
// larger than every vertex id, so both evaluate the spoke from V_k.
#ifndef TESSERA_QAS_GLSL
#define TESSERA_QAS_GLSL

/// Patch kinds (`QasPatchRecord.kind`, src/render/schemes/qas).
#define QAS_QUAD 0u
#define QAS_TRIANGLE 1u
#define QAS_FAN 2u

/// Corner id of a fan's centre (corner 0): patch::qas::FAN_CENTRE.
#define QAS_FAN_CENTRE 0xffffffffu

struct QasPatchRecord {
    uint face;      // base-mesh face id
    uint kind;      // QAS_QUAD | QAS_TRIANGLE | QAS_FAN
    uint sub;       // a fan's sub-face k (at corner 1, V_k); 0 otherwise
    uint sub_next;  // a fan's sub-face k + 1 (at corner 2, V_{k+1}); 0 otherwise
    uvec4 corners;  // base vertex ids of the corners (a triangle repeats corner 0; a fan:
                    // QAS_FAN_CENTRE, V_k, V_{k+1}, QAS_FAN_CENTRE)
    vec4 p[9];      // position coefficients (xyz)
    vec4 n[9];      // normal coefficients (xyz)
};

layout(std430, set = 0, binding = 4) readonly buffer QasPatches {
    QasPatchRecord qas[];
};

#endif
