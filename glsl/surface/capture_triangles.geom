#version 450
// Triangle capture (render::static_draw, `tessera bench --static`): every triangle the evaluation
// stage emits passes through unchanged. Its bucket is a fixed integer hash of the bits of its
// three world positions modulo `bucket_modulus` (render::pass::capture::triangle_bucket mirrors
// it), so the bucket is a property of the triangle, not of the order the device runs the
// geometry stage in. Every triangle is counted (`triangle_count`) and counted in its bucket
// (`bucket_counts`); one whose bucket lies in [bucket_first, bucket_end) is appended at a slot of
// its own atomic counter (`stored_count`, counted past the capacity too, stored only below it):
// per vertex the world position (3 words) and the unit normal octahedrally encoded
// (packSnorm2x16, 1 word), then the first vertex's colour class; 13 words. A frame larger than one
// binding is captured in chunks of consecutive buckets, one frame each (render::static_draw).
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;

layout(location = 0) in vec3 g_world[];
layout(location = 1) in vec3 g_normal[];
layout(location = 2) flat in uint g_class[];
layout(location = 0) out vec3 t_world;
layout(location = 1) out vec3 t_normal;
layout(location = 2) flat out uint t_class;

#define TRIANGLE_WORDS 13u
// render::pass::capture::MAX_BUCKETS
#define MAX_BUCKETS 4096

layout(std430, set = 0, binding = 3) buffer TriangleCapture {
    uint triangle_count;
    uint triangle_capacity;
    uint bucket_first;
    uint bucket_end;
    uint stored_count;
    uint bucket_modulus;
    uint triangle_pad[2];
    uint bucket_counts[MAX_BUCKETS];
    uint triangle_words[];
};

// Octahedral encoding of a direction into [-1, 1]^2 (zero vectors map to +z).
vec2 octahedral(vec3 n) {
    float l1 = abs(n.x) + abs(n.y) + abs(n.z);
    if (l1 == 0.0) return vec2(0.0);
    n /= l1;
    vec2 e = n.xy;
    if (n.z < 0.0) {
        e = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
    }
    return e;
}

// MurmurHash3's 32-bit block mix and finaliser (Appleby) over the nine position words.
uint triangle_hash() {
    uint h = 0u;
    for (int i = 0; i < 3; ++i) {
        for (int c = 0; c < 3; ++c) {
            uint k = floatBitsToUint(g_world[i][c]) * 0xcc9e2d51u;
            k = ((k << 15) | (k >> 17)) * 0x1b873593u;
            h ^= k;
            h = ((h << 13) | (h >> 19)) * 5u + 0xe6546b64u;
        }
    }
    h ^= 36u;
    h ^= h >> 16;
    h *= 0x85ebca6bu;
    h ^= h >> 13;
    h *= 0xc2b2ae35u;
    h ^= h >> 16;
    return h;
}

void main() {
    atomicAdd(triangle_count, 1u);
    uint bucket = triangle_hash() % clamp(bucket_modulus, 1u, uint(MAX_BUCKETS));
    atomicAdd(bucket_counts[bucket], 1u);
    if (bucket >= bucket_first && bucket < bucket_end) {
        uint slot = atomicAdd(stored_count, 1u);
        if (slot < triangle_capacity) {
            uint base = slot * TRIANGLE_WORDS;
            for (int i = 0; i < 3; ++i) {
                uint w = base + 4u * uint(i);
                triangle_words[w] = floatBitsToUint(g_world[i].x);
                triangle_words[w + 1u] = floatBitsToUint(g_world[i].y);
                triangle_words[w + 2u] = floatBitsToUint(g_world[i].z);
                triangle_words[w + 3u] = packSnorm2x16(octahedral(g_normal[i]));
            }
            triangle_words[base + 12u] = g_class[0];
        }
    }
    for (int i = 0; i < 3; ++i) {
        gl_Position = gl_in[i].gl_Position;
        t_world = g_world[i];
        t_normal = g_normal[i];
        t_class = g_class[i];
        EmitVertex();
    }
    EndPrimitive();
}
