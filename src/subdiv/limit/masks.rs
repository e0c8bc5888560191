//! Closed-form Catmull-Clark limit masks on an explicit quad one-ring, and the numerical
//! eigen-analysis of a local subdivision matrix used where no closed form applies.
//!
//! Ring convention (valence `n`, all faces quads): `e[i]` is the far end of the i-th edge
//! counter-clockwise around the vertex, `f[i]` the vertex opposite the centre in the quad
//! between edges `i` and `i + 1`.

use std::borrow::Cow;
use std::f64::consts::PI;
use std::sync::OnceLock;

/// Weights of the smooth interior limit position on a quad ring:
/// `(n^2 v + 4 sum e + sum f) / (n (n + 5))` (Halstead, Kass, DeRose 1993, §A; the dominant left
/// eigenvector of the Catmull-Clark subdivision matrix). Returns `(w_v, w_e, w_f)`.
pub fn smooth_position(n: usize) -> (f64, f64, f64) {
    let nf = n as f64;
    let d = nf * (nf + 5.0);
    (nf * nf / d, 4.0 / d, 1.0 / d)
}

/// Smooth interior limit tangent on a quad ring, pointing along edge `start` (Halstead et al.
/// 1993 eq. for the subdominant eigenvectors):
/// `t = sum_i A_n c_i e_i + (c_i + c_{i+1}) f_i`, `c_i = cos(2 pi (i - start) / n)`,
/// `A_n = 1 + cos(2pi/n) + cos(pi/n) sqrt(2 (9 + cos(2pi/n)))`, scaled by `1/12` so that the
/// regular case `n = 4` gives exactly the bicubic B-spline partial derivative.
/// Returns `(w_e, w_f)` (the centre weight is 0).
pub fn smooth_tangent(n: usize, start: usize) -> (Vec<f64>, Vec<f64>) {
    let table = SmoothTangent::of(n);
    (0..n).map(|i| table.at(i, start)).unzip()
}

/// [`smooth_tangent`] of one valence along edge 0, from which every `start` is a rotation (its
/// weights depend on `i - start` only): computed once per valence ([`SmoothTangent::of`]).
#[derive(Debug, Clone)]
pub struct SmoothTangent {
    /// `A_n c_k / 12` for `k = i - start` (mod `n`).
    edge: Vec<f64>,
    /// `(c_k + c_{k+1}) / 12`.
    face: Vec<f64>,
}

/// Valences whose [`SmoothTangent`] is kept once computed (larger ones are computed per call).
const TABLED_VALENCES: usize = 64;

impl SmoothTangent {
    /// The weights of valence `n` (`n >= 1`), computed on first use of that valence (up to
    /// 64).
    pub fn of(n: usize) -> Cow<'static, SmoothTangent> {
        static TABLES: [OnceLock<SmoothTangent>; TABLED_VALENCES + 1] =
            [const { OnceLock::new() }; TABLED_VALENCES + 1];
        match TABLES.get(n) {
            Some(cell) => Cow::Borrowed(cell.get_or_init(|| Self::new(n))),
            None => Cow::Owned(Self::new(n)),
        }
    }

    fn new(n: usize) -> SmoothTangent {
        let nf = n as f64;
        let c1 = (2.0 * PI / nf).cos();
        let a = 1.0 + c1 + (PI / nf).cos() * (2.0 * (9.0 + c1)).sqrt();
        let c: Vec<f64> = (0..n).map(|k| (2.0 * PI * k as f64 / nf).cos()).collect();
        SmoothTangent {
            edge: c.iter().map(|&ck| a * ck / 12.0).collect(),
            face: (0..n).map(|k| (c[k] + c[(k + 1) % n]) / 12.0).collect(),
        }
    }

    /// `(w_e, w_f)` of ring index `i` for the tangent along edge `start`.
    pub fn at(&self, i: usize, start: usize) -> (f64, f64) {
        let n = self.edge.len();
        let k = (i + n - start % n) % n;
        (self.edge[k], self.face[k])
    }
}

