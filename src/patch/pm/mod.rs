//! Pm-patches (Myles, Ni, Peters 2008, "Fast parallel construction of smooth surfaces from
//! meshes with tri/quad/pent facets"): one G1 patch per facet of a closed tri/quad/pent mesh,
//! no refinement. CPU construction and reference evaluation; no Vulkan.
//!
//! Facet classes ([`classify`], §3):
//! - **ordinary**: a quad whose four corners have valence 4 and whose corners' faces are all
//!   quads: a bicubic Bézier patch (16 points, [`construct::bicubic`]);
//! - **polar**: a triangle of a closed triangle fan whose outer vertices have valence 4
//!   ([`is_pole`]; a triangle with two or three such centres is not polar): a singular bicubic
//!   whose row `j = 3` collapses to the pole (13 points, [`construct::polar`]);
//! - **Pm** (every other triangle, quad and pentagon, `m = 3, 4, 5`): `m` quartic triangular
//!   sectors around a centre `b_004`, cubic outer boundaries, `6m + 1` points
//!   ([`construct::pm_facet`]).
//!
//! Facets with more than five sides, holes, facets on the boundary or at a vertex without a
//! closed fan are refused ([`NotPm`], naming the facet). Sharpness tags become crease scalars
//! ([`PmOptions::with_crease_tags`], eq. 14: `a = (2/3) 2^{-s}` for an edge of sharpness `s`,
//! `0` when infinitely sharp; derivation in `crease.rs`).
//!
//! Control points per facet (paper Table 1; the quad row is lost in the scan):
//!
//! | facet | here | Loop-Schaefer 2008 (25 m) | Ni et al. 2008 (24 m) |
//! |---|---|---|---|
//! | triangle | 13 (polar) or 19 (P3) | 75 | 72 |
//! | quad | 16 (ordinary) or 25 (P4) | 100 | 96 |
//! | pentagon | 31 (P5) | 125 | 120 |
//!
//! # Per-vertex stage ([`pm_vertex`], §5.1, eq. 13-16)
//! At a vertex `p` of valence `n` with spokes `p_{3j}` ([`crate::topology::Topology::vertex_edges`] order) and
//! facet `j` between spokes `j` and `j + 1` (`p̄_j` the mean of its far vertices, or of the two
//! spoke ends for a triangle — the unbiased padding):
//! - `f_j = (4p + 2(p_{3j} + p_{3j+3}) + p̄_j) / 9` (13); with crease scalars (14)
//!   `f_j = (1-a_j)(1-a_{j+1}) p + (1-a_j) a_{j+1} (p + p_{3j})/2 + a_j (1-a_{j+1}) (p + p_{3j+3})/2
//!   + a_j a_{j+1} (p + p_{3j} + p_{3j+3} + p̄_j)/4`, `a_j` the scalar of spoke `j`. Fixed by:
//!   `a = 2/3` gives (13) (expanded), `a_j = 0` puts `f_j` and `f_{j-1}` on spoke `j` (a C0 crease),
//!   all `a = 0` gives the control polyhedron (tested).
//! - `v = Σ_j (9 f_j + (n - 4) p) / (n (n + 5))`: the Catmull-Clark limit point on all-quad rings.
//! - `e_j = (f_j + f_{j-1})/2`, `t_1 = κ_n Σ_j cos(2πj/n) e_j`, `t_2 = κ_n Σ_j sin(2πj/n) e_j`
//!   (15) and the tangent point along spoke `j`: `t_j = v + cos(2πj/n) t_1 + sin(2πj/n) t_2` (16).
//!   `κ_n` is unreadable; `κ_4 = 1/2` is fixed by `t_j = e_j` at valence 4 (then `v` is the
//!   midpoint of `e_j` and `e_{j+2}` for any facet types, so ordinary patches are B-splines).
//!   G1 holds for any `κ_n`; of the two readings with `κ_4 = 1/2`, `1/(n λ_n)` is nearer the
//!   Catmull-Clark limit on every mesh measured (`tests/pm.rs`) and is the default
//!   ([`TangentScale`]), `λ_n = (c_n + 5 + sqrt((c_n + 9)(c_n + 1)))/16`.
//!
//! # Per-facet stage ([`construct`], §5.2, eq. 16-22)
//! Every facet edge is the cubic `[v^0, t^{0→1}, t^{1→0}, v^1]` (17), built from the same vertex
//! data on both sides (bitwise equal control points).
//! - Ordinary: corner `k`'s 2×2 block is `v`, the two tangent points along the facet edges and
//!   the corner's `f` in the facet: the B-spline to Bézier conversion on regular rings (exact
//!   limit, tested ≤ 1e-9 of the diagonal).
//! - Polar `(a, b, p)`: rows 0-1 as ordinary from `a`, `b`; `h_02`, `h_32` the pole's tangent
//!   points along the spokes; (18) `h_12 = (2 h_02 + h_32 + (c - 1) v_p)/(2 + c)`, `h_22`
//!   mirrored, `c = cos(2π/n_p)`: affine (weights sum to 1) and C1 between fan neighbours, one
//!   normal at the pole (tested G1 for valences 3-12); crease (19) `ĥ_12 = (3/2) a h_12 +
//!   (1 - (3/2) a) h_02` (identity at `a = 2/3`).
//! - Pm sector `i` (corners `v^i`, `v^{i+1}`, centre; quartic `b_{abc}`, `a` for `v^i`, `c` for the
//!   centre): stored per sector `v^i, b_210 = t^{i→i+1}, b_120 = t^{i+1→i}, b_211, b_121, b_112`,
//!   then `b_004` ([`construct::slot`]). Derived (same functions on CPU and later GPU):
//!   - degree raising (2): `b_310 = (v^i + 3 b_210)/4`, `b_220 = (b_210 + b_120)/2`, ...;
//!   - spokes (3), re-derived as the C1 condition between sectors over a regular m-gon domain:
//!     `b^i_{3-l,0,l+1} = k_1 b^i_{4-l,0,l} + k_2 (b^i_{3-l,1,l} + b^{i-1}_{1,3-l,l})` with
//!     `k_2 = 1/(2(1 - cos(2π/m)))`, `k_1 = 1 - 2 k_2` (the domain points satisfy it because
//!     `V_{i-1} + V_{i+1} = 2 cos(2π/m) V_i`); `l = 0, 1, 2` define `b_301, b_202, b_103`;
//!   - `l = 3` is eq. (5), `b_004 = k_1 b^i_103 + k_2 (b^{i+1}_103 + b^{i-1}_103)`: it holds iff the
//!     `b_103 - b_004` carry only the Fourier modes ±1, which the `b_112` below guarantee (tested
//!     to 1e-12);
//!   - (20), G1 with the patch across outer edge `i` (`μ = 1 - cos(2π/m)`, `χ = 1 + cos(2π/n)`,
//!     `S = sin(2π/n^0) + sin(2π/n^1)`, `f_out` the corner's face point in the facet across):
//!     `b_211 = b_310 + χ^0/(4μ) (t^{1→0} - t^{0→1}) + (2μ - χ^1)/(8μ) (t^{0→1} - v^0) +
//!     3 (f^0_in - f^0_out)/(8 μ S)`, `b_121` mirrored. The `1/μ` factor and the transversal
//!     coefficient `3/(8 S)` are the legible fragments; the rest is fixed by G1 (tested ≤ 1e-6
//!     rad across every edge between any two patch kinds; 3.3 instead of 3 breaks it by 2e-3);
//!   - `b_004 = Σ_i (w_m v^i + 3 (t^i_next + t^i_prev) + 9 f^i) / (m (w_m + 15))`, affine by the
//!     denominator; `w_4 = 1` (the centre of the bicubic of the corner blocks), `w_3 = 2`,
//!     `w_5 = 3` as read (any value keeps G1);
//!   - (21)/(22) `b_112` (superscripts are sectors mod `m`):
//!     - `m = 3`: `b^i_112 = b_004 + (b_004 - b^{i+2}_202)/2` (reproduces linear functions; the
//!       mean of the `b_103` is then `b_004`);
//!     - `m = 4`: `b^i_112 = b_004 + 3 (b^i_211 + b^i_121 - b^{i+2}_211 - b^{i+2}_121)/16 +
//!       (b^{i+3}_211 + b^{i+1}_121 - b^{i+3}_121 - b^{i+1}_211)/16` (zero mean; mode 2 of the
//!       `b_103` vanishes anyway since `k_1 = 0`);
//!     - `m = 5`: `b^i_112 = (1 - c) b_004 + c/(1 - c) [b^i_202 + b^{i+1}_202 + c' (b^{i+2}_202 +
//!       b^{i-1}_202) + c b^{i+3}_202]`, `c = cos 72°`, `c' = cos 144°` (weights sum to `c`;
//!       modes 2 and 3 of the `b_103` cancel).
//!
//! The construction is generic over [`GregoryPoint`](crate::patch::gregory::GregoryPoint): on
//! positions it gives the patches ([`pm_patches`]), on unit [`Weights`](crate::patch::gregory::Weights)
//! the stencil row of every control point over the control vertices ([`pm_facets_weights`]),
//! for the later GPU stencil variant.
//!
//! Parameters ([`PmPatch::sample`]): ordinary `(u, v)` with facet corners at `(0,0), (1,0),
//! (1,1), (0,1)`; polar `(u, v)` with corner `pole + 1` at `(0, 0)`, `pole + 2` at `(1, 0)`, the
//! pole at `v = 1`; Pm sector `i` barycentric `(1 - s - t, s, t)` of `(v^i, v^{i+1}, b_004)`.

mod build;
pub mod construct;
mod corner;
mod crease;
mod error;
mod eval;
mod vertex;

pub use build::{
    classify, is_pole, pm_facets, pm_facets_weights, pm_patch, pm_patches, pm_vertices, FacetClass,
    PmPatch,
};
pub use corner::{corner_slots, facet_corner, CornerSlots, FacetCorner};
pub use crease::crease_scalar;
pub use error::NotPm;
pub use eval::{
    bicubic_eval, bicubic_sample, pm_sector_sample, polar_as_bicubic, quartic_eval, PmSample,
};
pub use vertex::{
    cos_n, far_vertices, lambda, pm_vertex, sin_n, PmOptions, PmVertex, TangentScale, SMOOTH_CREASE,
};
