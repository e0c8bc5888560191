//! The per-facet stage (paper §5.2, eq. 16-22, Fig. 11): control points of the three patch
//! types from the facet's corners, generic over the point type so positions and stencil weights
//! come from the same arithmetic.

use super::corner::FacetCorner;
use super::vertex::{cos_n, sin_n};
use crate::patch::gregory::{combine, GregoryPoint};

/// Grid positions of the four corners of a bicubic patch, `(i, j)` with `i` along `u`.
const QUAD_CORNERS: [(usize, usize); 4] = [(0, 0), (3, 0), (3, 3), (0, 3)];

/// Bézier index of `(i, j)` in a 16-point bicubic (row-major in `j`).
pub const fn bicubic_index(i: usize, j: usize) -> usize {
    i + 4 * j
}

/// One step from grid coordinate `from` towards `to`.
fn toward(from: usize, to: usize) -> usize {
    match to.cmp(&from) {
        std::cmp::Ordering::Greater => from + 1,
        std::cmp::Ordering::Less => from - 1,
        std::cmp::Ordering::Equal => from,
    }
}

/// The bicubic patch of an ordinary quad: corner `k`'s block is `v` at the corner, its two
/// tangent points along the facet's edges and `f_in` inside (the B-spline to Bézier
/// conversion when the one-ring is regular).
pub fn bicubic<P: GregoryPoint>(c: &[FacetCorner<P>]) -> [P; 16] {
    let mut b: [P; 16] = std::array::from_fn(|_| P::zero());
    for (k, corner) in c.iter().enumerate().take(4) {
        let (x, y) = QUAD_CORNERS[k];
        let (nx, ny) = QUAD_CORNERS[(k + 1) % 4];
        let (px, py) = QUAD_CORNERS[(k + 3) % 4];
        let next = (toward(x, nx), toward(y, ny));
        let prev = (toward(x, px), toward(y, py));
        let inner = (toward(x, 3 - x), toward(y, 3 - y));
        b[bicubic_index(x, y)] = corner.v.clone();
        b[bicubic_index(next.0, next.1)] = corner.next.clone();
        b[bicubic_index(prev.0, prev.1)] = corner.prev.clone();
        b[bicubic_index(inner.0, inner.1)] = corner.f_in.clone();
    }
    b
}

/// Index of the pole in a 13-point polar patch.
pub const POLE: usize = 12;

/// The singular bicubic of a polar triangle `(a, b, p)` (corners in facet order, `p` the
/// pole): rows `j = 0, 1` as an ordinary patch's from the valence-4 corners `a`, `b`; row
/// `j = 2` is the pole's tangent points `h_02`, `h_32` and eq. (18)
/// `h_12 = (2 h_02 + h_32 + (c - 1) v_p) / (2 + c)` (and mirrored), `c = cos(2π/n_p)`, with the
/// crease blend of eq. (19); row `j = 3` collapses to the pole `v_p` (index [`POLE`]).
/// Layout: `h[i + 4 j]` for `j < 3`, then the pole.
pub fn polar<P: GregoryPoint>(
    a: &FacetCorner<P>,
    b: &FacetCorner<P>,
    p: &FacetCorner<P>,
    crease: [f64; 2],
) -> [P; 13] {
    let c = cos_n(1, p.valence);
    let h02 = p.next.clone();
    let h32 = p.prev.clone();
    let mid = |near: &P, far: &P, a: f64| {
        let s = 1.5 * a;
        combine(&[
            (s * 2.0 / (2.0 + c), near),
            (s / (2.0 + c), far),
            (s * (c - 1.0) / (2.0 + c), &p.v),
            (1.0 - s, near),
        ])
    };
    let h12 = mid(&h02, &h32, crease[0]);
    let h22 = mid(&h32, &h02, crease[1]);
    [
        a.v.clone(),
        a.next.clone(),
        b.prev.clone(),
        b.v.clone(),
        a.prev.clone(),
        a.f_in.clone(),
        b.f_in.clone(),
        b.next.clone(),
        h02,
        h12,
        h22,
        h32,
        p.v.clone(),
    ]
}

/// Stored points per Pm sector: `v^i, b_210, b_120, b_211, b_121, b_112` (module docs).
pub const SECTOR_POINTS: usize = 6;

