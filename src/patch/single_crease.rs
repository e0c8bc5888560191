//! Single-crease patches: a regular quad whose only feature is one semi-sharp crease line,
//! evaluated directly instead of being isolated `ceil(s)` levels deep (Nießner, Loop, Greiner
//! 2012, "Efficient evaluation of semi-smooth creases in Catmull-Clark subdivision surfaces").
//!
//! # Curve case (§3)
//!
//! A cubic B-spline segment `f(t) = N(t) P`, `P = (P0, P1, P2, P3)`, `t` in `[0, 1]` from `P1` to
//! `P2`, where `P2` is a crease vertex of sharpness `s` (the surface's crease line crosses every
//! row at `P2`). One refinement step towards `P2` keeps the right half `t` in `[1/2, 1]` with the
//! control points `R P` (smooth) or `R_p P` (crease rule `P2' = P2`):
//!
//! ```text
//! R = 1/8 [1 6 1 0; 0 4 4 0; 0 1 6 1; 0 0 4 4]    R_p = 1/8 [1 6 1 0; 0 4 4 0; 0 0 8 0; 0 0 4 4]
//! ```
//!
//! Because `N(t) = N(2t - 1) R` on `[1/2, 1]`, the curve on `[1 - 2^-s, 1]` (refined `s` times by
//! the crease rule, smooth afterwards) is `N(t) (R^-1)^s R_p^s P = N(t) M_s P` (§3), and on
//! `[0, 1 - 2^-s]` it is the infinitely sharp curve `N(t) M_∞ P`, `M_∞` the end condition
//! `P3 -> 2 P2 - P1` ([`m_inf`]).
//!
//! **Closed form of `M_s`** (the printed matrix is cut off; derived here). Both matrices are
//! diagonalisable, `R = V Λ V^-1` and `R_p = W Μ W^-1` with
//!
//! ```text
//! Λ = diag(1/8, 1/4, 1/2, 1)  V = [1 11 -2 1; 0 2 -1 1; 0 -1 0 1; 0 2 1 1]
//!                             V^-1 = [1 -3 3 -1; 0 1/6 -1/3 1/6; 0 -1/2 0 1/2; 0 1/6 2/3 1/6]
//! Μ = diag(1/8, 1/2, 1/2, 1)  W = [1 2 0 1; 0 1 0 1; 0 0 0 1; 0 0 1 1]
//!                             W^-1 = [1 -2 1 0; 0 1 -1 0; 0 0 -1 1; 0 0 1 0]
//! ```
//!
//! so with `σ = 2^s` the powers are `Λ^-s = diag(σ^3, σ^2, σ, 1)` and `Μ^s = diag(σ^-3, σ^-1,
//! σ^-1, 1)`, and `M_s = V Λ^-s V^-1 W Μ^s W^-1` multiplies out to
//!
//! ```text
//!               [ 6σ  -(σ-1)(2σ-1)(3σ-1)  2(σ-1)(2σ-1)(3σ-1)  -(σ-1)(2σ-1)(3σ-1) ]
//! M_s = 1/(6σ)  [ 0    (σ+1)(2σ+1)        -2(σ-1)(2σ-1)        (σ-1)(2σ-1)       ]
//!               [ 0   -(σ-1)(σ+1)          2(σ²+3σ-1)         -(σ-1)(σ+1)        ]
//!               [ 0    (σ-1)(2σ-1)        -2(σ-1)(2σ-1)        (σ+1)(2σ+1)       ]
//! ```
//!
//! which agrees with the visible part of the paper's matrix (there factored as
//! `(1-σ)/(6σ) (...)`), is the identity at `s = 0` and equals the matrix product for every
//! integer `s` (tested). The curve is C² at `t = 1 - 2^-s`: both sides are uniform B-spline
//! segments of the same `s`-times refined polygon.
//!
//! **Fractional sharpness (§3.1).** One blended step `(1-f) R + f R_p`, `f = s - ⌊s⌋`, makes the
//! limit linear in `f`: `(1-f) f_⌊s⌋ + f f_⌈s⌉`. Hence three segments, split at
//! `1 - 2^-⌊s⌋` and `1 - 2^-⌈s⌉`, with `M_∞`, `M_∞̂ = (1-f) M_⌊s⌋ + f M_∞` and
//! `M_ŝ = (1-f) M_⌊s⌋ + f M_⌈s⌉` ([`curve_segments`]; empty segments are dropped, so
//! `0 < s < 1` has two).
//!
//! # Surface (§3, §4)
//!
//! `S(u, v)` is the tensor product of the curve case across the crease line with the smooth
//! cubic B-spline along it: with one sharpness along a straight line of a regular grid, every
//! DeRose rule (crease vertex `1/8, 3/4, 1/8` along the line, held across it; crease edge
//! midpoint; fractional blends) is the 1-D crease rule across times the 1-D smooth rule along.
//! [`SingleCreasePatch`] documents the eligibility rule and the mapping to the
//! [`RegularPatch`](crate::subdiv::bspline::RegularPatch) `cvs` order.

