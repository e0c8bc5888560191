//! The fit of the factors of [`super::tangents_tri`] (`(s, ρ)` per ring face-size sequence):
//! run by `examples/gregory_ring_factors.rs` to regenerate
//! [`super::tangents_tri::FITTED_FACTORS`] and by `tests/gregory_triangles.rs`; never while a
//! surface is built.
//!
//! # The fit
//!
//! `(s, ρ)` depend on the ring's face-size sequence `k_0 … k_{n−1}` (up to rotation and
//! reflection, [`super::tangents_tri::ring_key`]) and minimise the squared distance from the
//! Gregory patches around a vertex with that ring to the exact Catmull-Clark limit, on a
//! characteristic configuration:
//!
//! - the control net ([`characteristic_mesh`]): the vertex at the origin, sector `i` spanning the
//!   directions `w_i, w_{i+1}` (`w_i` at angle `2πi/n`), filled with `K × K` quads (`k_i = 4`,
//!   vertices `a w_i + b w_{i+1}`, `0 ≤ a, b ≤ K`, as `super::tangent_fit::fit_mesh`) or with a
//!   triangular grid of side `K` (`k_i = 3`, `a + b ≤ K`), `K = 4`, lifted to the heights `z =
//!   h(x, y)` of the three quadratics `½(x² + y²)`, `½(x² − y²)`, `xy` (every curvature at the
//!   vertex, as for quads);
//! - every other smooth vertex of the net with a triangle in its ring takes the same `(s, ρ)`
//!   (the fitted vertex's triangles meet neighbours that follow the rule too; fitting against
//!   paper neighbours instead, as the quad table does against valence-4 neighbours that need no
//!   factor, gave factors that made `catmark_pyramid` and `catmark_smoothtris0` worse than the
//!   paper's: `s` compensated for the neighbours' face points; a second stage in which the
//!   neighbours take this fit of their own rings was worse again on both); quad-ring vertices
//!   keep the paper's construction;
//! - every control point is affine in `(s, ρ)`, so at a sample `G(s, ρ) = G₁₁ + (s − 1) B +
//!   (ρ − 1) C`; the error is the distance to the closest exact point `L` along its normal `N`
//!   (a Gregory triangle is not parameterised like the three quads Catmull-Clark makes of a
//!   triangle, so the quads' equal-parameter pairing does not apply): `d = (G − L)·N`, paired by
//!   `super::accuracy::closest_exact` at the current `(s, ρ)` and re-paired `ROUNDS` times
//!   (ICP); each round is a 2 × 2 least-squares solve
//!   `[Σ B_N², Σ B_N C_N; Σ B_N C_N, Σ C_N²] (s − 1, ρ − 1) = −[Σ a B_N, Σ a C_N]`;
//! - samples: every face at the vertex, an `M × M` grid of cell midpoints (quads) or the
//!   centroids of the `M²` cells of a barycentric grid (triangles), each weighted by its face's
//!   planar area over its sample count (an area integral).
//!

use super::accuracy::{closest_exact, nearby_exact_samples};
use super::build::{gregory_patch, gregory_vertices_with};
use super::tangents::GregoryTangents;
use super::tangents_tri::RingFactors;
use super::vertex::{GregoryVertex, VertexKind};
use crate::mesh::{ControlMesh, ControlMeshDesc};
use crate::subdiv::eval::LimitEvaluator;
use crate::topology::Topology;
use glam::DVec3;
use std::collections::HashMap;
use std::f64::consts::PI;

/// Sector size of the characteristic configuration.
pub const FIT_K: usize = 4;
/// Samples per face side.
pub const FIT_SAMPLES: usize = 8;
/// ICP rounds (the pairs settle after two or three).
pub const ROUNDS: usize = 3;

