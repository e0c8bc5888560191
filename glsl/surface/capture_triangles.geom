#version 450
// Triangle capture (render::static_draw, `tessera bench --static`): every triangle the evaluation
// stage emits passes through unchanged and is appended to the capture buffer (set 0 binding 3)
// at a slot from its atomic counter: per vertex the world position (3 words) and the unit normal
// octahedrally encoded (packSnorm2x16, 1 word), then the first vertex's colour class; 13 words.
// Only the window of slots [first, first + capacity) is stored (slot first at record 0); every
// slot is counted, so the host sees how many triangles the frame drew and captures a frame larger
// than one binding in chunks, one frame per window (render::static_draw).
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;

layout(location = 0) in vec3 g_world[];
layout(location = 1) in vec3 g_normal[];
layout(location = 2) flat in uint g_class[];
layout(location = 0) out vec3 t_world;
layout(location = 1) out vec3 t_normal;
layout(location = 2) flat out uint t_class;

#define TRIANGLE_WORDS 13u

layout(std430, set = 0, binding = 3) buffer TriangleCapture {
    uint triangle_count;
    uint triangle_capacity;
    uint triangle_first;
    uint triangle_pad;
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

void main() {
    uint slot = atomicAdd(triangle_count, 1u);
    if (slot >= triangle_first && slot - triangle_first < triangle_capacity) {
        uint base = (slot - triangle_first) * TRIANGLE_WORDS;
        for (int i = 0; i < 3; ++i) {
            uint w = base + 4u * uint(i);
            triangle_words[w] = floatBitsToUint(g_world[i].x);
            triangle_words[w + 1u] = floatBitsToUint(g_world[i].y);
            triangle_words[w + 2u] = floatBitsToUint(g_world[i].z);
            triangle_words[w + 3u] = packSnorm2x16(octahedral(g_normal[i]));
        }
        triangle_words[base + 12u] = g_class[0];
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
