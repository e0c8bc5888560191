//! Edge-tangent factors fitted per vertex on a rest pose, then frozen
//! ([`GregoryTangents::Fitted`]; issue 10, part 1, docs/measured.md "Factors fitted per vertex
//! on the rest pose, then frozen"). A factor fitted once and kept is a constant per vertex,
//! like a crease sharpness: every Gregory control point stays a fixed linear combination of the
//! control points, so the stencils, the `gregory-vs` construction and animation keep working.
//!
//! The unknowns ([`free_factors`]), starting from [`GregoryTangents::Optimal`]:
//! - per crease sector that the construction gives a free length ([`GregoryTangents::Scaled`]
//!   scales it: three or more faces, or two faces on a band), the factor `s` on its
//!   cross-boundary tangent `s T/3` ([`GregoryVertex::sectored`]); the two sectors of a crease
//!   vertex get one factor each;
//! - optionally (the experiment of `examples/gregory_vertex_fit.rs`, not carried by
//!   `Fitted`), per smooth vertex of valence other than 4, the factor `s` on its edge tangents.
//!
//! Sectors of two faces off a band and valence-4 vertices keep the construction's lengths: a
//! face beside them may be a regular B-spline patch, whose edge curve they must stay.
//!
//! Every control point is affine in every factor, so the normal distance of the Gregory faces'
//! samples (12 × 12 per face, [`face_samples`]) to their closest exact points
//! ([`closest_exact`], re-paired each round: ICP) is affine in the factors, and each round is
//! one linear least-squares solve for all of them at once ([`solve_normal_equations`]). A
//! factor moves only the patches of the faces at its vertex, so only those faces are sampled
//! (exact grids of them and their vertex neighbours only) and a round costs their samples plus,
//! per factor, one patch rebuild per face at its vertex.

use glam::DVec3;
use rayon::prelude::*;

use super::closest::{closest_exact, nearby_exact_samples, Located};
use super::tangent_fit::solve_normal_equations;
use super::tangents_boundary::crease_factor_slot;
use super::tangents_tri_fit::face_samples;
use super::{
    check_face_level0, gregory_faces, gregory_patch, gregory_vertices_with, sectors, vertex_ring,
    GregoryPatch, GregoryTangents, GregoryVertex, VertexKind,
};
use crate::mesh::ControlMesh;
use crate::subdiv::eval::{GridSample, LimitEvaluator};
use crate::topology::Topology;
use crate::Result;

/// ICP rounds of [`VertexFit::fit`] (three settle the factors to 4 digits).
pub const ROUNDS: usize = 6;

/// Exact grid (per face edge) the closest-point search starts from.
const DENSE_GRID: usize = 24;

/// Per-vertex Gregory data of a mesh (`None` where a vertex has none).
pub type Vertices = Vec<Option<GregoryVertex<DVec3>>>;

/// One free factor: the edge points it moves (`(edge, direction per unit of factor)` of its
/// vertex) and the construction's value.
#[derive(Debug, Clone)]
pub struct FreeFactor {
    /// The vertex.
    pub vertex: u32,
    /// The crease sector (in [`sectors`] order), `None` for a smooth vertex's factor.
    pub sector: Option<usize>,
    /// What it scales, for reports.
    pub label: String,
    /// The construction's (`Optimal`'s) value.
    pub start: f64,
    /// The edge points it moves: `(edge, d)` with `e[edge]` moving by `d` per unit of factor.
    pub moves: Vec<(usize, DVec3)>,
}