/// The characteristic control net of a ring with face sizes `sizes` (3 or 4 each), heights `h`
/// (module docs). Faces `0..n` are the faces at vertex 0, face `i` in sector `i` with corner 0
/// there.
pub fn characteristic_mesh(
    sizes: &[usize],
    h: impl Fn(f64, f64) -> f64,
) -> crate::Result<ControlMesh> {
    let n = sizes.len();
    let k = FIT_K;
    if n < 3 || sizes.iter().any(|&s| s != 3 && s != 4) {
        return Err(crate::Error::Invalid(format!(
            "characteristic ring {sizes:?}: triangles and quads, valence 3 or more"
        )));
    }
    let mut index: HashMap<(usize, usize, usize), u32> = HashMap::new();
    let mut positions = vec![DVec3::new(0.0, 0.0, h(0.0, 0.0))];
    let dir = |i: usize| {
        let (s, c) = (2.0 * PI * (i % n) as f64 / n as f64).sin_cos();
        (c, s)
    };
    for (i, &size) in sizes.iter().enumerate() {
        let ((c0, s0), (c1, s1)) = (dir(i), dir(i + 1));
        for a in 1..=k {
            let bmax = if size == 3 { k - a } else { k };
            for b in 0..=bmax {
                let (x, y) = (a as f64 * c0 + b as f64 * c1, a as f64 * s0 + b as f64 * s1);
                index.insert((i, a, b), positions.len() as u32);
                positions.push(DVec3::new(x, y, h(x, y)));
            }
        }
    }
    let id = |i: usize, a: usize, b: usize| -> u32 {
        match (a, b) {
            (0, 0) => 0,
            (0, b) => index[&((i + 1) % n, b, 0)],
            _ => index[&(i, a, b)],
        }
    };
    let (mut first, mut rest) = (Vec::new(), Vec::new());
    let (mut first_sizes, mut rest_sizes) = (Vec::new(), Vec::new());
    for (i, &size) in sizes.iter().enumerate() {
        for a in 0..k {
            for b in 0..k {
                let faces: Vec<Vec<u32>> = if size == 4 {
                    vec![vec![
                        id(i, a, b),
                        id(i, a + 1, b),
                        id(i, a + 1, b + 1),
                        id(i, a, b + 1),
                    ]]
                } else if a + b < k {
                    let mut t = vec![vec![id(i, a, b), id(i, a + 1, b), id(i, a, b + 1)]];
                    if a + b + 1 < k {
                        t.push(vec![id(i, a + 1, b), id(i, a + 1, b + 1), id(i, a, b + 1)]);
                    }
                    t
                } else {
                    Vec::new()
                };
                for (t, face) in faces.into_iter().enumerate() {
                    let (fv, fs) = if a == 0 && b == 0 && t == 0 {
                        (&mut first, &mut first_sizes)
                    } else {
                        (&mut rest, &mut rest_sizes)
                    };
                    fs.push(face.len() as u32);
                    fv.extend(face);
                }
            }
        }
    }
    first.extend(rest);
    first_sizes.extend(rest_sizes);
    ControlMesh::new(ControlMeshDesc {
        positions,
        face_sizes: first_sizes,
        face_vertices: first,
        ..Default::default()
    })
}

/// The three height functions of the fit.
fn heights() -> [fn(f64, f64) -> f64; 3] {
    [
        |x, y| 0.5 * (x * x + y * y),
        |x, y| 0.5 * (x * x - y * y),
        |x, y| x * y,
    ]
}

/// Sample parameters of one face with their weight (module docs).
pub fn face_samples(triangle: bool) -> Vec<(f64, f64)> {
    let m = FIT_SAMPLES;
    let mf = m as f64;
    if triangle {
        let mut out = Vec::new();
        for i in 0..m {
            for j in 0..m - i {
                out.push(((i as f64 + 1.0 / 3.0) / mf, (j as f64 + 1.0 / 3.0) / mf));
                if i + j + 1 < m {
                    out.push(((i as f64 + 2.0 / 3.0) / mf, (j as f64 + 2.0 / 3.0) / mf));
                }
            }
        }
        out
    } else {
        (0..m * m)
            .map(|q| (((q % m) as f64 + 0.5) / mf, ((q / m) as f64 + 0.5) / mf))
            .collect()
    }
}

