//! Independent CPU references written out here, not taken from the crate: the uniform cubic
//! B-spline basis and Gregory patches evaluated along their edges.

use tessera::patch::gregory::{GregoryPatch, PatchPoint};

/// Uniform cubic B-spline basis at `t` (direct polynomial form).
pub fn bspline_basis(t: f64) -> [f64; 4] {
    bspline_with_derivative(t).0
}

/// Uniform cubic B-spline basis and its derivative at `t`.
pub fn bspline_with_derivative(t: f64) -> ([f64; 4], [f64; 4]) {
    let s = 1.0 - t;
    (
        [
            s * s * s / 6.0,
            (3.0 * t * t * t - 6.0 * t * t + 4.0) / 6.0,
            (-3.0 * t * t * t + 3.0 * t * t + 3.0 * t + 1.0) / 6.0,
            t * t * t / 6.0,
        ],
        [
            -s * s / 2.0,
            (9.0 * t * t - 12.0 * t) / 6.0,
            (-9.0 * t * t + 6.0 * t + 3.0) / 6.0,
            t * t / 2.0,
        ],
    )
}

/// Evaluates patch `p` at `t` along its edge `k` (from corner k to corner k+1): quads in (u, v),
/// triangles in the patch's (s, t).
pub fn eval_on_edge(p: &GregoryPatch, k: usize, t: f64) -> PatchPoint {
    let (u, v) = match p {
        GregoryPatch::Quad(_) => match k {
            0 => (t, 0.0),
            1 => (1.0, t),
            2 => (1.0 - t, 1.0),
            _ => (0.0, 1.0 - t),
        },
        GregoryPatch::Triangle(_) => match k {
            0 => (t, 0.0),
            1 => (1.0 - t, t),
            _ => (0.0, 1.0 - t),
        },
    };
    p.eval(u, v)
}

/// Two patches meet along their shared edge `e` at `t`: `a` runs it as its edge `ka`, `b` the
/// other way as its edge `kb`. Positions agree within 1e-12 and, when `normals`, the tangent
/// planes within 1e-7 rad.
pub fn assert_meet_on_edge(
    e: u32,
    (a, ka): (&GregoryPatch, usize),
    (b, kb): (&GregoryPatch, usize),
    t: f64,
    normals: bool,
) {
    let (pa, pb) = (eval_on_edge(a, ka, t), eval_on_edge(b, kb, 1.0 - t));
    assert!(
        (pa.position - pb.position).length() < 1e-12,
        "edge {e} at t={t}: positions differ"
    );
    if normals {
        let angle = pa.normal().angle_between(pb.normal());
        assert!(
            angle < 1e-7,
            "edge {e} at t={t}: normals differ by {angle} rad"
        );
    }
}
