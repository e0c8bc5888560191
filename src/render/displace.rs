//! The procedural displacement of `--displacement procedural` on the CPU: the same function of
//! the undisplaced limit position that `glsl/common/displace.glsl` evaluates in every
//! evaluation stage, for tests and for users reproducing displaced points without a GPU.
//!
//! `d(p) = (sin(5x + 1) + sin(5y + 2) + sin(5z + 3)) / 3` lies in [-1, 1] and is smooth, and it
//! depends on the position alone (not on a face's parameterisation), so it is continuous across
//! faces; the displaced point is `p + scale * d(p) * n` with the unit limit normal `n`.

use glam::DVec3;

/// Offsets of the three sine waves.
const PHASE: DVec3 = DVec3::new(1.0, 2.0, 3.0);
/// Angular frequency of the waves (radians per world unit).
const FREQUENCY: f64 = 5.0;

/// `d(p)` and its gradient.
pub fn procedural(p: DVec3) -> (f64, DVec3) {
    let a = FREQUENCY * p + PHASE;
    let d = (a.x.sin() + a.y.sin() + a.z.sin()) / 3.0;
    let grad = DVec3::new(a.x.cos(), a.y.cos(), a.z.cos()) * (FREQUENCY / 3.0);
    (d, grad)
}

/// The displaced point `p + scale d(p) n` and its shading normal: `n` tilted by the tangential
/// part of `scale grad d` (first order; the surface's curvature term is left out), as the
/// shaders compute it.
pub fn displaced(p: DVec3, n: DVec3, scale: f64) -> (DVec3, DVec3) {
    let (d, g) = procedural(p);
    let tangential = g - g.dot(n) * n;
    (p + scale * d * n, (n - scale * tangential).normalize())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gradient_matches_finite_differences() {
        let p = DVec3::new(0.3, -0.7, 1.1);
        let (_, g) = procedural(p);
        let h = 1e-6;
        for (k, e) in [DVec3::X, DVec3::Y, DVec3::Z].into_iter().enumerate() {
            let fd = (procedural(p + h * e).0 - procedural(p - h * e).0) / (2.0 * h);
            assert!((fd - g[k]).abs() < 1e-8, "axis {k}: {fd} vs {}", g[k]);
        }
    }

    #[test]
    fn displaces_along_the_normal_within_bounds() {
        let (p, n) = (DVec3::new(0.1, 0.2, 0.3), DVec3::Z);
        let (q, m) = displaced(p, n, 0.5);
        assert!((q - p).cross(n).length() < 1e-15, "moved along n only");
        assert!((q - p).length() <= 0.5 + 1e-15);
        assert!((m.length() - 1.0).abs() < 1e-12);
        assert_eq!(displaced(p, n, 0.0), (p, n));
    }
}
