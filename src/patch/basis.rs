//! Cubic basis functions shared by the patch schemes.
//!
//! Uniform cubic B-spline basis (de Boor; the Catmull-Clark regular case, Köbler 2013 §2.1,
//! defined in [`crate::subdiv::bspline`] and re-exported here) and cubic Bernstein basis, each
//! with first derivatives, the bicubic tensor evaluation, and the B-spline to Bézier change of
//! basis.

use glam::DVec3;

pub use crate::subdiv::bspline::{bspline, bspline_deriv, eval_tensor};

/// Cubic Bernstein basis values at `t`.
pub fn bernstein(t: f64) -> [f64; 4] {
    let s = 1.0 - t;
    [s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t]
}

/// First derivatives of [`bernstein`] with respect to `t`.
pub fn bernstein_deriv(t: f64) -> [f64; 4] {
    let s = 1.0 - t;
    [
        -3.0 * s * s,
        3.0 * s * (s - 2.0 * t),
        3.0 * t * (2.0 * s - t),
        3.0 * t * t,
    ]
}

/// Row `i` gives Bézier point `i` of a uniform cubic B-spline segment as weights of its four
/// B-spline control points (the standard change of basis: `b0 = (p0 + 4p1 + p2)/6`,
/// `b1 = (2p1 + p2)/3`, `b2 = (p1 + 2p2)/3`, `b3 = (p1 + 4p2 + p3)/6`).
pub const BSPLINE_TO_BEZIER: [[f64; 4]; 4] = [
    [1.0 / 6.0, 4.0 / 6.0, 1.0 / 6.0, 0.0],
    [0.0, 2.0 / 3.0, 1.0 / 3.0, 0.0],
    [0.0, 1.0 / 3.0, 2.0 / 3.0, 0.0],
    [0.0, 1.0 / 6.0, 4.0 / 6.0, 1.0 / 6.0],
];

/// Converts a bicubic B-spline patch (`cvs[4*j + i]`, `i` along u) to the 16 control points
/// of the same surface in bicubic Bézier form (same indexing).
pub fn bspline_to_bezier(cvs: &[DVec3; 16]) -> [DVec3; 16] {
    let m = &BSPLINE_TO_BEZIER;
    // Rows first (along u), then columns (along v).
    let mut tmp = [DVec3::ZERO; 16];
    for j in 0..4 {
        for (i, row) in m.iter().enumerate() {
            tmp[4 * j + i] = (0..4).map(|k| row[k] * cvs[4 * j + k]).sum();
        }
    }
    let mut out = [DVec3::ZERO; 16];
    for i in 0..4 {
        for (j, row) in m.iter().enumerate() {
            out[4 * j + i] = (0..4).map(|k| row[k] * tmp[4 * k + i]).sum();
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn partitions_of_unity_and_derivatives() {
        for k in 0..=10 {
            let t = k as f64 / 10.0;
            let b: f64 = bspline(t).iter().sum();
            let d: f64 = bspline_deriv(t).iter().sum();
            let bb: f64 = bernstein(t).iter().sum();
            let bd: f64 = bernstein_deriv(t).iter().sum();
            assert!((b - 1.0).abs() < 1e-14 && d.abs() < 1e-14);
            assert!((bb - 1.0).abs() < 1e-14 && bd.abs() < 1e-14);
            // Derivatives against central differences.
            let h = 1e-6;
            for i in 0..4 {
                let fd = (bspline(t + h)[i] - bspline(t - h)[i]) / (2.0 * h);
                assert!((fd - bspline_deriv(t)[i]).abs() < 1e-8);
                let fd = (bernstein(t + h)[i] - bernstein(t - h)[i]) / (2.0 * h);
                assert!((fd - bernstein_deriv(t)[i]).abs() < 1e-8);
            }
        }
    }

    #[test]
    fn bezier_form_matches_bspline() {
        let mut cvs = [DVec3::ZERO; 16];
        for (k, c) in cvs.iter_mut().enumerate() {
            let x = k as f64;
            *c = DVec3::new((x * 1.3).sin(), (x * 0.7).cos(), x * x * 0.01);
        }
        let bez = bspline_to_bezier(&cvs);
        for (u, v) in [(0.0, 0.0), (0.3, 0.8), (1.0, 0.5), (0.25, 1.0)] {
            let a = eval_tensor(
                &cvs,
                &bspline(u),
                &bspline_deriv(u),
                &bspline(v),
                &bspline_deriv(v),
            );
            let b = eval_tensor(
                &bez,
                &bernstein(u),
                &bernstein_deriv(u),
                &bernstein(v),
                &bernstein_deriv(v),
            );
            assert!((a.0 - b.0).length() < 1e-12);
            assert!((a.1 - b.1).length() < 1e-12);
            assert!((a.2 - b.2).length() < 1e-12);
        }
    }
}
