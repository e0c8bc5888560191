// Sparse stencil rows over the refined points (src/patch/adaptive/draw.rs `SparseRows`), applied
// every frame after the refinement kernels: row r sums weights[k] * point(ids[k]) for k in
// offsets[r] .. offsets[r + 1], ids ascending, precise (no fused multiply-add), so a row two
// patches share gives the same bits. One thread per row; push constants as refine.glsl (first
// row, row count, first row of this dispatch).
//
// set 0: 0 offsets, 1 ids, 2 weights, 3 refined points (tightly packed xyz), 4 and 5 outputs
// (vec4), 6 per-row flags (limit_frames.comp), 7 vertex points (vec4: the first stage, the
// per-vertex sums of smooth, dart and crease end-cap corners, written by endcap_points.comp
// before the other rows run). An id with bit 31 set (DERIVED_ID) reads vertex point id & 0x7fffffff.

layout(local_size_x = 64) in;

layout(std430, set = 0, binding = 0) readonly buffer RowOffsets { uint row_offsets[]; };
layout(std430, set = 0, binding = 1) readonly buffer RowIds { uint row_ids[]; };
layout(std430, set = 0, binding = 2) readonly buffer RowWeights { float row_weights[]; };
layout(std430, set = 0, binding = 3) readonly buffer Points { float points[]; };
layout(std430, set = 0, binding = 4) writeonly buffer OutA { vec4 out_a[]; };
layout(std430, set = 0, binding = 5) writeonly buffer OutB { vec4 out_b[]; };
layout(std430, set = 0, binding = 6) readonly buffer Flags { uint flags[]; };
layout(std430, set = 0, binding = 7) readonly buffer VertexPoints { vec4 vertex_points[]; };

layout(push_constant) uniform Range {
    uint first;
    uint count;
    uint start;
} range;

const uint NO_ROW = 0xffffffffu;

/// This thread's item (0-based within the kernel), or NO_ROW past the end.
uint item() {
    uint i = range.start + gl_GlobalInvocationID.x;
    return i < range.count ? i : NO_ROW;
}

const uint DERIVED_ID = 0x80000000u;

vec3 load(uint i) {
    if ((i & DERIVED_ID) != 0u) {
        return vertex_points[i & ~DERIVED_ID].xyz;
    }
    return vec3(points[3u * i], points[3u * i + 1u], points[3u * i + 2u]);
}

vec3 row_sum(uint r) {
    precise vec3 acc = vec3(0.0);
    for (uint k = row_offsets[r]; k < row_offsets[r + 1u]; ++k) {
        precise vec3 term = row_weights[k] * load(row_ids[k]);
        acc = acc + term;
    }
    return acc;
}
