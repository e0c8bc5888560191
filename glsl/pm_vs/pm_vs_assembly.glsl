// Pm-patches, vertex-stage variant, stage 2 (paper §5.2, Fig. 11): the TCS assembles the patch's
// Bézier coefficients from its corners' per-vertex data (pm_vs.vert), as patch::pm::construct
// does on the CPU: corner k's vertex point, tangent points along its facet edges (eq. 16) and face
// points, then the bicubic (ordinary), singular bicubic (polar, eq. 18-19) or Pm sector
// (eq. 2-3, 20-22) coefficients, relative to the record's origin (pm_origin). The patch
// primitive's control points are the facet's vertices in facet order. Needs pm.glsl and
// pm_vs.glsl first.
#ifndef TESSERA_PM_VS_ASSEMBLY_GLSL
#define TESSERA_PM_VS_ASSEMBLY_GLSL

layout(location = 0) in vec4 v_data[][PMVS_SLOTS];

/// This patch's words in pmvs_patch, and its corners' control positions minus the origin.
uint pmvs_base;
vec3 pmvs_offset[5];

/// Reads the patch's words and corner offsets (m corners).
void pmvs_init(uint rec, int m) {
    pmvs_base = (chunk.patch_base + uint(gl_PrimitiveID)) * PMVS_PATCH_WORDS;
    vec3 origin = pm_origin(rec);
    for (int k = 0; k < m; ++k) {
        pmvs_offset[k] = control_point(pmvs_patch[pmvs_base + uint(k)]) - origin;
    }
}

/// Corner k as an index into v_data, clamped to the patch's vertices. lavapipe's TCS gathers an
/// input for every SIMD lane, inactive ones too, and an inactive lane of a divergent branch may
/// carry any k: one crash in 21 runs of `tests/scheme_pm.rs` (session 12) was such a read at
/// k = -1, 768 bytes (one `draw_tcs_inputs` vertex) before a heap block. Active lanes always have
/// 0 <= k < gl_PatchVerticesIn, so the clamp changes nothing on any device.
int pmvs_corner(int k) {
    return clamp(k, 0, gl_PatchVerticesIn - 1);
}

float pmvs_get(int k, int f) {
    return v_data[pmvs_corner(k)][f / 4][f % 4];
}

vec3 pmvs_get3(int k, int f) {
    return vec3(pmvs_get(k, f), pmvs_get(k, f + 1), pmvs_get(k, f + 2));
}

/// Field `shift` of corner k's word (pm_vs.glsl).
int pmvs_field(int k, int shift) {
    return int((pmvs_patch[pmvs_base + 5u + uint(k)] >> uint(shift)) & 63u);
}

int pmvs_valence(int k) {
    return int(v_data[pmvs_corner(k)][0].w);
}

/// Corner k's vertex point v.
vec3 pmvs_v(int k) {
    return pmvs_offset[pmvs_corner(k)] + v_data[pmvs_corner(k)][0].xyz;
}

/// Corner k's face point of facet j of its ring.
vec3 pmvs_f(int k, int j) {
    return pmvs_offset[pmvs_corner(k)] + pmvs_get3(k, 10 + 3 * j);
}

/// Corner k's tangent point along spoke j, eq. (16): v + cos(2 pi j / n) t_1 + sin(2 pi j / n) t_2.
vec3 pmvs_tangent(int k, int j) {
    int n = pmvs_valence(k);
    return (pmvs_v(k) + pmvs_cos(j, n) * pmvs_get3(k, 4)) + pmvs_sin(j, n) * pmvs_get3(k, 7);
}

/// FacetCorner::next, prev, f_in, f_next, f_prev of corner k.
vec3 pmvs_next(int k) {
    return pmvs_tangent(k, pmvs_field(k, 18));
}

vec3 pmvs_prev(int k) {
    return pmvs_tangent(k, pmvs_field(k, 24));
}

vec3 pmvs_f_in(int k) {
    return pmvs_f(k, pmvs_field(k, 0));
}

vec3 pmvs_f_next(int k) {
    return pmvs_f(k, pmvs_field(k, 6));
}

vec3 pmvs_f_prev(int k) {
    return pmvs_f(k, pmvs_field(k, 12));
}

/// Bicubic coefficient idx (b[i + 4j]) of an ordinary facet: corner k's block is v, the tangent
/// points along its edges and f_in (construct::bicubic). Table: corner << 2 | kind (0 v, 1 next,
/// 2 prev, 3 f_in).
const int PMVS_BICUBIC[16] = int[16](0, 1, 6, 4, 2, 3, 7, 5, 13, 15, 11, 10, 12, 14, 9, 8);

vec3 pmvs_corner_point(int k, int kind) {
    if (kind == 0) {
        return pmvs_v(k);
    } else if (kind == 1) {
        return pmvs_next(k);
    } else if (kind == 2) {
        return pmvs_prev(k);
    }
    return pmvs_f_in(k);
}

