//! Per-vertex quantities of the Gregory construction: limit position, edge points and the
//! transversal vectors `r` (Loop et al. 2009, §3.2-3.4 and §4.6, computed per vertex as in §4.1),
//! generic over the point type so the same code yields positions and stencil weights.

use super::point::{combine, GregoryPoint};
use super::tangents::GregoryTangents;
use super::tangents_boundary::sector_band;
use glam::DVec3;
use std::collections::HashMap;
use std::f64::consts::PI;
use std::sync::{Arc, Mutex};

/// The split one-ring of a vertex (paper Fig. 5), in the crate's ring order: `m[i]` is the
/// midpoint of the `i`-th incident edge, `c[i]` the centroid of the `i`-th incident face, which
/// lies between edges `i` and `(i + 1) % m.len()`, counter-clockwise seen from outside. A
/// boundary vertex has one more edge than faces (edges 0 and last are the boundary edges).
#[derive(Debug, Clone)]
pub struct VertexRing<P = DVec3> {
    /// The vertex itself.
    pub v: P,
    /// Edge midpoints, one per incident edge.
    pub m: Vec<P>,
    /// Face centroids, one per incident face.
    pub c: Vec<P>,
    /// Per incident edge: infinitely sharp (boundary edges included).
    pub sharp: Vec<bool>,
    /// The vertex follows the corner rule (infinitely sharp vertex or more than two sharp edges).
    pub corner: bool,
    /// Sizes of the incident faces, one per face in ring order (what
    /// [`GregoryTangents::ring_factors`] is keyed on).
    pub face_sizes: Vec<usize>,
    /// The 2-ring key of crease rings (two sharp edges, no corner tag; empty for others), one
    /// per incident edge: for a smooth edge whose far end is itself a crease vertex, the faces of
    /// the far end's crease sector holding the edge (the edge is then one of its inner edges),
    /// else 0 ([`crate::patch::gregory::tangents_boundary`], "Bands").
    pub far_sector: Vec<usize>,
    /// Per incident edge: a promoted crease ([`crate::topology::Topology::is_promoted_edge`]),
    /// sharp for the construction but smooth in the limit; empty where there is none.
    pub promoted: Vec<bool>,
    /// The vertex is a decayed corner ([`crate::topology::Topology::is_decayed_corner`]): the
    /// adaptive end caps give its all-quad ring the tangents of
    /// [`super::tangents::DECAYED_CORNER_SCALE`].
    pub decayed_corner: bool,
    /// The vertex's frozen crease-sector factors
    /// ([`crate::topology::Topology::crease_factors`], read under `GregoryTangents::Fitted`).
    pub crease_factors: Option<[f32; 2]>,
}

impl<P> VertexRing<P> {
    /// Whether incident edge `j` is a promoted crease ([`Self::promoted`]).
    pub fn is_promoted(&self, j: usize) -> bool {
        self.promoted.get(j).copied().unwrap_or(false)
    }

    /// Whether the face points beside incident edge `j` are one-sided
    /// ([`GregoryVertex::one_sided`], where the tangents take that rule) for a face in a sector
    /// of `faces` faces of a vertex of kind `kind`: on a sharp edge, but on a promoted crease
    /// only beside a two-face sector of a crease vertex (the regular crease's sector, whose
    /// cross-boundary tangent is the boundary bicubic's). Elsewhere the exact limit is smooth
    /// across a promoted edge and the reflected ring of eq. 6 measured closer to it (end-cap
    /// normal RMS at L1: bishop 8.03e-3 -> 6.17e-3 rad, `catmark_torus_creases1` 2.84e-2 ->
    /// 2.67e-2), while in the regular crease's sector the one-sided point did (car L1 8.83e-3,
    /// 9.07e-3 with the reflected ring there too).
    pub fn one_sided_edge(&self, j: usize, kind: VertexKind, faces: usize) -> bool {
        self.sharp[j] && (!self.is_promoted(j) || (kind == VertexKind::Crease && faces == 2))
    }

    /// Every incident face is a quad (the rings [`GregoryTangents::Optimal`] is fitted on).
    pub fn quads(&self) -> bool {
        self.face_sizes.iter().all(|&k| k == 4)
    }
}

/// How the construction treats a vertex.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum VertexKind {
    /// Interior, no sharp edge: §3.2-3.4.
    Smooth,
    /// Exactly two sharp edges (a boundary vertex, or a vertex on an infinitely sharp crease):
    /// §4.6 with the 1:4:1 curve limit and the cross-boundary tangent.
    Crease,
    /// Corner rule: `p = v` (§4.6); each sector is bounded by two sharp edges.
    Corner,
    /// Interior vertex with exactly one infinitely sharp edge (smooth vertex rule, crease rule
    /// on that edge): limit position and tangent plane from the eigenvectors of the ring's
    /// subdivision matrix (`dart_limit`); not covered by the paper.
    Dart,
    /// Corner rule with fewer than two sharp edges (a cone point, e.g. an infinitely sharp
    /// vertex tag on a smooth or dart vertex): [`GregoryVertex::cone`], an approximation for
    /// adaptive end caps only (the exact surface has no finite edge tangents there).
    Cone,
}

/// Corner point, edge points and transversal vectors of one vertex.
///
/// `e[j]` is the edge point on incident edge `j`. For incident face `j` (between edges `j` and
/// `j + 1`), `r_plus[j]` is the transversal vector across edge `j` and `r_minus[j]` the one
/// across edge `j + 1`, both pointing into face `j` (the paper's `r_i^+`, `r_i^-`), and
/// `cosine[j]` is `c = cos(2π/n)` of condition (1) for the sector holding face `j`.
#[derive(Debug, Clone)]
pub struct GregoryVertex<P = DVec3> {
    /// Treatment of the vertex.
    pub kind: VertexKind,
    /// Number of incident faces (the valence of an interior vertex).
    pub n: usize,
    /// Limit position (§3.2; §4.6 on creases and corners).
    pub p: P,
    /// Edge points, one per incident edge (§3.3; 2:1 on sharp edges, §4.6).
    pub e: Vec<P>,
    /// Transversal vectors across the face's first edge, one per incident face (§3.4).
    pub r_plus: Vec<P>,
    /// Transversal vectors across the face's second edge, one per incident face (§3.4).
    pub r_minus: Vec<P>,
    /// `cos(2π/n)` of the face's sector, one per incident face.
    pub cosine: Vec<f64>,
    /// Per incident face `j` under [`GregoryTangents::Optimal`] at boundary, crease and corner
    /// vertices whose faces are all quads, which of its edges at this corner are sharp: bit 0
    /// edge `j`, bit 1 edge `j + 1` (the face points beside them are one-sided,
    /// `tangents_boundary`). Empty otherwise (eq. 6 with the reflected ring of §4.6 beside sharp
    /// edges too).
    pub one_sided: Vec<u8>,
}

/// `λ`, the subdominant eigenvalue of Catmull-Clark subdivision at valence `n` (§3.3).
pub fn subdominant_eigenvalue(n: usize) -> f64 {
    let n = n as f64;
    let c2 = (2.0 * PI / n).cos();
    let c1 = (PI / n).cos();
    (5.0 + c2 + c1 * (18.0 + 2.0 * c2).sqrt()) / 16.0
}

/// A sector of a crease or corner vertex: `k` faces starting at sharp edge `start`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Sector {
    /// First edge (sharp) of the sector in ring order.
    pub start: usize,
    /// Number of faces.
    pub faces: usize,
}

/// The sectors of a ring with at least one sharp edge, in ring order.
pub fn sectors(sharp: &[bool], face_count: usize) -> Vec<Sector> {
    let ne = sharp.len();
    let mut out = Vec::new();
    for s in (0..ne).filter(|&s| sharp[s]) {
        if s >= face_count {
            continue; // the last edge of a boundary ring starts no sector
        }
        let mut k = 1;
        while !sharp[(s + k) % ne] {
            k += 1;
        }
        out.push(Sector { start: s, faces: k });
    }
    out
}

/// Weights of the cross-boundary tangent `T` of a crease sector with `k >= 2` faces, over the
/// split ring (edge midpoints, face centroids) as §3.2-3.3 write interior stencils. Returns
/// `(w_v, w_m[0..=k], w_c[0..k])`; the weights sum to 0.
///
/// `T` is the sine mode of the sector's subdivision matrix (the tangent stencil of Biermann et
/// al. 2000, derived here for the standard Catmull-Clark crease rules): over a quad sector with
/// edge neighbours `e_i` and diagonal vertices `f_i`, `θ = π/k`, `s_i = sin(iθ)`,
/// `L = Σ_{i=1}^{k-1} s_i e_i + B Σ_i (s_i + s_{i+1}) f_i + γ (e_0 + e_k) + w v` is a left
/// eigenvector with eigenvalue `μ = 1/4 + x`, where `32x² - 4(1+cosθ)x - (1+cosθ) = 0`,
/// `B = 1/(16x)`, `γ = (s_1 (1/16 + B/4) - (1 + 2B) cot(θ/2)/8) / x` and `w` makes the sum 0.
/// `T = 8μ/(3k) L`, scaled like the paper's `λ q` so that for `k = 2` it is exactly `∂/∂v`
/// of the boundary B-spline patch.
pub fn crease_tangent_weights(k: usize) -> (f64, Vec<f64>, Vec<f64>) {
    let th = PI / k as f64;
    let c = th.cos();
    let x = (4.0 * (1.0 + c) + (16.0 * (1.0 + c) * (1.0 + c) + 128.0 * (1.0 + c)).sqrt()) / 64.0;
    let mu = 0.25 + x;
    let bb = 1.0 / (16.0 * x);
    let sum_s = 1.0 / (0.5 * th).tan();
    let gamma = (th.sin() * (1.0 / 16.0 + bb / 4.0) - (1.0 + 2.0 * bb) * sum_s / 8.0) / x;
    let scale = 8.0 * mu / (3.0 * k as f64);
    let a: Vec<f64> = (0..=k)
        .map(|i| {
            if i == 0 || i == k {
                scale * gamma
            } else {
                scale * (i as f64 * th).sin()
            }
        })
        .collect();
    let b: Vec<f64> = (0..k)
        .map(|i| scale * bb * ((i as f64 * th).sin() + ((i + 1) as f64 * th).sin()))
        .collect();
    // f_i = 4 c_i - v - e_i - e_{i+1}, e_i = 2 m_i - v.
    let wm: Vec<f64> = (0..=k)
        .map(|i| {
            let bp = if i > 0 { b[i - 1] } else { 0.0 };
            let bn = if i < k { b[i] } else { 0.0 };
            2.0 * (a[i] - bp - bn)
        })
        .collect();
    let wc: Vec<f64> = b.iter().map(|x| 4.0 * x).collect();
    let wv = -(wm.iter().sum::<f64>() + wc.iter().sum::<f64>());
    (wv, wm, wc)
}

