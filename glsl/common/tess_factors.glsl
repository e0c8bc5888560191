// Tessellation factors from data both patches of an edge share (needs frame.glsl; TCS only).
// Uniform: the requested level. Adaptive: the projected length, in pixels, of the chord between
// the limit points of the edge's two end vertices, divided by the target pixels per edge.
// Distance (QAS's camera-distance metric, Boubekeur, Schlick 2007 §3): the requested level times
// the reference distance over the distance from the eye to the midpoint of those limit points.
// The end vertices are taken in increasing vertex-id order so both neighbours run the same
// arithmetic. Spokes of QAS n-gon fans (from a vertex to the face centre): the same rules on the
// chord from the vertex's limit point to the centre.
#ifndef TESSERA_TESS_FACTORS_GLSL
#define TESSERA_TESS_FACTORS_GLSL

#include "cull.glsl"

/// Screen position (pixels) of a world point; points behind the eye are pushed to the near side.
vec2 to_pixels(vec3 p) {
    vec4 c = frame.view_proj * vec4(p, 1.0);
    float w = max(c.w, 1e-4);
    return (c.xy / w * 0.5 + 0.5) * frame.viewport.xy;
}

/// Distance-mode level (unclamped) of the chord from world point a to b: level x reference
/// distance / distance of the eye to their midpoint.
float distance_tess_level_between(vec3 a, vec3 b) {
    precise vec3 mid = 0.5 * (a + b);
    precise float d = length(mid - frame.eye.xyz);
    return frame.tess.x * frame.tess.z / max(d, 1e-30);
}

/// Distance-mode level (unclamped) of the edge between base vertices a and b: level x reference
/// distance / distance of the eye to the midpoint of their limit points.
float distance_tess_level(uint a, uint b) {
    uint lo = min(a, b);
    uint hi = max(a, b);
    return distance_tess_level_between(vertex_limit[lo].xyz, vertex_limit[hi].xyz);
}

/// Outer level of the chord from world point a to b in the current mode (the patches sharing
/// it pass the same points in the same order).
float chord_tess_level(vec3 a, vec3 b) {
    float max_level = frame.tess.w;
    if (frame.tess.y == TESS_MODE_DISTANCE) {
        return clamp(distance_tess_level_between(a, b), 1.0, max_level);
    }
    if (frame.tess.y != TESS_MODE_ADAPTIVE) {
        // A split patch covers its domain with split x split sub-patches of level / split.
        return clamp(frame.tess.x / float(chunk.split), 1.0, max_level);
    }
    float len = length(to_pixels(b) - to_pixels(a));
    return clamp(len / max(frame.tess.z, 1e-3), 1.0, max_level);
}

/// Outer level of the edge between base vertices a and b.
float edge_tess_level(uint a, uint b) {
    uint lo = min(a, b);
    uint hi = max(a, b);
    return chord_tess_level(vertex_limit[lo].xyz, vertex_limit[hi].xyz);
}

/// Outer level of a spoke from base vertex `corner` to a face centre `centre` that every patch
/// of the spoke holds bitwise (QAS n-gon fans): the chord between the corner's limit point and
/// the centre.
float spoke_tess_level(uint corner, vec3 centre) {
    return chord_tess_level(vertex_limit[corner].xyz, centre);
}

/// Sets the levels of a quad patch with corner vertex ids c (TCS only): outer levels from the
/// edges (Vulkan quad domain: outer[0] is the u=0 edge, [1] v=0, [2] u=1, [3] v=1), inner the
/// larger of the opposite outer levels.
void set_quad_tess_levels(uvec4 c) {
    float o0 = edge_tess_level(c.x, c.w);
    float o1 = edge_tess_level(c.x, c.y);
    float o2 = edge_tess_level(c.y, c.z);
    float o3 = edge_tess_level(c.w, c.z);
    gl_TessLevelOuter[0] = o0;
    gl_TessLevelOuter[1] = o1;
    gl_TessLevelOuter[2] = o2;
    gl_TessLevelOuter[3] = o3;
    gl_TessLevelInner[0] = max(o1, o3);
    gl_TessLevelInner[1] = max(o0, o2);
}

#endif
