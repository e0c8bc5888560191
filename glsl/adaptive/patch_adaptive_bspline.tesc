#version 450
// B-spline patch of the adaptive scheme (any level, no finer neighbour): control points by
// bspline_tcs.glsl from the refined buffer, levels by patch level (adaptive.glsl).
#include "frame.glsl"
#include "adaptive.glsl"
#include "adaptive_levels.glsl"
#include "adaptive_bspline.glsl"
#include "bspline/bspline_tcs.glsl"

void main() {
    PatchInfo info = patches[chunk.patch_base + uint(gl_PrimitiveID)];
    bspline_control_points(info.flags);
    if (gl_InvocationID == 0) {
        vec4 o = patch_edge_levels(info.corners, apatches[info.pad0].level);
        // Vulkan quad domain: outer[0] is the u=0 edge, [1] v=0, [2] u=1, [3] v=1.
        gl_TessLevelOuter[0] = o.w;
        gl_TessLevelOuter[1] = o.x;
        gl_TessLevelOuter[2] = o.y;
        gl_TessLevelOuter[3] = o.z;
        gl_TessLevelInner[0] = max(o.x, o.z);
        gl_TessLevelInner[1] = max(o.w, o.y);
    }
}