/// The free factors of the mesh (module docs): crease sectors, and smooth vertices of valence
/// other than 4 if `smooth`; `base` the [`GregoryTangents::Optimal`] construction.
pub fn free_factors(
    topo: &Topology,
    positions: &[DVec3],
    base: &Vertices,
    smooth: bool,
) -> Vec<FreeFactor> {
    let one = gregory_vertices_with(topo, positions, GregoryTangents::Scaled(1.0));
    let two = gregory_vertices_with(topo, positions, GregoryTangents::Scaled(2.0));
    let mut out = Vec::new();
    for v in 0..topo.vertex_count() {
        let (Some(g), Some(g1), Some(g2)) = (&base[v], &one[v], &two[v]) else {
            continue;
        };
        match g.kind {
            VertexKind::Crease => {
                let ring = vertex_ring(topo, positions, v as u32);
                for (index, sec) in sectors(&ring.sharp, g.n).into_iter().enumerate() {
                    let ne = ring.m.len();
                    let moves: Vec<(usize, DVec3)> = (1..sec.faces)
                        .map(|i| (sec.start + i) % ne)
                        .map(|j| (j, g2.e[j] - g1.e[j]))
                        .filter(|(_, d)| d.length_squared() > 0.0)
                        .collect();
                    let Some(&(j, d)) = moves.first() else {
                        continue;
                    };
                    out.push(FreeFactor {
                        vertex: v as u32,
                        sector: Some(index),
                        label: format!("crease sector of {} faces", sec.faces),
                        start: 1.0 + (g.e[j] - g1.e[j]).dot(d) / d.length_squared(),
                        moves,
                    });
                }
            }
            VertexKind::Smooth if smooth && g.n != 4 => {
                let start =
                    g1.e.iter()
                        .zip(&g.e)
                        .map(|(a, b)| (*b - g.p).length() / (*a - g.p).length())
                        .next()
                        .unwrap_or(1.0);
                out.push(FreeFactor {
                    vertex: v as u32,
                    sector: None,
                    label: format!("smooth valence {}", g.n),
                    start,
                    moves: g1
                        .e
                        .iter()
                        .enumerate()
                        .map(|(j, e)| (j, *e - g.p))
                        .collect(),
                });
            }
            _ => {}
        }
    }
    out
}

/// The vertices `base` with factor offsets `x` (from the construction's) applied.
pub fn with_offsets(base: &Vertices, factors: &[FreeFactor], x: &[f64]) -> Vertices {
    let mut verts = base.clone();
    for (u, &dx) in factors.iter().zip(x) {
        if let Some(g) = verts[u.vertex as usize].as_mut() {
            for &(j, d) in &u.moves {
                g.e[j] += dx * d;
            }
        }
    }
    verts
}

/// One ICP round: the normal equations `a s = b` of the offsets' step, and the summed squared
/// normal distance `e2` over `w` samples before the step.
struct Round {
    a: Vec<Vec<f64>>,
    b: Vec<f64>,
    e2: f64,
    w: f64,
}

/// One mesh's fit: its construction, the faces sampled and the free factors.
pub struct VertexFit<'a> {
    topo: &'a Topology,
    /// The `Optimal` construction.
    pub base: Vertices,
    /// The level-0 Gregory faces at a vertex with a free factor (the faces sampled).
    pub faces: Vec<u32>,
    /// The free factors.
    pub factors: Vec<FreeFactor>,
}

