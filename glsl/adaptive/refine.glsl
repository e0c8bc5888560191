// Shared by the three refinement kernels (Köbler 2013, section 4.3; tables of section 4.2, laid
// out by `subdiv::tables::RefinementTables::gpu_tables`). One thread per table record.
//
// set 0: binding 0 the packed tables (`uint[]`, weights as f32 bits), binding 1 the vertex buffer
// of every level (`float[]`, tightly packed xyz, the layout of the vertex buffer the draws read).
// Push constants: the kernel's first record word, its record count, and the first record of this
// dispatch (dispatches are split at 65535 workgroups).

layout(local_size_x = 64) in;

layout(std430, set = 0, binding = 0) readonly buffer Tables { uint tables[]; };
layout(std430, set = 0, binding = 1) buffer Points { float points[]; };

layout(push_constant) uniform Range {
    uint first;
    uint count;
    uint start;
} range;

const uint NO_POINT = 0xffffffffu;

// The word index of this thread's record (`stride` words per record), or NO_POINT past the end.
uint record(uint stride) {
    uint i = range.start + gl_GlobalInvocationID.x;
    return i < range.count ? range.first + i * stride : NO_POINT;
}

vec3 load(uint i) {
    return vec3(points[3u * i], points[3u * i + 1u], points[3u * i + 2u]);
}

void store(uint i, vec3 p) {
    points[3u * i] = p.x;
    points[3u * i + 1u] = p.y;
    points[3u * i + 2u] = p.z;
}