/// The per-vertex sums of a smooth vertex's edge points (§3.2-3.3): the limit position `p` and
/// the two Fourier sums of the ring
/// `q_c = κ Σ_i (a cos(2πi/n) m_i + b cos((2πi+π)/n) c_i)`,
/// `q_s = κ Σ_i (a sin(2πi/n) m_i + b sin((2πi+π)/n) c_i)`, with `a = 1 - σ cos(π/n)`,
/// `b = 2σ`, `σ = (4 + cos²(π/n))^(-1/2)`, `κ = 2/3 s(n) λ 2/n` (`s(n)` the tangent factor of
/// [`GregoryTangents::ring_factors`]: 1 for the paper's construction). Since
/// `cos(2π(i-j)/n) = cos(2πi/n) cos(2πj/n) + sin(2πi/n) sin(2πj/n)`, the paper's edge point
/// `e_j = p + 2/3 s(n) λ q_j` with
/// `q_j = 2/n Σ_i (a cos(2π(i-j)/n) m_i + b cos((2π(i-j)+π)/n) c_i)` is
/// `p + cos(2πj/n) q_c + sin(2πj/n) q_s` (the per-vertex stage of §4.1).
#[derive(Debug, Clone)]
pub struct InteriorBasis<P = DVec3> {
    /// Limit position `p = (n-3)/(n+5) v + 4/(n(n+5)) Σ (m_i + c_i)` (§3.2, the stencil
    /// generalised to mixed quad/triangle rings).
    pub p: P,
    /// The cosine sum `q_c`.
    pub qc: P,
    /// The sine sum `q_s`.
    pub qs: P,
}

impl<P: GregoryPoint> InteriorBasis<P> {
    /// The sums of a ring whose faces close around the vertex.
    pub fn new(ring: &VertexRing<P>, tangents: GregoryTangents) -> InteriorBasis<P> {
        let n = ring.m.len();
        debug_assert_eq!(ring.c.len(), n);
        let nf = n as f64;
        let mut p = combine(&[((nf - 3.0) / (nf + 5.0), &ring.v)]);
        let w = 4.0 / (nf * (nf + 5.0));
        for i in 0..n {
            p.add_scaled(w, &ring.m[i]);
            p.add_scaled(w, &ring.c[i]);
        }
        let cos_pi_n = (PI / nf).cos();
        let sigma = 1.0 / (4.0 + cos_pi_n * cos_pi_n).sqrt();
        let factors = tangents.vertex_ring_factors(&ring.face_sizes, ring.decayed_corner);
        let scale = (2.0 / 3.0) * (factors.tangent * subdominant_eigenvalue(n)) * 2.0 / nf;
        let (a, b) = (scale * (1.0 - sigma * cos_pi_n), scale * 2.0 * sigma);
        let (mut qc, mut qs) = (P::zero(), P::zero());
        for i in 0..n {
            let t = 2.0 * PI * i as f64 / nf;
            let (sm, cm) = t.sin_cos();
            let (sc, cc) = (t + PI / nf).sin_cos();
            qc.add_scaled(a * cm, &ring.m[i]);
            qc.add_scaled(b * cc, &ring.c[i]);
            qs.add_scaled(a * sm, &ring.m[i]);
            qs.add_scaled(b * sc, &ring.c[i]);
        }
        InteriorBasis { p, qc, qs }
    }
}

/// `(sin, cos)` of `2 pi j / n`, the weights of `q_s` and `q_c` in a smooth vertex's edge point
/// `e_j` ([`InteriorBasis`]): one expression wherever those weights are written, so that rows
/// written elsewhere (the end caps' turned rows) are bitwise the construction's.
pub fn edge_sin_cos(j: usize, n: usize) -> (f64, f64) {
    (2.0 * PI * j as f64 / n as f64).sin_cos()
}

/// Whether [`GregoryVertex::new`] takes [`GregoryVertex::interior`] on `ring`: no sharp edge,
/// no corner tag, and the faces close around the vertex.
pub fn is_interior_ring<P>(ring: &VertexRing<P>) -> bool {
    !ring.corner && !ring.sharp.contains(&true) && ring.c.len() == ring.m.len()
}

/// Which construction [`GregoryVertex::new`] takes on a ring.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Rule {
    /// No sharp edge, no corner tag, faces closed around the vertex.
    Interior,
    /// One infinitely sharp edge (this ring edge), faces closed around the vertex.
    Dart(usize),
    /// Corner tag with fewer than two sharp edges.
    Cone,
    /// Two sharp edges, no corner tag.
    Crease,
    /// Corner tag (or more than two sharp edges) with at least two sharp edges.
    Corner,
    /// Not covered (a ring that does not close without a sharp edge).
    Uncovered,
}

/// What the rules read of a ring's edges ([`VertexRing::sharp`]): how many there are, how many
/// are infinitely sharp, and the first sharp one's place (0 without one).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct SharpEdges {
    /// Edges of the ring.
    pub edges: usize,
    /// Infinitely sharp edges.
    pub sharp: usize,
    /// Ring index of the first infinitely sharp edge (0 without one).
    pub first: usize,
}

impl SharpEdges {
    /// The counts of `sharp` (per edge: infinitely sharp).
    pub fn of(sharp: &[bool]) -> SharpEdges {
        Self::of_flags(sharp.iter().copied())
    }

    /// The counts of the per-edge flags `sharp` (infinitely sharp), in one pass.
    #[inline(always)]
    pub fn of_flags(sharp: impl IntoIterator<Item = bool>) -> SharpEdges {
        let mut shape = SharpEdges {
            edges: 0,
            sharp: 0,
            first: 0,
        };
        for s in sharp {
            if s {
                if shape.sharp == 0 {
                    shape.first = shape.edges;
                }
                shape.sharp += 1;
            }
            shape.edges += 1;
        }
        shape
    }
}

impl Rule {
    fn of<P>(ring: &VertexRing<P>) -> Rule {
        Rule::of_shape(SharpEdges::of(&ring.sharp), ring.corner, ring.c.len())
    }

    /// [`Rule::of`] a ring with these edges, corner tag and face count.
    pub(super) fn of_shape(edges: SharpEdges, corner: bool, faces: usize) -> Rule {
        let sharp = edges.sharp;
        let closed = faces == edges.edges;
        if sharp == 1 && !corner && closed {
            Rule::Dart(edges.first)
        } else if corner && sharp < 2 {
            Rule::Cone
        } else if corner {
            Rule::Corner
        } else if sharp == 2 {
            Rule::Crease
        } else if sharp == 0 && closed {
            Rule::Interior
        } else {
            Rule::Uncovered
        }
    }
}

/// Whether [`GregoryVertex::new`] (equally [`GregoryVertex::from_vertex_points`]) is `Some` on a
/// ring with these edges, corner tag and face count, without building it: the
/// interior rule always, a dart when `darts` solves its valence and sharp edge, a cone of at
/// least two edges whose faces close, a crease or corner with a face.
pub(super) fn has_construction(
    edges: SharpEdges,
    corner: bool,
    faces: usize,
    darts: &DartLimits,
) -> bool {
    let n = edges.edges;
    match Rule::of_shape(edges, corner, faces) {
        Rule::Interior => true,
        Rule::Dart(d) => darts.get(n, d).is_some(),
        Rule::Cone => n >= 2 && faces == n,
        Rule::Crease | Rule::Corner => faces > 0,
        Rule::Uncovered => false,
    }
}

/// Derived points per vertex of the two-stage construction ([`GregoryVertex::vertex_points`]).
pub const VERTEX_POINTS: usize = 3;

/// The smallest crease sector (faces) whose cross-boundary tangent is a derived point
/// ([`GregoryVertex::vertex_points`]). A sector of one face has no inner edge; one of two
/// faces has one inner edge point, whose tangent reads six ring vertices, mostly those its
/// corner point and sharp edge point read already: a derived point there adds more row terms
/// than it saves (`catmark_car`, isolation 2 / 4, single-crease patches off: 1,080,333 /
/// 3,506,711 terms from three faces, 1,085,209 / 3,526,659 from two, 1,084,945 / 3,511,323
/// without crease vertex points).
const DERIVED_CREASE_SECTOR: usize = 3;

impl<P> GregoryVertex<P> {
    /// The data with every point `x` replaced by `point(x)` (in the order `p`, `e`, `r_plus`,
    /// `r_minus`), the rest as it is.
    pub(super) fn map<Q>(&self, mut point: impl FnMut(&P) -> Q) -> GregoryVertex<Q> {
        let p = point(&self.p);
        let mut all = |xs: &[P]| xs.iter().map(&mut point).collect();
        GregoryVertex {
            kind: self.kind,
            n: self.n,
            p,
            e: all(&self.e),
            r_plus: all(&self.r_plus),
            r_minus: all(&self.r_minus),
            cosine: self.cosine.clone(),
            one_sided: self.one_sided.clone(),
        }
    }
}

impl<P: GregoryPoint> GregoryVertex<P> {
    /// The construction for any supported ring: [`Self::interior`] when no edge is sharp,
    /// [`Self::dart`] at one sharp edge, [`Self::cone`] at a corner tag with fewer than two
    /// sharp edges, otherwise [`Self::sectored`]. `None` for rings the construction does not
    /// cover (a ring that does not close: fewer faces than edges without a sharp edge, e.g.
    /// next to a hole).
    pub fn new(
        ring: &VertexRing<P>,
        tangents: GregoryTangents,
        darts: &DartLimits,
    ) -> Option<GregoryVertex<P>> {
        match Rule::of(ring) {
            Rule::Dart(_) => Self::dart(ring, tangents, darts),
            Rule::Cone => Self::cone(ring),
            Rule::Crease | Rule::Corner => Self::sectored(ring, tangents),
            Rule::Interior => Some(Self::interior(ring, tangents)),
            Rule::Uncovered => None,
        }
    }

