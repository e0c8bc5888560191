//! The least-squares fit behind [`super::tangents::OPTIMAL_SCALE`] (derivation in the module
//! docs of [`super::tangents`]): the test control nets, the error terms and the closed-form
//! minimiser, used by `examples/gregory_tangent_table.rs` and `tests/gregory_tangents.rs`.

use super::build::{gregory_patch, gregory_patch_at_with, gregory_vertex_with};
use super::tangents::GregoryTangents;
use super::vertex::GregoryVertex;
use crate::mesh::{ControlMesh, ControlMeshDesc};
use crate::subdiv::eval::LimitEvaluator;
use crate::topology::Topology;
use glam::DVec3;
use std::f64::consts::PI;

/// Sectors of `FIT_K × FIT_K` quads around the fitted vertex.
pub const FIT_K: usize = 4;
/// Samples per face side (midpoints of a grid).
pub const FIT_SAMPLES: usize = 12;

/// The three height functions of the fit ([`super::tangents`] docs).
pub fn fit_heights() -> [fn(f64, f64) -> f64; 3] {
    [
        |x, y| 0.5 * (x * x + y * y),
        |x, y| 0.5 * (x * x - y * y),
        |x, y| x * y,
    ]
}

/// The fit's control net at valence `n` with heights `h` ([`super::tangents`] docs). Faces `0..n` are the
/// faces at the extraordinary vertex (vertex 0), face `i` in sector `i` with corner 0 there.
pub fn fit_mesh(n: usize, h: impl Fn(f64, f64) -> f64) -> crate::Result<ControlMesh> {
    fan_mesh(n, 2.0 * PI / n as f64, true, FIT_K, h)
}

/// The fit's control net for a crease sector of `k` faces ([`super::tangents_boundary`] docs):
/// vertex 0 on the mesh boundary with `k` sectors of `FIT_K × FIT_K` quads spanning a half
/// plane (sector `i` between the directions at angles `πi/k` and `π(i + 1)/k`), faces `0..k` at
/// vertex 0 as in [`fit_mesh`].
pub fn crease_fit_mesh(k: usize, h: impl Fn(f64, f64) -> f64) -> crate::Result<ControlMesh> {
    fan_mesh(k, PI / k as f64, false, FIT_K, h)
}

/// The band net of a crease sector of `k` faces ([`super::tangents_boundary`], "Bands"):
/// [`crease_fit_mesh`] one face deep, `k` quads around vertex 0 spanning a half plane, every
/// other vertex on the boundary: the inner edges of vertex 0 end on two-face crease sectors
/// whose inner edge ends on vertex 0 (`sector_band` 1 at vertex 0, `k` at the others).
pub fn band_fit_mesh(k: usize, h: impl Fn(f64, f64) -> f64) -> crate::Result<ControlMesh> {
    fan_mesh(k, PI / k as f64, false, 1, h)
}

