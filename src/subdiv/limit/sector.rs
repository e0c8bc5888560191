//! Tangent plane of a quad sector bounded by two infinitely sharp edges (crease or corner rule),
//! per face: the limit of the face's own surface normal at the vertex.
//!
//! Near the vertex the surface is `v + sum_j lambda_j^k c_j phi_j` (left eigenvectors `l_j` of the
//! sector's subdivision matrix, `c_j = l_j . P`, eigenfunctions `phi_j`), so the normal along a
//! face's diagonal tends to the cross product of the two leading coefficients, or to a
//! face-dependent mix when the second place is tied. Spectra of a sector of `k` quads (the
//! eigenvalue 1 left out; `1/2^J` a Jordan block):
//!
//! | k | crease rule                  | corner rule                        | tangent plane         |
//! |---|------------------------------|------------------------------------|-----------------------|
//! | 1 | 1/2, (1/4)^J                 | 1/2, 1/2, 1/4                      | crease / both edges   |
//! | 2 | 1/2, 1/2, 1/4                | (1/2)^J, 1/2                       | crease / both edges   |
//! | 3 | .5797, 1/2, .4101            | .5797, 1/2, 1/2 (no Jordan block)  | crease / per face     |
//! | 4 | .6111, (1/2)^J               | .6111, (1/2)^J, 1/2                | lead of the 1/2 block |
//! | 5+| .6263, .5500, 1/2, ...       | .6263, .5500, 1/2, ...             | two leading modes     |
//!
//! The crease tangent `(e_lo - e_hi) / 2` and a corner's edge tangents `e - v` are exact
//! eigenvectors of 1/2. In a Jordan block of 1/2 the term growing like `k 2^-k` multiplies the
//! eigenvector that vanishes on the block's right eigenvectors, the linear functions of the
//! sector's flat layout: for four faces both sharp edges are the same line of the layout and that
//! eigenvector is `e_lo - e_hi`, the crease tangent. From five faces on two interior modes exceed
//! 1/2 and the sharp edges' tangents leave the tangent plane (the surface is not tangent-plane
//! continuous along the sharp edges at such a vertex; each face still has one limit normal).
//!
//! A corner-tagged vertex with one sharp edge and four quads (a four-face corner sector whose two
//! sharp edges are one) has the tie without the Jordan block: 0.6111, 1/2, 1/2 ([`corner_tag4`]).

use super::masks::{self, Dense, EigenLimit};

/// Ring entries of one sector (`0` is the vertex): the far ends of the lower and upper sharp
/// edges, of the face's two edges, the number of faces and the face's place among them.
#[derive(Debug, Clone, Copy)]
pub struct SectorRing {
    /// Ring size.
    pub m: usize,
    /// Far end of the sharp edge the sector starts at (counter-clockwise).
    pub lo: usize,
    /// Far end of the sharp edge the sector ends at.
    pub hi: usize,
    /// Far end of the face's first edge (counter-clockwise).
    pub a: usize,
    /// Far end of the face's second edge.
    pub b: usize,
    /// Faces in the sector.
    pub faces: usize,
    /// The face's place in the sector, from `lo`.
    pub face: usize,
    /// Corner rule (the vertex stays) rather than the crease rule.
    pub corner: bool,
}

/// `e_x - v` as ring weights.
fn edge(m: usize, x: usize) -> Vec<f64> {
    let mut t = vec![0.0; m];
    t[x] += 1.0;
    t[0] -= 1.0;
    t
}

fn combine(a: &[f64], wa: f64, b: &[f64], wb: f64) -> Vec<f64> {
    a.iter().zip(b).map(|(x, y)| wa * x + wb * y).collect()
}

/// Right eigenvector of the mode 0.5797 of the three-face corner sector on the ring
/// `(v, e_0 .. e_3, f_0 .. f_2)`, up to scale: zero on the sharp edges, symmetric. Computed
/// once by power iteration on a 49 x 49 window of the flat L-shaped layout (faces
/// `[0,1]^2, [-1,0] x [0,1], [-1,0]^2`) with the linear functions and constants deflated.
const CORNER3_MODE: [f64; 8] = [
    0.0,
    0.0,
    1.0,
    1.0,
    0.0,
    0.758_305_739_214_035_2,
    1.516_611_478_428_070_4,
    0.758_305_739_214_035_2,
];

/// The gradient of that eigenfunction at the diagonal point `(t, t)` of face 0 of the layout is
/// proportional to `(-CORNER3_RATIO, 1)` for every `t` (self-similarity; face 2 is the mirror
/// image, face 1 lies on the mirror line with gradient `(-1, 1)`).
const CORNER3_RATIO: f64 = 0.192_249_564_268_589_4;

