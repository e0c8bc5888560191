// The TCS body of a whole (non-transition) patch of the adaptive scheme with 16 control vertices:
// the patch type's control points, levels by patch level (adaptive_levels.glsl). The stage file
// includes what its type needs and defines, before including this:
//   PATCH_CONTROL_POINTS(info)  writes this invocation's outputs for PatchInfo `info`.
#ifndef TESSERA_ADAPTIVE_PATCH_TCS_GLSL
#define TESSERA_ADAPTIVE_PATCH_TCS_GLSL

void main() {
    PatchInfo info = patches[chunk.patch_base + uint(gl_PrimitiveID)];
    PATCH_CONTROL_POINTS(info);
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

#endif