vec3 pmvs_bicubic(uint rec, uint idx) {
    pmvs_init(rec, 4);
    int e = PMVS_BICUBIC[idx];
    return pmvs_corner_point(e >> 2, e & 3);
}

/// Polar coefficient idx (16 points, row 3 the pole) of facet (a, b, pole) (construct::polar):
/// rows 0-1 from corners a, b as an ordinary patch; h_02, h_32 the pole's tangent points along
/// the spokes; eq. (18) h_12 = (2 h_02 + h_32 + (c - 1) v_p) / (2 + c) and mirrored, blended by
/// eq. (19) with the spokes' crease scalars; row 3 the pole's v.
vec3 pmvs_polar(uint rec, uint idx) {
    pmvs_init(rec, 3);
    int pole = int(pm_words[rec + 1u] >> 24);
    int a = (pole + 1) % 3;
    int b = (pole + 2) % 3;
    int h = min(int(idx), 12);
    if (h == 0) return pmvs_v(a);
    if (h == 1) return pmvs_next(a);
    if (h == 2) return pmvs_prev(b);
    if (h == 3) return pmvs_v(b);
    if (h == 4) return pmvs_prev(a);
    if (h == 5) return pmvs_f_in(a);
    if (h == 6) return pmvs_f_in(b);
    if (h == 7) return pmvs_next(b);
    if (h == 8) return pmvs_next(pole);
    if (h == 11) return pmvs_prev(pole);
    if (h == 12) return pmvs_v(pole);
    float c = pmvs_cos(1, pmvs_valence(pole));
    vec3 near = h == 9 ? pmvs_next(pole) : pmvs_prev(pole);
    vec3 far = h == 9 ? pmvs_prev(pole) : pmvs_next(pole);
    float s = 1.5 * uintBitsToFloat(pmvs_patch[pmvs_base + uint(h - 9 + 10)]);
    return (((s * 2.0 / (2.0 + c)) * near + (s / (2.0 + c)) * far)
            + (s * (c - 1.0) / (2.0 + c)) * pmvs_v(pole)) + (1.0 - s) * near;
}

/// The Pm facet's stored points (construct::pm_facet): per sector i the boundary cubic's
/// v^i = pmvs_v(i), b_210 = pmvs_next(i), b_120 = pmvs_prev(i + 1) and the interior b_211,
/// b_121, b_112; the centre b_004.
vec3 pmvs_b211[5];
vec3 pmvs_b121[5];
vec3 pmvs_b112[5];
vec3 pmvs_b202[5];
vec3 pmvs_centre;

/// Eq. (20), one side: (1/4 - k_v) v + (3/4 - k_t + k_v) t_out + k_t t_back + k_f (f_in - f_out).
vec3 pmvs_edge_point(float mu, float s, vec3 v, vec3 t_out, vec3 t_back, vec3 f_in, vec3 f_out,
                     float chi_here, float chi_there) {
    float k_t = chi_here / (4.0 * mu);
    float k_v = (2.0 * mu - chi_there) / (8.0 * mu);
    float k_f = 3.0 / (8.0 * mu * s);
    return (((0.25 - k_v) * v + (0.75 - k_t + k_v) * t_out) + k_t * t_back + k_f * f_in)
           - k_f * f_out;
}

/// Eq. (3): k_1 on + k_2 (left + right), k_2 = 1 / (2 (1 - cos(2 pi / m))).
vec3 pmvs_spoke(int m, vec3 on, vec3 left, vec3 right) {
    float k2 = 1.0 / (2.0 * (1.0 - pmvs_cos(1, m)));
    return ((1.0 - 2.0 * k2) * on + k2 * left) + k2 * right;
}

/// b_301 and b_202 of sector i (the spoke from corner i; construct::spokes).
vec3 pmvs_b301(int m, int i) {
    vec3 v = pmvs_v(i);
    return pmvs_spoke(m, v, 0.25 * v + 0.75 * pmvs_next(i), 0.25 * v + 0.75 * pmvs_prev(i));
}

/// Eq. (20) on outer edge i (corner i to i + 1): b^i_211 and b^i_121.
void pmvs_edge_points(int m, int i, out vec3 b211, out vec3 b121) {
    float mu = 1.0 - pmvs_cos(1, m);
    int j = (i + 1) % m;
    int n0 = pmvs_valence(i);
    int n1 = pmvs_valence(j);
    float s = pmvs_sin(1, n0) + pmvs_sin(1, n1);
    float chi0 = 1.0 + pmvs_cos(1, n0);
    float chi1 = 1.0 + pmvs_cos(1, n1);
    b211 = pmvs_edge_point(mu, s, pmvs_v(i), pmvs_next(i), pmvs_prev(j), pmvs_f_in(i),
                           pmvs_f_next(i), chi0, chi1);
    b121 = pmvs_edge_point(mu, s, pmvs_v(j), pmvs_prev(j), pmvs_next(i), pmvs_f_in(j),
                           pmvs_f_prev(j), chi1, chi0);
}

