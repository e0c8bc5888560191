// Stencil variant of Gregory patches (Loop et al. 2009, §4.3): the TCS body shared by the quad
// (20 points) and triangle (15 points) shaders. The input patch is the face's one-ring in the
// canonical local order of its connectivity type, padded to the pipeline's patch size; invocation
// i computes control point i as the weighted sum of the ring vertices whose weight is nonzero
// (mask bit set), in ascending GLOBAL vertex id (per-patch slot order in the record), with
// `precise` so that no multiply-add is fused: a corner or edge point shared with
// a neighbouring patch gets the same nonzero terms in the same order on both sides and so is
// bitwise equal. Output order: p0.., e_plus0.., e_minus0.., f_plus0.., f_minus0.. (as
// GregoryQuad / GregoryTriangle); the next stencil rows are the neighbours' edge points g_eout,
// then the neighbours' face points g_nbr (contract in gregory/gregory.glsl). Each row sums its
// terms relative to its corner's origin, the control position of that corner's vertex
// (weights sum to one): w_i (x_i - o), so the points keep their digits far from the coordinate
// origin and a point shared with a neighbour still has the same terms, hence the same bits.
// Define GREGORY_TRI for triangles.
// Needs frame.glsl and tess_factors.glsl (and, for triangles, gregory/gregory.glsl).
#ifndef TESSERA_GREGORY_STENCIL_GLSL
#define TESSERA_GREGORY_STENCIL_GLSL

#ifdef GREGORY_TRI
#define GREGORY_CORNERS 3
#define GREGORY_POINTS 15
#define GREGORY_EDGE_PAIRS 6
#define GREGORY_NBR_LOCATION 7
#else
#define GREGORY_CORNERS 4
#define GREGORY_POINTS 20
#define GREGORY_EDGE_PAIRS 8
#define GREGORY_NBR_LOCATION 9
#endif

#include "control_points.glsl"

/// Stencil blocks: one per connectivity type, STENCIL_ROWS x STENCIL_COLS floats
/// (src/render/gregory_stencil/gpu.rs mirrors this layout).
#define STENCIL_ROWS 36u
#define STENCIL_COLS 32u

struct StencilRecord {
    uint face;       // base-mesh face
    uint type_id;    // connectivity type (stencil block)
    uint ring_len;   // ring vertices actually used (<= patch size)
    uint pad;
    uvec4 corners;   // corner vertex ids (w repeats corner 0 for triangles)
    uvec4 order[2];  // ring slots in ascending global vertex id, one byte each, low byte first
};

layout(std430, set = 1, binding = 0) readonly buffer StencilWeights {
    float stencil_weights[];
};
layout(std430, set = 1, binding = 1) readonly buffer StencilMasks {
    uint stencil_masks[];
};
layout(std430, set = 1, binding = 2) readonly buffer StencilRecords {
    StencilRecord stencil_records[];
};

layout(vertices = GREGORY_POINTS) out;
layout(location = 0) in vec3 v_pos[];
layout(location = 0) out vec3 g_cp[];
layout(location = 1) patch out vec3 g_eout[GREGORY_EDGE_PAIRS];
layout(location = GREGORY_NBR_LOCATION) patch out vec3 g_nbr[GREGORY_EDGE_PAIRS];

/// Stencil row `row` of the patch's connectivity type applied to the input ring (canonical local
/// order) relative to the origin of the row's corner `corner`: nonzero terms only, in ascending
/// global vertex id, no fused multiply-add.
vec3 stencil_row(StencilRecord rec, uint row, int corner) {
    vec3 origin = control_point(rec.corners[corner]);
    uint base = (rec.type_id * STENCIL_ROWS + row) * STENCIL_COLS;
    uint mask = stencil_masks[rec.type_id * STENCIL_ROWS + row];
    precise vec3 acc = vec3(0.0);
    for (uint i = 0u; i < rec.ring_len; ++i) {
        uint k = (rec.order[i >> 4u][(i >> 2u) & 3u] >> (8u * (i & 3u))) & 0xffu;
        if ((mask & (1u << k)) != 0u) {
            precise vec3 term = stencil_weights[base + k] * (v_pos[k] - origin);
            acc = acc + term;
        }
    }
    return acc;
}

void main() {
    StencilRecord rec = stencil_records[chunk.patch_base + uint(gl_PrimitiveID)];
    int id = gl_InvocationID;
    g_cp[gl_InvocationID] = stencil_row(rec, uint(id), id % GREGORY_CORNERS);
    // Pair i of g_eout / g_nbr lies at corner i / 2 (even i) or i / 2 + 1 (odd i).
    if (id < GREGORY_EDGE_PAIRS) {
        int corner = (id / 2 + (id & 1)) % GREGORY_CORNERS;
        g_eout[id] = stencil_row(rec, uint(GREGORY_POINTS + id), corner);
    } else if (id < 2 * GREGORY_EDGE_PAIRS) {
        int i = id - GREGORY_EDGE_PAIRS;
        int corner = (i / 2 + (i & 1)) % GREGORY_CORNERS;
        g_nbr[i] = stencil_row(rec, uint(GREGORY_POINTS + id), corner);
    }

    if (gl_InvocationID == 0) {
        uvec4 c = rec.corners;
#ifdef GREGORY_TRI
        set_gregory_tri_tess_levels(c);
#else
        set_quad_tess_levels(c);
#endif
    }
    CULL_PATCH_AT(g_cp, GREGORY_POINTS, control_point(rec.corners[cull_k % GREGORY_CORNERS]));
}

#endif