/// Limit position of a crease vertex (two infinitely sharp edges, crease rule): the cubic
/// B-spline of the crease polygon, `(e_a + 4 v + e_b) / 6`. Returns `(w_v, w_end)`.
pub fn crease_position() -> (f64, f64) {
    (4.0 / 6.0, 1.0 / 6.0)
}

/// A small dense square matrix, row-major.
#[derive(Debug, Clone)]
pub struct Dense {
    /// Dimension.
    pub m: usize,
    /// `m * m` entries, row-major.
    pub a: Vec<f64>,
}

impl Dense {
    /// Row vector times matrix: `x S`.
    pub fn left_mul(&self, x: &[f64]) -> Vec<f64> {
        let mut y = Vec::with_capacity(self.m);
        self.left_mul_into(x, &mut y);
        y
    }

    /// [`Self::left_mul`] into `y` (the power iterations' buffers). Row by row, each `y[j]`
    /// summed in increasing `i`, zero entries of `x` skipped; `y` and each row as slices of
    /// length `m` (the rows by `chunks_exact`), so the inner loop needs no bounds checks.
    fn left_mul_into(&self, x: &[f64], y: &mut Vec<f64>) {
        let m = self.m;
        y.clear();
        y.resize(m, 0.0);
        let y = &mut y[..m];
        for (row, &xi) in self.a.chunks_exact(m).zip(x) {
            if xi == 0.0 {
                continue;
            }
            for (yj, &r) in y.iter_mut().zip(&row[..m]) {
                *yj += xi * r;
            }
        }
    }
}

/// The dominant left eigenvector (eigenvalue 1) of an affine subdivision matrix by power
/// iteration from the unit vector at `centre`, normalised to sum 1.
pub fn dominant(s: &Dense, centre: usize) -> Option<Vec<f64>> {
    let mut l = vec![0.0; s.m];
    l[centre] = 1.0;
    let mut next = Vec::with_capacity(s.m);
    for _ in 0..4000 {
        s.left_mul_into(&l, &mut next);
        let diff: f64 = next.iter().zip(&l).map(|(a, b)| (a - b).abs()).sum();
        std::mem::swap(&mut l, &mut next);
        if diff < 1e-15 {
            let total: f64 = l.iter().sum();
            if total.abs() < 1e-12 {
                return None;
            }
            l.iter_mut().for_each(|x| *x /= total);
            return Some(l);
        }
    }
    None
}

/// Limit masks when one subdominant left eigenvector is known exactly (`lock`, e.g. the crease
/// tangent `(e_lo - e_hi) / 2` or a corner's edge tangent `e_lo - v`): the second tangent is the
/// dominant mode of `S` on the complement of `1`-eigenvector and `lock` (power iteration with
/// deflation and Gram-Schmidt against `lock`), signed to have a positive product with `hint`.
/// Used at crease and corner sectors, where the spectrum may hold a repeated eigenvalue that
/// stalls plain subspace iteration (e.g. a boundary vertex with 4 faces: 1, 0.611, 0.5, 0.5).
pub fn eigen_limit_locked(
    s: &Dense,
    centre: usize,
    lock: Vec<f64>,
    hint: Vec<f64>,
) -> Option<EigenLimit> {
    let l = dominant(s, centre)?;
    locked(s, l, lock, hint)
}

