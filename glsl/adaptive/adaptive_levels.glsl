// Tessellation levels of the adaptive scheme's patches (control stages only). Needs frame.glsl.
#ifndef TESSERA_ADAPTIVE_LEVELS_GLSL
#define TESSERA_ADAPTIVE_LEVELS_GLSL

#include "tess_factors.glsl"

/// Outer tessellation level of the edge between slots a and b of a level-`level` patch. Uniform
/// mode: the requested level / 2^level, at least 1, so the density is the same at every level
/// and both sides of an edge (same level) agree; distance mode: the distance rule / 2^level
/// likewise; screen-space mode: the chord rule of edge_tess_level (the chord itself halves with
/// the level).
float level_edge_tess(uint a, uint b, uint level) {
    if (frame.tess.y == TESS_MODE_DISTANCE) {
        return clamp(distance_tess_level(a, b) / float(1u << level), 1.0, frame.tess.w);
    }
    if (frame.tess.y != TESS_MODE_ADAPTIVE) {
        return clamp(frame.tess.x / float(1u << level), 1.0, frame.tess.w);
    }
    return edge_tess_level(a, b);
}

/// Outer levels of the four corner-to-corner edges of a level-`level` patch, in B-spline edge
/// order (v=0, u=1, v=1, u=0).
vec4 patch_edge_levels(uvec4 c, uint level) {
    return vec4(level_edge_tess(c.x, c.y, level), level_edge_tess(c.y, c.z, level),
                level_edge_tess(c.w, c.z, level), level_edge_tess(c.x, c.w, level));
}

/// Sets the levels of a whole level-`level` quad patch with corner slots c (Vulkan quad domain:
/// outer[0] is the u=0 edge, [1] v=0, [2] u=1, [3] v=1; inner the larger opposite outer level), or
/// of one of its sub-patches when the draw splits it (push constant `split` > 1).
void set_level_quad_tess_levels(uvec4 c, uint level) {
    if (chunk.split > 1u) {
        // One of split x split sub-patches (uniform mode): every level the sub-patch level, level
        // / 2^level / split (split_lattice in adaptive.glsl is split times its ceiling).
        float l = clamp(frame.tess.x / float(chunk.split << level), 1.0, frame.tess.w);
        gl_TessLevelOuter[0] = l;
        gl_TessLevelOuter[1] = l;
        gl_TessLevelOuter[2] = l;
        gl_TessLevelOuter[3] = l;
        gl_TessLevelInner[0] = l;
        gl_TessLevelInner[1] = l;
        return;
    }
    vec4 o = patch_edge_levels(c, level);
    gl_TessLevelOuter[0] = o.w;
    gl_TessLevelOuter[1] = o.x;
    gl_TessLevelOuter[2] = o.y;
    gl_TessLevelOuter[3] = o.z;
    gl_TessLevelInner[0] = max(o.x, o.z);
    gl_TessLevelInner[1] = max(o.w, o.y);
}

#endif