/// `sectors` sectors of `depth × depth` quads around vertex 0, sector `i` spanning the
/// directions at angles `i·angle` and `(i + 1)·angle`; `closed`: the last sector meets the first.
fn fan_mesh(
    sectors: usize,
    angle: f64,
    closed: bool,
    depth: usize,
    h: impl Fn(f64, f64) -> f64,
) -> crate::Result<ControlMesh> {
    let (n, k) = (sectors, depth);
    let per = k * (k + 1);
    let id = |i: usize, a: usize, b: usize| -> u32 {
        if a == 0 && b > 0 && !closed && i + 1 == n {
            // The last ray of an open fan.
            return (1 + n * per + b - 1) as u32;
        }
        let (i, a, b) = if a == 0 && b > 0 {
            ((i + 1) % n, b, 0)
        } else {
            (i, a, b)
        };
        if a == 0 {
            0
        } else {
            (1 + i * per + (a - 1) * (k + 1) + b) as u32
        }
    };
    let dir = |i: usize| (angle * i as f64).sin_cos();
    let mut positions = vec![DVec3::new(0.0, 0.0, h(0.0, 0.0))];
    for i in 0..n {
        let ((s0, c0), (s1, c1)) = (dir(i), dir(i + 1));
        for a in 1..=k {
            for b in 0..=k {
                let (x, y) = (a as f64 * c0 + b as f64 * c1, a as f64 * s0 + b as f64 * s1);
                positions.push(DVec3::new(x, y, h(x, y)));
            }
        }
    }
    if !closed {
        let (s1, c1) = dir(n);
        for b in 1..=k {
            let (x, y) = (b as f64 * c1, b as f64 * s1);
            positions.push(DVec3::new(x, y, h(x, y)));
        }
    }
    let mut faces = Vec::new();
    let mut rest = Vec::new();
    for i in 0..n {
        for a in 0..k {
            for b in 0..k {
                let quad = [
                    id(i, a, b),
                    id(i, a + 1, b),
                    id(i, a + 1, b + 1),
                    id(i, a, b + 1),
                ];
                if a == 0 && b == 0 {
                    faces.extend(quad);
                } else {
                    rest.extend(quad);
                }
            }
        }
    }
    faces.extend(rest);
    ControlMesh::new(ControlMeshDesc {
        positions,
        face_sizes: vec![4; n * k * k],
        face_vertices: faces,
        ..Default::default()
    })
}

/// `[Σ a², Σ ab, Σ b²]` of the fit at valence `n` ([`super::tangents`] docs), summed over the three heights,
/// where the normal distance at a sample is `a + s b` for tangents `Scaled(s)`; the samples are
/// weighted so that `E(s) = Σ (a + s b)²` is the mean squared distance.
pub fn fit_terms(n: usize) -> crate::Result<[f64; 3]> {
    terms_on(n, |h| fit_mesh(n, h))
}

/// [`fit_terms`] for a crease sector of `k` faces, on [`crease_fit_mesh`].
pub fn crease_fit_terms(k: usize) -> crate::Result<[f64; 3]> {
    terms_on(k, |h| crease_fit_mesh(k, h))
}

/// The error terms over faces `0..faces` of the nets `net(h)` for the three heights.
fn terms_on(
    faces: usize,
    net: impl Fn(fn(f64, f64) -> f64) -> crate::Result<ControlMesh>,
) -> crate::Result<[f64; 3]> {
    let mut sums = [0.0; 3];
    let m = FIT_SAMPLES;
    let weight = 1.0 / (3 * faces * m * m) as f64;
    for h in fit_heights() {
        let mesh = net(h)?;
        let topo = Topology::new(&mesh)?;
        let exact = LimitEvaluator::new(&mesh)?;
        for f in 0..faces as u32 {
            let patch = |s: f64| {
                gregory_patch_at_with(&topo, mesh.positions(), f, GregoryTangents::Scaled(s))
                    .map_err(|e| crate::Error::Invalid(e.to_string()))
            };
            let (g0, g1) = (patch(0.0)?, patch(1.0)?);
            let uv = sample_grid(m);
            let limit = exact.eval_points(f as usize, 0, &uv)?;
            for (&(u, v), l) in uv.iter().zip(&limit) {
                let p0 = g0.eval(u, v).position;
                let p1 = g1.eval(u, v).position;
                let a = (p0 - l.position).dot(l.normal);
                let b = (p1 - p0).dot(l.normal);
                add_sample(&mut sums, weight, a, b);
            }
        }
    }
    Ok(sums)
}