    /// The first stage of the two-stage construction (§4.1: per-vertex sums computed once,
    /// before the per-patch points): derived points of `ring` of which every corner and edge
    /// point of [`Self::new`] is a fixed combination with `O(1)` other ring points
    /// ([`Self::from_vertex_points`]), so stencil rows built over them hold `O(1)` terms per
    /// corner instead of `O(n)`:
    /// - smooth: `p`, `q_c`, `q_s` ([`InteriorBasis`]; `e_j = p + cos q_c + sin q_s`);
    /// - dart: `p = l · ring` and the two exact tangent masks applied, `t_1 · ring`,
    ///   `t_2 · ring` ([`Self::dart`]; `e_j = p + a_j t_1 · ring + b_j t_2 · ring`);
    /// - crease and boundary: the scaled cross-boundary tangent `s(k) T/3` of each of its (at
    ///   most two) sectors of `k >= DERIVED_CREASE_SECTOR` faces in [`sectors`] order, zero for
    ///   a smaller sector (its tangent stays expanded) and for a missing second sector; the
    ///   third point zero ([`Self::sectored`]).
    ///
    /// `None` for corner and cone rings, whose points read `O(1)` ring points each already
    /// (`p = v`, chords and the sharp edges' points), and for rings not covered.
    pub fn vertex_points(
        ring: &VertexRing<P>,
        tangents: GregoryTangents,
        darts: &DartLimits,
    ) -> Option<[P; 3]> {
        match Rule::of(ring) {
            Rule::Interior => {
                let InteriorBasis { p, qc, qs } = InteriorBasis::new(ring, tangents);
                Some([p, qc, qs])
            }
            Rule::Dart(d) => {
                let lim = darts.get(ring.m.len(), d)?;
                let [t1, t2] = &lim.tangents;
                Some([
                    lim.apply(&lim.position, ring),
                    lim.apply(t1, ring),
                    lim.apply(t2, ring),
                ])
            }
            Rule::Crease => {
                let mut out = [P::zero(), P::zero(), P::zero()];
                let secs = sectors(&ring.sharp, ring.c.len());
                for (i, (t, sec)) in out.iter_mut().zip(secs).enumerate() {
                    if sec.faces >= DERIVED_CREASE_SECTOR {
                        *t = crease_sector_tangent(ring, tangents, i, sec);
                    }
                }
                Some(out)
            }
            Rule::Cone | Rule::Corner | Rule::Uncovered => None,
        }
    }

    /// [`Self::new`] with the first stage given: `points` the ring's
    /// [`Self::vertex_points`] (ignored on corner and cone rings), computed elsewhere. In weight
    /// space with `points` the unit weights of three derived points, the second stage of the
    /// adaptive end caps' rows; on positions with `points = vertex_points(ring)`, bitwise
    /// [`Self::new`].
    pub fn from_vertex_points(
        ring: &VertexRing<P>,
        tangents: GregoryTangents,
        darts: &DartLimits,
        points: [P; 3],
    ) -> Option<GregoryVertex<P>> {
        let [a, b, c] = points;
        match Rule::of(ring) {
            Rule::Interior => Some(Self::interior_from_basis(
                ring,
                tangents,
                InteriorBasis { p: a, qc: b, qs: c },
            )),
            Rule::Dart(d) => Self::dart_from_points(ring, tangents, darts, d, [a, b, c]),
            Rule::Crease => Self::sectored_with(ring, tangents, &|i, sec| match i {
                _ if sec.faces < DERIVED_CREASE_SECTOR => {
                    crease_sector_tangent(ring, tangents, i, sec)
                }
                0 => a.clone(),
                _ => b.clone(),
            }),
            Rule::Corner => Self::sectored(ring, tangents),
            Rule::Cone => Self::cone(ring),
            Rule::Uncovered => None,
        }
    }

    /// The construction for a vertex whose faces close around it (no boundary, no crease):
    /// [`Self::interior_from_basis`] of [`InteriorBasis::new`].
    pub fn interior(ring: &VertexRing<P>, tangents: GregoryTangents) -> GregoryVertex<P> {
        Self::interior_from_basis(ring, tangents, InteriorBasis::new(ring, tangents))
    }

    /// [`Self::interior`] with its per-vertex sums given: every edge point is
    /// `e_j = p + cos(2πj/n) q_c + sin(2πj/n) q_s` ([`InteriorBasis`]), a fixed combination of
    /// the three; `r_j = 1/3 (m_{j+1} - m_{j-1}) + 2/3 (c_j - c_{j-1})` (§3.4; the end caps'
    /// valence-3 rings reweight the two, [`GregoryTangents::transversal_shape`]). With `basis`
    /// the unit weights of three derived points, the rows of every patch at the vertex hold
    /// `O(1)` terms instead of `O(n)` (the two-stage form of the adaptive end caps).
    pub fn interior_from_basis(
        ring: &VertexRing<P>,
        tangents: GregoryTangents,
        basis: InteriorBasis<P>,
    ) -> GregoryVertex<P> {
        let n = ring.m.len();
        debug_assert_eq!(ring.c.len(), n);
        let nf = n as f64;
        let factors = tangents.vertex_ring_factors(&ring.face_sizes, ring.decayed_corner);
        let InteriorBasis { p, qc, qs } = basis;
        let e = (0..n)
            .map(|j| {
                let (sn, cs) = edge_sin_cos(j, n);
                combine(&[(1.0, &p), (cs, &qc), (sn, &qs)])
            })
            .collect();
        let shape = tangents.vertex_transversal_shape(&ring.face_sizes, ring.decayed_corner);
        let mut r: Vec<P> = (0..n).map(|j| inner_r(ring, j, n, shape)).collect();
        if factors.transversal != 1.0 {
            r = r
                .iter()
                .map(|x| combine(&[(factors.transversal, x)]))
                .collect();
        }
        let r_minus = (0..n)
            .map(|j| combine(&[(-1.0, &r[(j + 1) % n])]))
            .collect();
        GregoryVertex {
            kind: VertexKind::Smooth,
            n,
            p,
            e,
            r_plus: r,
            r_minus,
            cosine: vec![(2.0 * PI / nf).cos(); n],
            one_sided: Vec::new(),
        }
    }

    /// The construction at a dart (an interior vertex with one infinitely sharp edge `d`).
    ///
    /// The dart keeps the smooth vertex rule, but its sharp edge takes the crease (midpoint)
    /// rule, so the smooth limit stencils of §3.2-3.3 are not eigenvectors of its subdivision
    /// matrix. `dart_limit` computes, on the split ring, the exact limit position mask `l`
    /// (the dominant left eigenvector) and two masks `t_1, t_2` spanning the exact tangent plane
    /// (the two leading subdominant left eigenvectors, as `subdiv::limit` does). Then
    /// - `p = l · ring`;
    /// - `e_j = p + P(2/3 s(n) λ q_j)`, the smooth edge tangent of §3.3 projected (orthogonally, in
    ///   mask space) onto `span(t_1, t_2)`: every edge point lies in the exact tangent plane
    ///   and tends to the smooth one when the dart's perturbation vanishes;
    /// - `r` and `cos(2π/n)` as for a smooth vertex (§3.4).
    pub fn dart(
        ring: &VertexRing<P>,
        tangents: GregoryTangents,
        darts: &DartLimits,
    ) -> Option<GregoryVertex<P>> {
        let d = ring.sharp.iter().position(|&s| s)?;
        let lim = darts.get(ring.m.len(), d)?;
        let [t1, t2] = &lim.tangents;
        let points = [
            lim.apply(&lim.position, ring),
            lim.apply(t1, ring),
            lim.apply(t2, ring),
        ];
        Self::dart_from_points(ring, tangents, darts, d, points)
    }

    /// [`Self::dart`] from its first stage `[p, t_1 · ring, t_2 · ring]`
    /// ([`Self::vertex_points`]): the projection of each smooth edge mask onto
    /// `span(t_1, t_2)` is `a_j t_1 + b_j t_2` ([`RingLimit::project_coefficients`]), so
    /// `e_j = p + a_j (t_1 · ring) + b_j (t_2 · ring)`. The masks of sharp edge `d` being
    /// edge 0's rotated by `d` ([`DartLimits::get`]), `(a_j, b_j)` are projected on edge 0's
    /// masks with edge `j - d`'s smooth mask: the same coefficients, whose bits depend only on
    /// `j - d`, not on where the vertex's ring starts (the end caps' shared rows, read from
    /// another ring start, are then bitwise each face's at its edge points).
    fn dart_from_points(
        ring: &VertexRing<P>,
        tangents: GregoryTangents,
        darts: &DartLimits,
        d: usize,
        points: [P; 3],
    ) -> Option<GregoryVertex<P>> {
        let n = ring.m.len();
        let lim = darts.get(n, 0)?;
        // `r` and the cosines of a smooth vertex; its edge points (zero sums) are replaced.
        let zero = InteriorBasis {
            p: P::zero(),
            qc: P::zero(),
            qs: P::zero(),
        };
        let smooth = Self::interior_from_basis(ring, tangents, zero);
        let [p, t1, t2] = points;
        // The smooth edge points' offsets `e_j - p` as masks: the same sums as `interior`.
        let scale = tangents.ring_scale(n, ring.quads());
        let e = (0..n)
            .map(|j| {
                let edge = smooth_edge_mask(n, (j + n - d) % n, scale);
                let (a, b) = lim.project_coefficients(&edge);
                combine(&[(1.0, &p), (a, &t1), (b, &t2)])
            })
            .collect();
        Some(GregoryVertex {
            kind: VertexKind::Dart,
            p,
            e,
            ..smooth
        })
    }

    /// The construction at a cone point: the corner rule (`v` stays) with fewer than two sharp
    /// edges, so one sector wraps the whole (closed) ring.
    ///
    /// The exact surface has no tangent plane there: the ring's rotationally symmetric mode
    /// (eigenvalue `μ₀ = (3 + √5)/8 ≈ 0.6545` on a ring of quads, from the 2 × 2 block
    /// `[[1/2, 1/8], [1/2, 1/4]]` of the mean edge and face offsets once `v` is fixed) exceeds
    /// every angular mode (`λ ≤ 1/2`), so every edge curve leaves `v` along the one cusp axis
    /// with an infinite derivative (`|x(t) - v| ~ t^{-log₂ μ₀} = t^0.61`), and each face's
    /// normal tends to a vector perpendicular to the axis that turns with the direction of
    /// approach. No finite edge point is exact. The approximation (as OpenSubdiv's end caps at
    /// sharp corners): `p = v` (exact), edge points along the refined edges `e_j = (v + 2m_j)/3`
    /// (the edge chords, which turn towards the axis level by level), `r` and `cos(2π/n)` as
    /// for a smooth vertex (§3.4). Each face keeps its own corner normal.
    pub fn cone(ring: &VertexRing<P>) -> Option<GregoryVertex<P>> {
        let n = ring.m.len();
        if n < 2 || ring.c.len() != n {
            return None;
        }
        let e = ring
            .m
            .iter()
            .map(|m| combine(&[(1.0 / 3.0, &ring.v), (2.0 / 3.0, m)]))
            .collect();
        let r: Vec<P> = (0..n).map(|j| inner_r(ring, j, n, 0.0)).collect();
        let r_minus = (0..n)
            .map(|j| combine(&[(-1.0, &r[(j + 1) % n])]))
            .collect();
        Some(GregoryVertex {
            kind: VertexKind::Cone,
            n,
            p: ring.v.clone(),
            e,
            r_plus: r,
            r_minus,
            cosine: vec![(2.0 * PI / n as f64).cos(); n],
            one_sided: Vec::new(),
        })
    }

