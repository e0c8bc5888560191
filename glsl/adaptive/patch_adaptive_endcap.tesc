#version 450
// End cap (endcap.glsl): loads its 36 precomputed points; levels by patch level as every
// adaptive patch (adaptive.glsl), from the corner slots.
#include "frame.glsl"
#include "adaptive.glsl"
#include "adaptive_levels.glsl"
#include "gregory/gregory.glsl"
#include "endcap.glsl"

layout(vertices = 20) out;
layout(location = 0) out vec3 g_cp[];
layout(location = 1) patch out vec3 g_eout[8];
layout(location = 9) patch out vec3 g_nbr[8];

void main() {
    GregoryPatchInfo info = gpatches[chunk.patch_base + uint(gl_PrimitiveID)];
    uint base = info.pad1;
    int id = gl_InvocationID;
    g_cp[gl_InvocationID] = endcap_points[base + uint(id)].xyz;
    if (id < 8) {
        g_eout[id] = endcap_points[base + 20u + uint(id)].xyz;
    } else if (id < 16) {
        g_nbr[id - 8] = endcap_points[base + 20u + uint(id)].xyz;
    }
    if (id == 0) {
        set_level_quad_tess_levels(info.corners, apatches[info.pad0].level);
    }
    CULL_PATCH(g_cp, 20);
}