/// [`eigen_limit_locked`] with `s`'s dominant mode `l` given.
fn locked(s: &Dense, l: Vec<f64>, lock: Vec<f64>, hint: Vec<f64>) -> Option<EigenLimit> {
    let nl = norm(&lock);
    if nl < 1e-300 {
        return None;
    }
    let lock_unit: Vec<f64> = lock.iter().map(|x| x / nl).collect();
    let project = |x: &mut Vec<f64>| -> bool {
        let c: f64 = x.iter().sum();
        for (xi, li) in x.iter_mut().zip(&l) {
            *xi -= c * li;
        }
        let d = dot(x, &lock_unit);
        for (xi, li) in x.iter_mut().zip(&lock_unit) {
            *xi -= d * li;
        }
        let n = norm(x);
        if n < 1e-300 {
            return false;
        }
        x.iter_mut().for_each(|v| *v /= n);
        true
    };
    let mut hint = hint;
    if !project(&mut hint) {
        return None;
    }
    let mut x = hint.clone();
    let mut y = Vec::with_capacity(s.m);
    // A repeated quotient eigenvalue with a Jordan block (e.g. a crease vertex whose sector has
    // one face: spectrum 1, 1/2, 1/4, 1/4) converges only like 1/k: allow many cheap steps and
    // accept a direction that has stopped moving to 1e-7 per step (its error is then ~1e-4).
    let max_iter = (20_000_000 / (s.m * s.m)).clamp(4000, 50_000);
    for it in 0..max_iter {
        s.left_mul_into(&x, &mut y);
        if !project(&mut y) {
            return None;
        }
        let sign = if dot(&y, &x) < 0.0 { -1.0 } else { 1.0 };
        let diff: f64 = y
            .iter()
            .zip(&x)
            .map(|(a, b)| (a - sign * b).powi(2))
            .sum::<f64>()
            .sqrt();
        std::mem::swap(&mut x, &mut y);
        if diff < 1e-13 || (it + 1 == max_iter && diff < 1e-7) {
            if dot(&x, &hint) < 0.0 {
                x.iter_mut().for_each(|v| *v = -*v);
            }
            return Some(EigenLimit {
                position: l,
                tangents: [lock, x],
            });
        }
    }
    None
}

/// Orientation of the tangent pair `t` for the face whose edge vectors at the vertex are `xa`,
/// `xb` (counter-clockwise): `+1` if `t[0] x t[1]` is the face's outward normal, `-1` if not.
///
/// The face's corner `(v, e_a, e_b)` after `k` steps is `(xa S^k, xb S^k)`; its wedge tends to
/// `D l_1 ^ l_2` over the leading left modes, with `D` the orientation of the characteristic map
/// on that face. Orthonormalising the pair each step (Gram-Schmidt, which keeps the wedge's sign)
/// and pairing it with `t[0] ^ t[1]` gives that sign; the iteration stops once the pairing has
/// settled. `None` if `t` is degenerate or the pairing vanishes.
pub fn face_orientation(
    s: &Dense,
    centre: usize,
    xa: &[f64],
    xb: &[f64],
    t: [&[f64]; 2],
) -> Option<f64> {
    let l = dominant(s, centre)?;
    let deflate = |x: &mut Vec<f64>| {
        let c: f64 = x.iter().sum();
        for (xi, li) in x.iter_mut().zip(&l) {
            *xi -= c * li;
        }
    };
    let unit = |x: &mut Vec<f64>| -> bool {
        let n = norm(x);
        x.iter_mut().for_each(|v| *v /= n);
        n > 1e-300
    };
    let (mut t0, mut t1) = (t[0].to_vec(), t[1].to_vec());
    if !unit(&mut t0) || !unit(&mut t1) {
        return None;
    }
    let (mut ya, mut yb) = (xa.to_vec(), xb.to_vec());
    let mut product = Vec::with_capacity(s.m);
    let mut last = 0.0;
    let steps = (4_000_000 / (s.m * s.m)).clamp(40, 400);
    for it in 0..steps {
        s.left_mul_into(&ya, &mut product);
        std::mem::swap(&mut ya, &mut product);
        s.left_mul_into(&yb, &mut product);
        std::mem::swap(&mut yb, &mut product);
        deflate(&mut ya);
        deflate(&mut yb);
        if !unit(&mut ya) {
            return None;
        }
        let d = dot(&yb, &ya);
        yb.iter_mut().zip(&ya).for_each(|(b, a)| *b -= d * a);
        if !unit(&mut yb) {
            return None;
        }
        let w = dot(&t0, &ya) * dot(&t1, &yb) - dot(&t0, &yb) * dot(&t1, &ya);
        if it >= 8 && (w - last).abs() < 1e-9 {
            break;
        }
        last = w;
    }
    (last.abs() > 1e-6).then(|| last.signum())
}

/// Result of [`eigen_limit`]: weights over the ring entries of the local subdivision matrix.
#[derive(Debug, Clone)]
pub struct EigenLimit {
    /// Dominant left eigenvector (eigenvalue 1), normalised to sum 1: the limit position mask.
    pub position: Vec<f64>,
    /// Two vectors spanning the subdominant left invariant subspace: tangent masks, in the
    /// orientation of the starting pair.
    pub tangents: [Vec<f64>; 2],
}

pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

/// Limit masks from the local subdivision matrix `s` (rows: the ring after one step in terms of
/// the ring before; affine, so rows sum to 1). Halstead et al. 1993 §A: limit position and
/// tangents are left eigenvectors of the subdivision matrix.
///
/// `centre` is the ring entry of the vertex; `start = [x_a, x_b]` are the face's two edge
/// vectors at the vertex (`e_a - e_centre`, `e_b - e_centre`, counter-clockwise). The first
/// tangent is the dominant mode reached from `x_a + x_b` ([`subdominant`]), the second the
/// dominant mode of the quotient by the first, signed by `x_b - x_a`. Since
/// `(x_a + x_b) x (x_b - x_a) = 2 x_a x x_b`, the pair keeps the face's orientation. This also
/// covers spectra whose top mode is simple (darts, corner tags with smooth edges, sectors of five
/// or more faces) where the tangent plane is spanned by two modes of different eigenvalues.
/// Returns `None` when the iteration does not converge.
pub fn eigen_limit(s: &Dense, centre: usize, start: [Vec<f64>; 2]) -> Option<EigenLimit> {
    let [xa, xb] = start;
    let sum: Vec<f64> = xa.iter().zip(&xb).map(|(a, b)| a + b).collect();
    // One dominant mode for both iterations (each would find the same).
    let l = dominant(s, centre)?;
    let t1 = subdominant_with(s, &l, sum)?;
    let hint: Vec<f64> = xa.iter().zip(&xb).map(|(a, b)| b - a).collect();
    locked(s, l, t1, hint)
}

/// The dominant left eigenvector of `s` once the eigenvalue 1 is deflated (power iteration from
/// `start`, unit length, the sign it converges to). `None` without convergence.
pub fn subdominant(s: &Dense, centre: usize, start: Vec<f64>) -> Option<Vec<f64>> {
    let l = dominant(s, centre)?;
    subdominant_with(s, &l, start)
}

