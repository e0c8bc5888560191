//! The closest point of the exact Catmull-Clark limit ([`LimitEvaluator`]) to a point near a
//! face: the nearest dense exact samples of the face and of every face sharing a vertex with
//! it on its side of infinitely sharp creases (one per (sub-)face, the three nearest faces),
//! refined by Gauss-Newton projection steps within their faces, the closest result kept. What [`super::accuracy`] measures
//! distances and normals with, and [`super::vertex_fit`] pairs its samples with.

use crate::mesh::INFINITE_SHARPNESS;
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
/// face and of every face sharing a vertex with it on `f`'s side of infinitely sharp creases
/// (reachable from `f` across edges that are not, within those faces; promoted creases, smooth
/// in the limit, are crossed). Across such a crease the
/// exact normal jumps by the dihedral angle and the crease line is on both sides: a sample that
/// bulges past it would be paired, by a tie, with the other side's normal.
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
    let mut reached = vec![false; near.len()];
    let mut stack = vec![f];
    if let Ok(i) = near.binary_search(&f) {
        reached[i] = true;
    }
    while let Some(g) = stack.pop() {
        for &e in topo.face_edges(g) {
            if topo.edge_sharpness(e) >= INFINITE_SHARPNESS && !topo.is_promoted_edge(e) {
                continue;
            }
            for &h in topo.edge_faces(e) {
                if let Ok(i) = near.binary_search(&h) {
                    if !reached[i] {
                        reached[i] = true;
                        stack.push(h);
                    }
                }
            }
        }
    }
    near.iter()
        .zip(&reached)
        .filter(|(_, &r)| r)
        .filter_map(|(&g, _)| dense[g as usize].as_ref().map(|s| (g, s)))
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

/// How many (sub-)faces [`closest_exact`] projects from: the nearest seed of each of the
/// nearest `SEED_FACES` (sub-)faces. The projection stays inside its seed's (sub-)face, so one
/// seed in the wrong face (near an edge, or where the patch bulges towards a neighbour)
/// cannot reach the closest point; three cover an edge and its two ends' next faces.
pub const SEED_FACES: usize = 3;

/// The exact point closest to `x`: the nearest seed of each of the [`SEED_FACES`] nearest
/// (sub-)faces among `candidates` (from [`nearby_exact_samples`] of face `f`), each refined by
/// Gauss-Newton projection within its (sub-)face, and the closest of those.
pub fn closest_exact(
    ev: &LimitEvaluator,
    x: DVec3,
    candidates: &[Located],
    f: u32,
) -> Result<Located> {
    // The nearest seed per (face, sub), in the order first met.
    let mut seeds: Vec<(f64, Located)> = Vec::new();
    for c in candidates {
        let d = (c.sample.position - x).length_squared();
        match seeds
            .iter_mut()
            .find(|(_, s)| s.face == c.face && s.sub == c.sub)
        {
            Some(seed) if d < seed.0 => *seed = (d, *c),
            Some(_) => {}
            None => seeds.push((d, *c)),
        }
    }
    seeds.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut nearest = seeds.iter().take(SEED_FACES).map(|&(_, seed)| {
        let l = project(ev, x, seed)?;
        Ok(((l.sample.position - x).length_squared(), l))
    });
    let first = nearest
        .next()
        .ok_or_else(|| crate::Error::Invalid(format!("face {f}: no exact samples")))??;
    nearest
        .try_fold(first, |best, next: Result<(f64, Located)>| {
            let next = next?;
            Ok(if next.0 < best.0 { next } else { best })
        })
        .map(|(_, l)| l)
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A point `δ` off the exact surface along its normal, just inside face `g` next to a
    /// neighbour: the exact point it was pushed from is `δ` away, so the closest point can be no
    /// farther. Seeds on a coarse grid put the nearest seed on the shared edge, in whichever face
    /// comes first; a single projection from the neighbour's copy stops at the edge (`project`
    /// stays in its face) and reads a larger distance.
    #[test]
    fn closest_is_never_farther_than_a_known_surface_point() {
        let mesh = crate::assets::default_mesh();
        let topo = Topology::new(&mesh).unwrap();
        let ev = LimitEvaluator::new(&mesh).unwrap();
        let dense = ev.eval_all_grids(2).unwrap();
        let delta = 1e-3;
        let mut checked = 0;
        for g in (0..topo.face_count()).filter(|&g| topo.face_size(g as u32) == 4) {
            for (u, v) in [
                (0.04, 0.5),
                (0.96, 0.5),
                (0.5, 0.04),
                (0.5, 0.96),
                (0.3, 0.07),
            ] {
                let s = ev.eval(g, 0, u, v).unwrap();
                let x = s.position + delta * s.normal.normalize();
                for &f in topo.face_vertices(g as u32) {
                    for &f in topo.vertex_faces(f) {
                        let candidates = nearby_exact_samples(&topo, &dense, f);
                        if !candidates.iter().any(|c| c.face == g) {
                            continue;
                        }
                        let close = closest_exact(&ev, x, &candidates, f).unwrap();
                        let d = (close.sample.position - x).length();
                        assert!(
                            d <= delta * (1.0 + 1e-6),
                            "face {g} ({u}, {v}) seeded near face {f}: {d:e} > {delta:e}"
                        );
                        checked += 1;
                    }
                }
            }
        }
        assert!(checked > 100, "{checked} points checked");
    }
}