    /// The construction at a boundary, crease or corner vertex (§4.6), sector by sector.
    ///
    /// - `p`: corner `v`; crease `(a + 4v + b)/6` of the two sharp-edge neighbours
    ///   (`= (v + m_a + m_b)/3`).
    /// - Sharp edge `j`: `e_j = (2v + w_j)/3 = (v + 2 m_j)/3` (the cubic B-spline curve).
    /// - Inner edge at angle `θ = iα` of a sector with `k` faces starting at sharp edge `s` and
    ///   ending at sharp edge `t`: corners (`α = π/(2k)`, the sector spans a right angle)
    ///   `e = p + cosθ (e_s - p) + sinθ (e_t - p)`; creases (`α = π/k`)
    ///   `e = p + cosθ (e_s - p) + sinθ s(k) T/3` with `T` from [`crease_tangent_weights`] and
    ///   `s(k)` the cross-boundary factor [`GregoryTangents::crease_scale`] (1: the paper's).
    ///   These edge points form the affine `n`-gon of condition (1) with `cos(2π/n) = cos α`.
    /// - `r` across inner edges as in §3.4; across a sharp edge, the ring reflected across it
    ///   (`m_{s-1} → 2v - m_{s+1}`, `c_{s-1} → 2 m_s - c_s`, the phantom rule of boundary
    ///   B-splines): `r = 2/3 (m_{s+1} - v) + 4/3 (c_s - m_s)`.
    /// - `Optimal` on rings of quads marks the sharp sides of every face (`one_sided`): the
    ///   patch assembly makes the face point beside one sharp edge the corner's other one, and
    ///   a face alone in a corner sector takes the far cosine 0 in eq. 6 (OpenSubdiv's rules,
    ///   `tangents_boundary`).
    /// - A crease sector of one face (`one_face_crease_r`, end caps only): `cos = 0` and face
    ///   points in the exact tangent plane.
    /// - A corner sector of more than two faces (end caps only): inner edge points on the
    ///   refined chords `(v + 2 m_j)/3`, as at a cone point ([`Self::cone`]): the sector's leading
    ///   interior mode (0.58 to 0.63) exceeds the sharp edges' 1/2, so the exact inner edge
    ///   curves have no finite tangent and the sharp edges' tangents do not span the surface.
    pub fn sectored(ring: &VertexRing<P>, tangents: GregoryTangents) -> Option<GregoryVertex<P>> {
        Self::sectored_with(ring, tangents, &|i, sec| {
            crease_sector_tangent(ring, tangents, i, sec)
        })
    }

    /// [`Self::sectored`] with the scaled cross-boundary tangent `s(k) T/3` of crease sector `i`
    /// (in [`sectors`] order, `k >= 2` faces) given by `tangent(i, sector)`.
    fn sectored_with(
        ring: &VertexRing<P>,
        tangents: GregoryTangents,
        tangent: &dyn Fn(usize, Sector) -> P,
    ) -> Option<GregoryVertex<P>> {
        let ne = ring.m.len();
        let nf = ring.c.len();
        let sharp_edges: Vec<usize> = (0..ne).filter(|&j| ring.sharp[j]).collect();
        let kind = if ring.corner {
            VertexKind::Corner
        } else if sharp_edges.len() == 2 {
            VertexKind::Crease
        } else {
            return None;
        };
        if sharp_edges.len() < 2 || nf == 0 {
            return None;
        }
        let p = match kind {
            VertexKind::Crease => {
                let (a, b) = (sharp_edges[0], sharp_edges[1]);
                combine(&[
                    (1.0 / 3.0, &ring.v),
                    (1.0 / 3.0, &ring.m[a]),
                    (1.0 / 3.0, &ring.m[b]),
                ])
            }
            _ => ring.v.clone(),
        };
        let mut e: Vec<P> = vec![P::zero(); ne];
        for &j in &sharp_edges {
            e[j] = combine(&[(1.0 / 3.0, &ring.v), (2.0 / 3.0, &ring.m[j])]);
        }
        let mut r_plus = vec![P::zero(); nf];
        let mut r_minus = vec![P::zero(); nf];
        let mut cosine = vec![0.0; nf];
        // Faces of the sector holding each face (0 in a crease sector of one face).
        let mut sector_of = vec![0; nf];
        for (index, sec) in sectors(&ring.sharp, nf).into_iter().enumerate() {
            let (s, k) = (sec.start, sec.faces);
            let t = (s + k) % ne;
            let edge = |i: usize| (s + i) % ne;
            let face = |i: usize| (s + i) % ne;
            let alpha = match kind {
                VertexKind::Corner => PI / (2.0 * k as f64),
                _ if k < 2 => {
                    let (rp, rm) = one_face_crease_r(ring, &p, &e, s, t);
                    r_plus[face(0)] = rp;
                    r_minus[face(0)] = rm;
                    continue;
                }
                _ => PI / k as f64,
            };
            let ds = combine(&[(1.0, &e[s]), (-1.0, &p)]);
            let second = match kind {
                VertexKind::Corner => combine(&[(1.0, &e[t]), (-1.0, &p)]),
                _ => tangent(index, sec),
            };
            for i in 1..k {
                e[edge(i)] = if kind == VertexKind::Corner && k > 2 {
                    // Wide corner sector: the refined edge's chord (see above).
                    combine(&[(1.0 / 3.0, &ring.v), (2.0 / 3.0, &ring.m[edge(i)])])
                } else {
                    let (sn, cs) = (i as f64 * alpha).sin_cos();
                    combine(&[(1.0, &p), (cs, &ds), (sn, &second)])
                };
            }
            for i in 0..k {
                cosine[face(i)] = alpha.cos();
                sector_of[face(i)] = k;
            }
            // Transversal vectors: inner edges (§3.4), then the two reflected sharp sides.
            for i in 1..k {
                let r = inner_r(ring, edge(i), ne, 0.0);
                r_minus[face(i - 1)] = combine(&[(-1.0, &r)]);
                r_plus[face(i)] = r;
            }
            r_plus[face(0)] = combine(&[
                (2.0 / 3.0, &ring.m[edge(1)]),
                (-2.0 / 3.0, &ring.v),
                (4.0 / 3.0, &ring.c[face(0)]),
                (-4.0 / 3.0, &ring.m[s]),
            ]);
            r_minus[face(k - 1)] = combine(&[
                (2.0 / 3.0, &ring.m[edge(k - 1)]),
                (-2.0 / 3.0, &ring.v),
                (4.0 / 3.0, &ring.c[face(k - 1)]),
                (-4.0 / 3.0, &ring.m[t]),
            ]);
        }
        Some(GregoryVertex {
            kind,
            n: nf,
            p,
            e,
            r_plus,
            r_minus,
            cosine,
            one_sided: if tangents.one_sided_face_points(ring.quads()) {
                let side =
                    |j: usize, x: usize| u8::from(ring.one_sided_edge(x, kind, sector_of[j]));
                (0..nf)
                    .map(|j| side(j, j) | (side(j, (j + 1) % ne) << 1))
                    .collect()
            } else {
                Vec::new()
            },
        })
    }
}

/// The transversal vector across inner edge `j` of a ring with `ne` edges, pointing into face
/// `j` (§3.4), with the shape `t` ([`GregoryTangents::transversal_shape`]):
/// `r_j = (1/3 + t) (m_{j+1} - m_{j-1}) + (2/3 - t) (c_j - c_{j-1})`, the paper's at `t = 0`
/// (bit for bit: `1/3 + 0` and `2/3 - 0` are the same weights).
fn inner_r<P: GregoryPoint>(ring: &VertexRing<P>, j: usize, ne: usize, t: f64) -> P {
    let (next, prev) = ((j + 1) % ne, (j + ne - 1) % ne);
    let (wm, wc) = (1.0 / 3.0 + t, 2.0 / 3.0 - t);
    combine(&[
        (wm, &ring.m[next]),
        (-wm, &ring.m[prev]),
        (wc, &ring.c[j]),
        (-wc, &ring.c[prev]),
    ])
}

/// The scaled cross-boundary tangent `s(k) T/3` of crease sector `sec` (`k >= 2` faces, number
/// `index` in [`sectors`] order) of `ring`: [`crease_tangent_weights`] over the sector's edge
/// midpoints and face centroids, times the factor [`GregoryTangents::sector_scale`] (§4.6; the
/// paper's at `s = 1`; a frozen per-vertex factor under `Fitted`).
fn crease_sector_tangent<P: GregoryPoint>(
    ring: &VertexRing<P>,
    tangents: GregoryTangents,
    index: usize,
    sec: Sector,
) -> P {
    let (s, k, ne) = (sec.start, sec.faces, ring.m.len());
    let (wv, wm, wc) = crease_tangent_weights(k);
    // `f * w` is `w` bit for bit at the paper's `f = 1`.
    let far = (1..k).map(|i| ring.far_sector.get((s + i) % ne).copied().unwrap_or(0));
    let f = tangents.sector_scale(
        k,
        sector_band(k, far),
        ring.quads(),
        ring.crease_factors,
        index,
    );
    let mut tan = combine(&[(f * wv / 3.0, &ring.v)]);
    for (i, w) in wm.iter().enumerate() {
        tan.add_scaled(f * w / 3.0, &ring.m[(s + i) % ne]);
    }
    for (i, w) in wc.iter().enumerate() {
        tan.add_scaled(f * w / 3.0, &ring.c[(s + i) % ne]);
    }
    tan
}

/// `(r_plus, r_minus)` of the face alone in a crease sector between sharp edges `s` and `t`
/// (a valence-2 `EdgeOnly` boundary corner, or two infinitely sharp edges around one face).
///
/// With the sector's ring `v, a = w_s, b = w_t, f` the crease rule is closed on it: `a - b` is
/// a left eigenvector of `1/2` (the crease curve) and `a + b - 2v`, `f - v` form a Jordan block
/// of `1/4` (`(f - v)' = (f - v)/4 + (a + b - 2v)/8`), so the limit normal is
/// `(a - b) × (a + b - 2v)`: the plane of `v, a, b`, which holds `p = (a + 4v + b)/6`. The edge
/// points of both sharp edges are the crease curve's (`(2v + w)/3`, exact), so `e_s - p =
/// -(e_t - p)` and the patch's corner is singular; near it the patch normal is
/// `(e_s - p) × (A + 9 (f - p))` to first order, with `A = a + b - 2v` the curve's second
/// derivative there and `f` the face point (`e_s + e_t - p = p` makes the twist `f - p`).
/// Putting the face points in the tangent plane makes that normal the exact one whatever the
/// direction of approach: `f = p + (m_s + m_t - 2v)/3` (`= p + A/6`, OpenSubdiv's face point
/// on a flat corner, `(4v + 2a + 2b + f)/9`, when `f = a + b - v`). With the sector's
/// `cos = 0`, eq. 6 gives `f = e + (c_b (p - e) + r)/d`, so `r = 3 (p - e) + m_s + m_t - 2v`
/// (the `c_b` and `d = 4` terms move `f` along the crease tangent only: still in the plane).
fn one_face_crease_r<P: GregoryPoint>(
    ring: &VertexRing<P>,
    p: &P,
    e: &[P],
    s: usize,
    t: usize,
) -> (P, P) {
    let r = |x: usize| {
        combine(&[
            (3.0, p),
            (-3.0, &e[x]),
            (1.0, &ring.m[s]),
            (1.0, &ring.m[t]),
            (-2.0, &ring.v),
        ])
    };
    (r(s), r(t))
}