/// Offsets within a sector's stored block.
pub mod slot {
    /// `v^i = b_400`.
    pub const V: usize = 0;
    /// `b_210` of the cubic boundary (`t^{i -> i+1}`).
    pub const B210: usize = 1;
    /// `b_120` of the cubic boundary (`t^{i+1 -> i}`).
    pub const B120: usize = 2;
    /// `b_211`.
    pub const B211: usize = 3;
    /// `b_121`.
    pub const B121: usize = 4;
    /// `b_112`.
    pub const B112: usize = 5;
}

/// Weight `w_m` of the corner point in the centre `b_004` (module docs).
fn centre_weight(m: usize) -> f64 {
    match m {
        3 => 2.0,
        5 => 3.0,
        _ => 1.0,
    }
}

/// The spoke coefficients of eq. (3): `k_2 = 1/(2(1 - cos(2π/m)))`, `k_1 = 1 - 2 k_2`.
pub fn spoke_weights(m: usize) -> (f64, f64) {
    let k2 = 1.0 / (2.0 * (1.0 - cos_n(1, m)));
    (1.0 - 2.0 * k2, k2)
}

/// Eq. (3) for one spoke coefficient: `k_1 on + k_2 (left + right)`.
pub fn spoke_point<P: GregoryPoint>(m: usize, on: &P, left: &P, right: &P) -> P {
    let (k1, k2) = spoke_weights(m);
    combine(&[(k1, on), (k2, left), (k2, right)])
}

/// Degree raising of the cubic boundary (eq. 2): `b_310 = (v^i + 3 b_210)/4`.
pub fn raise<P: GregoryPoint>(v: &P, t: &P) -> P {
    combine(&[(0.25, v), (0.75, t)])
}

/// The `6m + 1` points of a Pm-patch (`m = c.len()` in 3..=5), sector blocks then `b_004`.
pub fn pm_facet<P: GregoryPoint>(c: &[FacetCorner<P>]) -> Vec<P> {
    let m = c.len();
    let mut out: Vec<P> = Vec::with_capacity(SECTOR_POINTS * m + 1);
    for i in 0..m {
        let (c0, c1) = (&c[i], &c[(i + 1) % m]);
        let [b211, b121] = edge_interior(m, c0, c1);
        out.extend([
            c0.v.clone(),
            c0.next.clone(),
            c1.prev.clone(),
            b211,
            b121,
            P::zero(),
        ]);
    }
    let centre = centre(c);
    let b202: Vec<P> = (0..m).map(|i| spokes(&out, m, i)[1].clone()).collect();
    for i in 0..m {
        let b112 = centre_ring(&out, &b202, &centre, m, i);
        out[SECTOR_POINTS * i + slot::B112] = b112;
    }
    out.push(centre);
    out
}

/// Eq. (20): the interior points `b_211`, `b_121` next to outer edge `c0 -> c1` of a Pm-patch,
/// fixed by G1 with the patch across (module docs).
fn edge_interior<P: GregoryPoint>(m: usize, c0: &FacetCorner<P>, c1: &FacetCorner<P>) -> [P; 2] {
    let mu = 1.0 - cos_n(1, m);
    let s = sin_n(1, c0.valence) + sin_n(1, c1.valence);
    let chi = |c: &FacetCorner<P>| 1.0 + cos_n(1, c.valence);
    let one = |v: &P, t_out: &P, t_back: &P, f_in: &P, f_out: &P, chi_here: f64, chi_there: f64| {
        let k_t = chi_here / (4.0 * mu);
        let k_v = (2.0 * mu - chi_there) / (8.0 * mu);
        let k_f = 3.0 / (8.0 * mu * s);
        combine(&[
            (0.25 - k_v, v),
            (0.75 - k_t + k_v, t_out),
            (k_t, t_back),
            (k_f, f_in),
            (-k_f, f_out),
        ])
    };
    [
        one(
            &c0.v,
            &c0.next,
            &c1.prev,
            &c0.f_in,
            &c0.f_next,
            chi(c0),
            chi(c1),
        ),
        one(
            &c1.v,
            &c1.prev,
            &c0.next,
            &c1.f_in,
            &c1.f_prev,
            chi(c1),
            chi(c0),
        ),
    ]
}

/// The centre `b_004 = Σ_i (w_m v^i + 3 (t^i_next + t^i_prev) + 9 f^i) / (m (w_m + 15))`.
fn centre<P: GregoryPoint>(c: &[FacetCorner<P>]) -> P {
    let m = c.len() as f64;
    let w = centre_weight(c.len());
    let d = m * (w + 15.0);
    let mut terms: Vec<(f64, &P)> = Vec::with_capacity(4 * c.len());
    for x in c {
        terms.extend([
            (w / d, &x.v),
            (3.0 / d, &x.next),
            (3.0 / d, &x.prev),
            (9.0 / d, &x.f_in),
        ]);
    }
    combine(&terms)
}