/// The vertex `g` with factors `f` applied (module docs).
pub fn with_factors(g: &GregoryVertex<DVec3>, f: RingFactors) -> GregoryVertex<DVec3> {
    let mut out = g.clone();
    for e in &mut out.e {
        *e = g.p + f.tangent * (*e - g.p);
    }
    for r in out.r_plus.iter_mut().chain(out.r_minus.iter_mut()) {
        *r *= f.transversal;
    }
    out
}

/// One height's characteristic configuration, ready to evaluate.
struct Config {
    topo: Topology,
    exact: LimitEvaluator,
    paper: Vec<Option<GregoryVertex<DVec3>>>,
    faces: Vec<u32>,
    dense: Vec<Option<Vec<crate::subdiv::eval::GridSample>>>,
    areas: Vec<f64>,
}

fn config(sizes: &[usize], h: fn(f64, f64) -> f64) -> crate::Result<Config> {
    let mesh = characteristic_mesh(sizes, h)?;
    let topo = Topology::new(&mesh)?;
    let exact = LimitEvaluator::new(&mesh)?;
    let paper = gregory_vertices_with(&topo, mesh.positions(), GregoryTangents::Paper);
    let faces: Vec<u32> = topo.vertex_faces(0).to_vec();
    let mut dense = vec![None; topo.face_count()];
    for &f in &faces {
        for &v in topo.face_vertices(f) {
            for &g in topo.vertex_faces(v) {
                if dense[g as usize].is_none() && exact.has_limit_surface(g as usize) {
                    dense[g as usize] = Some(exact.eval_grid(g as usize, 2 * FIT_SAMPLES)?);
                }
            }
        }
    }
    let areas = faces
        .iter()
        .map(|&f| {
            let fv = topo.face_vertices(f);
            let q = |i: usize| {
                let p = mesh.positions()[fv[i % fv.len()] as usize];
                DVec3::new(p.x, p.y, 0.0)
            };
            (1..fv.len() - 1)
                .map(|i| 0.5 * (q(i) - q(0)).cross(q(i + 1) - q(0)).length())
                .sum()
        })
        .collect();
    Ok(Config {
        topo,
        exact,
        paper,
        faces,
        dense,
        areas,
    })
}

/// The normal equations of one ICP round at factors `at`: `[Σ a², Σ aB, Σ aC, Σ B², Σ BC, Σ C²]`
/// (normal components, area-weighted), so that the weighted squared distance at `(s, ρ)` with
/// the round's pairs is `E = Σ (a + (s − 1) B + (ρ − 1) C)²`.
pub fn fit_terms(sizes: &[usize], at: RingFactors) -> crate::Result<[f64; 6]> {
    terms_on(&configs(sizes)?, at)
}

/// The three configurations of a ring (one per height).
fn configs(sizes: &[usize]) -> crate::Result<Vec<Config>> {
    heights().into_iter().map(|h| config(sizes, h)).collect()
}

