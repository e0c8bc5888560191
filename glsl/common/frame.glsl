// Per-frame uniforms and the storage buffers shared by the surface shaders. Rust mirrors them byte
// for byte (keep them in sync): `Frame` is FrameUniforms in src/render/settings.rs, `PatchInfo`
// src/render/layout.rs.
#ifndef TESSERA_FRAME_GLSL
#define TESSERA_FRAME_GLSL

/// Tessellation-factor modes (`Frame.tess.y`).
#define TESS_MODE_UNIFORM 0.0
#define TESS_MODE_ADAPTIVE 1.0
#define TESS_MODE_DISTANCE 2.0

/// Colour modes (`Frame.flags.x`).
#define COLOR_NONE 0u
#define COLOR_PATCH_TYPE 1u
#define COLOR_ERROR 2u
#define COLOR_LEVEL 3u

/// Patch classes for colouring (per patch / per fallback vertex).
#define CLASS_REGULAR 0u
#define CLASS_IRREGULAR 1u
#define CLASS_TRIANGLE 2u
#define CLASS_SINGLE_CREASE 3u
/// Error-map classes: CLASS_HEAT_BASE + e, e in 0..1023 (render::heatmap).
#define CLASS_HEAT_BASE 16u
/// Adaptive-scheme classes: CLASS_ADAPTIVE + 16 kind + level (glsl/adaptive/adaptive.glsl).
#define CLASS_ADAPTIVE 2048u
/// Pm-patch classes: CLASS_PM + ordinary 0, polar 1, m = 3, 4, 5 as 2, 3, 4 (glsl/pm/pm.glsl).
#define CLASS_PM 4096u

layout(std140, set = 0, binding = 0) uniform Frame {
    mat4 view_proj;      // world -> clip (Vulkan clip space: y down, depth 0..1)
    vec4 eye;            // xyz: camera position in world space
    vec4 viewport;       // xy: framebuffer size in pixels
    vec4 tess;           // x: uniform level, y: mode, z: pixels per edge (distance mode: the
                         // reference distance), w: max level
    vec4 light_dir;      // xyz: direction towards the key light (world), normalised
    uvec4 flags;         // x: colour mode, y: bit 0 patch culling (cull.glsl), z: bit 0 texture coordinates (texcoord.glsl)
    vec4 displace;       // x: displacement scale along the normal (0: off), y: mode (displace.glsl)
} frame;

/// Per-draw constants (push_patch_chunk, src/render/patch_pipeline.rs). Patches are drawn in
/// chunks and gl_PrimitiveID restarts at 0 in every draw, so `patch_base` is the chunk's first
/// patch. With uniform levels above the sub-patch limit every patch is drawn as split x split
/// sub-patches of the domain, one draw per sub-patch index `sub_index` (row-major,
/// `sub_index % split` along u).
layout(push_constant) uniform DrawChunk {
    uint patch_base;
    uint sub_index;
    uint split;
} chunk;

/// Domain origin and size of the current sub-patch: (u0, v0, size), exact dyadic numbers.
vec3 sub_domain() {
    float size = 1.0 / float(chunk.split);
    return vec3(float(chunk.sub_index % chunk.split) * size,
                float(chunk.sub_index / chunk.split) * size, size);
}

/// Per-patch data of the regular B-spline patches (one entry per patch, indexed by gl_PrimitiveID).
struct PatchInfo {
    uint face;           // base-mesh face id
    uint flags;          // bits 0-3: boundary mask (patch::RegularPatch), bits 4-7: edge e runs from the larger vertex id
    uint pad0;
    uint pad1;
    uvec4 corners;       // vertex ids of the face corners 0..3 (cvs 5, 6, 10, 9)
};

layout(std430, set = 0, binding = 1) readonly buffer Patches {
    PatchInfo patches[];
};

/// Limit positions of the base-mesh vertices (xyz; w unused), the data neighbours share.
layout(std430, set = 0, binding = 2) readonly buffer VertexLimits {
    vec4 vertex_limit[];
};

#include "displace.glsl"

#endif
