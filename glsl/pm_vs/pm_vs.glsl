// Pm-patches, vertex-stage variant (Myles, Ni, Peters 2008 §5-6.1): the per-vertex stage in the
// vertex shader (pm_vs.vert: eq. 13-15) and the per-patch assembly in the TCS (eq. 16-22, Fig. 11),
// the same arithmetic as src/patch/pm (vertex.rs, corner.rs, construct.rs), which the module docs
// there derive. Evaluation: the pm variant's TES (glsl/pm/patch_pm_*.tese) over the same word
// buffer (pm.glsl), whose edge and centre records keep shared edges bitwise watertight.
//
// Connectivity (binding 5, `uint pmvs_conn[]`, src/render/schemes/pm_vs/mod.rs writes it):
//   pmvs_conn[4v .. 4v + 4] = (offset, n, f32 bits of the tangent scale kappa_n, 0); n = 0 for a
//   vertex no drawn facet uses. From `offset`, 4 words per facet j of v's ring (between spokes j
//   and j + 1, crate ring order): the spoke end p_{3j}; the offset and count of the facet's far
//   vertices (neither v nor a spoke end; p̄_j is their mean: a quad's diagonal vertex, a
//   pentagon's two, none for a triangle, whose p̄_j is the mean of its spoke ends, the paper's
//   unbiased Fig. 8 padding); the f32 bits of the crease scalar a_j of spoke j (eq. 14). The far
//   vertex lists follow the vertex records.
// Per-patch words (binding 6, `uint pmvs_patch[]`, PMVS_PATCH_WORDS per patch in draw order):
//   [0, 5) the facet's vertices in facet order (the patch primitive's control points are these
//   vertices); [5, 10) per facet corner k: slot | f_next << 6 | f_prev << 12 | next_spoke << 18 |
//   prev_spoke << 24 (patch::pm::FacetCorner: the facet's slot j_k in corner k's ring, the slots
//   of the facets across edges k and k - 1, the spokes of edges k and k - 1); [10, 12) a polar
//   patch's crease scalars of its spokes (f32 bits, eq. 19).
// Varyings (PMVS_SLOTS vec4 per vertex; one location of the budget is left to gl_PerVertex):
//   slot 0 = (v - p, n); floats from 4 on: t_1 (3), t_2 (3), then f_j - p (3 per facet). Points
//   relative to the control position p of the vertex: the TCS adds p - origin, so patch
//   coefficients are differences of nearby points as in the stencil variant.
#ifndef TESSERA_PM_VS_GLSL
#define TESSERA_PM_VS_GLSL

#ifndef PMVS_SLOTS
#define PMVS_SLOTS 31
#endif
/// Largest valence the varyings hold: 4 + 6 + 3 n floats.
#define PMVS_MAX_VALENCE ((4 * PMVS_SLOTS - 10) / 3)
#define PMVS_PATCH_WORDS 12u
#define PMVS_TAU 6.283185307179586

layout(std430, set = 0, binding = 5) readonly buffer PmVsConnectivity {
    uint pmvs_conn[];
};

layout(std430, set = 0, binding = 6) readonly buffer PmVsPatches {
    uint pmvs_patch[];
};

/// cos(2 pi j / n), sin(2 pi j / n) (patch::pm::cos_n, sin_n).
float pmvs_cos(int j, int n) {
    return cos(float(PMVS_TAU) * float(j) / float(n));
}

float pmvs_sin(int j, int n) {
    return sin(float(PMVS_TAU) * float(j) / float(n));
}

#endif
