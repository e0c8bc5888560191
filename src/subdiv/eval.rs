//! Exact evaluation of the Catmull-Clark limit surface at any `(face, sub, u, v)`.
//!
//! Parameterisation (crate contract): quad corners 0..3 at `(0,0), (1,0), (1,1), (0,1)`; a
//! non-quad face is split as Catmull-Clark splits it, sub-face `k` with `(0,0)` at corner `k`,
//! `(1,0)` at the midpoint of edge `k -> k+1`, `(1,1)` at the centre, `(0,1)` at the midpoint of
//! edge `k-1 -> k`.
//!
//! Method (Stam 1998 style exact evaluation, realised by local refinement as in the
//! feature-adaptive scheme, Köbler 2013 §3.2): a (boundary-)regular quad is a bicubic B-spline
//! patch ([`RegularPatch`]). Otherwise the faces sharing a vertex with the target face are
//! extracted, refined once, and the points are handed to the child faces containing them; the
//! child's vertex neighbourhood is exact because it is computed from complete one-rings. A point
//! exactly at a vertex takes that vertex's limit mask ([`super::limit::vertex_mask`]).

use glam::DVec3;
use rayon::prelude::*;

use super::bspline::{eval_bspline, RegularPatch};
use super::limit;
use super::Level;
use crate::mesh::ControlMesh;
use crate::{Error, Result};

pub use super::bspline::LimitSample;

/// One sample of [`LimitEvaluator::eval_grid`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridSample {
    /// Sub-face (0 for quads).
    pub sub: usize,
    /// Parameter u.
    pub u: f64,
    /// Parameter v.
    pub v: f64,
    /// The limit sample.
    pub sample: LimitSample,
}

/// Exact limit-surface evaluator of a control mesh.
#[derive(Debug, Clone)]
pub struct LimitEvaluator {
    level: Level,
    positions: Vec<DVec3>,
    patches: Vec<Option<RegularPatch>>,
}

/// A point on its way down the refinement: output slot, local `(u, v)`, and the 2x2 matrix
/// taking local partials to the top-level ones (`[du; dv]_top = a * [ds; dt]`).
#[derive(Debug, Clone, Copy)]
struct Pt {
    idx: usize,
    u: f64,
    v: f64,
    a: [[f64; 2]; 2],
}

/// Refinement depth after which a point still not in a regular sub-patch is snapped to the
/// nearest corner (it is then within `2^-40` of that vertex in parameter space).
const MAX_DEPTH: u32 = 40;
/// Points this close to a corner (parameter space, after rescaling) are taken as the corner.
const CORNER_EPS: f64 = 1e-12;

fn corner_of(u: f64, v: f64, eps: f64) -> Option<usize> {
    let lo = |x: f64| x <= eps;
    let hi = |x: f64| x >= 1.0 - eps;
    match (lo(u) || hi(u), lo(v) || hi(v)) {
        (true, true) => Some(match (hi(u), hi(v)) {
            (false, false) => 0,
            (true, false) => 1,
            (true, true) => 2,
            (false, true) => 3,
        }),
        _ => None,
    }
}

fn nearest_corner(u: f64, v: f64) -> usize {
    match (u > 0.5, v > 0.5) {
        (false, false) => 0,
        (true, false) => 1,
        (true, true) => 2,
        (false, true) => 3,
    }
}

fn mat_mul(a: [[f64; 2]; 2], b: [[f64; 2]; 2]) -> [[f64; 2]; 2] {
    let mut c = [[0.0; 2]; 2];
    for i in 0..2 {
        for j in 0..2 {
            c[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j];
        }
    }
    c
}

/// Quarter `k` of a quad: `(s, t)` of the child from parent `(u, v)`, and the matrix `C_k` with
/// `[P_u; P_v] = C_k [P_s; P_t]`.
fn to_child(k: usize, u: f64, v: f64) -> (f64, f64, [[f64; 2]; 2]) {
    match k {
        0 => (2.0 * u, 2.0 * v, [[2.0, 0.0], [0.0, 2.0]]),
        1 => (2.0 * v, 2.0 * (1.0 - u), [[0.0, -2.0], [2.0, 0.0]]),
        2 => (2.0 * (1.0 - u), 2.0 * (1.0 - v), [[-2.0, 0.0], [0.0, -2.0]]),
        _ => (2.0 * (1.0 - v), 2.0 * u, [[0.0, 2.0], [-2.0, 0.0]]),
    }
}

fn quarter(u: f64, v: f64) -> usize {
    match (u <= 0.5, v <= 0.5) {
        (true, true) => 0,
        (false, true) => 1,
        (false, false) => 2,
        (true, false) => 3,
    }
}

fn finish(s: LimitSample, a: [[f64; 2]; 2]) -> LimitSample {
    let du = a[0][0] * s.du + a[0][1] * s.dv;
    let dv = a[1][0] * s.du + a[1][1] * s.dv;
    LimitSample::new(s.position, du, dv)
}

