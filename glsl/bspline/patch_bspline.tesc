#version 450
// Regular bicubic B-spline patch: control points by bspline_tcs.glsl, tessellation levels from
// data the neighbouring patch shares (common/tess_factors.glsl).
#include "frame.glsl"
#include "tess_factors.glsl"
#include "bspline_tcs.glsl"

void main() {
    PatchInfo info = patches[chunk.patch_base + uint(gl_PrimitiveID)];
    bspline_control_points(info.flags);
    if (gl_InvocationID == 0) {
        uvec4 c = info.corners;
        // Vulkan quad domain: outer[0] is the u=0 edge, [1] v=0, [2] u=1, [3] v=1.
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
}