/// Eq. (21)/(22): `b^i_112` from the centre and the spoke points (module docs).
fn centre_ring<P: GregoryPoint>(pts: &[P], b202: &[P], centre: &P, m: usize, i: usize) -> P {
    let at = |k: usize, s: usize| &pts[SECTOR_POINTS * ((i + k) % m) + s];
    let b = |k: usize| &b202[(i + k) % m];
    match m {
        3 => combine(&[(1.5, centre), (-0.5, b(2))]),
        4 => combine(&[
            (1.0, centre),
            (3.0 / 16.0, at(0, slot::B211)),
            (3.0 / 16.0, at(0, slot::B121)),
            (-3.0 / 16.0, at(2, slot::B211)),
            (-3.0 / 16.0, at(2, slot::B121)),
            (1.0 / 16.0, at(3, slot::B211)),
            (1.0 / 16.0, at(1, slot::B121)),
            (-1.0 / 16.0, at(3, slot::B121)),
            (-1.0 / 16.0, at(1, slot::B211)),
        ]),
        _ => {
            let (c, c2) = (cos_n(1, m), cos_n(2, m));
            let k = c / (1.0 - c);
            combine(&[
                (1.0 - c, centre),
                (k, b(0)),
                (k, b(1)),
                (k * c2, b(2)),
                (k * c2, b(4)),
                (k * c, b(3)),
            ])
        }
    }
}

/// The spoke from corner `i` to the centre, shared by sectors `i - 1` and `i`: `[b_301, b_202,
/// b_103]` of sector `i` (eq. 3 with `l = 0, 1, 2`). Before the `b_112` are set only the first
/// two are meaningful.
pub fn spokes<P: GregoryPoint>(pts: &[P], m: usize, i: usize) -> [P; 3] {
    let cur = |s: usize| &pts[SECTOR_POINTS * i + s];
    let prv = |s: usize| &pts[SECTOR_POINTS * ((i + m - 1) % m) + s];
    let b310 = raise(cur(slot::V), cur(slot::B210));
    let b130_prev = raise(cur(slot::V), prv(slot::B120));
    let b301 = spoke_point(m, cur(slot::V), &b310, &b130_prev);
    let b202 = spoke_point(m, &b301, cur(slot::B211), prv(slot::B121));
    let b103 = spoke_point(m, &b202, cur(slot::B112), prv(slot::B112));
    [b301, b202, b103]
}

/// The 15 quartic coefficients of sector `i`, indexed by [`quartic_index`].
pub fn sector_quartic<P: GregoryPoint>(pts: &[P], i: usize) -> [P; 15] {
    let m = (pts.len() - 1) / SECTOR_POINTS;
    let j = (i + 1) % m;
    let cur = |s: usize| &pts[SECTOR_POINTS * i + s];
    let v1 = &pts[SECTOR_POINTS * j + slot::V];
    let s0 = spokes(pts, m, i);
    let s1 = spokes(pts, m, j);
    let mut q: [P; 15] = std::array::from_fn(|_| P::zero());
    let mut put = |a: usize, b: usize, x: P| q[quartic_index(a, b)] = x;
    put(4, 0, cur(slot::V).clone());
    put(3, 1, raise(cur(slot::V), cur(slot::B210)));
    put(
        2,
        2,
        combine(&[(0.5, cur(slot::B210)), (0.5, cur(slot::B120))]),
    );
    put(1, 3, raise(v1, cur(slot::B120)));
    put(0, 4, v1.clone());
    put(3, 0, s0[0].clone());
    put(2, 0, s0[1].clone());
    put(1, 0, s0[2].clone());
    put(0, 3, s1[0].clone());
    put(0, 2, s1[1].clone());
    put(0, 1, s1[2].clone());
    put(2, 1, cur(slot::B211).clone());
    put(1, 2, cur(slot::B121).clone());
    put(1, 1, cur(slot::B112).clone());
    put(0, 0, pts[pts.len() - 1].clone());
    q
}

/// Index of `b_{a, b, 4 - a - b}` in a quartic triangle's 15 coefficients.
pub const fn quartic_index(a: usize, b: usize) -> usize {
    // Rows by c = 4 - a - b: c = 0 has 5 entries (b = 0..4), c = 1 has 4, ...
    let c = 4 - a - b;
    let before = [0, 5, 9, 12, 14][c];
    before + b
}
