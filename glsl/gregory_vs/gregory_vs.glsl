// Two-stage Gregory construction (Loop et al. 2009, §4.1-4.2): data shared by gregory_vs.vert
// (per-vertex stage) and gregory_vs_{quad,tri}.tesc (per-patch stage).
//
// Connectivity (the paper's Fig. 7 textures as one storage buffer, binding 4, `uint conn[]`; the
// layout of patch::gregory::GregoryVertexTable with its ring offsets made absolute):
//   conn[4v .. 4v + 4] = (offset, ne, nf, kind): ne incident edges, nf incident faces
//   (ne = nf + 1 on a boundary), kind GVS_KIND_*. From `offset`: ne words w_j (far vertex of
//   ring edge j, crate ring order: face i lies between edges i and i + 1, counter-clockwise seen
//   from outside); nf sector words `start | faces << 16` (the sector holding face i, from sharp
//   edge `start`; smooth vertices: 0 | nf << 16); per face i: its size, then its size - 3
//   vertices other than v, w_i, w_{i+1} (c_i = mean of all of them); smooth vertices then two
//   words, the f32 bits of the edge-tangent factor s and of the transversal factor rho
//   (patch::gregory::GregoryTangents::ring_factors); crease vertices then nf words, the f32 bits
//   of the cross-boundary factor s(k) of face i's sector.
// Per-patch ring offsets (Fig. 8, binding 5, `uint corner_ring[]`): corner_ring[4 * patch + k] =
//   index of the patch's face in the ring of corner k's vertex.
// Varyings from the vertex stage (GVS_SLOTS vec4; one location of the budget is left to the
//   built-in gl_PerVertex block the validation layer counts): slot 0 = (p, nf); then floats,
//   packed 4 per slot from slot 1: smooth vertices 6 per ring edge j (e_j, r_j: r_j across edge j
//   pointing into face j), crease/corner vertices 9 per ring edge j (e_j, r_plus_j, r_minus_j:
//   the transversal vectors of face j across its edges j and j + 1, both into face j).
#ifndef TESSERA_GREGORY_VS_GLSL
#define TESSERA_GREGORY_VS_GLSL

#ifndef GVS_SLOTS
#define GVS_SLOTS 31
#endif
/// Largest smooth valence and largest crease/corner edge count the varyings hold.
#define GVS_MAX_VALENCE ((4 * GVS_SLOTS - 4) / 6)
#define GVS_MAX_SECTORED_EDGES ((4 * GVS_SLOTS - 4) / 9)

#define GVS_KIND_NONE 0u
#define GVS_KIND_SMOOTH 1u
#define GVS_KIND_CREASE 2u
#define GVS_KIND_CORNER 3u

layout(std430, set = 0, binding = 4) readonly buffer GregoryConnectivity {
    uint conn[];
};

layout(std430, set = 0, binding = 5) readonly buffer GregoryCornerRing {
    uint corner_ring[];
};

#define GVS_PI 3.14159265358979

/// cos of condition (1) for face i of vertex v (§3.4; §4.6: pi/k per crease sector of k faces,
/// pi/(2k) per corner sector).
float gvs_face_cosine(uint v, int i) {
    uint off = conn[4u * v];
    uint ne = conn[4u * v + 1u];
    uint nf = conn[4u * v + 2u];
    uint kind = conn[4u * v + 3u];
    if (kind == GVS_KIND_SMOOTH) {
        return cos(2.0 * GVS_PI / float(nf));
    }
    uint k = conn[off + ne + uint(i)] >> 16;
    return kind == GVS_KIND_CORNER ? cos(GVS_PI / (2.0 * float(k))) : cos(GVS_PI / float(k));
}

#endif