use glam::DVec3;

use crate::patch::basis::bspline_to_bezier;
use crate::subdiv::bspline::{eval_bspline, LimitSample};
pub use crate::subdiv::single_crease::CreaseSide;
use crate::subdiv::single_crease::{single_crease_line, CreaseLine};
use crate::topology::Topology;

/// How the GPU patch frame (crease along `u' = 1`) maps to the face's `(u, v)`; the value is
/// flags bits 8-9 of the GPU records (`face_uv` in `glsl/single_crease/single_crease_tes.glsl`). Rotations only, so the domain keeps its
/// orientation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rotation {
    /// Crease on the face's `u = 1`: `(u, v) = (u', v')`.
    Identity = 0,
    /// Crease on `u = 0`: `(u, v) = (1 - u', 1 - v')`.
    Half = 1,
    /// Crease on `v = 1`: `(u, v) = (1 - v', u')`.
    Quarter = 2,
    /// Crease on `v = 0`: `(u, v) = (v', 1 - u')`.
    ThreeQuarters = 3,
}

impl Rotation {
    /// The rotation bringing `side` to `u = 1`.
    pub fn of(side: CreaseSide) -> Rotation {
        match side {
            CreaseSide::U1 => Rotation::Identity,
            CreaseSide::U0 => Rotation::Half,
            CreaseSide::V1 => Rotation::Quarter,
            CreaseSide::V0 => Rotation::ThreeQuarters,
        }
    }

    /// The face's `(u, v)` of the GPU frame's `(u', v')`.
    pub fn face_uv(self, u: f64, v: f64) -> (f64, f64) {
        match self {
            Rotation::Identity => (u, v),
            Rotation::Half => (1.0 - u, 1.0 - v),
            Rotation::Quarter => (1.0 - v, u),
            Rotation::ThreeQuarters => (v, 1.0 - u),
        }
    }

    /// The face corner (0: `(0,0)`, 1: `(1,0)`, 2: `(1,1)`, 3: `(0,1)`) at GPU-frame corner `k`.
    /// Rotations keep the orientation, so GPU edge `k` (corner `k` to `k + 1`) is face edge
    /// `face_corner(k)`; the crease (GPU edge 1) is face edge `face_corner(1)`.
    pub fn face_corner(self, k: usize) -> usize {
        let (u, v) = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)][k % 4];
        match self.face_uv(u, v) {
            (0.0, 0.0) => 0,
            (1.0, 0.0) => 1,
            (1.0, 1.0) => 2,
            _ => 3,
        }
    }

    /// The face grid point `(i, j)` (`cvs[4j + i]`) at GPU grid point `(i', j')` (the same map on
    /// the 4×4 net, grid spacing 1 centred on the face).
    fn grid(self, i: usize, j: usize) -> (usize, usize) {
        match self {
            Rotation::Identity => (i, j),
            Rotation::Half => (3 - i, 3 - j),
            Rotation::Quarter => (3 - j, i),
            Rotation::ThreeQuarters => (j, 3 - i),
        }
    }
}

/// The patch's control-vertex ids in the GPU frame: crease along `u = 1` (column 2).
pub fn gpu_cvs(p: &SingleCreasePatch) -> [u32; 16] {
    let rot = Rotation::of(p.side);
    std::array::from_fn(|k| {
        let (i, j) = rot.grid(k % 4, k / 4);
        p.cvs[4 * j + i]
    })
}