/// [`subdominant`] with `s`'s dominant mode `l` given.
fn subdominant_with(s: &Dense, l: &[f64], start: Vec<f64>) -> Option<Vec<f64>> {
    let deflate_unit = |x: &mut Vec<f64>| -> bool {
        let c: f64 = x.iter().sum();
        for (xi, li) in x.iter_mut().zip(l) {
            *xi -= c * li;
        }
        let n = norm(x);
        if n < 1e-300 {
            return false;
        }
        x.iter_mut().for_each(|v| *v /= n);
        true
    };
    let mut x = start;
    if !deflate_unit(&mut x) {
        return None;
    }
    let mut y = Vec::with_capacity(s.m);
    let max_iter = (20_000_000 / (s.m * s.m)).clamp(4000, 50_000);
    for it in 0..max_iter {
        s.left_mul_into(&x, &mut y);
        if !deflate_unit(&mut y) {
            return None;
        }
        let diff: f64 = y
            .iter()
            .zip(&x)
            .map(|(a, b)| (a - b).powi(2))
            .sum::<f64>()
            .sqrt();
        std::mem::swap(&mut x, &mut y);
        if diff < 1e-13 || (it + 1 == max_iter && diff < 1e-7) {
            return Some(x);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The local subdivision matrix of a smooth interior quad ring of valence n, built from the
    /// Catmull-Clark rules (independent of the closed-form masks). Ring order: v, e_0..e_{n-1},
    /// f_0..f_{n-1}.
    fn smooth_ring_matrix(n: usize) -> Dense {
        let m = 2 * n + 1;
        let mut a = vec![0.0; m * m];
        let nf = n as f64;
        let e = |i: usize| 1 + (i % n);
        let f = |i: usize| 1 + n + (i % n);
        // Face point of quad i: (v + e_i + f_i + e_{i+1}) / 4.
        let face_row = |i: usize| {
            let mut r = vec![0.0; m];
            r[0] += 0.25;
            r[e(i)] += 0.25;
            r[f(i)] += 0.25;
            r[e(i + 1)] += 0.25;
            r
        };
        for i in 0..n {
            let r = face_row(i);
            a[f(i) * m..(f(i) + 1) * m].copy_from_slice(&r);
        }
        // Edge point of edge i: (v + e_i + F_{i-1} + F_i) / 4.
        for i in 0..n {
            let mut r = vec![0.0; m];
            r[0] += 0.25;
            r[e(i)] += 0.25;
            for (k, x) in face_row(i).iter().enumerate() {
                r[k] += 0.25 * x;
            }
            for (k, x) in face_row(i + n - 1).iter().enumerate() {
                r[k] += 0.25 * x;
            }
            a[e(i) * m..(e(i) + 1) * m].copy_from_slice(&r);
        }
        // Vertex point: (n-2)/n v + 1/n^2 sum e + 1/n^2 sum F.
        let mut r = vec![0.0; m];
        r[0] += (nf - 2.0) / nf;
        for i in 0..n {
            r[e(i)] += 1.0 / (nf * nf);
            for (k, x) in face_row(i).iter().enumerate() {
                r[k] += x / (nf * nf);
            }
        }
        a[..m].copy_from_slice(&r);
        Dense { m, a }
    }

    /// The per-valence table gives the closed form bit for bit (Halstead's `A_n c_k / 12` and
    /// `(c_k + c_{k+1}) / 12`, each cosine taken at its own `k = i - start` mod `n`), for tabled
    /// valences and for valences past the table, any `start` (also past `n`).
    #[test]
    fn smooth_tangent_table_is_the_closed_form() {
        for n in (3..=12).chain([63, 64, 65, 100]) {
            let nf = n as f64;
            let c1 = (2.0 * PI / nf).cos();
            let a = 1.0 + c1 + (PI / nf).cos() * (2.0 * (9.0 + c1)).sqrt();
            let c =
                |i: usize, start: usize| (2.0 * PI * ((i + n - start % n) % n) as f64 / nf).cos();
            for start in [0, 1, n - 1, n + 2] {
                let (we, wf) = smooth_tangent(n, start);
                for i in 0..n {
                    let (e, f) = (
                        a * c(i, start) / 12.0,
                        (c(i, start) + c(i + 1, start)) / 12.0,
                    );
                    assert_eq!(we[i].to_bits(), e.to_bits(), "n {n}, start {start}, e {i}");
                    assert_eq!(wf[i].to_bits(), f.to_bits(), "n {n}, start {start}, f {i}");
                }
            }
        }
    }

    #[test]
    fn numeric_matches_closed_form_smooth() {
        for n in [3usize, 4, 5, 6, 8, 12] {
            let s = smooth_ring_matrix(n);
            let m = s.m;
            let mut x1 = vec![0.0; m];
            x1[1] = 1.0;
            x1[0] = -1.0;
            let mut x2 = vec![0.0; m];
            x2[2] = 1.0;
            x2[0] = -1.0;
            let r = eigen_limit(&s, 0, [x1, x2]).expect("converges");
            let (wv, we, wf) = smooth_position(n);
            assert!((r.position[0] - wv).abs() < 1e-12, "n={n}");
            for i in 0..n {
                assert!((r.position[1 + i] - we).abs() < 1e-12);
                assert!((r.position[1 + n + i] - wf).abs() < 1e-12);
            }
            // Both closed-form tangents lie in the numerical subspace.
            for start in 0..2 {
                let (te, tf) = smooth_tangent(n, start);
                let mut t = vec![0.0; m];
                t[1..=n].copy_from_slice(&te);
                t[n + 1..].copy_from_slice(&tf);
                let a = dot(&t, &r.tangents[0]);
                let b = dot(&t, &r.tangents[1]);
                let res: f64 = t
                    .iter()
                    .zip(r.tangents[0].iter().zip(&r.tangents[1]))
                    .map(|(ti, (p, q))| (ti - a * p - b * q).powi(2))
                    .sum::<f64>()
                    .sqrt();
                assert!(res < 1e-10 * norm(&t), "n={n} res={res}");
            }
        }
    }
}
