//! The quadratic Bézier patches of QAS (Boubekeur, Schlick 2007), written once over any point
//! type (positions, normals): the coefficients that interpolate limit points at the domain's
//! corners, edge midpoints and (quads) centre, and their evaluation.
//!
//! Quads (biquadratic, 9 coefficients, index `3 j + i`, `i` along `u`): the 1-D quadratic
//! through `p(0), p(½), p(1)` has Bézier points `p(0)`, `2 p(½) - (p(0) + p(1)) / 2`, `p(1)`
//! (Bernstein weights at ½ are ¼, ½, ¼); the tensor product gives the edge coefficients by that
//! rule and the centre `4 f - Σ edge points + ¼ Σ corners`. Triangles (quadratic, 6
//! coefficients): the paper's `p110 = (4 p_e - p0 - p1) / 2`, which is the same edge rule, so a
//! quad and a triangle sharing an edge have the same boundary curve.

use std::ops::{Add, Mul, Sub};

/// What the construction runs on: positions, normals (`DVec3`) or scalars.
pub trait QuadPoint:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<f64, Output = Self>
{
}

impl<T: Copy + Add<Output = T> + Sub<Output = T> + Mul<f64, Output = T>> QuadPoint for T {}

/// The Bézier point of an edge whose quadratic interpolates `a`, `mid` (at ½) and `b`:
/// `(4 mid - (a + b)) / 2`; symmetric in `a` and `b` bit for bit (IEEE addition commutes), so
/// both faces of an edge get the same coefficient.
pub fn edge_control<T: QuadPoint>(a: T, mid: T, b: T) -> T {
    (mid * 4.0 - (a + b)) * 0.5
}

/// Grid slots (`3 j + i`) of a quad's limit points: corners 0-3 at `(0,0) (1,0) (1,1) (0,1)`.
pub const QUAD_CORNER_SLOTS: [usize; 4] = [0, 2, 8, 6];
/// Grid slots of a quad's edge midpoints: edge `k` joins corners `k` and `k + 1`.
pub const QUAD_EDGE_SLOTS: [usize; 4] = [1, 5, 7, 3];
/// Grid slot of a quad's centre (the face point).
pub const QUAD_CENTRE_SLOT: usize = 4;

/// The biquadratic Bézier coefficients interpolating the 3 x 3 grid `p` of values at
/// `u, v ∈ {0, ½, 1}` (slot `3 j + i`).
pub fn quad_coefficients<T: QuadPoint>(p: &[T; 9]) -> [T; 9] {
    let mut c = *p;
    for k in 0..4 {
        let (a, b) = (QUAD_CORNER_SLOTS[k], QUAD_CORNER_SLOTS[(k + 1) % 4]);
        c[QUAD_EDGE_SLOTS[k]] = edge_control(p[a], p[QUAD_EDGE_SLOTS[k]], p[b]);
    }
    let edges = (p[1] + p[7]) + (p[3] + p[5]);
    let corners = (p[0] + p[8]) + (p[2] + p[6]);
    c[QUAD_CENTRE_SLOT] = p[QUAD_CENTRE_SLOT] * 4.0 - edges + corners * 0.25;
    c
}

/// The points a quadratic triangle interpolates, as barycentric weights `(u, v)` of corners 1
/// and 2: corners 0, 1, 2, then the midpoints of edges 0-1, 1-2, 2-0 ([`tri_coefficients`]).
pub const TRI_NODES: [(f64, f64); 6] = [
    (0.0, 0.0),
    (1.0, 0.0),
    (0.0, 1.0),
    (0.5, 0.0),
    (0.5, 0.5),
    (0.0, 0.5),
];

/// The quadratic triangle's Bézier coefficients from its corner values `p[0..3]` and edge
/// midpoint values `p[3..6]` (edge `k` joins corners `k` and `k + 1`): corners, then the edge
/// coefficients of edges 0, 1, 2.
pub fn tri_coefficients<T: QuadPoint>(p: &[T; 6]) -> [T; 6] {
    let mut c = *p;
    for k in 0..3 {
        c[3 + k] = edge_control(p[k], p[3 + k], p[(k + 1) % 3]);
    }
    c
}

/// Quadratic Bernstein weights and their derivatives at `t`.
pub fn bernstein2(t: f64) -> ([f64; 3], [f64; 3]) {
    let s = 1.0 - t;
    (
        [s * s, 2.0 * t * s, t * t],
        [-2.0 * s, 2.0 * (s - t), 2.0 * t],
    )
}