/// Limit at corner `k` of quad `face` of `level`, in the face's `(u, v)` frame.
fn corner_sample(level: &Level, pos: &[DVec3], face: u32, k: usize) -> Result<LimitSample> {
    let v = level.topology().face_vertices(face)[k];
    let (p, tu, tv) = limit::vertex_mask(level, v, face)?.apply(pos);
    // `tu` points to corner k+1, `tv` to corner k-1; express them as d/du and d/dv.
    let (du, dv) = match k {
        0 => (tu, tv),
        1 => (-tv, tu),
        2 => (-tu, -tv),
        _ => (tv, -tu),
    };
    let s = LimitSample::new(p, du, dv);
    if s.normal != DVec3::ZERO {
        return Ok(s);
    }
    // Degenerate tangent masks (e.g. valence-2 vertices of two back-to-back quads, whose two
    // rings coincide): fall back to the face's own orientation (Newell normal of the current
    // level's face), keeping `du` when it is usable.
    let fv = level.topology().face_vertices(face);
    let n = fv.len();
    let q = |k: usize| pos[fv[k % n] as usize];
    let newell: DVec3 = (0..n).map(|k| q(k).cross(q(k + 1))).sum();
    let normal = newell.normalize_or_zero();
    let du = if du.cross(normal).length() > 0.0 {
        du
    } else {
        q(k + 1) - q(k)
    };
    let dv = normal.cross(du);
    Ok(LimitSample::new(p, du, dv))
}

fn eval_rec(
    level: &Level,
    pos: &[DVec3],
    face: u32,
    pts: Vec<Pt>,
    out: &mut [LimitSample],
    depth: u32,
    sub: Option<usize>,
) -> Result<()> {
    let topo = level.topology();
    if sub.is_none() {
        if let Some(p) = RegularPatch::gather(topo, face) {
            let cp = p.control_points(pos);
            for pt in pts {
                out[pt.idx] = finish(eval_bspline(&cp, pt.u, pt.v), pt.a);
            }
            return Ok(());
        }
    }
    let mut rest = Vec::with_capacity(pts.len());
    if sub.is_none() {
        for pt in pts {
            let corner = if depth >= MAX_DEPTH {
                Some(nearest_corner(pt.u, pt.v))
            } else {
                corner_of(pt.u, pt.v, CORNER_EPS)
            };
            match corner {
                Some(k) => out[pt.idx] = finish(corner_sample(level, pos, face, k)?, pt.a),
                None => rest.push(pt),
            }
        }
    } else {
        rest = pts;
    }
    if rest.is_empty() {
        return Ok(());
    }
    // Local refinement of the faces sharing a vertex with `face` (target first).
    let fv = topo.face_vertices(face);
    let mut faces = vec![face];
    for &v in fv {
        for &g in topo.vertex_faces(v) {
            if !faces.contains(&g) {
                faces.push(g);
            }
        }
    }
    let (sub_level, map) = level.extract(&faces);
    let sub_pos: Vec<DVec3> = map.iter().map(|&i| pos[i as usize]).collect();
    let (child, r) = sub_level.refine();
    let child_pos = r.apply_vec(&sub_pos);
    let first = sub_level.child_faces(0).start;
    if let Some(k) = sub {
        return eval_rec(
            &child,
            &child_pos,
            first + k as u32,
            rest,
            out,
            depth + 1,
            None,
        );
    }
    let mut parts: [Vec<Pt>; 4] = Default::default();
    for pt in rest {
        let k = quarter(pt.u, pt.v);
        let (s, t, c) = to_child(k, pt.u, pt.v);
        parts[k].push(Pt {
            idx: pt.idx,
            u: s.clamp(0.0, 1.0),
            v: t.clamp(0.0, 1.0),
            a: mat_mul(pt.a, c),
        });
    }
    for (k, part) in parts.into_iter().enumerate() {
        if !part.is_empty() {
            eval_rec(
                &child,
                &child_pos,
                first + k as u32,
                part,
                out,
                depth + 1,
                None,
            )?;
        }
    }
    Ok(())
}

impl LimitEvaluator {
    /// Builds the evaluator (topology, tags, regular patches of the base faces).
    pub fn new(mesh: &ControlMesh) -> Result<LimitEvaluator> {
        let level = Level::from_mesh(mesh)?;
        let topo = level.topology();
        let patches = (0..topo.face_count() as u32)
            .map(|f| RegularPatch::gather(topo, f))
            .collect();
        Ok(LimitEvaluator {
            positions: mesh.positions().to_vec(),
            level,
            patches,
        })
    }

