// The TCS body of every Pm patch type: invocation i writes coefficient i relative to the patch's
// origin (pm_origin: the TES adds it back), by default by summing its stencil row (pm.glsl,
// pm_coefficient) over the control positions, or as the stage file defines PM_COEFFICIENT(rec, k)
// (the vertex-stage variant: pm_vs.glsl); invocation 0 sets the levels (PM_SET_LEVELS(rec),
// defined by the stage file); then the patch is culled when its coefficients lie outside the
// view (common/cull.glsl). Define PM_POINTS (output coefficients) before including.
#ifndef TESSERA_PM_TCS_GLSL
#define TESSERA_PM_TCS_GLSL

#ifndef PM_COEFFICIENT
#define PM_COEFFICIENT(rec, k) pm_coefficient(rec, k)
#endif

layout(vertices = PM_POINTS) out;
layout(location = 0) out vec3 g_cp[];

void main() {
    uint rec = pm_record(chunk.patch_base + uint(gl_PrimitiveID));
    g_cp[gl_InvocationID] = PM_COEFFICIENT(rec, uint(gl_InvocationID));
    if (gl_InvocationID == 0) {
        PM_SET_LEVELS(rec);
    }
    // The coefficients bound the patch (Bézier convex hull; common/cull.glsl).
    CULL_PATCH_AT(g_cp, PM_POINTS, pm_origin(rec));
}

#endif
