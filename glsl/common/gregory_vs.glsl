// Two-stage Gregory construction (Loop et al. 2009, §4.1-4.2): data shared by gregory_vs.vert
// (per-vertex stage) and gregory_vs_{quad,tri}.tesc (per-patch stage).
//
// Connectivity (the paper's Fig. 7 textures as a storage buffer, binding 4, `uint conn[]`):
//   conn[2v] = offset of vertex v's ring records, conn[2v + 1] = n (number of faces around v);
//   ring record i (2 words at offset + 2i), in the crate's ring order (face i between ring edges
//   i and i + 1, counter-clockwise seen from outside): the neighbour along ring edge i and the
//   offset of face i's record; a face record is (size, vertex ids...) (src/render/gregory_vs.rs).
// Per-patch ring offsets (Fig. 8, binding 5, `uint corner_ring[]`): corner_ring[4 * patch + k] =
//   index of the patch's face in the ring of corner k's vertex.
// Varyings from the vertex stage (GVS_SLOTS vec4 = 4 * GVS_SLOTS components; one location of the
//   budget is left to the built-in gl_PerVertex block the validation layer counts): slot 0 = (p, n);
//   then floats 6j..6j+2 = e_j, 6j+3..6j+5 = r_j, packed 4 per slot from slot 1. Largest
//   valence: GVS_MAX_VALENCE = (4 * GVS_SLOTS - 4) / 6.
#ifndef TESSERA_GREGORY_VS_GLSL
#define TESSERA_GREGORY_VS_GLSL

#ifndef GVS_SLOTS
#define GVS_SLOTS 31
#endif
#define GVS_MAX_VALENCE ((4 * GVS_SLOTS - 4) / 6)

layout(std430, set = 0, binding = 4) readonly buffer GregoryConnectivity {
    uint conn[];
};

layout(std430, set = 0, binding = 5) readonly buffer GregoryCornerRing {
    uint corner_ring[];
};

#define GVS_PI 3.14159265358979

#endif