    /// Replaces the control positions (animation: topology, tags and patches are kept).
    /// Errors if the count differs or a coordinate is not finite.
    pub fn set_positions(&mut self, positions: &[DVec3]) -> Result<()> {
        if positions.len() != self.positions.len() {
            return Err(Error::Invalid(format!(
                "limit evaluator: got {} positions, mesh has {} vertices",
                positions.len(),
                self.positions.len()
            )));
        }
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(Error::Invalid(format!(
                "limit evaluator: vertex {i} has a non-finite coordinate"
            )));
        }
        self.positions.copy_from_slice(positions);
        Ok(())
    }

    /// The control positions.
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }

    /// The base level.
    pub fn level(&self) -> &Level {
        &self.level
    }

    /// Number of base faces.
    pub fn face_count(&self) -> usize {
        self.level.topology().face_count()
    }

    /// Number of parameter domains of `face`: 1 for a quad, its size otherwise.
    pub fn sub_face_count(&self, face: usize) -> usize {
        let n = self.level.topology().face_size(face as u32);
        if n == 4 {
            1
        } else {
            n
        }
    }

    /// Whether `face` has a limit surface (false for holes and, with
    /// `BoundaryInterpolation::None`, faces touching the boundary).
    pub fn has_limit_surface(&self, face: usize) -> bool {
        face < self.face_count() && self.level.topology().has_limit_surface(face as u32)
    }

    fn check(&self, face: usize, sub: usize) -> Result<()> {
        if face >= self.face_count() {
            return Err(Error::Invalid(format!(
                "limit evaluation: face {face} out of range ({} faces)",
                self.face_count()
            )));
        }
        if !self.has_limit_surface(face) {
            return Err(Error::Invalid(format!(
                "limit evaluation: face {face} has no limit surface (hole or unsupported boundary)"
            )));
        }
        if sub >= self.sub_face_count(face) {
            return Err(Error::Invalid(format!(
                "limit evaluation: face {face} has no sub-face {sub}"
            )));
        }
        Ok(())
    }

    /// Evaluates one point. `sub` is 0 for quads, the sub-face for other faces.
    pub fn eval(&self, face: usize, sub: usize, u: f64, v: f64) -> Result<LimitSample> {
        Ok(self.eval_points(face, sub, &[(u, v)])?[0])
    }

    /// Evaluates many points of one face (or sub-face) together, sharing the local refinement.
    pub fn eval_points(
        &self,
        face: usize,
        sub: usize,
        uv: &[(f64, f64)],
    ) -> Result<Vec<LimitSample>> {
        self.check(face, sub)?;
        if let Some(&(u, v)) = uv
            .iter()
            .find(|(u, v)| !(0.0..=1.0).contains(u) || !(0.0..=1.0).contains(v))
        {
            return Err(Error::Invalid(format!(
                "limit evaluation: face {face}: ({u}, {v}) outside [0, 1]^2"
            )));
        }
        let zero = LimitSample::new(DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
        let mut out = vec![zero; uv.len()];
        if let Some(p) = &self.patches[face] {
            let cp = p.control_points(&self.positions);
            for (o, &(u, v)) in out.iter_mut().zip(uv) {
                *o = eval_bspline(&cp, u, v);
            }
            return Ok(out);
        }
        let pts = uv
            .iter()
            .enumerate()
            .map(|(idx, &(u, v))| Pt {
                idx,
                u,
                v,
                a: [[1.0, 0.0], [0.0, 1.0]],
            })
            .collect();
        let is_quad = self.level.topology().face_size(face as u32) == 4;
        let sub = if is_quad { None } else { Some(sub) };
        eval_rec(
            &self.level,
            &self.positions,
            face as u32,
            pts,
            &mut out,
            0,
            sub,
        )?;
        Ok(out)
    }

    /// Evaluates `face` on the `(n+1) x (n+1)` grid `u = i/n, v = j/n` (j outer, i inner) of
    /// each of its sub-faces (one for a quad).
    pub fn eval_grid(&self, face: usize, n: usize) -> Result<Vec<GridSample>> {
        self.check(face, 0)?;
        let n = n.max(1);
        let uv: Vec<(f64, f64)> = (0..=n)
            .flat_map(|j| (0..=n).map(move |i| (i as f64 / n as f64, j as f64 / n as f64)))
            .collect();
        let mut out = Vec::with_capacity(uv.len() * self.sub_face_count(face));
        for sub in 0..self.sub_face_count(face) {
            let s = self.eval_points(face, sub, &uv)?;
            out.extend(
                uv.iter()
                    .zip(s)
                    .map(|(&(u, v), sample)| GridSample { sub, u, v, sample }),
            );
        }
        Ok(out)
    }

    /// [`Self::eval_grid`] for every face with a limit surface, in parallel; faces without a
    /// limit surface give `None`.
    pub fn eval_all_grids(&self, n: usize) -> Result<Vec<Option<Vec<GridSample>>>> {
        (0..self.face_count())
            .into_par_iter()
            .map(|f| {
                if self.has_limit_surface(f) {
                    self.eval_grid(f, n).map(Some)
                } else {
                    Ok(None)
                }
            })
            .collect()
    }
}
