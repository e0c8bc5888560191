//! The closest point of the exact Catmull-Clark limit ([`LimitEvaluator`]) to a point near a
//! face: the nearest of dense exact samples of the face and of every face sharing a vertex
//! with it, refined by Gauss-Newton projection steps. What [`super::accuracy`] measures
//! distances and normals with, and [`super::vertex_fit`] pairs its samples with.

use crate::subdiv::eval::{GridSample, LimitEvaluator, LimitSample};
use crate::topology::Topology;
use crate::Result;
use glam::DVec3;

/// One exact sample with its location.
#[derive(Debug, Clone, Copy)]
pub struct Located {
    /// Face.
    pub face: usize,
    /// Sub-face (0 for quads).
    pub sub: usize,
    /// Parameter u.
    pub u: f64,
    /// Parameter v.
    pub v: f64,
    /// The exact sample there.
    pub sample: LimitSample,
}

/// Candidate starting points for [`closest_exact`] near face `f`: the dense exact samples of the
/// face and of every face sharing a vertex with it.
pub fn nearby_exact_samples(
    topo: &Topology,
    dense: &[Option<Vec<GridSample>>],
    f: u32,
) -> Vec<Located> {
    let mut near: Vec<u32> = topo
        .face_vertices(f)
        .iter()
        .flat_map(|&v| topo.vertex_faces(v).iter().copied())
        .collect();
    near.sort_unstable();
    near.dedup();
    near.iter()
        .filter_map(|&g| dense[g as usize].as_ref().map(|s| (g, s)))
        .flat_map(|(g, s)| {
            s.iter().map(move |x| Located {
                face: g as usize,
                sub: x.sub,
                u: x.u,
                v: x.v,
                sample: x.sample,
            })
        })
        .collect()
}

/// The exact point closest to `x`: the nearest of `candidates` (from [`nearby_exact_samples`]
/// of face `f`), refined by `project`.
pub fn closest_exact(
    ev: &LimitEvaluator,
    x: DVec3,
    candidates: &[Located],
    f: u32,
) -> Result<Located> {
    let start = candidates
        .iter()
        .min_by(|a, b| {
            let da = (a.sample.position - x).length_squared();
            let db = (b.sample.position - x).length_squared();
            da.total_cmp(&db)
        })
        .copied()
        .ok_or_else(|| crate::Error::Invalid(format!("face {f}: no exact samples")))?;
    project(ev, x, start)
}

/// Angle between two normals; a zero normal (collinear derivatives) counts as the worst case,
/// π, not as 0.
pub fn normal_angle(a: DVec3, b: DVec3) -> f64 {
    let angle = a.angle_between(b);
    if angle.is_finite() {
        angle
    } else {
        std::f64::consts::PI
    }
}

/// Gauss-Newton projection of `x` onto the exact surface starting from `start`, within its
/// (sub-)face, `[0, 1]^2` clamped.
fn project(ev: &LimitEvaluator, x: DVec3, start: Located) -> Result<Located> {
    let mut best = start;
    let mut d_best = (best.sample.position - x).length_squared();
    let mut cur = start;
    for _ in 0..6 {
        let s = cur.sample;
        let r = x - s.position;
        let (a, b, c) = (s.du.dot(s.du), s.du.dot(s.dv), s.dv.dot(s.dv));
        let det = a * c - b * b;
        if det.abs() < 1e-300 {
            break;
        }
        let (ru, rv) = (s.du.dot(r), s.dv.dot(r));
        let du = (c * ru - b * rv) / det;
        let dv = (a * rv - b * ru) / det;
        let u = (cur.u + du).clamp(0.0, 1.0);
        let v = (cur.v + dv).clamp(0.0, 1.0);
        if (u - cur.u).abs() < 1e-13 && (v - cur.v).abs() < 1e-13 {
            break;
        }
        let sample = ev.eval(cur.face, cur.sub, u, v)?;
        cur = Located {
            u,
            v,
            sample,
            ..cur
        };
        let d = (sample.position - x).length_squared();
        if d < d_best {
            d_best = d;
            best = cur;
        }
    }
    Ok(best)
}