fn terms_on(configs: &[Config], at: RingFactors) -> crate::Result<[f64; 6]> {
    let mut sums = [0.0; 6];
    for c in configs {
        let center = c.paper[0]
            .as_ref()
            .ok_or_else(|| crate::Error::Invalid("characteristic vertex has no data".into()))?;
        let patches = |f: RingFactors| -> crate::Result<Vec<super::GregoryPatch<DVec3>>> {
            let mut verts = c.paper.clone();
            verts[0] = Some(with_factors(center, f));
            for (v, g) in verts.iter_mut().enumerate().skip(1) {
                let tri = c
                    .topo
                    .vertex_faces(v as u32)
                    .iter()
                    .any(|&x| c.topo.face_size(x) == 3);
                if let (true, Some(x)) = (tri, c.paper[v].as_ref()) {
                    if x.kind == VertexKind::Smooth {
                        *g = Some(with_factors(x, f));
                    }
                }
            }
            c.faces
                .iter()
                .map(|&g| {
                    gregory_patch(&c.topo, &verts, g)
                        .map_err(|e| crate::Error::Invalid(e.to_string()))
                })
                .collect()
        };
        let one = patches(RingFactors::ONE)?;
        let ds = patches(RingFactors {
            tangent: 2.0,
            transversal: 1.0,
        })?;
        let dr = patches(RingFactors {
            tangent: 1.0,
            transversal: 2.0,
        })?;
        for (k, &f) in c.faces.iter().enumerate() {
            let candidates = nearby_exact_samples(&c.topo, &c.dense, f);
            let uv = face_samples(c.topo.face_size(f) == 3);
            let w = c.areas[k] / uv.len() as f64;
            for &(u, v) in &uv {
                let g1 = one[k].eval(u, v).position;
                let b = ds[k].eval(u, v).position - g1;
                let cc = dr[k].eval(u, v).position - g1;
                let x = g1 + (at.tangent - 1.0) * b + (at.transversal - 1.0) * cc;
                let l = closest_exact(&c.exact, x, &candidates, f)?;
                let n = l.sample.normal;
                let (a, b, cc) = ((g1 - l.sample.position).dot(n), b.dot(n), cc.dot(n));
                for (slot, val) in
                    sums.iter_mut()
                        .zip([a * a, a * b, a * cc, b * b, b * cc, cc * cc])
                {
                    *slot += w * val;
                }
            }
        }
    }
    Ok(sums)
}

/// The squared distance of [`fit_terms`] at factors `f`.
pub fn fit_error(t: &[f64; 6], f: RingFactors) -> f64 {
    let (x, y) = (f.tangent - 1.0, f.transversal - 1.0);
    t[0] + 2.0 * (x * t[1] + y * t[2]) + x * x * t[3] + 2.0 * x * y * t[4] + y * y * t[5]
}

/// The minimiser of [`fit_error`] (2 × 2 normal equations).
pub fn minimise(t: &[f64; 6]) -> RingFactors {
    let det = t[3] * t[5] - t[4] * t[4];
    if det.abs() <= 1e-300 {
        return RingFactors::ONE;
    }
    let x = (-t[1] * t[5] + t[2] * t[4]) / det;
    let y = (-t[2] * t[3] + t[1] * t[4]) / det;
    RingFactors {
        tangent: 1.0 + x,
        transversal: 1.0 + y,
    }
}

/// The fit of a ring's factors (module docs): `ROUNDS` ICP rounds from the paper's `(1, 1)`.
pub fn fit_factors(sizes: &[usize]) -> crate::Result<RingFactors> {
    let configs = configs(sizes)?;
    let mut f = RingFactors::ONE;
    for _ in 0..ROUNDS {
        f = minimise(&terms_on(&configs, f)?);
    }
    Ok(f)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn characteristic_mesh_has_the_ring() {
        let sizes = [3, 4, 3, 3, 4];
        let mesh = characteristic_mesh(&sizes, |_, _| 0.0).unwrap();
        let topo = Topology::new(&mesh).unwrap();
        let faces = topo.vertex_faces(0);
        assert_eq!(faces.len(), 5);
        let mut got: Vec<usize> = faces.iter().map(|&f| topo.face_size(f)).collect();
        got.sort_unstable();
        assert_eq!(got, vec![3, 3, 3, 4, 4]);
        // Every corner of the faces at the vertex is interior (its ring closes).
        for &f in faces {
            for &v in topo.face_vertices(f) {
                assert!(!topo.is_boundary_vertex(v), "vertex {v}");
            }
        }
        assert!(characteristic_mesh(&[3, 5, 3], |_, _| 0.0).is_err());
    }
}