/// The biquadratic patch `c` at `(u, v)`: value, `d/du`, `d/dv`.
pub fn eval_quad<T: QuadPoint>(c: &[T; 9], u: f64, v: f64) -> (T, T, T) {
    let (bu, du) = bernstein2(u);
    let (bv, dv) = bernstein2(v);
    let row = |j: usize, w: &[f64; 3]| c[3 * j] * w[0] + c[3 * j + 1] * w[1] + c[3 * j + 2] * w[2];
    let (r, ru) = (
        [0, 1, 2].map(|j| row(j, &bu)),
        [0, 1, 2].map(|j| row(j, &du)),
    );
    let p = r[0] * bv[0] + r[1] * bv[1] + r[2] * bv[2];
    let pu = ru[0] * bv[0] + ru[1] * bv[1] + ru[2] * bv[2];
    let pv = r[0] * dv[0] + r[1] * dv[1] + r[2] * dv[2];
    (p, pu, pv)
}

/// The quadratic triangle `c` (as [`tri_coefficients`]) at barycentric weights
/// `(1 - u - v, u, v)` of corners 0, 1, 2: value, `d/du`, `d/dv`.
pub fn eval_tri<T: QuadPoint>(c: &[T; 6], u: f64, v: f64) -> (T, T, T) {
    let w = 1.0 - u - v;
    let p = c[0] * (w * w)
        + c[1] * (u * u)
        + c[2] * (v * v)
        + c[3] * (2.0 * w * u)
        + c[4] * (2.0 * u * v)
        + c[5] * (2.0 * v * w);
    // d/du with w = 1 - u - v: dw = -1.
    let pu = c[0] * (-2.0 * w) + c[1] * (2.0 * u) + c[3] * (2.0 * (w - u)) + c[4] * (2.0 * v)
        - c[5] * (2.0 * v);
    let pv = c[0] * (-2.0 * w) + c[2] * (2.0 * v) - c[3] * (2.0 * u)
        + c[4] * (2.0 * u)
        + c[5] * (2.0 * (w - v));
    (p, pu, pv)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An arbitrary biquadratic-or-not function sampled on the 3 x 3 grid.
    fn f(u: f64, v: f64) -> f64 {
        (1.3 * u).sin() + (0.7 * v).cos() * u + v * v * v
    }

    #[test]
    fn quad_interpolates_its_nine_values() {
        let mut p = [0.0; 9];
        for j in 0..3 {
            for i in 0..3 {
                p[3 * j + i] = f(i as f64 / 2.0, j as f64 / 2.0);
            }
        }
        let c = quad_coefficients(&p);
        for j in 0..3 {
            for i in 0..3 {
                let (x, _, _) = eval_quad(&c, i as f64 / 2.0, j as f64 / 2.0);
                assert!((x - p[3 * j + i]).abs() < 1e-14, "({i}, {j})");
            }
        }
    }

    #[test]
    fn quad_reproduces_biquadratics_and_derivatives() {
        let g = |u: f64, v: f64| 1.0 + 2.0 * u - 3.0 * v * v + u * u * v * v - 0.5 * u * v;
        let gu = |u: f64, v: f64| 2.0 + 2.0 * u * v * v - 0.5 * v;
        let gv = |u: f64, v: f64| -6.0 * v + 2.0 * u * u * v - 0.5 * u;
        let p: [f64; 9] = std::array::from_fn(|k| g((k % 3) as f64 / 2.0, (k / 3) as f64 / 2.0));
        let c = quad_coefficients(&p);
        for (u, v) in [(0.3, 0.8), (0.9, 0.1), (0.5, 0.25)] {
            let (x, xu, xv) = eval_quad(&c, u, v);
            assert!((x - g(u, v)).abs() < 1e-13);
            assert!((xu - gu(u, v)).abs() < 1e-12);
            assert!((xv - gv(u, v)).abs() < 1e-12);
        }
    }

    #[test]
    fn triangle_reproduces_quadratics_and_interpolates_edges() {
        let g = |u: f64, v: f64| 0.5 - u + 2.0 * v + 3.0 * u * v - u * u + 0.25 * v * v;
        let p = TRI_NODES.map(|(u, v)| g(u, v));
        let c = tri_coefficients(&p);
        for (k, &(u, v)) in TRI_NODES.iter().enumerate() {
            assert!((eval_tri(&c, u, v).0 - p[k]).abs() < 1e-14);
        }
        let (u, v, h) = (0.2, 0.3, 1e-6);
        let (x, xu, xv) = eval_tri(&c, u, v);
        assert!((x - g(u, v)).abs() < 1e-13);
        assert!((xu - (g(u + h, v) - g(u - h, v)) / (2.0 * h)).abs() < 1e-7);
        assert!((xv - (g(u, v + h) - g(u, v - h)) / (2.0 * h)).abs() < 1e-7);
    }

    #[test]
    fn quad_and_triangle_edges_agree() {
        // Edge 0 of both: corners a, b, midpoint m; same curve at every t.
        let (a, m, b) = (0.3, 1.7, -0.4);
        let q = quad_coefficients(&[a, m, b, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
        let t = tri_coefficients(&[a, b, 0.0, m, 0.0, 0.0]);
        for x in [0.1, 0.5, 0.77] {
            assert!((eval_quad(&q, x, 0.0).0 - eval_tri(&t, x, 0.0).0).abs() < 1e-15);
        }
    }
}
