// The TCS body of every Pm patch type: invocation i sums coefficient row i (pm.glsl) over the
// control positions, relative to the patch's origin (pm_origin: the TES adds it back); invocation
// 0 sets the levels (PM_SET_LEVELS(rec), defined by the stage file); then the patch is culled
// when its coefficients lie outside the view (common/cull.glsl). Define PM_POINTS (output
// coefficients) before including.
#ifndef TESSERA_PM_TCS_GLSL
#define TESSERA_PM_TCS_GLSL

layout(vertices = PM_POINTS) out;
layout(location = 0) out vec3 g_cp[];

void main() {
    uint rec = pm_record(chunk.patch_base + uint(gl_PrimitiveID));
    g_cp[gl_InvocationID] = pm_coefficient(rec, uint(gl_InvocationID));
    if (gl_InvocationID == 0) {
        PM_SET_LEVELS(rec);
    }
    // The coefficients bound the patch (Bézier convex hull; common/cull.glsl).
    CULL_PATCH_AT(g_cp, PM_POINTS, pm_origin(rec));
}

#endif