/// Face point next to the edge from corner `a` to corner `b` of a patch (eq. 6, re-derived from
/// conditions (1) and (3)):
/// `f = (c_b p_a + (d - 2 c_a - c_b) e_ab + 2 c_a e_ba + r) / d`, where `c_x = cos(2π/n_x)` (of
/// the sector holding the patch at a crease or corner vertex), `e_ab` is the edge point at `a`
/// towards `b`, `e_ba` the one at `b` towards `a`, `r` the transversal vector at `a` across the
/// edge pointing into the patch, and `d` is 3 for quads and 4 for triangles. (The printed eq. 6
/// shows `v` and `e_0^-` where the derivation from condition (3) gives `p_a` and the edge point
/// at the far end; with `n = 4` both reduce to `e_ab + r/3`, the B-spline case.)
pub fn face_point_cos<P: GregoryPoint>(
    d: f64,
    c_a: f64,
    c_b: f64,
    p_a: &P,
    e_ab: &P,
    e_ba: &P,
    r: &P,
) -> P {
    combine(&face_point_terms(d, c_a, c_b, p_a, e_ab, e_ba, r))
}

/// The terms `(weight, point)` [`face_point_cos`] combines, in its order (so a caller can
/// combine them where it likes, with the same bits).
pub(super) fn face_point_terms<'a, P>(
    d: f64,
    c_a: f64,
    c_b: f64,
    p_a: &'a P,
    e_ab: &'a P,
    e_ba: &'a P,
    r: &'a P,
) -> [(f64, &'a P); 4] {
    [
        (c_b / d, p_a),
        ((d - 2.0 * c_a - c_b) / d, e_ab),
        (2.0 * c_a / d, e_ba),
        (1.0 / d, r),
    ]
}

/// [`face_point_cos`] for interior vertices of valences `n_a`, `n_b` (`c = cos(2π/n)`), on
/// positions; bitwise equal to what the patch assembly computes for smooth corners.
pub fn face_point(
    d: f64,
    n_a: usize,
    n_b: usize,
    p_a: DVec3,
    e_ab: DVec3,
    e_ba: DVec3,
    r: DVec3,
) -> DVec3 {
    let c = |n: usize| (2.0 * PI / n as f64).cos();
    face_point_cos(d, c(n_a), c(n_b), &p_a, &e_ab, &e_ba, &r)
}

/// Limit masks of a ring configuration over the split ring `[v, m_0.., c_0..]` (see
/// [`dart_limit`]).
#[derive(Debug, Clone)]
pub struct RingLimit {
    /// Limit position weights (sum 1).
    pub position: Vec<f64>,
    /// Two tangent masks spanning the exact tangent plane (sum 0 each).
    pub tangents: [Vec<f64>; 2],
}

impl RingLimit {
    /// The masks of a dart of the same valence whose sharp edge is `d` ring edges further on
    /// (`d < n`): weight `1 + (i + d) % n` is this one's `1 + i`, and the same for the face
    /// centroids (`1 + n + …`); the vertex's weight stays.
    pub fn rotated(&self, d: usize) -> RingLimit {
        let n = (self.position.len() - 1) / 2;
        let rotate = |w: &[f64]| {
            let mut out = vec![0.0; w.len()];
            out[0] = w[0];
            for i in 0..n {
                let j = (i + d) % n;
                out[1 + j] = w[1 + i];
                out[1 + n + j] = w[1 + n + i];
            }
            out
        };
        RingLimit {
            position: rotate(&self.position),
            tangents: [rotate(&self.tangents[0]), rotate(&self.tangents[1])],
        }
    }

    /// `Σ w_k x_k` over the split ring.
    fn apply<P: GregoryPoint>(&self, w: &[f64], ring: &VertexRing<P>) -> P {
        let n = ring.m.len();
        let mut out = combine(&[(w[0], &ring.v)]);
        for i in 0..n {
            out.add_scaled(w[1 + i], &ring.m[i]);
        }
        for (i, c) in ring.c.iter().enumerate() {
            out.add_scaled(w[1 + n + i], c);
        }
        out
    }

    /// The coefficients `(a, b)` of the orthogonal projection `a t_1 + b t_2` of mask `q` onto
    /// `span(tangents)` (normal equations of the 2 × 2 Gram matrix).
    fn project_coefficients(&self, q: &[f64]) -> (f64, f64) {
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let [t1, t2] = &self.tangents;
        let (g11, g12, g22) = (dot(t1, t1), dot(t1, t2), dot(t2, t2));
        let (b1, b2) = (dot(t1, q), dot(t2, q));
        let det = g11 * g22 - g12 * g12;
        let a1 = (g22 * b1 - g12 * b2) / det;
        let a2 = (g11 * b2 - g12 * b1) / det;
        (a1, a2)
    }
}

/// The smooth edge-point offset `e_j - p = 2/3 s(n) λ q_j` of [`GregoryVertex::interior`] as a
/// mask over the split ring (zero weight on `v`).
fn smooth_edge_mask(n: usize, j: usize, factor: f64) -> Vec<f64> {
    let nf = n as f64;
    let cos_pi_n = (PI / nf).cos();
    let sigma = 1.0 / (4.0 + cos_pi_n * cos_pi_n).sqrt();
    let scale = (2.0 / 3.0) * (factor * subdominant_eigenvalue(n)) * 2.0 / nf;
    let mut q = vec![0.0; 1 + 2 * n];
    for i in 0..n {
        let k = ((i + n - j) % n) as f64;
        q[1 + i] = scale * (1.0 - sigma * cos_pi_n) * (2.0 * PI * k / nf).cos();
        q[1 + n + i] = scale * 2.0 * sigma * ((2.0 * PI * k + PI) / nf).cos();
    }
    q
}

/// `dart_limit` per `(n, d)`, solved once per valence `n` and cache: the split ring's
/// subdivision matrix of sharp edge `d` is that of edge 0 with the ring's indices rotated by
/// `d` (`dart_matrix`), so its masks are edge 0's rotated (`RingLimit::rotated`; the same
/// eigenvectors, the sums of the power iteration in another order: equal to rounding,
/// `tests::rotated_dart_masks_are_the_solves`). Each solve is a power iteration on a
/// `(2n + 1)²` matrix, read by both stages of the two-stage rows and the end-cap keys. One
/// cache lives as long as one build (an end-cap table, a vertex loop) and is shared by its
/// threads; a cache per call ([`DartLimits::default`]) solves every dart again.
#[derive(Debug, Default)]
pub struct DartLimits(Mutex<RingLimits>);

/// Masks per `(n, d)`, `None` where `dart_limit` has none.
type RingLimits = HashMap<(usize, usize), Option<Arc<RingLimit>>>;

impl DartLimits {
    /// An empty cache.
    pub fn new() -> DartLimits {
        DartLimits::default()
    }

    /// The masks of `dart_limit(n, d)`: `dart_limit(n, 0)` solved on the first request for
    /// valence `n`, rotated by `d` (outside the lock: two threads may both solve one valence,
    /// to the same bits).
    pub fn get(&self, n: usize, d: usize) -> Option<Arc<RingLimit>> {
        if let Some(lim) = self.lock().get(&(n, d)) {
            return lim.clone();
        }
        let lim = match d {
            0 => dart_limit(n, 0).map(Arc::new),
            _ if d >= n => None,
            _ => self.get(n, 0).map(|base| Arc::new(base.rotated(d))),
        };
        self.lock().entry((n, d)).or_insert(lim).clone()
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, RingLimits> {
        self.0
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    /// Number of `(n, d)` pairs solved.
    pub fn len(&self) -> usize {
        self.lock().len()
    }

    /// Whether no pair was solved.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Valences up to which [`dart_limit`] runs the power iterations of `subdiv::limit::masks`.
/// The dart's two leading subdominant eigenvalues and the next ones draw together like
/// `O(1/n²)` (valence 48: 0.65326, 0.65197, 0.64952), so those iterations (4000 steps) stall
/// from valence 48; `dart_limit_secular` solves every valence above.
pub const DART_POWER_ITERATION_MAX_VALENCE: usize = 40;

/// Largest `‖x S − λ x‖_∞ / ‖x‖_∞` `dart_limit_secular` accepts for its masks (measured:
/// 3e-11 at valence 48, 2e-12 at valence 200; rounding in the sums near the poles of the
/// secular equation).
const DART_RESIDUAL: f64 = 1e-9;

/// Exact limit masks of a dart of valence `n` whose sharp edge is ring edge `d`, over the split
/// ring `[v, m_0..m_{n-1}, c_0..c_{n-1}]`.
///
/// The split ring is closed under Catmull-Clark refinement whatever the face sizes (a face's
/// child at the vertex is always the quad `v', e'_i, F_i, e'_{i+1}` with `F_i = c_i`), so its
/// subdivision matrix `S` is `(2n+1)²` and depends only on `n` and `d`:
/// `v' = (n-3)/n v + 2/n avg(m) + 1/n avg(c)` (smooth vertex rule), `e'_i = (2 m_i + c_{i-1} +
/// c_i)/4` (smooth edge rule) except `e'_d = m_d` (crease rule), `m'_i = (v' + e'_i)/2`,
/// `c'_i = (v' + e'_i + c_i + e'_{i+1})/4`. Its left eigenvectors give the limit masks
/// (Halstead et al. 1993 §A); the spectrum of `S` is that of the one-ring matrix after one
/// step, so the tangent plane is the one `subdiv::limit` computes. Up to valence
/// [`DART_POWER_ITERATION_MAX_VALENCE`] by power iteration (`subdiv::limit::masks::eigen_limit`),
/// above by `dart_limit_secular`. `None` for `n < 2`, `d >= n`, or masks that miss their
/// eigen-equation (never seen; `dart_limit_secular`).
pub fn dart_limit(n: usize, d: usize) -> Option<RingLimit> {
    use crate::subdiv::limit::masks::eigen_limit;
    if n < 2 || d >= n {
        return None;
    }
    let s = dart_matrix(n, d);
    if n > DART_POWER_ITERATION_MAX_VALENCE {
        return dart_limit_secular(&s, n, d);
    }
    let (vi, mi) = (0usize, |i: usize| 1 + i % n);
    let mut x1 = vec![0.0; s.m];
    x1[mi(d)] = 1.0;
    x1[vi] = -1.0;
    let mut x2 = vec![0.0; s.m];
    x2[mi(d + 1)] = 1.0;
    x2[vi] = -1.0;
    let lim = eigen_limit(&s, vi, [x1, x2])?;
    Some(RingLimit {
        position: lim.position,
        tangents: lim.tangents,
    })
}

/// The subdivision matrix `S` of the split ring of a dart (see [`dart_limit`]), rows the ring
/// after one step.
fn dart_matrix(n: usize, d: usize) -> crate::subdiv::limit::masks::Dense {
    let m = 1 + 2 * n;
    let nf = n as f64;
    let (vi, mi, ci) = (0usize, |i: usize| 1 + i % n, |i: usize| 1 + n + i % n);
    let mut vrow = vec![0.0; m];
    vrow[vi] = (nf - 3.0) / nf;
    for i in 0..n {
        vrow[mi(i)] += 2.0 / (nf * nf);
        vrow[ci(i)] += 1.0 / (nf * nf);
    }
    let erow = |i: usize| {
        let mut r = vec![0.0; m];
        if i % n == d {
            r[mi(i)] = 1.0;
        } else {
            r[mi(i)] += 0.5;
            r[ci(i + n - 1)] += 0.25;
            r[ci(i)] += 0.25;
        }
        r
    };
    let mut a = vec![0.0; m * m];
    a[..m].copy_from_slice(&vrow);
    for i in 0..n {
        let (ei, ej) = (erow(i), erow(i + 1));
        for k in 0..m {
            a[mi(i) * m + k] = 0.5 * (vrow[k] + ei[k]);
            let own = if k == ci(i) { 1.0 } else { 0.0 };
            a[ci(i) * m + k] = 0.25 * (vrow[k] + ei[k] + own + ej[k]);
        }
    }
    crate::subdiv::limit::masks::Dense { m, a }
}

/// [`dart_limit`] without power iteration, for valences `n >= 8` (the bracket below holds no
/// sign change at valence 5; `dart_limit` calls it from valence 41): `S = S_0 + u δᵀ`, the smooth
/// split-ring matrix `S_0` plus a rank-one update, since only `e'_d` changes, by
/// `δ = m_d/2 − (c_{d−1} + c_d)/4`, and enters `m'_d` with weight 1/2 and `c'_{d−1}`, `c'_d`
/// with 1/4 (`u`). Both are symmetric under the reflection across edge `d`, so:
/// - an antisymmetric left eigenvector `x` of `S_0` has `x·u = 0` and stays one of `S`: the
///   leading one is the smooth tangent across edge `d` (the §3.3 edge mask turned a quarter
///   period, `sin` for `cos`), eigenvalue `λ(n)` ([`subdominant_eigenvalue`], the largest of `S`
///   after 1 from valence 5 up);
/// - a symmetric one is `x ∝ δᵀ (S_0 − μ)⁻¹` with `1 + δᵀ (S_0 − μ)⁻¹ u = 0`. `S_0` is
///   block-circulant: at frequency `k >= 1` it is the Hermitian block
///   `[[1/4, (1+ζ̄)/8], [(1+ζ)/8, s/16 + 1/4]]` on `(m, c)`, `ζ = e^{2πik/n}`,
///   `s = |1+ζ|² = 2 + 2 cos(2πk/n)`, at `k = 0` a 3 × 3 block with `v`, so the secular
///   equation is a sum of `n` closed-form terms and `x` a cosine sum. Its largest symmetric
///   root `μ` lies between the leading eigenvalues of the blocks `k = 2` and `k = 1`
///   (bisection).
///
/// The position is the dominant left eigenvector (power iteration, ratio `λ(n) < 0.66`). Every
/// mask must satisfy its eigen-equation to `DART_RESIDUAL` against `s` (built from the rules
/// directly), else `None`.
fn dart_limit_secular(
    s: &crate::subdiv::limit::masks::Dense,
    n: usize,
    d: usize,
) -> Option<RingLimit> {
    use crate::subdiv::limit::masks::dominant;
    if n < 8 {
        return None;
    }
    let nf = n as f64;
    let cos_k: Vec<f64> = (0..n).map(|k| (2.0 * PI * k as f64 / nf).cos()).collect();
    let s_k = |k: usize| 2.0 + 2.0 * cos_k[k % n];
    // The leading eigenvalue of the frequency-k block.
    let upper = |k: usize| {
        let (a, c) = (0.25, s_k(k) / 16.0 + 0.25);
        let det = a * c - s_k(k) / 64.0;
        0.5 * ((a + c) + ((a + c) * (a + c) - 4.0 * det).sqrt())
    };
    let det_k = |k: usize, mu: f64| (0.25 - mu) * (s_k(k) / 16.0 + 0.25 - mu) - s_k(k) / 64.0;
    // `δ̂_0ᵀ (B_0 − μ)⁻¹` on `(v, Σm, Σc)`.
    let rho0 = |mu: f64| {
        let b0 = [
            [(nf - 3.0) / nf, 2.0 / (nf * nf), 1.0 / (nf * nf)],
            [(nf - 3.0) / 2.0, 1.0 / nf + 0.25, 0.5 / nf + 0.25],
            [(nf - 3.0) / 4.0, 0.5 / nf + 0.25, 0.25 / nf + 0.5],
        ];
        let mut t = [[0.0; 3]; 3];
        for (i, row) in t.iter_mut().enumerate() {
            for (j, x) in row.iter_mut().enumerate() {
                *x = b0[j][i] - if i == j { mu } else { 0.0 };
            }
        }
        solve3(t, [0.0, 0.5, -0.5])
    };
    let secular = |mu: f64| {
        let r0 = rho0(mu);
        let mut g = 0.5 * (r0[1] + r0[2]);
        for k in 1..n {
            g += (1.0 - 4.0 * mu + s_k(k) * mu) / (16.0 * det_k(k, mu));
        }
        1.0 + g / nf
    };
    let (hi, lo) = (upper(1), upper(2));
    let (mut a, mut b) = (lo + 1e-9 * (hi - lo), hi - 1e-9 * (hi - lo));
    let (fa, fb) = (secular(a), secular(b));
    if !(fa.is_finite() && fb.is_finite()) || (fa > 0.0) == (fb > 0.0) {
        log::warn!("dart of valence {n}: no root of the secular equation in ({lo}, {hi})");
        return None;
    }
    loop {
        let c = 0.5 * (a + b);
        if c <= a || c >= b {
            break;
        }
        if (secular(c) > 0.0) == (fa > 0.0) {
            a = c;
        } else {
            b = c;
        }
    }
    let mu = 0.5 * (a + b);
    // `x = δᵀ (S_0 − μ)⁻¹`, by frequency: `v` and the frequency-0 terms from `rho0`, then the
    // `m` and `c` weights `(c_k − μ)/2 + s/32` and `−(1 + ζ̄)(1/16 + (1/4 − μ)/4)` over `det_k`.
    let r0 = rho0(mu);
    let (mut rm, mut rc) = (vec![0.0; n], vec![0.0; n]);
    for k in 1..n {
        let det = det_k(k, mu);
        rm[k] = ((s_k(k) / 16.0 + 0.25 - mu) / 2.0 + s_k(k) / 32.0) / det;
        rc[k] = (1.0 / 16.0 + (0.25 - mu) / 4.0) / det;
    }
    let m = 1 + 2 * n;
    let mut sym = vec![0.0; m];
    sym[0] = r0[0] / nf;
    for j in 0..n {
        let (mut wm, mut wc) = (r0[1], r0[2]);
        for k in 1..n {
            wm += rm[k] * cos_k[(j * k) % n];
            wc -= rc[k] * (cos_k[(j * k) % n] + cos_k[((j + 1) * k) % n]);
        }
        sym[1 + (j + d) % n] = wm / nf;
        sym[1 + n + (j + d) % n] = wc / nf;
    }
    let cos_pi_n = (PI / nf).cos();
    let sigma = 1.0 / (4.0 + cos_pi_n * cos_pi_n).sqrt();
    let mut anti = vec![0.0; m];
    for j in 0..n {
        let t = 2.0 * PI * j as f64 / nf;
        anti[1 + (j + d) % n] = (1.0 - sigma * cos_pi_n) * t.sin();
        anti[1 + n + (j + d) % n] = 2.0 * sigma * (t + PI / nf).sin();
    }
    let position = dominant(s, 0)?;
    for (x, lambda, what) in [
        (&position, 1.0, "position"),
        (&anti, subdominant_eigenvalue(n), "antisymmetric tangent"),
        (&sym, mu, "symmetric tangent"),
    ] {
        let r = eigen_residual(s, x, lambda);
        if r.is_nan() || r > DART_RESIDUAL {
            log::warn!("dart of valence {n}: {what} mask off its eigen-equation by {r:e}");
            return None;
        }
    }
    Some(RingLimit {
        position,
        tangents: [anti, sym],
    })
}

/// `‖x S − λ x‖_∞ / ‖x‖_∞`.
fn eigen_residual(s: &crate::subdiv::limit::masks::Dense, x: &[f64], lambda: f64) -> f64 {
    let y = s.left_mul(x);
    let inf = |v: &mut dyn Iterator<Item = f64>| v.fold(0.0, |m: f64, a| m.max(a.abs()));
    inf(&mut y.iter().zip(x).map(|(a, b)| a - lambda * b)) / inf(&mut x.iter().copied())
}

/// `t x = b` for a 3 × 3 matrix (Cramer's rule).
fn solve3(t: [[f64; 3]; 3], b: [f64; 3]) -> [f64; 3] {
    let det3 = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let det = det3(t);
    let mut x = [0.0; 3];
    for (c, xc) in x.iter_mut().enumerate() {
        let mut tc = t;
        for r in 0..3 {
            tc[r][c] = b[r];
        }
        *xc = det3(tc) / det;
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A closed ring of valence `n` with uneven positions.
    fn ring(n: usize) -> VertexRing<DVec3> {
        let p = |k: usize| {
            let t = k as f64;
            DVec3::new(
                (1.3 * t).sin() + t,
                (0.7 * t).cos() * 2.0,
                (2.1 * t).sin() * 0.5,
            )
        };
        VertexRing {
            v: DVec3::new(0.1, -0.2, 0.3),
            m: (0..n).map(p).collect(),
            c: (0..n).map(|i| p(i + 17) * 0.5).collect(),
            sharp: vec![false; n],
            corner: false,
            face_sizes: vec![4; n],
            far_sector: Vec::new(),
            promoted: Vec::new(),
            decayed_corner: false,
            crease_factors: None,
        }
    }

    #[test]
    fn interior_edge_points_are_the_papers_sums() {
        // The edge points as §3.3 writes them (one sum over the ring per edge, as the
        // construction computed them before the per-vertex sums `InteriorBasis`), against
        // `Paper`: equal to rounding (1e-14 of the ring's size; a wrong sign or phase in a
        // Fourier sum moves them by O(1)).
        for n in (3..=12).chain([50, 333]) {
            let r = ring(n);
            let g = GregoryVertex::interior(&r, GregoryTangents::Paper);
            let nf = n as f64;
            let cos_pi_n = (PI / nf).cos();
            let sigma = 1.0 / (4.0 + cos_pi_n * cos_pi_n).sqrt();
            let scale = (2.0 / 3.0) * subdominant_eigenvalue(n) * 2.0 / nf;
            for j in 0..n {
                let mut e = g.p;
                for i in 0..n {
                    let k = ((i + n - j) % n) as f64;
                    let wm = (1.0 - sigma * cos_pi_n) * (2.0 * PI * k / nf).cos();
                    let wc = 2.0 * sigma * ((2.0 * PI * k + PI) / nf).cos();
                    e += scale * wm * r.m[i];
                    e += scale * wc * r.c[i];
                }
                let err = g.e[j].distance(e) / r.m.iter().map(|m| m.length()).fold(1.0, f64::max);
                assert!(err <= 1e-14, "valence {n} edge {j}: {err:e}");
            }
        }
    }

    /// Every rule built from its first stage ([`GregoryVertex::from_vertex_points`] of
    /// [`GregoryVertex::vertex_points`]) is [`GregoryVertex::new`] bit for bit: smooth, dart,
    /// boundary sectors of 1 to 6 faces, creases with sectors of 3 and 2 and of 3 and 4 faces
    /// (fails if the sectors' tangents are read in the wrong order), a corner and a cone (no
    /// first stage).
    #[test]
    fn two_stage_rules_are_the_construction() {
        let with = |n: usize, sharp: &[usize], corner: bool| {
            let mut r = ring(n);
            sharp.iter().for_each(|&j| r.sharp[j] = true);
            r.corner = corner;
            r
        };
        let mut rings = vec![
            (ring(5), None),
            (with(6, &[2], false), Some(VertexKind::Dart)),
            (with(5, &[0, 3], false), Some(VertexKind::Crease)),
            (with(7, &[0, 3], false), Some(VertexKind::Crease)),
            (with(5, &[0, 3], true), None),
            (with(5, &[], true), None),
        ];
        rings.extend((1..=6).map(|k| (boundary_ring(k), Some(VertexKind::Crease))));
        let darts = DartLimits::new();
        for tangents in [GregoryTangents::Paper, GregoryTangents::Optimal] {
            for (r, kind) in &rings {
                let want = GregoryVertex::new(r, tangents, &darts).expect("covered");
                let points = GregoryVertex::vertex_points(r, tangents, &darts);
                assert_eq!(
                    points.is_some(),
                    want.kind != VertexKind::Corner && want.kind != VertexKind::Cone
                );
                let points = points.unwrap_or([DVec3::ZERO; 3]);
                let got = GregoryVertex::from_vertex_points(r, tangents, &darts, points).unwrap();
                if let Some(kind) = kind {
                    assert_eq!(want.kind, *kind);
                }
                let what = format!("{:?} {:?} {tangents:?}", want.kind, r.sharp);
                assert_eq!((got.p, &got.e), (want.p, &want.e), "{what}");
                assert_eq!(
                    (&got.r_plus, &got.r_minus),
                    (&want.r_plus, &want.r_minus),
                    "{what}"
                );
                assert_eq!(
                    (&got.cosine, &got.one_sided),
                    (&want.cosine, &want.one_sided),
                    "{what}"
                );
            }
        }
    }

    /// A dart's edge points from its first stage, `p + a_j (t_1 · ring) + b_j (t_2 · ring)`,
    /// are the smooth edge masks projected onto the exact tangent masks, projected here
    /// independently (Gram-Schmidt in mask space, then applied term by term): equal to 1e-13 of
    /// the ring's size (fails on swapped or mis-signed coefficients).
    #[test]
    fn dart_edge_points_are_the_projected_smooth_masks() {
        for (n, d) in [(3, 0), (5, 2), (8, 7)] {
            let mut r = ring(n);
            r.sharp[d] = true;
            let g = GregoryVertex::new(&r, GregoryTangents::Paper, &DartLimits::new()).unwrap();
            assert_eq!(g.kind, VertexKind::Dart);
            let lim = dart_limit(n, d).unwrap();
            let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
            let [t1, t2] = &lim.tangents;
            let u1: Vec<f64> = t1.iter().map(|x| x / dot(t1, t1).sqrt()).collect();
            let w: Vec<f64> = t2
                .iter()
                .zip(&u1)
                .map(|(x, u)| x - dot(t2, &u1) * u)
                .collect();
            let u2: Vec<f64> = w.iter().map(|x| x / dot(&w, &w).sqrt()).collect();
            let size = r.m.iter().map(|m| m.length()).fold(1.0, f64::max);
            for j in 0..n {
                let q = smooth_edge_mask(n, j, 1.0);
                let (c1, c2) = (dot(&q, &u1), dot(&q, &u2));
                let mask: Vec<f64> = u1.iter().zip(&u2).map(|(a, b)| c1 * a + c2 * b).collect();
                let mut e = g.p + mask[0] * r.v;
                for i in 0..n {
                    e += mask[1 + i] * r.m[i] + mask[1 + n + i] * r.c[i];
                }
                let err = g.e[j].distance(e) / size;
                assert!(err < 1e-13, "valence {n} dart {d} edge {j}: {err:e}");
            }
        }
    }

    /// The cache's rotated masks against the solve of each sharp edge, at every edge of
    /// valences 2 to 12, 40 (the last power iteration), 41 and 64 (secular): positions and
    /// tangents equal to 1e-12 (the same power iteration, its sums in another order). Fails on
    /// a rotation the wrong way (`(i + n - d) % n`), centroids left unrotated, or the vertex's
    /// weight moved.
    #[test]
    fn rotated_dart_masks_are_the_solves() {
        let darts = DartLimits::new();
        for n in (2..=12).chain([40, 41, 64]) {
            for d in 0..n {
                let want = dart_limit(n, d).unwrap();
                let got = darts.get(n, d).unwrap();
                let pairs = [
                    (&got.position, &want.position),
                    (&got.tangents[0], &want.tangents[0]),
                    (&got.tangents[1], &want.tangents[1]),
                ];
                for (k, (a, b)) in pairs.into_iter().enumerate() {
                    let scale = b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                    let err = a
                        .iter()
                        .zip(b)
                        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
                        / scale;
                    assert!(err < 1e-12, "valence {n} edge {d} mask {k}: {err:e}");
                }
            }
        }
    }

    /// The secular solve of the dart masks against the power iteration at every valence both
    /// cover (8 to 40, the sharp edge first, in the middle and last): equal positions (the
    /// same power iteration) and the same tangent plane, each power-iteration tangent inside
    /// the span of the secular pair to 1e-9 of its length (power iteration's own tolerance is
    /// 1e-13 per step; measured at most 4.8e-10). Fails on a wrong sign or phase in either Fourier mask, a misplaced
    /// rotation by `d`, or a root of the wrong bracket.
    #[test]
    fn secular_dart_masks_are_the_power_iterations() {
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        for n in 8..=DART_POWER_ITERATION_MAX_VALENCE {
            for d in [0, n / 2, n - 1] {
                let power = dart_limit(n, d).unwrap();
                let secular = dart_limit_secular(&dart_matrix(n, d), n, d)
                    .unwrap_or_else(|| panic!("valence {n} edge {d}: no secular masks"));
                assert_eq!(power.position, secular.position);
                for t in &power.tangents {
                    let (a, b) = secular.project_coefficients(t);
                    let [s1, s2] = &secular.tangents;
                    let off: Vec<f64> =
                        (0..t.len()).map(|k| t[k] - a * s1[k] - b * s2[k]).collect();
                    let rel = (dot(&off, &off) / dot(t, t)).sqrt();
                    assert!(rel < 1e-9, "valence {n} edge {d}: {rel:e} off the plane");
                }
            }
        }
    }

    /// Every valence from 41 (where the power iteration hands over) to 128, and 1000, has
    /// dart masks (each within `DART_RESIDUAL` of its eigen-equation, checked inside), spanning
    /// a plane (the Gram determinant of the unit tangents well away from 0). Fails on main,
    /// where the power iteration stalls from valence 48 (`None`).
    #[test]
    fn dart_masks_solve_at_every_valence_above_the_power_iteration() {
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        for n in (DART_POWER_ITERATION_MAX_VALENCE + 1..=128).chain([1000]) {
            let d = n / 3;
            let lim = dart_limit(n, d).unwrap_or_else(|| panic!("valence {n}: no dart masks"));
            let [t1, t2] = &lim.tangents;
            let cos = dot(t1, t2) / (dot(t1, t1) * dot(t2, t2)).sqrt();
            assert!(cos.abs() < 0.99, "valence {n}: tangents parallel ({cos})");
            assert!((lim.position.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        }
    }

    /// A boundary ring of `k` faces (sharp edges 0 and `k`) with uneven positions.
    fn boundary_ring(k: usize) -> VertexRing<DVec3> {
        let base = ring(k + 1);
        let mut sharp = vec![false; k + 1];
        (sharp[0], sharp[k]) = (true, true);
        VertexRing {
            c: base.c[..k].to_vec(),
            sharp,
            ..base
        }
    }

    #[test]
    fn paper_crease_tangents_keep_the_papers_bits() {
        // The inner edge points of a crease sector as computed before the cross-boundary factor
        // existed (weights `w / 3`, same order), against `Paper`: bit for bit.
        for k in 2..=7 {
            let r = boundary_ring(k);
            let g = GregoryVertex::sectored(&r, GregoryTangents::Paper).unwrap();
            let (wv, wm, wc) = crease_tangent_weights(k);
            let mut tan = wv / 3.0 * r.v;
            for (i, w) in wm.iter().enumerate() {
                tan += w / 3.0 * r.m[i];
            }
            for (i, w) in wc.iter().enumerate() {
                tan += w / 3.0 * r.c[i];
            }
            let (ds, alpha) = (g.e[0] - g.p, PI / k as f64);
            for i in 1..k {
                let (sn, cs) = (i as f64 * alpha).sin_cos();
                let e = g.p + cs * ds + sn * tan;
                assert_eq!(g.e[i], e, "sector of {k} faces, edge {i}");
            }
        }
    }

    #[test]
    fn crease_factors_scale_only_the_cross_boundary_tangent() {
        for k in [3, 5] {
            let r = boundary_ring(k);
            let paper = GregoryVertex::sectored(&r, GregoryTangents::Paper).unwrap();
            let scaled = GregoryVertex::sectored(&r, GregoryTangents::Scaled(0.5)).unwrap();
            assert_eq!(paper.p, scaled.p);
            assert_eq!((paper.e[0], paper.e[k]), (scaled.e[0], scaled.e[k]));
            let ds = paper.e[0] - paper.p;
            for i in 1..k {
                let (sn, cs) = (i as f64 * PI / k as f64).sin_cos();
                // e_i - p - cos θ (e_s - p) = sin θ s T/3: halved.
                let t = |g: &GregoryVertex<DVec3>| (g.e[i] - g.p - cs * ds) / sn;
                assert!((t(&scaled) - 0.5 * t(&paper)).length() < 1e-14, "{k} {i}");
            }
        }
    }

    #[test]
    fn optimal_marks_the_sharp_sides() {
        for k in [1, 3, 5] {
            let r = boundary_ring(k);
            let paper = GregoryVertex::sectored(&r, GregoryTangents::Paper).unwrap();
            let opt = GregoryVertex::sectored(&r, GregoryTangents::Optimal).unwrap();
            assert!(paper.one_sided.is_empty());
            let mut sides = vec![0u8; k];
            sides[0] |= 1;
            sides[k - 1] |= 2;
            assert_eq!(opt.one_sided, sides);
            // Not on a ring with a triangle (docs/measured.md: nonquads loses to the reflected ring).
            let mut tri = boundary_ring(k);
            tri.face_sizes[k / 2] = 3;
            let opt = GregoryVertex::sectored(&tri, GregoryTangents::Optimal).unwrap();
            assert!(opt.one_sided.is_empty(), "{k}");
        }
    }

    #[test]
    fn scaled_tangents_scale_the_edge_vectors() {
        for n in [3, 5, 9] {
            let r = ring(n);
            let paper = GregoryVertex::interior(&r, GregoryTangents::Paper);
            let scaled = GregoryVertex::interior(&r, GregoryTangents::Scaled(0.75));
            assert_eq!(paper.p, scaled.p);
            for (a, b) in paper.e.iter().zip(&scaled.e) {
                let d = (*b - scaled.p) - 0.75 * (*a - paper.p);
                assert!(d.length() < 1e-14, "valence {n}: {d}");
            }
        }
    }

    /// One Catmull-Clark step on a split ring, from the rules (face points `c_i`; edge points
    /// `m_i` on sharp edges, `(2 m_i + c_{i-1} + c_i)/4` on smooth ones; vertex kept (corner),
    /// `3/4 v + 1/8 (w_a + w_b)` (crease, `w = 2m - v`) or the smooth rule), then the child
    /// ring `v', (v' + E_i)/2, (v' + E_i + F_i + E_{i+1})/4`; rescaled by 2 about `v'` (the rules
    /// are affine invariant) so that long runs neither underflow nor change directions.
    fn refine_ring(r: &VertexRing<DVec3>) -> VertexRing<DVec3> {
        let (ne, nf) = (r.m.len(), r.c.len());
        let sharp: Vec<usize> = (0..ne).filter(|&i| r.sharp[i]).collect();
        let v = if r.corner {
            r.v
        } else if sharp.len() == 2 {
            let w = |i: usize| 2.0 * r.m[i] - r.v;
            0.75 * r.v + 0.125 * (w(sharp[0]) + w(sharp[1]))
        } else {
            let n = ne as f64;
            let avg = |x: &[DVec3]| x.iter().sum::<DVec3>() / n;
            (n - 3.0) / n * r.v + 2.0 / n * avg(&r.m) + 1.0 / n * avg(&r.c)
        };
        let edge: Vec<DVec3> = (0..ne)
            .map(|i| {
                if r.sharp[i] {
                    r.m[i]
                } else {
                    (2.0 * r.m[i] + r.c[(i + nf - 1) % nf] + r.c[i % nf]) / 4.0
                }
            })
            .collect();
        let grow = |x: DVec3| v + 2.0 * (x - v);
        VertexRing {
            v,
            m: edge.iter().map(|&e| grow((v + e) / 2.0)).collect(),
            c: (0..nf)
                .map(|i| grow((v + edge[i] + r.c[i] + edge[(i + 1) % ne]) / 4.0))
                .collect(),
            ..r.clone()
        }
    }

    /// A quad face alone between the two sharp edges of a crease vertex (a valence-2 `EdgeOnly`
    /// boundary corner): `p` is where refinement takes the vertex, both face points lie in the
    /// limit tangent plane, and the patch's normal next to the corner,
    /// `(e_s - p) x (A + 9 (f - p))` with `A = a + b - 2v`, is the limit normal of the refined
    /// face (20,000 rescaled steps; the Jordan block of 1/4 converges like 1/k).
    #[test]
    fn one_face_crease_sector_is_the_refinement_limit() {
        let v = DVec3::new(0.1, 0.2, -0.1);
        let (a, b, f) = (
            DVec3::new(1.0, 0.1, 0.3),
            DVec3::new(-0.2, 1.1, 0.2),
            DVec3::new(0.9, 1.2, 0.9),
        );
        let ring = VertexRing {
            v,
            m: vec![(v + a) / 2.0, (v + b) / 2.0],
            c: vec![(v + a + b + f) / 4.0],
            sharp: vec![true, true],
            corner: false,
            face_sizes: vec![4],
            far_sector: Vec::new(),
            promoted: Vec::new(),
            decayed_corner: false,
            crease_factors: None,
        };
        let g =
            GregoryVertex::new(&ring, GregoryTangents::Paper, &DartLimits::new()).expect("covered");
        let mut x = ring.clone();
        let mut limit = x.v;
        for _ in 0..60 {
            // Unscaled steps for the position.
            let next = refine_ring(&x);
            limit = next.v;
            x = VertexRing {
                m: next
                    .m
                    .iter()
                    .map(|&m| next.v + 0.5 * (m - next.v))
                    .collect(),
                c: next
                    .c
                    .iter()
                    .map(|&c| next.v + 0.5 * (c - next.v))
                    .collect(),
                ..next
            };
        }
        assert!((g.p - limit).length() < 1e-12, "{} vs {limit}", g.p);
        let mut y = ring.clone();
        for _ in 0..20_000 {
            y = refine_ring(&y);
            let s = 1.0 / (y.m[0] - y.v).length();
            y.m.iter_mut().for_each(|m| *m = y.v + s * (*m - y.v));
            y.c.iter_mut().for_each(|c| *c = y.v + s * (*c - y.v));
        }
        let exact = (y.m[0] - y.m[1]).cross(y.c[0] - y.v).normalize();
        let d = g.e[0] - g.p;
        let far = (v + 2.0 * a) / 3.0;
        for (e, r) in [(g.e[0], g.r_plus[0]), (g.e[1], g.r_minus[0])] {
            for c_b in [0.0, 0.5, -0.3] {
                let fp = face_point_cos(3.0, g.cosine[0], c_b, &g.p, &e, &far, &r);
                let n = d.cross(2.0 * (a + b - 2.0 * v) / 2.0 + 9.0 * (fp - g.p));
                assert!(
                    n.dot((a - v).cross(b - v)).abs()
                        > 0.99 * n.length() * (a - v).cross(b - v).length()
                );
                let angle = n.angle_between(exact);
                assert!(angle < 1e-3, "c_b {c_b}: {angle}");
            }
        }
    }

    /// A cone point (corner tag on a smooth ring of five quads): `p = v`, the edge points are the
    /// refined chords, and refinement confirms the cusp the approximation is built for: the
    /// ring's mean offset shrinks by `(3 + √5)/8` per step, faster than any angular mode decays,
    /// so the chords (and with them the edge points) turn onto one axis.
    #[test]
    fn cone_points_follow_the_refined_chords() {
        let mut r = ring(5);
        r.corner = true;
        let g =
            GregoryVertex::new(&r, GregoryTangents::Paper, &DartLimits::new()).expect("covered");
        assert_eq!(g.kind, VertexKind::Cone);
        assert_eq!(g.p, r.v);
        for (e, m) in g.e.iter().zip(&r.m) {
            assert!((*e - (r.v + 2.0 * *m) / 3.0).length() < 1e-15);
        }
        let mean = |x: &VertexRing<DVec3>| x.m.iter().sum::<DVec3>() / 5.0 - x.v;
        let mut x = r.clone();
        let mut ratio = 0.0;
        // Angular modes fall behind by (0.55 / 0.6545)^k: 200 steps leave ~1e-15.
        for _ in 0..200 {
            let next = refine_ring(&x);
            // `refine_ring` grows offsets by 2.
            ratio = 0.5 * mean(&next).length() / mean(&x).length();
            let s = 1.0 / mean(&next).length();
            x = VertexRing {
                m: next.m.iter().map(|&m| next.v + s * (m - next.v)).collect(),
                c: next.c.iter().map(|&c| next.v + s * (c - next.v)).collect(),
                ..next
            };
        }
        assert!((ratio - (3.0 + 5f64.sqrt()) / 8.0).abs() < 1e-9, "{ratio}");
        let g = GregoryVertex::new(&x, GregoryTangents::Paper, &DartLimits::new()).unwrap();
        let axis = mean(&x);
        for e in &g.e {
            assert!((*e - g.p).angle_between(axis) < 1e-6);
        }
    }

    /// A corner sector of three quads: `p = v`, every edge point the refined chord, and the
    /// inner chords shrink by the sector's leading eigenvalue 0.5797 (above the sharp edges'
    /// 1/2), as `subdiv::limit::sector` tabulates.
    #[test]
    fn wide_corner_sectors_follow_the_refined_chords() {
        let base = ring(4);
        let r = VertexRing {
            c: base.c[..3].to_vec(),
            sharp: vec![true, false, false, true],
            corner: true,
            ..base
        };
        let g =
            GregoryVertex::new(&r, GregoryTangents::Paper, &DartLimits::new()).expect("covered");
        assert_eq!((g.kind, g.p), (VertexKind::Corner, r.v));
        for (e, m) in g.e.iter().zip(&r.m) {
            assert!((*e - (r.v + 2.0 * *m) / 3.0).length() < 1e-15);
        }
        let mut x = r;
        let mut ratio = 0.0;
        for _ in 0..200 {
            let next = refine_ring(&x);
            ratio = 0.5 * (next.m[1] - next.v).length() / (x.m[1] - x.v).length();
            let s = 1.0 / (next.m[1] - next.v).length();
            x = VertexRing {
                m: next.m.iter().map(|&m| next.v + s * (m - next.v)).collect(),
                c: next.c.iter().map(|&c| next.v + s * (c - next.v)).collect(),
                ..next
            };
        }
        assert!((ratio - 0.579_682_326).abs() < 1e-6, "{ratio}");
    }
}
