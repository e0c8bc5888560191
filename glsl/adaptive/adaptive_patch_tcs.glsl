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
        set_level_quad_tess_levels(info.corners, apatches[info.pad0].level);
    }
    CULL_PATCH(c_bspline, 16);
}

#endif