/// A 4×4 matrix acting on four curve control points: `out[i] = Σ_k m[i][k] p[k]`.
pub type Mat4 = [[f64; 4]; 4];

/// `M_∞`: the infinitely sharp end condition `P3 -> 2 P2 - P1` (§3).
pub fn m_inf() -> Mat4 {
    [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, -1.0, 2.0, 0.0],
    ]
}

/// `M_s = (R^-1)^s R_p^s` in closed form with `σ = 2^s` (module docs; §3). Defined for real
/// `s >= 0`, but only integer `s` is a subdivision rule: fractional sharpness blends, see
/// [`curve_segments`].
pub fn m_s(s: f64) -> Mat4 {
    let g = 2f64.powf(s);
    let a = (g - 1.0) * (2.0 * g - 1.0);
    let b = a * (3.0 * g - 1.0);
    let c = (g + 1.0) * (2.0 * g + 1.0);
    let d = (g - 1.0) * (g + 1.0);
    let k = 1.0 / (6.0 * g);
    [
        [1.0, -b * k, 2.0 * b * k, -b * k],
        [0.0, c * k, -2.0 * a * k, a * k],
        [0.0, -d * k, 2.0 * (g * g + 3.0 * g - 1.0) * k, -d * k],
        [0.0, a * k, -2.0 * a * k, c * k],
    ]
}

/// The smooth one-step matrix `R` of the curve case (§3).
pub fn r_smooth() -> Mat4 {
    scale([
        [1., 6., 1., 0.],
        [0., 4., 4., 0.],
        [0., 1., 6., 1.],
        [0., 0., 4., 4.],
    ])
}

/// The crease one-step matrix `R_p` of the curve case (§3): `P2` stays.
pub fn r_crease() -> Mat4 {
    scale([
        [1., 6., 1., 0.],
        [0., 4., 4., 0.],
        [0., 0., 8., 0.],
        [0., 0., 4., 4.],
    ])
}

fn scale(m: Mat4) -> Mat4 {
    m.map(|r| r.map(|x| x / 8.0))
}

/// `(1 - w) a + w b`.
fn lerp(a: &Mat4, b: &Mat4, w: f64) -> Mat4 {
    std::array::from_fn(|i| std::array::from_fn(|k| (1.0 - w) * a[i][k] + w * b[i][k]))
}

/// One polynomial piece of the curve case: `f(t) = N(t) m P` for `t` in `[t0, t1]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurveSegment {
    /// Start parameter.
    pub t0: f64,
    /// End parameter.
    pub t1: f64,
    /// Control point transform of this piece.
    pub m: Mat4,
}

/// The pieces of the curve with crease sharpness `s` at `P2`, in order of `t` (§3, §3.1): one
/// (`s = 0`, the identity), two (integer `s`, or `0 < s < 1`) or three (other fractional `s`).
pub fn curve_segments(s: f64) -> Vec<CurveSegment> {
    let lo = s.floor();
    let hi = s.ceil();
    let f = s - lo;
    let (a, b) = (1.0 - (-lo).exp2(), 1.0 - (-hi).exp2());
    let m_lo = m_s(lo);
    let mut out = Vec::with_capacity(3);
    let mut push = |t0: f64, t1: f64, m: Mat4| {
        if t1 > t0 {
            out.push(CurveSegment { t0, t1, m });
        }
    };
    push(0.0, a, m_inf());
    if f == 0.0 {
        push(a, 1.0, m_lo);
    } else {
        push(a, b, lerp(&m_lo, &m_inf(), f));
        push(b, 1.0, lerp(&m_lo, &m_s(hi), f));
    }
    out
}

/// The segment containing `t` (the first whose `t1 >= t`; the pieces join C², so the choice at
/// a split does not matter).
pub fn segment_at(segments: &[CurveSegment], t: f64) -> &CurveSegment {
    segments
        .iter()
        .find(|g| t <= g.t1)
        .unwrap_or(&segments[segments.len() - 1])
}

/// Applies `m` to four control points.
pub fn apply(m: &Mat4, p: &[DVec3; 4]) -> [DVec3; 4] {
    std::array::from_fn(|i| (0..4).map(|k| m[i][k] * p[k]).sum())
}