impl<'a> VertexFit<'a> {
    /// The fit of the mesh with topology `topo` and control points `positions`, smooth
    /// vertices' factors included if `smooth`.
    pub fn new(topo: &'a Topology, positions: &[DVec3], smooth: bool) -> VertexFit<'a> {
        let base = gregory_vertices_with(topo, positions, GregoryTangents::Optimal);
        let factors = free_factors(topo, positions, &base, smooth);
        let mut free = vec![false; topo.vertex_count()];
        for u in &factors {
            free[u.vertex as usize] = true;
        }
        let faces = gregory_faces(topo)
            .into_iter()
            .filter(|&f| topo.face_vertices(f).iter().any(|&v| free[v as usize]))
            .filter(|&f| check_face_level0(topo, f).is_ok())
            .collect();
        VertexFit {
            topo,
            base,
            faces,
            factors,
        }
    }

    /// The exact grids (`ev`) of the sampled faces and of the faces sharing a vertex with them
    /// (the closest-point candidates), `None` elsewhere.
    fn dense_grids(&self, ev: &LimitEvaluator) -> Result<Vec<Option<Vec<GridSample>>>> {
        let topo = self.topo;
        let mut near = vec![false; topo.face_count()];
        for &f in &self.faces {
            for &v in topo.face_vertices(f) {
                for &g in topo.vertex_faces(v) {
                    near[g as usize] = topo.has_limit_surface(g);
                }
            }
        }
        near.par_iter()
            .enumerate()
            .map(|(g, &n)| match n {
                true => ev.eval_grid(g, DENSE_GRID).map(Some),
                false => Ok(None),
            })
            .collect()
    }

    /// The factor offsets from the construction's after [`ROUNDS`] ICP rounds (module docs)
    /// against the exact surface `ev`, with the RMS normal distance of the sampled faces before
    /// each round's solve and after the last (`ROUNDS + 1` entries; absolute, not divided by the
    /// diagonal).
    pub fn fit(&self, ev: &LimitEvaluator) -> Result<(Vec<f64>, Vec<f64>)> {
        let (topo, faces) = (self.topo, &self.faces);
        let n = self.factors.len();
        if n == 0 || faces.is_empty() {
            return Ok((vec![0.0; n], Vec::new()));
        }
        let dense = self.dense_grids(ev)?;
        let cands: Vec<_> = faces
            .iter()
            .map(|&f| nearby_exact_samples(topo, &dense, f))
            .collect();
        let mut index = vec![None; topo.face_count()];
        for (i, &f) in faces.iter().enumerate() {
            index[f as usize] = Some(i);
        }
        // Per face, the factors that move it: those at its corners (an edge point enters the
        // patches of the faces at its vertex only, face points through eq. 6 included).
        let mut touching: Vec<Vec<usize>> = vec![Vec::new(); faces.len()];
        for (k, u) in self.factors.iter().enumerate() {
            for &f in topo.vertex_faces(u.vertex) {
                if let Some(i) = index[f as usize] {
                    touching[i].push(k);
                }
            }
        }
        let mut x = vec![0.0; n];
        let mut rms = Vec::with_capacity(ROUNDS + 1);
        for round in 0..=ROUNDS {
            let Round { a, b, e2, w } = self.normal_equations(ev, &x, &index, &touching, &cands)?;
            rms.push((e2 / w).sqrt());
            if round < ROUNDS {
                for (xi, s) in x.iter_mut().zip(solve_normal_equations(a, b)) {
                    *xi += s;
                }
            }
        }
        Ok((x, rms))
    }

    /// One ICP round's normal equations for the offsets' step from `x`, and the summed squared
    /// normal distance and sample count at `x`.
    fn normal_equations(
        &self,
        ev: &LimitEvaluator,
        x: &[f64],
        index: &[Option<usize>],
        touching: &[Vec<usize>],
        cands: &[Vec<Located>],
    ) -> Result<Round> {
        let (topo, faces, n) = (self.topo, &self.faces, self.factors.len());
        let mut current = with_offsets(&self.base, &self.factors, x);
        let now = patches(topo, &current, faces)?;
        // Per face, the patch with each touching factor moved by 1 (the others at `x`), in the
        // order of `touching`.
        let mut moved: Vec<Vec<GregoryPatch>> = vec![Vec::new(); faces.len()];
        for u in &self.factors {
            let slot = &mut current[u.vertex as usize];
            let saved = slot.clone();
            if let Some(g) = slot.as_mut() {
                for &(j, d) in &u.moves {
                    g.e[j] += d;
                }
            }
            for &f in topo.vertex_faces(u.vertex) {
                if let Some(i) = index[f as usize] {
                    moved[i].push(patch(topo, &current, f)?);
                }
            }
            current[u.vertex as usize] = saved;
        }
        // Per face: its samples' (distance, gradient) rows, in parallel.
        let rows: Vec<Vec<(f64, Vec<f64>)>> = faces
            .par_iter()
            .enumerate()
            .map(|(i, &f)| {
                face_samples(topo.face_size(f) == 3)
                    .into_iter()
                    .map(|(u, v)| {
                        let p = now[i].eval(u, v).position;
                        let l = closest_exact(ev, p, &cands[i], f)?;
                        let normal = l.sample.normal;
                        let g = moved[i]
                            .iter()
                            .map(|q| (q.eval(u, v).position - p).dot(normal))
                            .collect();
                        Ok(((p - l.sample.position).dot(normal), g))
                    })
                    .collect::<Result<Vec<_>>>()
            })
            .collect::<Result<_>>()?;
        let mut a = vec![vec![0.0; n]; n];
        let mut b = vec![0.0; n];
        let (mut e2, mut w) = (0.0, 0.0);
        for (i, face_rows) in rows.iter().enumerate() {
            for (d0, g) in face_rows {
                for (r, &kr) in touching[i].iter().enumerate() {
                    b[kr] -= d0 * g[r];
                    for (c, &kc) in touching[i].iter().enumerate() {
                        a[kr][kc] += g[r] * g[c];
                    }
                }
                e2 += d0 * d0;
                w += 1.0;
            }
        }
        Ok(Round { a, b, e2, w })
    }
}

/// The patch of face `f` from `verts`, its failure an error naming the face.
fn patch(topo: &Topology, verts: &Vertices, f: u32) -> Result<GregoryPatch> {
    gregory_patch(topo, verts, f)
        .map_err(|e| crate::Error::Invalid(format!("vertex fit: face {f}: {e}")))
}

fn patches(topo: &Topology, verts: &Vertices, faces: &[u32]) -> Result<Vec<GregoryPatch>> {
    faces.iter().map(|&f| patch(topo, verts, f)).collect()
}

/// The frozen crease-sector factors of `mesh` fitted on its own pose (the rest pose): per
/// vertex, the two sectors' factors rounded to `f32` (0 for a sector without one), for
/// [`Topology::with_crease_factors`]; empty when the mesh has no free crease sector. A fitted
/// factor that is not positive (a degenerate fit) keeps the construction's, with a warning.
/// Logs the fit's cost.
pub fn fit_crease_factors(mesh: &ControlMesh, topo: &Topology) -> Result<Vec<[f32; 2]>> {
    let clock = std::time::Instant::now();
    let fit = VertexFit::new(topo, mesh.positions(), false);
    if fit.factors.is_empty() {
        log::debug!("fitted Gregory tangents: no free crease sector");
        return Ok(Vec::new());
    }
    // The exact surface only where there is something to fit.
    let (x, rms) = fit.fit(&LimitEvaluator::new(mesh)?)?;
    let mut out = vec![[0.0f32; 2]; topo.vertex_count()];
    for (u, dx) in fit.factors.iter().zip(&x) {
        let Some(sector) = u.sector else { continue };
        let s = (u.start + dx) as f32;
        out[u.vertex as usize][crease_factor_slot(sector)] = if s.is_finite() && s > 0.0 {
            s
        } else {
            log::warn!(
                "fitted Gregory tangents: vertex {} ({}): fit gave {s}; keeping {}",
                u.vertex,
                u.label,
                u.start
            );
            u.start as f32
        };
    }
    log::info!(
        "fitted Gregory tangents: {} crease-sector factors over {} faces in {:.2?} \
         (RMS normal distance {:.3e} -> {:.3e})",
        fit.factors.len(),
        fit.faces.len(),
        clock.elapsed(),
        rms.first().copied().unwrap_or(0.0),
        rms.last().copied().unwrap_or(0.0)
    );
    Ok(out)
}

/// `topo` with the frozen factors of [`fit_crease_factors`] when `tangents` is
/// [`GregoryTangents::Fitted`], as is otherwise.
pub fn for_tangents(
    mesh: &ControlMesh,
    topo: Topology,
    tangents: GregoryTangents,
) -> Result<Topology> {
    match tangents {
        GregoryTangents::Fitted => {
            let factors = fit_crease_factors(mesh, &topo)?;
            Ok(topo.with_crease_factors(factors))
        }
        _ => Ok(topo),
    }
}