/// `[Σ a², Σ ab, Σ ac, Σ b², Σ bc, Σ c²]` of the band fit of `k >= 3` faces
/// ([`band_fit_mesh`], the three heights, every face sampled as in [`fit_terms`]), where the
/// normal distance at a sample is `a + s_c b + s_2 c` for the factor `s_c` at vertex 0 (the
/// band's centre) and `s_2` at its two-face crease vertices: the patches are affine in each
/// vertex's factor (edge points linear in the tangent, face points in the edge points, eq. 6).
pub fn band_fit_terms(k: usize) -> crate::Result<[f64; 6]> {
    let mut sums = [0.0; 6];
    let m = FIT_SAMPLES;
    let weight = 1.0 / (3 * k * m * m) as f64;
    for h in fit_heights() {
        let mesh = band_fit_mesh(k, h)?;
        let topo = Topology::new(&mesh)?;
        let exact = LimitEvaluator::new(&mesh)?;
        let point = |i: u32| mesh.positions()[i as usize];
        // Vertex data with factor `centre` at vertex 0 and `two` elsewhere.
        let data = |centre: f64, two: f64| -> Vec<Option<GregoryVertex<DVec3>>> {
            (0..topo.vertex_count() as u32)
                .map(|v| {
                    let s = if v == 0 { centre } else { two };
                    gregory_vertex_with(&topo, v, &point, GregoryTangents::Scaled(s))
                })
                .collect()
        };
        let (d00, d10, d01) = (data(0.0, 0.0), data(1.0, 0.0), data(0.0, 1.0));
        for f in 0..k as u32 {
            let patch = |d: &[Option<GregoryVertex<DVec3>>]| {
                gregory_patch(&topo, d, f).map_err(|e| crate::Error::Invalid(e.to_string()))
            };
            let (g00, g10, g01) = (patch(&d00)?, patch(&d10)?, patch(&d01)?);
            let uv = sample_grid(m);
            let limit = exact.eval_points(f as usize, 0, &uv)?;
            for (&(u, v), l) in uv.iter().zip(&limit) {
                let p00 = g00.eval(u, v).position;
                let a = (p00 - l.position).dot(l.normal);
                let b = (g10.eval(u, v).position - p00).dot(l.normal);
                let c = (g01.eval(u, v).position - p00).dot(l.normal);
                for (sum, x) in sums
                    .iter_mut()
                    .zip([a * a, a * b, a * c, b * b, b * c, c * c])
                {
                    *sum += weight * x;
                }
            }
        }
    }
    Ok(sums)
}

/// The least-squares factors `(s_c, s_2)` of the band of `k >= 3` faces: the minimiser of the
/// quadratic [`band_fit_terms`], `[[Σb², Σbc], [Σbc, Σc²]] (s_c, s_2) = −(Σab, Σac)`.
pub fn band_fit_scales(k: usize) -> crate::Result<(f64, f64)> {
    let [_, ab, ac, bb, bc, cc] = band_fit_terms(k)?;
    let det = bb * cc - bc * bc;
    Ok(((-ab * cc + ac * bc) / det, (-ac * bb + ab * bc) / det))
}

/// The mean squared normal distance of the band fit with factors `s_c`, `s_2`.
pub fn band_fit_error(t: &[f64; 6], centre: f64, two: f64) -> f64 {
    t[0] + 2.0 * centre * t[1]
        + 2.0 * two * t[2]
        + centre * centre * t[3]
        + 2.0 * centre * two * t[4]
        + two * two * t[5]
}

/// Midpoints of an `m × m` grid over the unit square.
fn sample_grid(m: usize) -> Vec<(f64, f64)> {
    (0..m * m)
        .map(|k| ((k % m) as f64 + 0.5, (k / m) as f64 + 0.5))
        .map(|(u, v)| (u / m as f64, v / m as f64))
        .collect()
}

/// The mean squared normal distance of the fit at valence `n` with factor `s`.
pub fn fit_error(terms: &[f64; 3], s: f64) -> f64 {
    terms[0] + 2.0 * s * terms[1] + s * s * terms[2]
}

/// Adds one sample of weight `w`, whose error is `a + s b`, to the terms `[Σ a², Σ ab, Σ b²]`.
pub fn add_sample(sums: &mut [f64; 3], w: f64, a: f64, b: f64) {
    sums[0] += w * a * a;
    sums[1] += w * a * b;
    sums[2] += w * b * b;
}

