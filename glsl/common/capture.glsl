// Capture of TES output for `tessera sample` and the GPU-vs-CPU tests (compiled in with CAPTURE).
// Each TES invocation takes a unique slot from an atomic counter and stores the base face id, the
// face's (u, v), the position and the normal, then the sub-face (NO_SUB_FACE: the base face's own
// domain), a tag (0, or CAPTURE_TAGGED | level << 8 | patch kind, for the adaptive scheme) and
// the texture coordinate (s, t) there (texcoord.glsl; 0 without texture coordinates).
// Slots past `capacity` are counted but not written, so the host can detect an undersized buffer.
#ifndef TESSERA_CAPTURE_GLSL
#define TESSERA_CAPTURE_GLSL

struct CaptureRecord {
    uint face;
    float u, v;
    float px, py, pz;
    float nx, ny, nz;
    uint sub_face;
    uint tag;
    float s, t;
};

#define NO_SUB_FACE 0xffffffffu
#define CAPTURE_TAGGED 0x80000000u

#include "texcoord.glsl"

layout(std430, set = 0, binding = 3) buffer Capture {
    uint capture_count;
    uint capture_capacity;
    uint capture_pad0;
    uint capture_pad1;
    CaptureRecord capture_records[];
};

/// One record with the texture coordinate `st` given (stages whose domains are not the
/// capture's sub-faces, e.g. Pm sectors).
void capture_with_texcoord(uint face, uint sub_face, vec2 uv, vec3 p, vec3 n, uint tag, vec2 st) {
    uint slot = atomicAdd(capture_count, 1u);
    if (slot < capture_capacity) {
        capture_records[slot] = CaptureRecord(face, uv.x, uv.y, p.x, p.y, p.z, n.x, n.y, n.z,
                                              sub_face, tag, st.x, st.y);
    }
}

void capture_tagged(uint face, uint sub_face, vec2 uv, vec3 p, vec3 n, uint tag) {
    vec2 st = has_texcoords() ? surface_texcoord(face, sub_face, uv) : vec2(0.0);
    capture_with_texcoord(face, sub_face, uv, p, n, tag, st);
}

void capture_point(uint face, vec2 uv, vec3 p, vec3 n) {
    capture_tagged(face, NO_SUB_FACE, uv, p, n, 0u);
}

#endif
