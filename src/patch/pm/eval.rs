//! Reference evaluation of the three patch types (position and unit normal).

use super::build::PmPatch;
use super::construct::{bicubic_index, quartic_index, sector_quartic, slot, POLE, SECTOR_POINTS};
use glam::DVec3;

/// A point of a patch with its unit normal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PmSample {
    /// Position.
    pub position: DVec3,
    /// Unit normal (facet orientation).
    pub normal: DVec3,
}

/// Cubic Bernstein values and derivatives at `t`.
fn bernstein3(t: f64) -> ([f64; 4], [f64; 4]) {
    let s = 1.0 - t;
    (
        [s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t],
        [
            -3.0 * s * s,
            3.0 * s * s - 6.0 * t * s,
            6.0 * t * s - 3.0 * t * t,
            3.0 * t * t,
        ],
    )
}

/// Position, `∂u`, `∂v` and `∂u∂v` of a bicubic Bézier patch `b[i + 4 j]`.
pub fn bicubic_eval(b: &[DVec3; 16], u: f64, v: f64) -> [DVec3; 4] {
    let (bu, du) = bernstein3(u);
    let (bv, dv) = bernstein3(v);
    let mut out = [DVec3::ZERO; 4];
    for j in 0..4 {
        for i in 0..4 {
            let p = b[bicubic_index(i, j)];
            out[0] += bu[i] * bv[j] * p;
            out[1] += du[i] * bv[j] * p;
            out[2] += bu[i] * dv[j] * p;
            out[3] += du[i] * dv[j] * p;
        }
    }
    out
}

/// Sample of a bicubic at `(u, v)`; where `∂u × ∂v` vanishes (a collapsed edge) the normal is
/// the limit `∂v × ∂u∂v` (the first non-zero term of the expansion towards the edge).
pub fn bicubic_sample(b: &[DVec3; 16], u: f64, v: f64) -> PmSample {
    let [p, du, dv, duv] = bicubic_eval(b, u, v);
    let n = du.cross(dv);
    let scale = du.length().max(dv.length()).max(1e-300);
    let normal = if n.length() > 1e-12 * scale * scale {
        n
    } else {
        // At v = 1 with row 3 collapsed: ∂u ≈ (v - 1) ∂u∂v, so n ∝ -(∂u∂v × ∂v).
        -duv.cross(dv)
    };
    PmSample {
        position: p,
        normal: normal.normalize_or_zero(),
    }
}

/// The 16 Bézier points of a polar patch's singular bicubic (row 3 = the pole).
pub fn polar_as_bicubic(h: &[DVec3; 13]) -> [DVec3; 16] {
    std::array::from_fn(|k| if k >= 12 { h[POLE] } else { h[k] })
}

/// Position and the derivatives along `b` and `c` (with `a = 1 - b - c`) of a quartic
/// triangle in barycentric coordinates.
pub fn quartic_eval(q: &[DVec3; 15], b: f64, c: f64) -> [DVec3; 3] {
    let a = 1.0 - b - c;
    let fact = [1.0, 1.0, 2.0, 6.0, 24.0];
    let pow = |x: f64, k: usize| if k == 0 { 1.0 } else { x.powi(k as i32) };
    let mut out = [DVec3::ZERO; 3];
    for ia in 0..=4usize {
        for ib in 0..=(4 - ia) {
            let ic = 4 - ia - ib;
            let p = q[quartic_index(ia, ib)];
            let mono = |da: usize, db: usize, dc: usize| {
                // Degree-3 Bernstein of (ia - da, ib - db, ic - dc) times 4.
                let (x, y, z) = (ia - da, ib - db, ic - dc);
                4.0 * 6.0 / (fact[x] * fact[y] * fact[z]) * pow(a, x) * pow(b, y) * pow(c, z)
            };
            out[0] +=
                24.0 / (fact[ia] * fact[ib] * fact[ic]) * pow(a, ia) * pow(b, ib) * pow(c, ic) * p;
            // d/db = D_b - D_a, d/dc = D_c - D_a.
            let d_a = if ia > 0 { mono(1, 0, 0) } else { 0.0 };
            let d_b = if ib > 0 { mono(0, 1, 0) } else { 0.0 };
            let d_c = if ic > 0 { mono(0, 0, 1) } else { 0.0 };
            out[1] += (d_b - d_a) * p;
            out[2] += (d_c - d_a) * p;
        }
    }
    out
}