/// Fills the facet's stored points (m corners; pmvs_init done).
void pmvs_facet(int m) {
    for (int i = 0; i < m; ++i) {
        pmvs_edge_points(m, i, pmvs_b211[i], pmvs_b121[i]);
    }
    // b_004 = sum_i (w_m v^i + 3 (t_next + t_prev) + 9 f_in) / (m (w_m + 15)).
    float w = m == 3 ? 2.0 : (m == 5 ? 3.0 : 1.0);
    float d = float(m) * (w + 15.0);
    pmvs_centre = vec3(0.0);
    for (int i = 0; i < m; ++i) {
        pmvs_centre += (w / d) * pmvs_v(i) + (3.0 / d) * pmvs_next(i) + (3.0 / d) * pmvs_prev(i)
                       + (9.0 / d) * pmvs_f_in(i);
    }
    for (int i = 0; i < m; ++i) {
        pmvs_b202[i] = pmvs_spoke(m, pmvs_b301(m, i), pmvs_b211[i], pmvs_b121[(i + m - 1) % m]);
    }
    // Eq. (21) / (22): b^i_112.
    for (int i = 0; i < m; ++i) {
        if (m == 3) {
            pmvs_b112[i] = 1.5 * pmvs_centre - 0.5 * pmvs_b202[(i + 2) % 3];
        } else if (m == 4) {
            pmvs_b112[i] = pmvs_centre
                + (3.0 / 16.0) * (pmvs_b211[i] + pmvs_b121[i] - pmvs_b211[(i + 2) % 4]
                                  - pmvs_b121[(i + 2) % 4])
                + (1.0 / 16.0) * (pmvs_b211[(i + 3) % 4] + pmvs_b121[(i + 1) % 4]
                                  - pmvs_b121[(i + 3) % 4] - pmvs_b211[(i + 1) % 4]);
        } else {
            float c = pmvs_cos(1, 5);
            float c2 = pmvs_cos(2, 5);
            float k = c / (1.0 - c);
            pmvs_b112[i] = (1.0 - c) * pmvs_centre + k * (pmvs_b202[i] + pmvs_b202[(i + 1) % 5])
                + (k * c2) * (pmvs_b202[(i + 2) % 5] + pmvs_b202[(i + 4) % 5])
                + (k * c) * pmvs_b202[(i + 3) % 5];
        }
    }
}

/// The spoke from corner i to the centre: b_301, b_202, b_103 (eq. 3, l = 0, 1, 2).
vec3 pmvs_spoke_point(int m, int i, int l) {
    if (l == 0) {
        return pmvs_b301(m, i);
    } else if (l == 1) {
        return pmvs_b202[i];
    }
    return pmvs_spoke(m, pmvs_b202[i], pmvs_b112[i], pmvs_b112[(i + m - 1) % m]);
}

/// Quartic coefficient idx (quartic_index order: rows by c = 4 - a - b, b along each row) of
/// sector i of the m-sided facet (construct::sector_quartic).
vec3 pmvs_sector(uint rec, uint idx) {
    uint kind = pm_words[rec + 1u];
    int i = int((kind >> 8) & 0xffu);
    int m = int((kind >> 16) & 0xffu);
    pmvs_init(rec, m);
    int j = (i + 1) % m;
    const int ROW[15] = int[15](0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 3, 3, 4);
    const int FIRST[5] = int[5](0, 5, 9, 12, 14);
    int c = ROW[idx];
    int b = int(idx) - FIRST[c];
    int a = 4 - b - c;
    if (c == 0) {
        // The outer boundary, degree-raised (eq. 2).
        if (b == 0) return pmvs_v(i);
        if (b == 1) return 0.25 * pmvs_v(i) + 0.75 * pmvs_next(i);
        if (b == 2) return 0.5 * pmvs_next(i) + 0.5 * pmvs_prev(j);
        if (b == 3) return 0.25 * pmvs_v(j) + 0.75 * pmvs_prev(j);
        return pmvs_v(j);
    }
    if (c == 1) {
        // The row next to the boundary needs corners i and i + 1 only (b_301, b_211, b_121, b_031).
        if (b == 0) return pmvs_b301(m, i);
        if (a == 0) return pmvs_b301(m, j);
        vec3 b211, b121;
        pmvs_edge_points(m, i, b211, b121);
        return a == 2 ? b211 : b121;
    }
    // The inner coefficients need the whole facet.
    pmvs_facet(m);
    if (c == 4) return pmvs_centre;
    if (b == 0) return pmvs_spoke_point(m, i, 3 - a);
    if (a == 0) return pmvs_spoke_point(m, j, 3 - b);
    return pmvs_b112[i];
}

#endif