/// Three-face corner sector: the normal of face `j` along its diagonal is
/// `c_1 x -(phi_y c_lo + phi_x c_hi)` (`c_lo = e_lo - v` pairs with the layout's `x`,
/// `c_hi = e_hi - v` with `-y`), `grad phi` at that face's diagonal from the constants above.
fn corner3(s: &Dense, r: &SectorRing) -> Option<EigenLimit> {
    if r.m != CORNER3_MODE.len() {
        return None;
    }
    let l1 = masks::subdominant(s, 0, CORNER3_MODE.to_vec())?;
    // Sign so that c_1 multiplies the eigenfunction that is positive inside the sector.
    let sign = masks::dot(&l1, &CORNER3_MODE).signum();
    if sign == 0.0 {
        return None;
    }
    let t1: Vec<f64> = l1.iter().map(|x| sign * x).collect();
    let (lo, hi) = (edge(r.m, r.lo), edge(r.m, r.hi));
    let (gx, gy) = match r.face {
        0 => (-CORNER3_RATIO, 1.0),
        1 => (-1.0, 1.0),
        _ => (-1.0, CORNER3_RATIO),
    };
    let t2 = combine(&lo, -gy, &hi, -gx);
    let mut position = vec![0.0; r.m];
    position[0] = 1.0;
    Some(EigenLimit {
        position,
        tangents: [t1, t2],
    })
}

/// Right eigenvector of the leading mode (0.6111) of a corner-tagged vertex with four quads and
/// one sharp edge on the ring `(v, e_0 .. e_3, f_0 .. f_3)`, `e_0` the sharp edge's far end:
/// zero on the sharp edge, symmetric about it (`f_0 = f_3 = sqrt 2 - 1`). Inverse iteration on
/// the ring matrix written from the rules (checked below; tests/limit_corners.rs builds the ring
/// matrix from `refine`).
const TAG4_MODE: [f64; 9] = [
    0.0,
    0.0,
    0.598_317_451_815_773_8,
    0.846_148_654_962_378_3,
    0.598_317_451_815_773_8,
    0.414_213_562_373_095,
    1.0,
    1.0,
    0.414_213_562_373_095,
];

/// `d phi / du : d phi / dv` of that eigenfunction at the diagonal points `(2^-k, 2^-k)` of faces
/// 0 and 1 (`u` along `e_j`, `v` along `e_{j+1}`); faces 3 and 2 are their mirror images (`u`, `v`
/// swapped). From the face's tangents at `(2^-16, 2^-16)` projected on the mode (the ratio agrees
/// to 1e-12 between `2^-20` and `2^-24`; tests/limit_corners.rs).
const TAG4_RATIO: [f64; 2] = [-0.262_698_010_402_848_6, 0.545_792_811_746_672_8];

/// Corner tag with one sharp edge and four quads (spectrum 1, 0.6111, 1/2, 1/2, 0.3657, ...):
/// the second place is a tie of two modes whose right eigenvectors are the linear functions `x`,
/// `y` of the flat layout (`e_j` at `j` quarter turns from the sharp edge), so, as in the
/// three-face corner sector, every face has its own normal: along face `j`'s diagonal the normal
/// tends to `c_1 x (-G_y c_x + G_x c_y)`, `G` the layout gradient of the 0.6111 eigenfunction
/// there (`TAG4_RATIO`) and `c_x`, `c_y` the coefficients of the `1/2` left eigenvectors dual
/// to `x`, `y` (deflated power iteration of `2 S` from `e_0 - v` and `e_1 - v`, which pair with
/// `x`, `y` as the duals do).
pub fn corner_tag4(s: &Dense, face: usize) -> Option<EigenLimit> {
    if s.m != TAG4_MODE.len() || face >= 4 {
        return None;
    }
    let l0 = masks::dominant(s, 0)?;
    let l1 = masks::subdominant(s, 0, TAG4_MODE.to_vec())?;
    let p1 = masks::dot(&l1, &TAG4_MODE);
    if p1.abs() < 1e-12 {
        return None;
    }
    let t1: Vec<f64> = l1.iter().map(|x| p1.signum() * x).collect();
    // Component on the left eigenspace of 1/2: the constant and the 0.6111 mode deflated every
    // step, the rest (0.3657 and below) decays by 0.73 per step.
    let half = |start: Vec<f64>| -> Option<Vec<f64>> {
        let mut x = start;
        for _ in 0..400 {
            let mut y: Vec<f64> = s.left_mul(&x).iter().map(|v| 2.0 * v).collect();
            let c: f64 = y.iter().sum();
            let d = masks::dot(&y, &TAG4_MODE) / p1;
            for ((yi, a), b) in y.iter_mut().zip(&l0).zip(&l1) {
                *yi -= c * a + d * b;
            }
            let diff: f64 = y.iter().zip(&x).map(|(a, b)| (a - b).abs()).sum();
            x = y;
            if diff < 1e-15 {
                return Some(x);
            }
        }
        None
    };
    let (lx, ly) = (half(edge(s.m, 1))?, half(edge(s.m, 2))?);
    let quarter = |j: usize| [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)][j % 4];
    let (gu, gv) = match face {
        0 => (TAG4_RATIO[0], 1.0),
        1 => (TAG4_RATIO[1], 1.0),
        2 => (1.0, TAG4_RATIO[1]),
        _ => (1.0, TAG4_RATIO[0]),
    };
    let (a, b) = (quarter(face), quarter(face + 1));
    let g = (gu * a.0 + gv * b.0, gu * a.1 + gv * b.1);
    let t2 = combine(&lx, -g.1, &ly, g.0);
    let mut position = vec![0.0; s.m];
    position[0] = 1.0;
    Some(EigenLimit {
        position,
        tangents: [t1, t2],
    })
}

