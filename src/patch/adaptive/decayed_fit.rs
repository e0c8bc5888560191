//! The least-squares fit behind [`crate::patch::gregory::tangents::DECAYED_CORNER_SCALE`]: the tangent fit
//! of [`crate::patch::gregory::tangent_fit`] (normal distance to the exact limit, three quadratic
//! heights, closed-form minimiser of a parabola) redone on the end caps of a decayed corner,
//! whose ring the corner rule shaped before it turned smooth. Run by
//! `examples/decayed_corner_table.rs` and checked by `tests/gregory_tangents.rs`.

use super::AdaptiveSurface;
use crate::mesh::{ControlMesh, ControlMeshDesc, Crease};
use crate::patch::gregory::tangent_fit::{add_sample, fit_heights, least_squares_scale};
use crate::patch::gregory::GregoryTangents;
use crate::subdiv::adaptive::{AdaptiveRefinement, PatchType};
use crate::subdiv::eval::LimitEvaluator;
use crate::subdiv::Level;
use glam::DVec3;
use std::f64::consts::PI;

/// Sharpness of the model's creases, and the isolation level the fit is taken at (where they
/// decay).
pub const DECAYED_FIT_SHARPNESS: u32 = 6;

/// Samples per end-cap side (corners included), as `examples/adaptive_grid.rs endcaps:9`.
const SAMPLES: usize = 9;

/// The model net at valence `n >= 3` with heights `h`: [`crease_fan`] with every first-ring
/// radius 1 and three creases of sharpness [`DECAYED_FIT_SHARPNESS`] to first-ring vertices 0,
/// `⌊n/3⌋` and `⌊2n/3⌋`. After one level vertex 0 is an all-quad valence-`n` corner for the
/// next five, a decayed corner at level 6.
pub fn decayed_fit_mesh(n: usize, h: impl Fn(f64, f64) -> f64) -> crate::Result<ControlMesh> {
    let creases = [0, n / 3, 2 * n / 3];
    crease_fan(&vec![1.0; n], &creases, DECAYED_FIT_SHARPNESS as f32, h)
}

/// A fan of `radii.len()` triangles around vertex 0 inside two rings of quads: first-ring vertex
/// `i` at radius `radii[i]` and angle `2πi/n`, rings 2 and 3 at radius 2 and 3, lifted to
/// `z = h(x, y)`, with creases of `sharpness` from vertex 0 to the first-ring vertices `creases`.
pub fn crease_fan(
    radii: &[f64],
    creases: &[usize],
    sharpness: f32,
    h: impl Fn(f64, f64) -> f64,
) -> crate::Result<ControlMesh> {
    let n = radii.len();
    let ring = |r: usize, i: usize| (1 + (r - 1) * n + i % n) as u32;
    let mut positions = vec![DVec3::new(0.0, 0.0, h(0.0, 0.0))];
    for r in 1..=3 {
        for (i, radius) in radii.iter().enumerate() {
            let (s, c) = (2.0 * PI * i as f64 / n as f64).sin_cos();
            let d = if r == 1 { *radius } else { r as f64 };
            let (x, y) = (d * c, d * s);
            positions.push(DVec3::new(x, y, h(x, y)));
        }
    }
    let (mut face_sizes, mut face_vertices) = (Vec::new(), Vec::new());
    for i in 0..n {
        face_sizes.push(3);
        face_vertices.extend([0, ring(1, i), ring(1, i + 1)]);
        for r in 1..=2 {
            face_sizes.push(4);
            face_vertices.extend([
                ring(r, i),
                ring(r + 1, i),
                ring(r + 1, i + 1),
                ring(r, i + 1),
            ]);
        }
    }
    let creases = creases
        .iter()
        .map(|&i| Crease {
            v0: 0,
            v1: ring(1, i),
            sharpness,
        })
        .collect();
    ControlMesh::new(ControlMeshDesc {
        positions,
        face_sizes,
        face_vertices,
        creases,
        ..Default::default()
    })
}

/// `[Σ a², Σ ab, Σ b²]` over the end caps at vertex 0 of [`decayed_fit_mesh`] at isolation
/// [`DECAYED_FIT_SHARPNESS`] (those in corner 0's sub-face of a fan triangle, within a quarter
/// of its side from the vertex), summed over the three heights, where the normal distance to
/// the exact limit at a sample is `a + s b` for tangents `Scaled(s)` (the patches are affine in
/// `s`: taken at `s = 1/4` and `3/4`).
pub fn decayed_fit_terms(n: usize) -> crate::Result<[f64; 3]> {
    let mut sums = [0.0; 3];
    for h in fit_heights() {
        let mesh = decayed_fit_mesh(n, h)?;
        let r = AdaptiveRefinement::new(&Level::from_mesh(&mesh)?, DECAYED_FIT_SHARPNESS)?;
        let surface = |s: f64| {
            AdaptiveSurface::with_tangents(&r, mesh.positions(), GregoryTangents::Scaled(s))
                .map_err(|e| crate::Error::Invalid(e.to_string()))
        };
        let (lo, hi) = (surface(0.25)?, surface(0.75)?);
        let exact = LimitEvaluator::new(&mesh)?;
        let k = (SAMPLES - 1) as f64;
        for (i, p) in lo.patches.iter().enumerate() {
            let d = p.domain;
            let at_vertex = d.sub_face == Some(0) && d.origin.x < 0.25 && d.origin.y < 0.25;
            if p.kind != PatchType::EndCap || !at_vertex {
                continue;
            }
            let st: Vec<(f64, f64)> = (0..SAMPLES * SAMPLES)
                .map(|j| ((j % SAMPLES) as f64 / k, (j / SAMPLES) as f64 / k))
                .collect();
            let uv: Vec<(f64, f64)> = st
                .iter()
                .map(|&(s, t)| {
                    let x = d.origin + s * d.u + t * d.v;
                    (x.x, x.y)
                })
                .collect();
            let limit = exact.eval_points(d.base_face as usize, 0, &uv)?;
            for (&(s, t), l) in st.iter().zip(&limit) {
                let (p0, p1) = (
                    lo.eval_patch(i, s, t).position,
                    hi.eval_patch(i, s, t).position,
                );
                let b = (p1 - p0).dot(l.normal) / 0.5;
                let a = (p0 - l.position).dot(l.normal) - 0.25 * b;
                add_sample(&mut sums, 1.0, a, b);
            }
        }
    }
    Ok(sums)
}

/// The least-squares factor of [`decayed_fit_terms`] at valence `n`.
pub fn decayed_fit_scale(n: usize) -> crate::Result<f64> {
    Ok(least_squares_scale(&decayed_fit_terms(n)?))
}