/// A regular quad with one semi-sharp crease line (Nießner, Loop, Greiner 2012, §3).
///
/// **Eligibility** ([`SingleCreasePatch::gather`]). The limit over a quad depends on the rules of
/// its 4 corners and of the 12 grid edges incident to them, which are exactly the four lines of
/// the 4×4 net through the face's own edges (grid columns 1, 2 and rows 1, 2); a child edge's
/// sharpness depends only on edges at its end vertex, also among these 12 (Chaikin too). So a face
/// qualifies when (a) each corner is an interior valence-4 vertex with only quads around it and
/// no vertex sharpness, and the 16-point net exists, and (b) of the 12 corner edges exactly the
/// three of one [`CreaseSide`] line are sharp, all with the same `s`, `0 < s < 10`, the other nine
/// smooth. Edges and vertices of the outer ring not incident to a corner (their sharpness,
/// valence, boundary) do not influence the face and are ignored. Everything else (two lines, an
/// L-shape, a crease ending inside the net, differing sharpness, an extraordinary or boundary
/// corner, infinitely sharp edges) is refused.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SingleCreasePatch {
    /// The face.
    pub face: u32,
    /// Control vertices in [`RegularPatch`](crate::subdiv::bspline::RegularPatch) order
    /// (`cvs[4*j + i]`, `i` along u; corners 5, 6, 10, 9).
    pub cvs: [u32; 16],
    /// The face edge the crease line runs along.
    pub side: CreaseSide,
    /// Sharpness along the line, `0 < s < 10`.
    pub sharpness: f32,
}

/// One Bézier control set of a [`SingleCreasePatch`]: the bicubic piece over the parameter range
/// `range` across the crease (`u` for `U0`/`U1`, `v` for `V0`/`V1`) and `[0, 1]` along it, in
/// Bézier form over that sub-rectangle (`points[4*j + i]`, `i` along u; local parameters
/// `(x - range.0) / (range.1 - range.0)` across, the patch parameter along).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BezierSet {
    /// Whether the sub-range is in `u` (`true`) or `v`.
    pub across_u: bool,
    /// Patch-parameter range across the crease.
    pub range: (f64, f64),
    /// The 16 Bézier control points.
    pub points: [DVec3; 16],
}

impl SingleCreasePatch {
    /// The single-crease patch of `face`, or `None` if the face is not eligible (type docs).
    pub fn gather(topo: &Topology, face: u32) -> Option<SingleCreasePatch> {
        Some(Self::from_line(face, single_crease_line(topo, face)?))
    }

    /// The patch of `face` with the net and crease line `line` (from [`single_crease_line`],
    /// its `cvs` in any numbering, e.g. the global ids of an adaptive refinement).
    pub fn from_line(face: u32, line: CreaseLine) -> SingleCreasePatch {
        SingleCreasePatch {
            face,
            cvs: line.cvs,
            side: line.side,
            sharpness: line.sharpness,
        }
    }

    /// The curve pieces across the crease ([`curve_segments`] of the sharpness).
    pub fn segments(&self) -> Vec<CurveSegment> {
        curve_segments(f64::from(self.sharpness))
    }

    /// The 16 B-spline control points (`cvs` order) of the polynomial piece `m`: every curve
    /// across the crease transformed by `m` in the paper's frame.
    pub fn piece_points(&self, positions: &[DVec3], m: &Mat4) -> [DVec3; 16] {
        let mut out = [DVec3::ZERO; 16];
        for r in 0..4 {
            let p = std::array::from_fn(|k| positions[self.cvs[self.side.slot(r, k)] as usize]);
            for (k, q) in apply(m, &p).into_iter().enumerate() {
                out[self.side.slot(r, k)] = q;
            }
        }
        out
    }

    /// Evaluates position, partial derivatives and unit normal at `(u, v)` in `[0, 1]^2`.
    pub fn eval(&self, positions: &[DVec3], u: f64, v: f64) -> LimitSample {
        let segs = self.segments();
        let g = segment_at(&segs, self.side.t(u, v));
        eval_bspline(&self.piece_points(positions, &g.m), u, v)
    }