/// Whether [`sector_limit`] orients the pair exactly (corner sectors of up to three faces: the
/// sharp edges' tangents in counter-clockwise order, or the three-face formula); elsewhere the
/// caller orients it by the face ([`masks::face_orientation`]).
pub fn exact_orientation(r: &SectorRing) -> bool {
    r.corner && r.lo != r.hi && r.faces <= 3
}

/// Position and tangent masks of face `r.face` of a sector bounded by two sharp edges (see the
/// module table). `None` if an iteration does not converge.
pub fn sector_limit(s: &Dense, r: &SectorRing) -> Option<EigenLimit> {
    let m = r.m;
    if r.lo == r.hi {
        // One sharp edge bounds the sector on both sides (it wraps round the vertex).
        let mut hint = vec![1.0 / (m - 1) as f64; m];
        hint[0] = -1.0;
        return masks::eigen_limit_locked(s, 0, edge(m, r.lo), hint);
    }
    if r.faces >= 5 {
        return masks::eigen_limit(s, 0, [edge(m, r.a), edge(m, r.b)]);
    }
    if r.corner && r.faces <= 2 {
        // Both sharp edges' tangents are exact eigenvectors of the top eigenvalue 1/2.
        let mut position = vec![0.0; m];
        position[0] = 1.0;
        return Some(EigenLimit {
            position,
            tangents: [edge(m, r.lo), edge(m, r.hi)],
        });
    }
    if r.corner && r.faces == 3 {
        return corner3(s, r);
    }
    // Crease sectors of up to four faces and corner sectors of four: lock `(e_lo - e_hi) / 2`,
    // the cross tangent is the dominant mode of the rest, pointing into the sector;
    // (lower edge, into the sector) is counter-clockwise.
    let lock = combine(&edge(m, r.lo), 0.5, &edge(m, r.hi), -0.5);
    let mut hint = vec![1.0 / (m - 1) as f64; m];
    hint[0] = -1.0;
    masks::eigen_limit_locked(s, 0, lock, hint)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The subdivision matrix of a sector of `k` quads written from the rules (ring
    /// `v, e_0 .. e_k, f_0 .. f_{k-1}`; `e_0`, `e_k` sharp): face points, smooth edge points
    /// `(v + e + F + F') / 4`, sharp edge midpoints, and the vertex kept (corner) or `1/8, 3/4,
    /// 1/8` (crease).
    fn sector_matrix(k: usize, corner: bool) -> Dense {
        let m = 2 * k + 2;
        let (e, f) = (|i: usize| 1 + i, |i: usize| k + 2 + i);
        let mut a = vec![0.0; m * m];
        let face = |i: usize| {
            let mut r = vec![0.0; m];
            for x in [0, e(i), e(i + 1), f(i)] {
                r[x] += 0.25;
            }
            r
        };
        if corner {
            a[0] = 1.0;
        } else {
            a[0] = 0.75;
            a[e(0)] = 0.125;
            a[e(k)] = 0.125;
        }
        for j in [0, k] {
            a[e(j) * m] = 0.5;
            a[e(j) * m + e(j)] = 0.5;
        }
        for j in 1..k {
            let (p, q) = (face(j - 1), face(j));
            for c in 0..m {
                a[e(j) * m + c] = 0.25 * (p[c] + q[c]);
            }
            a[e(j) * m] += 0.25;
            a[e(j) * m + e(j)] += 0.25;
        }
        for i in 0..k {
            a[f(i) * m..(f(i) + 1) * m].copy_from_slice(&face(i));
        }
        Dense { m, a }
    }

    /// Leading eigenvalue once 1 is deflated: Rayleigh quotient of the converged left vector.
    fn leading(s: &Dense) -> f64 {
        let mut start = vec![1.0; s.m];
        start[0] = 0.3;
        start[1] = -0.7;
        let l = masks::subdominant(s, 0, start).unwrap();
        let (m, a) = (s.m, &s.a);
        let ls: Vec<f64> = (0..m)
            .map(|c| (0..m).map(|r| l[r] * a[r * m + c]).sum())
            .collect();
        masks::dot(&ls, &l) / masks::dot(&l, &l)
    }

    #[test]
    fn leading_eigenvalues_of_the_table() {
        for (k, corner, want) in [
            (3, true, 0.57968),
            (3, false, 0.57968),
            (4, true, 0.61112),
            (5, false, 0.62634),
            (5, true, 0.62634),
        ] {
            let got = leading(&sector_matrix(k, corner));
            assert!((got - want).abs() < 1e-5, "k={k} corner={corner}: {got}");
        }
    }

    /// The ring matrix of a corner-tagged vertex with four quads and one sharp edge (`e_0`) from
    /// the rules: the vertex stays, the sharp edge's midpoint, smooth edge points, face points.
    fn corner_tag4_matrix() -> Dense {
        let m = 9;
        let (e, f) = (|i: usize| 1 + i % 4, |i: usize| 5 + i % 4);
        let face = |i: usize| {
            let mut r = vec![0.0; m];
            for x in [0, e(i), e(i + 1), f(i)] {
                r[x] += 0.25;
            }
            r
        };
        let mut a = vec![0.0; m * m];
        a[0] = 1.0;
        a[e(0) * m] = 0.5;
        a[e(0) * m + e(0)] = 0.5;
        for j in 1..4 {
            let (p, q) = (face(j - 1), face(j));
            for c in 0..m {
                a[e(j) * m + c] = 0.25 * (p[c] + q[c]);
            }
            a[e(j) * m] += 0.25;
            a[e(j) * m + e(j)] += 0.25;
        }
        for i in 0..4 {
            a[f(i) * m..(f(i) + 1) * m].copy_from_slice(&face(i));
        }
        Dense { m, a }
    }

    #[test]
    fn corner_tag4_modes_are_right_eigenvectors() {
        let s = corner_tag4_matrix();
        let m = s.m;
        let apply = |r: &[f64]| -> Vec<f64> {
            (0..m)
                .map(|i| (0..m).map(|c| s.a[i * m + c] * r[c]).sum())
                .collect()
        };
        let sr = apply(&TAG4_MODE);
        for (x, y) in sr.iter().zip(TAG4_MODE) {
            assert!((x - 0.611_116_526_694_538_8 * y).abs() < 1e-12, "{sr:?}");
        }
        // The flat layout's linear functions (e_j at j quarter turns, f_j = e_j + e_{j+1}).
        let quarter = [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)];
        for axis in 0..2 {
            let c = |j: usize| {
                if axis == 0 {
                    quarter[j % 4].0
                } else {
                    quarter[j % 4].1
                }
            };
            let mut r = vec![0.0; m];
            for j in 0..4 {
                r[1 + j] = c(j);
                r[5 + j] = c(j) + c(j + 1);
            }
            for (x, y) in apply(&r).iter().zip(&r) {
                assert!((x - 0.5 * y).abs() < 1e-15, "axis {axis}");
            }
        }
        // Every face gets a tangent pair.
        for face in 0..4 {
            let lim = corner_tag4(&s, face).unwrap();
            assert!(masks::dot(&lim.tangents[1], &lim.tangents[1]) > 1e-6);
        }
    }

    #[test]
    fn three_face_corner_mode_is_a_right_eigenvector() {
        let s = sector_matrix(3, true);
        let m = s.m;
        let r = CORNER3_MODE;
        let sr: Vec<f64> = (0..m)
            .map(|i| (0..m).map(|c| s.a[i * m + c] * r[c]).sum())
            .collect();
        let lambda = masks::dot(&sr, &r) / masks::dot(&r, &r);
        assert!((lambda - 0.579_682_326).abs() < 1e-8, "{lambda}");
        for (x, y) in sr.iter().zip(r) {
            assert!((x - lambda * y).abs() < 1e-9, "{sr:?}");
        }
    }
}