/// The least-squares factor `s* = −Σ ab / Σ b²`, the minimum of [`fit_error`].
pub fn least_squares_scale(terms: &[f64; 3]) -> f64 {
    -terms[1] / terms[2]
}

/// The least-squares factor `s*(n)` at valence `n` ([`super::tangents`] docs).
pub fn fit_scale(n: usize) -> crate::Result<f64> {
    Ok(least_squares_scale(&fit_terms(n)?))
}

/// The least-squares factor of a crease sector of `k` faces ([`super::tangents_boundary`] docs).
pub fn crease_fit_scale(k: usize) -> crate::Result<f64> {
    Ok(least_squares_scale(&crease_fit_terms(k)?))
}

/// Solves the normal equations `a x = b` of a least-squares fit of several factors at once (a
/// symmetric positive semi-definite `a`, a few dozen unknowns): Gaussian elimination with
/// partial pivoting, `1e-12` added to the diagonal so that a factor no sample sees gets 0.
/// Used by the on-mesh fits (`examples/gregory_ring_mesh_fit.rs`,
/// `examples/gregory_vertex_fit.rs`).
pub fn solve_normal_equations(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Vec<f64> {
    let n = b.len();
    for i in 0..n {
        a[i][i] += 1e-12;
        let p = (i..n)
            .max_by(|&x, &y| a[x][i].abs().total_cmp(&a[y][i].abs()))
            .unwrap_or(i);
        a.swap(i, p);
        b.swap(i, p);
        for r in i + 1..n {
            let f = a[r][i] / a[i][i];
            let pivot = a[i].clone();
            for (x, y) in a[r].iter_mut().zip(&pivot).skip(i) {
                *x -= f * y;
            }
            b[r] -= f * b[i];
        }
    }
    let mut x = vec![0.0; n];
    for i in (0..n).rev() {
        let s: f64 = (i + 1..n).map(|c| a[i][c] * x[c]).sum();
        x[i] = (b[i] - s) / a[i][i];
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_equations_recover_a_known_fit() {
        // Rows of a design matrix and a right-hand side made from known factors: the normal
        // equations' solution is those factors (the system needs a row swap: a[0][0] = 0).
        let rows = [
            [0.0, 2.0, 1.0],
            [1.0, -1.0, 0.5],
            [3.0, 0.0, -2.0],
            [1.0, 1.0, 1.0],
        ];
        let want = [0.7, -1.3, 2.1];
        let mut a = vec![vec![0.0; 3]; 3];
        let mut b = vec![0.0; 3];
        for row in &rows {
            let y: f64 = row.iter().zip(&want).map(|(r, w)| r * w).sum();
            for i in 0..3 {
                b[i] += row[i] * y;
                for j in 0..3 {
                    a[i][j] += row[i] * row[j];
                }
            }
        }
        a[0][0] = 0.0;
        b[0] -= 11.0 * want[0];
        let got = solve_normal_equations(a, b);
        for (g, w) in got.iter().zip(&want) {
            assert!((g - w).abs() < 1e-9, "{got:?}");
        }
        // A factor no sample sees stays 0.
        assert_eq!(
            solve_normal_equations(vec![vec![0.0]], vec![0.0]),
            vec![0.0]
        );
    }

    #[test]
    fn fit_mesh_is_regular_but_one_vertex() {
        let mesh = fit_mesh(5, |_, _| 0.0).unwrap();
        let topo = Topology::new(&mesh).unwrap();
        assert_eq!(topo.vertex_faces(0).len(), 5);
        // The faces at the vertex: corner 0 is the vertex, the others are interior valence 4.
        for f in 0..5 {
            let fv = topo.face_vertices(f);
            assert_eq!(fv[0], 0);
            for &v in &fv[1..] {
                assert!(!topo.is_boundary_vertex(v));
                assert_eq!(topo.vertex_faces(v).len(), 4);
            }
        }
    }
}