/// Sample of sector `i` of a Pm-patch (points in [`super::construct::pm_facet`] layout) at
/// barycentric `(1 - b - c, b, c)` of `(v^i, v^{i+1}, b_004)`.
pub fn pm_sector_sample(points: &[DVec3], i: usize, b: f64, c: f64) -> PmSample {
    let q = sector_quartic(points, i);
    let [p, db, dc] = quartic_eval(&q, b, c);
    PmSample {
        position: p,
        normal: db.cross(dc).normalize_or_zero(),
    }
}

impl PmPatch<DVec3> {
    /// Sample at a patch parameter: `(u, v)` for bicubic and polar patches (`sector` ignored;
    /// polar `v = 1` is the pole), barycentric `(1 - s - t, s, t)` of sector `sector` for Pm.
    pub fn sample(&self, sector: usize, s: f64, t: f64) -> PmSample {
        match self {
            PmPatch::Bicubic(b) => bicubic_sample(b, s, t),
            PmPatch::Polar { h, .. } => {
                let mut x = bicubic_sample(&polar_as_bicubic(h), s, t);
                if t == 1.0 {
                    // The collapsed edge is the pole itself, whatever u.
                    x.position = h[POLE];
                }
                x
            }
            PmPatch::Pm(p) => pm_sector_sample(p, sector, s, t),
        }
    }

    /// Sample on facet edge `k` (corner `k` to `k + 1`) at `t` in `[0, 1]`.
    pub fn edge_sample(&self, k: usize, t: f64) -> PmSample {
        let (sector, s, r) = self.edge_param(k, t);
        self.sample(sector, s, r)
    }

    /// The patch parameter of facet edge `k` at `t` (see [`Self::sample`]).
    fn edge_param(&self, k: usize, t: f64) -> (usize, f64, f64) {
        let lerp = |a: (f64, f64), b: (f64, f64)| (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1));
        let ((s, r), sector) = match self {
            PmPatch::Bicubic(_) => {
                let c = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
                (lerp(c[k], c[(k + 1) % 4]), 0)
            }
            PmPatch::Polar { pole, .. } => {
                // Corner pole + 1 at (0, 0), pole + 2 at (1, 0), the pole at v = 1.
                let e = (k + 3 - pole) % 3;
                let c = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
                (
                    match e {
                        1 => lerp(c[0], c[1]),
                        2 => lerp(c[1], c[2]),
                        _ => lerp(c[3], c[0]),
                    },
                    0,
                )
            }
            PmPatch::Pm(_) => ((t, 0.0), k),
        };
        (sector, s, r)
    }
}

impl<P: Clone> PmPatch<P> {
    /// The cubic Bézier control points of facet edge `k`, from corner `k` to `k + 1` (eq. 17,
    /// shared by both facets of the edge).
    pub fn edge_cubic(&self, k: usize) -> [P; 4] {
        let pick = |pts: &[P], idx: [usize; 4]| idx.map(|i| pts[i].clone());
        match self {
            PmPatch::Bicubic(b) => pick(
                &b[..],
                [
                    [0, 1, 2, 3],
                    [3, 7, 11, 15],
                    [15, 14, 13, 12],
                    [12, 8, 4, 0],
                ][k],
            ),
            PmPatch::Polar { h, pole } => pick(
                &h[..],
                [[POLE, 8, 4, 0], [0, 1, 2, 3], [3, 7, 11, POLE]][(k + 3 - pole) % 3],
            ),
            PmPatch::Pm(p) => {
                let m = (p.len() - 1) / SECTOR_POINTS;
                let s = SECTOR_POINTS * k;
                [
                    p[s + slot::V].clone(),
                    p[s + slot::B210].clone(),
                    p[s + slot::B120].clone(),
                    p[SECTOR_POINTS * ((k + 1) % m) + slot::V].clone(),
                ]
            }
        }
    }
}