    /// The two or three Bézier control sets of the pieces, in order of increasing patch
    /// parameter across the crease (§4: what the GPU's control stage builds).
    pub fn bezier_sets(&self, positions: &[DVec3]) -> Vec<BezierSet> {
        let across_u = matches!(self.side, CreaseSide::U0 | CreaseSide::U1);
        let reversed = matches!(self.side, CreaseSide::U0 | CreaseSide::V0);
        let mut sets: Vec<BezierSet> = self
            .segments()
            .iter()
            .map(|g| {
                let range = if reversed {
                    (1.0 - g.t1, 1.0 - g.t0)
                } else {
                    (g.t0, g.t1)
                };
                let full = bspline_to_bezier(&self.piece_points(positions, &g.m));
                BezierSet {
                    across_u,
                    range,
                    points: restrict(&full, across_u, range),
                }
            })
            .collect();
        sets.sort_by(|a, b| a.range.0.total_cmp(&b.range.0));
        sets
    }
}

/// Restricts a bicubic Bézier patch to `[a, b]` in `u` (or `v`) by blossoming each cubic across:
/// the new points are the blossom values `(a,a,a), (a,a,b), (a,b,b), (b,b,b)`.
fn restrict(p: &[DVec3; 16], across_u: bool, (a, b): (f64, f64)) -> [DVec3; 16] {
    let idx = |line: usize, k: usize| if across_u { 4 * line + k } else { 4 * k + line };
    let blossom = |c: [DVec3; 4], x: [f64; 3]| {
        let mut c = c.to_vec();
        for t in x {
            c = c.windows(2).map(|w| w[0].lerp(w[1], t)).collect();
        }
        c[0]
    };
    let mut out = [DVec3::ZERO; 16];
    for line in 0..4 {
        let c = std::array::from_fn(|k| p[idx(line, k)]);
        for (k, x) in [[a, a, a], [a, a, b], [a, b, b], [b, b, b]]
            .into_iter()
            .enumerate()
        {
            out[idx(line, k)] = blossom(c, x);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::patch::basis::{bspline, bspline_deriv};

    fn mul(a: &Mat4, b: &Mat4) -> Mat4 {
        std::array::from_fn(|i| std::array::from_fn(|k| (0..4).map(|j| a[i][j] * b[j][k]).sum()))
    }

    fn max_diff(a: &Mat4, b: &Mat4) -> f64 {
        (0..16)
            .map(|n| (a[n / 4][n % 4] - b[n / 4][n % 4]).abs())
            .fold(0.0, f64::max)
    }

    /// `R^-1`, by Gauss-Jordan (kept independent of the closed form).
    fn inverse(m: &Mat4) -> Mat4 {
        let mut a: Vec<[f64; 8]> = (0..4)
            .map(|i| {
                std::array::from_fn(|k| {
                    if k < 4 {
                        m[i][k]
                    } else {
                        f64::from(k - 4 == i)
                    }
                })
            })
            .collect();
        for c in 0..4 {
            let p = (c..4)
                .max_by(|&x, &y| a[x][c].abs().total_cmp(&a[y][c].abs()))
                .unwrap();
            a.swap(c, p);
            let d = a[c][c];
            a[c].iter_mut().for_each(|x| *x /= d);
            for r in 0..4 {
                if r != c {
                    let f = a[r][c];
                    let row = a[c];
                    a[r].iter_mut().zip(row).for_each(|(x, y)| *x -= f * y);
                }
            }
        }
        std::array::from_fn(|i| std::array::from_fn(|k| a[i][k + 4]))
    }

    fn second(t: f64) -> [f64; 4] {
        [1.0 - t, 3.0 * t - 2.0, 1.0 - 3.0 * t, t]
    }

    fn dot(n: [f64; 4], p: &[DVec3; 4]) -> DVec3 {
        (0..4).map(|k| n[k] * p[k]).sum()
    }

    fn eval(s: f64, p: &[DVec3; 4], t: f64) -> DVec3 {
        let segs = curve_segments(s);
        dot(bspline(t), &apply(&segment_at(&segs, t).m, p))
    }

    fn poly() -> [DVec3; 4] {
        [
            DVec3::new(0.0, 0.0, 0.3),
            DVec3::new(1.0, 1.3, -0.2),
            DVec3::new(2.1, 0.4, 0.5),
            DVec3::new(2.7, 1.9, 0.1),
        ]
    }

    #[test]
    fn closed_form_equals_the_matrix_product() {
        let (r, rp) = (r_smooth(), r_crease());
        let ri = inverse(&r);
        let id: Mat4 = std::array::from_fn(|i| std::array::from_fn(|k| f64::from(i == k)));
        assert!(max_diff(&mul(&r, &ri), &id) < 1e-14);
        let (mut a, mut b) = (id, id);
        for s in 0..=10 {
            let prod = mul(&a, &b);
            let scale = prod.iter().flatten().fold(1.0f64, |m, x| m.max(x.abs()));
            let err = max_diff(&m_s(s as f64), &prod) / scale;
            assert!(err < 1e-12, "s = {s}: relative {err:e}");
            a = mul(&a, &ri);
            b = mul(&rp, &b);
        }
    }

    #[test]
    fn pieces_join_c2_at_the_splits() {
        let p = poly();
        for s in [0.3, 1.0, 1.7, 2.0, 2.5, 4.5, 9.9] {
            let segs = curve_segments(s);
            let expect = if s.fract() == 0.0 || s < 1.0 { 2 } else { 3 };
            assert_eq!(segs.len(), expect, "s = {s}");
            for w in segs.windows(2) {
                let t = w[0].t1;
                assert_eq!(t, w[1].t0);
                let (l, r) = (apply(&w[0].m, &p), apply(&w[1].m, &p));
                let scale = r.iter().map(|q| q.length()).fold(1.0, f64::max);
                for (k, n) in [bspline(t), bspline_deriv(t), second(t)].iter().enumerate() {
                    let d = (dot(*n, &l) - dot(*n, &r)).length() / scale;
                    assert!(d < 1e-12, "s = {s}, t = {t}, derivative {k}: {d:e}");
                }
            }
        }
    }

    /// Exact limit of the curve case by DeRose refinement of a longer polygon: the crease vertex
    /// (index 6) is held while `s >= 1`, blended `(1 - s) smooth + s held` for `0 < s < 1`, then
    /// smooth; after `ceil(s) + 3` levels the limit of a vertex is `(x_-1 + 4 x + x_+1) / 6`.
    #[test]
    fn curve_equals_refined_limit() {
        let q: Vec<DVec3> = (0..13)
            .map(|i| {
                let x = i as f64;
                DVec3::new(x + 0.2 * (x * 1.3).sin(), (x * 0.7).cos(), 0.1 * x * x)
            })
            .collect();
        let p = [q[4], q[5], q[6], q[7]];
        for s in [0.0f64, 0.3, 1.0, 1.7, 2.0, 2.5, 4.5, 9.9] {
            let levels = s.ceil() as u32 + 3;
            let (mut x, mut crease, mut sharp) = (q.clone(), 6usize, s);
            for _ in 0..levels {
                let n = x.len();
                let mut y = vec![DVec3::ZERO; 2 * n - 1];
                y[0] = x[0];
                y[2 * n - 2] = x[n - 1];
                for i in 1..n - 1 {
                    let smooth = (x[i - 1] + 6.0 * x[i] + x[i + 1]) / 8.0;
                    let w = if i == crease { sharp.min(1.0) } else { 0.0 };
                    y[2 * i] = (1.0 - w) * smooth + w * x[i];
                }
                for i in 0..n - 1 {
                    y[2 * i + 1] = (x[i] + x[i + 1]) / 2.0;
                }
                x = y;
                crease *= 2;
                sharp = (sharp - 1.0).max(0.0);
            }
            let step = 1usize << levels;
            let mut worst = 0.0f64;
            for m in 0..=step {
                let i = 5 * step + m;
                let exact = (x[i - 1] + 4.0 * x[i] + x[i + 1]) / 6.0;
                let t = m as f64 / step as f64;
                worst = worst.max((eval(s, &p, t) - exact).length());
            }
            assert!(worst < 1e-11, "s = {s}: {worst:e}");
        }
    }
}
