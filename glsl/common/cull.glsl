// Patch culling in the control stages (`RenderDesc::cull_patches`, `--cull` / `--no-cull`;
// Frame.flags.y bit 0, cleared by the renderer whenever the TES captures): a patch whose bound
// lies entirely outside one plane of the view frustum gets zero outer levels and is discarded by
// the tessellator. Frustum only: no back-face test (the surface pipelines do not cull back faces
// by default, so back-facing patches of open meshes are visible).
//
// The bound: the convex hull of the patch's control points, which holds for every scheme drawn
// here: Bézier and B-spline patches (the single-crease and mirrored boundary B-spline points
// included: every weight of the evaluation is a convex combination) and Gregory patches (a
// Bézier patch whose interior points are convex blends of the face points). The six clip planes
// are linear in homogeneous coordinates (-w <= x, y <= w, 0 <= z <= w, as the rasterizer clips),
// so if every control point lies outside one of them, so does every convex combination: exact for
// the hull, whatever the sign of w. The hull is grown by a ball of radius
// |Frame.displace.x| (the displacement moves points by at most |scale| * max|d| along the unit
// normal, max|d| = 1) plus 1e-5 of the largest control-point coordinate (f32 rounding of the
// evaluation stage; edges evaluated from the neighbour's data equal this patch's own boundary
// only in exact arithmetic).
//
// Watertight: culling only zeroes the levels of a patch that draws nothing visible; the levels
// of every other patch are computed as before (their shared-edge levels are unchanged).
//
// Usage, at the end of a control stage's main() (top level: it holds a barrier), after the levels
// are set, with the per-vertex outputs or record array holding the patch's control points:
//   CULL_PATCH(points, count);
// Needs frame.glsl.
#ifndef TESSERA_CULL_GLSL
#define TESSERA_CULL_GLSL

/// Culling on (Frame.flags.y bit 0).
bool cull_enabled() {
    return (frame.flags.y & 1u) != 0u;
}

/// The six frustum planes of Frame.view_proj in world space, inside where dot(plane, (p, 1)) >= 0.
void cull_planes(out vec4 planes[6]) {
    mat4 m = frame.view_proj;
    vec4 r0 = vec4(m[0][0], m[1][0], m[2][0], m[3][0]);
    vec4 r1 = vec4(m[0][1], m[1][1], m[2][1], m[3][1]);
    vec4 r2 = vec4(m[0][2], m[1][2], m[2][2], m[3][2]);
    vec4 r3 = vec4(m[0][3], m[1][3], m[2][3], m[3][3]);
    planes[0] = r3 + r0;
    planes[1] = r3 - r0;
    planes[2] = r3 + r1;
    planes[3] = r3 - r1;
    planes[4] = r2;
    planes[5] = r3 - r2;
}

/// Running bound of a patch: per plane the largest signed distance of a control point, and the
/// largest coordinate magnitude.
struct CullBound {
    vec4 planes[6];
    float reach[6];
    float magnitude;
};

CullBound cull_begin() {
    CullBound b;
    cull_planes(b.planes);
    for (int i = 0; i < 6; ++i) {
        b.reach[i] = -3.0e38;
    }
    b.magnitude = 0.0;
    return b;
}

void cull_add(inout CullBound b, vec3 p) {
    for (int i = 0; i < 6; ++i) {
        b.reach[i] = max(b.reach[i], dot(b.planes[i].xyz, p) + b.planes[i].w);
    }
    vec3 a = abs(p);
    b.magnitude = max(b.magnitude, max(a.x, max(a.y, a.z)));
}

/// True when the grown hull lies entirely outside one frustum plane.
bool cull_outside(CullBound b) {
    float grow = abs(frame.displace.x) + 1e-5 * b.magnitude;
    for (int i = 0; i < 6; ++i) {
        if (b.reach[i] < -grow * length(b.planes[i].xyz)) {
            return true;
        }
    }
    return false;
}

/// Zero outer levels: the tessellator discards the patch (quad and triangle domains alike).
void cull_discard_patch() {
    gl_TessLevelOuter[0] = 0.0;
    gl_TessLevelOuter[1] = 0.0;
    gl_TessLevelOuter[2] = 0.0;
    gl_TessLevelOuter[3] = 0.0;
}

/// Culls the patch whose control points are points[0 .. count) plus `origin` (patches whose
/// stages pass points relative to an origin, e.g. pm/pm_tcs.glsl). `origin` is evaluated per
/// point and may name the point's index `cull_k` (Gregory points relative to their corner).
#define CULL_PATCH_AT(points, count, origin)                                                  \
    barrier();                                                                                \
    if (gl_InvocationID == 0 && cull_enabled()) {                                             \
        CullBound cull_bound = cull_begin();                                                  \
        for (int cull_k = 0; cull_k < (count); ++cull_k) {                                    \
            cull_add(cull_bound, (points[cull_k]).xyz + (origin));                            \
        }                                                                                     \
        if (cull_outside(cull_bound)) {                                                       \
            cull_discard_patch();                                                             \
        }                                                                                     \
    }

/// Culls the patch whose control points are points[0 .. count) (after its levels are set).
#define CULL_PATCH(points, count) CULL_PATCH_AT(points, count, vec3(0.0))

#endif
