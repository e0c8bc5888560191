//! The CPU surface of an adaptive refinement: B-spline patches and Gregory end caps, evaluable
//! at base-face parameters.

use std::collections::HashMap;

use glam::{DVec2, DVec3};
use thiserror::Error;

use super::census_index::patch_index;
use super::lattice_frames::{lattice_normal, LatticeFrames};
use super::promoted::{
    band_offset_factor, corner_offset_code, corner_offset_share, corner_offset_vertex,
    crease_turn_share, exact_corner_position, exact_corner_tangents_shared, fillet_bend,
    fillet_cross_derivative, fillet_end, fillet_end_code, fillet_end_fade, fillet_end_sharpness,
    fillet_fine_code, fillet_fine_sharpness, fillet_many_share, fillet_offset_factor,
    fillet_rotation, fillet_sharpness, irregular_crease_vertex, positional_fillet_end,
    promoted_vertex, turn_towards, within_fillet, FilletEnd,
};
use crate::patch::basis::{bernstein_deriv, eval_tensor};
use crate::patch::gregory::{
    apply_terms, gregory_patch_at_for, Coverage, DartLimits, GregoryPatch, GregoryTangents,
    NotGregory,
};
use crate::patch::regular::RegularPatch;
use crate::patch::single_crease::SingleCreasePatch;
#[cfg(doc)]
use crate::subdiv::adaptive::EndCapSharpness;
use crate::subdiv::adaptive::{AdaptivePatch, AdaptiveRefinement, Domain, PatchCensus, PatchType};
use crate::subdiv::limit::SharedVertexMasks;
use crate::topology::is_sharp_edge;

pub use super::census_index::EndCapTopologies;

/// Why an end cap could not be built.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EndCapFailure {
    /// A corner vertex of the face has an incomplete one-ring in the sparse level (its ring was
    /// cut by the sparse selection), so a patch built there would not be the mesh's.
    Incomplete {
        /// The corner vertex (index in the level).
        vertex: u32,
    },
    /// The Gregory construction refuses the face (face and vertex indices in the level).
    Gregory(NotGregory),
}

/// An end-cap face of an adaptive refinement without a Gregory patch, named by its base face.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Error)]
#[error("end cap of base face {base_face}{} (level {level} face {face}): {}", sub_suffix(*.sub_face), failure_text(.failure))]
pub struct EndCapError {
    /// The base face the end cap lies in.
    pub base_face: u32,
    /// Its sub-face when the base face is not a quad.
    pub sub_face: Option<u32>,
    /// The level of the end cap.
    pub level: u32,
    /// The face of that level.
    pub face: u32,
    /// Why it has no patch.
    pub failure: EndCapFailure,
}

fn sub_suffix(sub: Option<u32>) -> String {
    sub.map(|k| format!(" sub-face {k}")).unwrap_or_default()
}

fn failure_text(f: &EndCapFailure) -> String {
    match f {
        EndCapFailure::Incomplete { vertex } => {
            format!("corner vertex {vertex} has an incomplete one-ring")
        }
        EndCapFailure::Gregory(e) => e.to_string(),
    }
}

/// The shape of one patch of the adaptive surface.
#[derive(Debug, Clone, PartialEq)]
pub enum PatchShape {
    /// A B-spline patch; control vertices are global ids into the refined buffer.
    BSpline(RegularPatch),
    /// An end cap.
    Gregory(Box<GregoryPatch>),
    /// A single-crease patch (control vertices global ids), evaluated exactly with its full
    /// sharpness.
    SingleCrease(SingleCreasePatch),
}

/// One patch of an [`AdaptiveSurface`].
#[derive(Debug, Clone, PartialEq)]
pub struct SurfacePatch {
    /// Its level.
    pub level: u32,
    /// Its face (index in the level).
    pub face: u32,
    /// Its type in the census.
    pub kind: PatchType,
    /// Its place in the base face.
    pub domain: Domain,
    /// Its control points.
    pub shape: PatchShape,
}

/// A point of the adaptive surface with derivatives in the base face's (or sub-face's)
/// `(u, v)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePoint {
    /// Position.
    pub position: DVec3,
    /// dP/du (base parameters).
    pub du: DVec3,
    /// dP/dv (base parameters).
    pub dv: DVec3,
    /// Index of the patch in [`AdaptiveSurface::patches`].
    pub patch: usize,
}

/// Every patch of an [`AdaptiveRefinement`] over its refined positions, evaluable on the CPU.
#[derive(Debug, Clone)]
pub struct AdaptiveSurface {
    /// Every vertex of every level (global numbering, [`AdaptiveRefinement::refine_positions`]).
    pub positions: Vec<DVec3>,
    /// The patches in census order.
    pub patches: Vec<SurfacePatch>,
    /// Per base face: its patches (indices into `patches`).
    by_base: Vec<Vec<u32>>,
    /// End caps with a corner or edge on a promoted crease (`super::promoted`), by patch index.
    promoted: HashMap<usize, PromotedCap>,
    /// End caps with lattice regions (`super::lattice_frames`), by patch index.
    lattice: HashMap<usize, Vec<LatticeNormals>>,
}

/// A lattice region of an end cap (`super::lattice_frames::LatticeRegion`) with its nodes'
/// exact limit normals (`None`: the node takes the drawn normal).
#[derive(Debug, Clone)]
struct LatticeNormals {
    corner: usize,
    steps: u32,
    cells: u32,
    normals: Vec<Option<DVec3>>,
}

/// What an end cap shares on promoted creases: per face edge the end cap across it (patch
/// index, its edge) and the edge's residual sharpness, per corner the exact limit normal, per
/// other edge between two end caps that end cap, the fillet sharpness at its ends (0: none) and
/// how the normal turns there rather than the tangent bending, per corner whether its vertex is
/// an irregular crease vertex (`super::promoted::irregular_crease_vertex`) and whether the
/// positional fillet reaches it whole (`super::promoted::positional_fillet_end`).
#[derive(Debug, Clone, Default)]
struct PromotedCap {
    edges: [Option<(usize, usize)>; 4],
    sharpness: [f64; 4],
    corners: [Option<DVec3>; 4],
    ends: [[f64; 2]; 4],
    fillet_ends: [[Option<FilletEnd>; 2]; 4],
    others: [Option<(usize, usize)>; 4],
    irregular: [bool; 4],
    positional: [bool; 4],
    /// Per corner the positional fillet does not reach whole: the exact limit position minus
    /// the end cap's corner, and the offset's width sharpness ([`corner_offset_share`]).
    corner_offsets: [Option<(DVec3, f64)>; 4],
}

/// The own `(s, t)` of the point at `x` along quad edge `k` (corner `k` -> `k + 1`).
fn quad_edge_point(k: usize, x: f64) -> (f64, f64) {
    match k {
        0 => (x, 0.0),
        1 => (1.0, x),
        2 => (1.0 - x, 1.0),
        _ => (0.0, 1.0 - x),
    }
}

/// Own `(s, t)` as (distance from quad edge `k`, position along it from corner `k`): the inverse
/// of [`quad_edge_point`] on the edge (`w = 0`).
fn edge_coordinates(k: usize, s: f64, t: f64) -> (f64, f64) {
    match k {
        0 => (t, s),
        1 => (1.0 - s, t),
        2 => (1.0 - t, 1.0 - s),
        _ => (s, 1.0 - t),
    }
}

/// The quad corner an own `(s, t)` is (`None` elsewhere).
fn quad_corner(s: f64, t: f64) -> Option<usize> {
    match (s, t) {
        (0.0, 0.0) => Some(0),
        (1.0, 0.0) => Some(1),
        (1.0, 1.0) => Some(2),
        (0.0, 1.0) => Some(3),
        _ => None,
    }
}

/// The quad edge `(k, x)` an own `(s, t)` lies on, corners excluded (`None` inside).
fn on_quad_edge(s: f64, t: f64) -> Option<(usize, f64)> {
    match (s, t) {
        (_, 0.0) => Some((0, s)),
        (1.0, _) => Some((1, t)),
        (_, 1.0) => Some((2, 1.0 - s)),
        (0.0, _) => Some((3, 1.0 - t)),
        _ => None,
    }
}

/// Along quad edge `k`: (the edge's direction, the cross-edge derivative into the patch) from
/// the own derivatives `ds`, `dt`.
fn edge_frame(k: usize, ds: DVec3, dt: DVec3) -> (DVec3, DVec3) {
    match k {
        0 => (ds, dt),
        1 => (dt, -ds),
        2 => (-ds, -dt),
        _ => (-dt, ds),
    }
}

/// Builds the end caps of `refinement` (`census` its [`PatchCensus`], `positions` its
/// [`AdaptiveRefinement::refine_positions`]) in census order: for every end-cap face the Gregory
/// patch of that face in its level's sparse topology.
///
/// Residual semi-sharpness (edges and vertices still semi-sharp on the isolation level) is seen
/// through [`AdaptiveRefinement::end_cap_topology`]: by default sharpness `>= 1` as infinitely
/// sharp, the rest smooth ([`EndCapSharpness::Crease`]); with [`EndCapSharpness::Smooth`] all of
/// it smooth, as OpenSubdiv's Gregory-basis end caps. The refined points keep the semi-sharp
/// rules up to that level.
pub fn end_caps(
    refinement: &AdaptiveRefinement,
    census: &PatchCensus,
    positions: &[DVec3],
    tangents: GregoryTangents,
) -> Result<Vec<SurfacePatch>, EndCapError> {
    end_caps_seen(
        refinement,
        census,
        &EndCapTopologies::new(refinement, census),
        positions,
        tangents,
    )
}

/// [`end_caps`] over the levels' end-cap topologies `topologies`.
fn end_caps_seen(
    refinement: &AdaptiveRefinement,
    census: &PatchCensus,
    topologies: &EndCapTopologies,
    positions: &[DVec3],
    tangents: GregoryTangents,
) -> Result<Vec<SurfacePatch>, EndCapError> {
    let tangents = tangents.for_end_caps();
    let darts = DartLimits::new();
    census
        .patches
        .iter()
        .filter(|p| p.kind == PatchType::EndCap)
        .map(|p| {
            check_end_cap(refinement, p)?;
            let lev = &refinement.levels[p.level as usize];
            let t = topologies.get(p.level);
            let first = lev.first_vertex as usize;
            let local = &positions[first..first + lev.level.vertex_count()];
            let patch = gregory_patch_at_for(t, local, p.face, tangents, Coverage::EndCap, &darts)
                .map_err(|e| end_cap_error(refinement, p, EndCapFailure::Gregory(e)))?;
            Ok(SurfacePatch {
                level: p.level,
                face: p.face,
                kind: p.kind,
                domain: lev.domains[p.face as usize],
                shape: PatchShape::Gregory(Box::new(patch)),
            })
        })
        .collect()
}

/// The error of end cap `p` failing with `failure`, named by its base face.
pub(super) fn end_cap_error(
    refinement: &AdaptiveRefinement,
    p: &AdaptivePatch,
    failure: EndCapFailure,
) -> EndCapError {
    let domain = refinement.levels[p.level as usize].domains[p.face as usize];
    EndCapError {
        base_face: domain.base_face,
        sub_face: domain.sub_face,
        level: p.level,
        face: p.face,
        failure,
    }
}

/// Fails when a corner of end cap `p` has an incomplete one-ring in its sparse level.
pub(super) fn check_end_cap(
    refinement: &AdaptiveRefinement,
    p: &AdaptivePatch,
) -> Result<(), EndCapError> {
    let lev = &refinement.levels[p.level as usize];
    match lev
        .topology()
        .face_vertices(p.face)
        .iter()
        .find(|&&v| !lev.level.is_complete_vertex(v))
    {
        Some(&vertex) => Err(end_cap_error(
            refinement,
            p,
            EndCapFailure::Incomplete { vertex },
        )),
        None => Ok(()),
    }
}

impl AdaptiveSurface {
    /// The surface of `refinement` with base-mesh positions `base`: every census patch, end
    /// caps built by [`end_caps`].
    pub fn new(
        refinement: &AdaptiveRefinement,
        base: &[DVec3],
    ) -> Result<AdaptiveSurface, EndCapError> {
        Self::with_tangents(refinement, base, GregoryTangents::default())
    }

    /// [`Self::new`] with end caps built with the given Gregory edge tangents.
    pub fn with_tangents(
        refinement: &AdaptiveRefinement,
        base: &[DVec3],
        tangents: GregoryTangents,
    ) -> Result<AdaptiveSurface, EndCapError> {
        let census = PatchCensus::new(refinement);
        let positions = refinement.refine_positions(base);
        let topologies = EndCapTopologies::new(refinement, &census);
        let mut caps =
            end_caps_seen(refinement, &census, &topologies, &positions, tangents)?.into_iter();
        let patches = census
            .patches
            .iter()
            .map(|p| {
                let shape = match (p.bspline, p.crease) {
                    (_, Some(c)) => {
                        PatchShape::SingleCrease(SingleCreasePatch::from_line(p.face, c))
                    }
                    (Some(b), None) => PatchShape::BSpline(b),
                    (None, None) => return caps.next().expect("one end cap per end-cap patch"),
                };
                SurfacePatch {
                    level: p.level,
                    face: p.face,
                    kind: p.kind,
                    domain: refinement.levels[p.level as usize].domains[p.face as usize],
                    shape,
                }
            })
            .collect::<Vec<SurfacePatch>>();
        let mut by_base = vec![Vec::new(); refinement.levels[0].level.face_count()];
        for (i, p) in patches.iter().enumerate() {
            by_base[p.domain.base_face as usize].push(i as u32);
        }
        // Exact limit masks, one table for the whole surface.
        let masks = SharedVertexMasks::default();
        let inputs = (&census, &topologies, &masks);
        let promoted = promoted_caps(refinement, inputs, &patches, &positions);
        let lattice = lattice_normals(refinement, inputs, &positions);
        Ok(AdaptiveSurface {
            positions,
            patches,
            by_base,
            promoted,
            lattice,
        })
    }

    /// The unit normal of patch `i` at its own `(s, t)`: [`Self::promoted_normal`] where that
    /// applies, else the patch's own `du x dv`; inside an end cap, with the cross-edge
    /// derivative of every promoted edge within its fillet changed by
    /// `super::promoted::fillet_cross_derivative` (as `glsl/gregory/gregory_quad_tes.glsl`), and
    /// on its other edges from a promoted crease the shared normal with the tangent bent
    /// (`bent_edge_normal`).
    pub fn normal(&self, i: usize, s: f64, t: f64) -> DVec3 {
        let (_, ds, dt) = self.eval_own(i, s, t);
        self.normal_from(i, s, t, ds, dt)
    }

    /// [`Self::eval_patch`] and [`Self::normal`] at one point, the patch evaluated once.
    pub fn eval_with_normal(&self, i: usize, s: f64, t: f64) -> (SurfacePoint, DVec3) {
        let (position, ds, dt) = self.eval_own(i, s, t);
        let normal = self.normal_from(i, s, t, ds, dt);
        let position = position + self.fillet_position(i, s, t);
        (self.to_base(i, position, ds, dt), normal)
    }

    /// The positional fillet of end cap `i` at own `(s, t)`: what the limit adds to the end
    /// cap's crease surface within the fillet of a promoted edge between two end caps,
    /// `super::promoted::fillet_offset_factor` times the sum of both sides' cross-edge derivatives at
    /// the edge point, faded towards an end that is no `super::promoted::positional_fillet_end`
    /// (`super::promoted::fillet_end_fade`). As the GPU (`glsl/gregory/gregory_quad_tes.glsl`,
    /// `gregory_edge`): on a promoted edge its own offset, on another edge between two end caps
    /// the offsets of the creases through its positional ends (the sum there is the edge's
    /// derivative and its continuation's beyond the crease), at a positional corner the
    /// crease's; zero elsewhere. Plus, at each promoted corner it does not reach whole, the
    /// exact limit position's offset from the corner faded by `super::promoted::corner_offset_share`
    /// (the GPU's `exact_corner_offsets`, `glsl/adaptive/patch_adaptive_endcap.tese`).
    pub fn fillet_position(&self, i: usize, s: f64, t: f64) -> DVec3 {
        let Some(cap) = self.promoted.get(&i) else {
            return DVec3::ZERO;
        };
        let corners: DVec3 = (0..4)
            .filter_map(|c| {
                let (delta, sharpness) = cap.corner_offsets[c]?;
                let (w, x) = edge_coordinates(c, s, t);
                Some(delta * corner_offset_share(sharpness, x, w))
            })
            .sum();
        corners + self.crease_fillet_position(cap, i, s, t)
    }

    /// [`Self::fillet_position`] without the corner offsets.
    fn crease_fillet_position(&self, cap: &PromotedCap, i: usize, s: f64, t: f64) -> DVec3 {
        if let Some(c) = quad_corner(s, t) {
            return self.crease_end_offset(cap, i, c, 0.0);
        }
        if let Some((k, x)) = on_quad_edge(s, t) {
            if cap.edges[k].is_some() {
                return self.band_offset(cap, i, k, 0.0, x);
            }
            if cap.others[k].is_none() {
                return DVec3::ZERO;
            }
            return self.crease_end_offset(cap, i, k, x)
                + self.crease_end_offset(cap, i, (k + 1) % 4, 1.0 - x);
        }
        (0..4)
            .map(|k| {
                let (w, x) = edge_coordinates(k, s, t);
                self.band_offset(cap, i, k, w, x)
            })
            .sum()
    }

    /// The positional fillet of promoted edge `k` of end cap `i` at distance `w` from it, `x`
    /// along it from corner `k` (zero unless the edge is a promoted crease between two end caps
    /// and `w` within its fillet).
    fn band_offset(&self, cap: &PromotedCap, i: usize, k: usize, w: f64, x: f64) -> DVec3 {
        let Some(across) = cap.edges[k] else {
            return DVec3::ZERO;
        };
        let sharp = cap.sharpness[k];
        if !within_fillet(sharp, w) {
            return DVec3::ZERO;
        }
        let fade = |c: usize, y: f64| {
            if cap.positional[c] {
                1.0
            } else {
                fillet_end_fade(sharp, y)
            }
        };
        let share = fade(k, x) * fade((k + 1) % 4, 1.0 - x);
        if share == 0.0 {
            return DVec3::ZERO;
        }
        let (_, d_own, d_across) = self.edge_derivatives(i, k, x, across);
        (d_own + d_across) * (fillet_offset_factor(sharp, w) * share)
    }

    /// At corner `c` of end cap `i`, a [`positional_fillet_end`]: the positional fillet of the
    /// promoted edge there at distance `w` from it along the other edge at `c` (zero elsewhere).
    fn crease_end_offset(&self, cap: &PromotedCap, i: usize, c: usize, w: f64) -> DVec3 {
        if !cap.positional[c] {
            return DVec3::ZERO;
        }
        // The promoted edge at `c`: edge `c` (from it) or edge `c - 1` (to it).
        let (k, x) = if cap.edges[c].is_some() {
            (c, 0.0)
        } else {
            ((c + 3) % 4, 1.0)
        };
        let Some(across) = cap.edges[k] else {
            return DVec3::ZERO;
        };
        let (_, d_own, d_across) = self.edge_derivatives(i, k, x, across);
        (d_own + d_across) * fillet_offset_factor(cap.sharpness[k], w)
    }

    /// [`Self::normal`] from the patch's own derivatives `ds`, `dt` at `(s, t)`: the drawn
    /// normal ([`Self::drawn_normal`]), interpolated with the exact lattice normals within a
    /// lattice region (`super::lattice_frames::lattice_normal`, the GPU's `lattice_normals`).
    fn normal_from(&self, i: usize, s: f64, t: f64, ds: DVec3, dt: DVec3) -> DVec3 {
        let drawn = self.drawn_normal(i, s, t, ds, dt);
        let Some(regions) = self.lattice.get(&i) else {
            return drawn;
        };
        if quad_corner(s, t).is_some() {
            return drawn;
        }
        regions
            .iter()
            .find_map(|r| {
                let (w, x) = edge_coordinates(r.corner, s, t);
                lattice_normal(r.steps, r.cells, x, w, drawn, |a, b| {
                    r.normals[(a + r.cells * b) as usize]
                })
            })
            .map_or(drawn, DVec3::normalize_or_zero)
    }

    /// The end cap's own normal at `(s, t)` from its derivatives `ds`, `dt` ([`Self::normal`]
    /// without the lattice).
    fn drawn_normal(&self, i: usize, s: f64, t: f64, mut ds: DVec3, mut dt: DVec3) -> DVec3 {
        self.promoted_normal(i, s, t).unwrap_or_else(|| {
            let Some(cap) = self.promoted.get(&i) else {
                return ds.cross(dt).normalize_or_zero();
            };
            if let Some((k, x)) = on_quad_edge(s, t) {
                if let Some(n) = self.bent_edge_normal(cap, i, k, x) {
                    return n;
                }
            }
            let inside = s > 0.0 && s < 1.0 && t > 0.0 && t < 1.0;
            if inside {
                for k in 0..4 {
                    let Some((d, a)) = self.fillet_change(cap, i, k, s, t) else {
                        continue;
                    };
                    // `d` changes the derivative into the patch across edge k, `a` the one
                    // along it (`edge_frame`).
                    match k {
                        0 => (ds, dt) = (ds + a, dt + d),
                        1 => (ds, dt) = (ds - d, dt + a),
                        2 => (ds, dt) = (ds - a, dt - d),
                        _ => (ds, dt) = (ds + d, dt - a),
                    }
                }
            }
            ds.cross(dt).normalize_or_zero()
        })
    }

    /// On edge `k` of end cap `i` (at `x` from corner `k`), an edge between two end caps from a
    /// vertex on a promoted crease: the normal both sides share (`gregory_edge` of
    /// `glsl/gregory/gregory.glsl`), `cross(tangent, d_own - d_across)`, with the tangent bent by
    /// the crease's fillet within it: `super::promoted::fillet_cross_derivative` of the sum of
    /// the edge's derivative from that end and its continuation's beyond the crease (the end
    /// cap across it; `super::promoted::fillet_bend` where there is none); from a crease vertex
    /// that is not regular, the normal turned towards the limit's there instead
    /// (`super::promoted::fillet_rotation`), or where three or more creases meet there from the
    /// normal at the point (`super::promoted::turn_towards`); `None` elsewhere.
    fn bent_edge_normal(&self, cap: &PromotedCap, i: usize, k: usize, x: f64) -> Option<DVec3> {
        let across = cap.others[k]?;
        let (mut tangent, d_own, d_across) = self.edge_derivatives(i, k, x, across);
        let mut bent = false;
        let mut turns = [None; 2];
        for (side, w) in [(0, x), (1, 1.0 - x)] {
            let (sharp, c) = (cap.ends[k][side], (k + side) % 4);
            let Some(normal) = cap.corners[c].filter(|_| sharp > 0.0) else {
                continue;
            };
            bent = true;
            if let Some(end @ (FilletEnd::Turn(_) | FilletEnd::TurnMany(_))) =
                cap.fillet_ends[k][side]
            {
                // The edge's own normal at that end, as the normal below.
                let own = matches!(end, FilletEnd::Turn(_)).then(|| {
                    let (t0, own0, across0) = self.edge_derivatives(i, k, side as f64, across);
                    t0.cross(own0 - across0)
                });
                turns[side] = Some((sharp, w, own, normal));
                continue;
            }
            // The derivative from that end into the edge.
            let (a, b) = quad_edge_point(k, side as f64);
            let (_, ds0, dt0) = self.eval_own(i, a, b);
            let sign = if side == 0 { 1.0 } else { -1.0 };
            let along = sign * edge_frame(k, ds0, dt0).0;
            // The patch's other edge at that end is the promoted crease the edge crosses
            // (`vertex_fillet_sharpness`): the sum is `along` plus the derivative of its
            // continuation beyond the crease, the cross-edge derivative at that end of the end
            // cap across the crease (as `fillet_change` there).
            let (crease, at) = if side == 0 {
                ((k + 3) % 4, 1.0)
            } else {
                ((k + 1) % 4, 0.0)
            };
            tangent += sign
                * match cap.edges[crease] {
                    Some(beyond) => {
                        let (_, _, d_beyond) = self.edge_derivatives(i, crease, at, beyond);
                        fillet_cross_derivative(sharp, w, along + d_beyond)
                    }
                    None => fillet_bend(sharp, w, along, normal),
                };
        }
        let mut n = tangent.cross(d_own - d_across).normalize_or_zero();
        for (sharp, w, own, limit) in turns.into_iter().flatten() {
            n = match own {
                Some(own) => fillet_rotation(sharp, w, own, limit, n),
                None => turn_towards(n, limit, fillet_many_share(sharp, w)),
            };
        }
        bent.then_some(n)
    }

    /// The changes of end cap `i`'s derivatives (into the patch across its edge `k`, along it
    /// from corner `k`) at own `(s, t)` where edge `k` is a promoted crease between two end caps
    /// and `(s, t)` lies in its fillet: `super::promoted::fillet_cross_derivative`, and between
    /// two quads `super::promoted::fillet_offset_factor` times the derivative along the edge of
    /// both sides' cross-edge derivatives' sum at the edge point (`edge_cross_slopes`, the band
    /// offset's slope on the edge itself); `None` elsewhere.
    fn fillet_change(
        &self,
        cap: &PromotedCap,
        i: usize,
        k: usize,
        s: f64,
        t: f64,
    ) -> Option<(DVec3, DVec3)> {
        let across = cap.edges[k]?;
        let (w, x) = edge_coordinates(k, s, t);
        if !within_fillet(cap.sharpness[k], w) {
            return None;
        }
        let (_, d_own, d_across) = self.edge_derivatives(i, k, x, across);
        let along = self
            .edge_cross_slopes(i, k, x, across)
            .map_or(DVec3::ZERO, |slope| {
                fillet_offset_factor(cap.sharpness[k], w) * slope
            });
        Some((
            fillet_cross_derivative(cap.sharpness[k], w, d_own + d_across),
            along,
        ))
    }

    /// The normal the GPU draws on a promoted crease (`super::promoted`), at own `(s, t)` of end
    /// cap `i`: at a corner on one the exact limit normal; on an edge that is one (an end cap on
    /// both sides) the normal both sides share, `cross(tangent, d_own - d_across)` of the two
    /// cross-edge derivatives (`gregory_edge` of `glsl/gregory/gregory.glsl`), turned towards the
    /// limit normal of an irregular crease vertex at either end within its fillet
    /// (`super::promoted::crease_turn_share`). `None` elsewhere.
    pub fn promoted_normal(&self, i: usize, s: f64, t: f64) -> Option<DVec3> {
        let cap = self.promoted.get(&i)?;
        if let Some(k) = quad_corner(s, t) {
            return cap.corners[k];
        }
        let (k, x) = on_quad_edge(s, t)?;
        let across = cap.edges[k]?;
        let (mut tangent, d_own, d_across) = self.edge_derivatives(i, k, x, across);
        // The band offset `h (d_own + d_across) / 6` of the fillet along the edge
        // (`super::promoted::band_offset_factor`): its derivative along the edge turns the
        // tangent.
        if let Some(slope) = self.edge_cross_slopes(i, k, x, across) {
            tangent += band_offset_factor(cap.sharpness[k]) * slope;
        }
        let mut n = tangent.cross(d_own - d_across).normalize_or_zero();
        // Within the fillet of an irregular crease vertex at either end: turned towards its
        // limit normal (`super::promoted::crease_turn_share`).
        for (side, w) in [(0, x), (1, 1.0 - x)] {
            let c = (k + side) % 4;
            if let (true, Some(limit)) = (cap.irregular[c], cap.corners[c]) {
                n = turn_towards(n, limit, crease_turn_share(cap.sharpness[k], w));
            }
        }
        Some(n)
    }

    /// At `x` along edge `k` of quad end cap `i` (from corner `k`), with quad end cap `j`
    /// across it on its edge `k2`: the derivative along the edge (by `x`) of the sum of both
    /// cross-edge derivatives, from the Bézier nets with the face points frozen on the edge
    /// (§4.4, as `cross_quad_slope` in `glsl/gregory/gregory.glsl`); `None` unless both are
    /// quads.
    fn edge_cross_slopes(
        &self,
        i: usize,
        k: usize,
        x: f64,
        (j, k2): (usize, usize),
    ) -> Option<DVec3> {
        // d/dx of the derivative into the patch: +-d2/dsdt by the edge (`edge_frame`).
        let sign = |k: usize| if k % 2 == 0 { 1.0 } else { -1.0 };
        let (s, t) = quad_edge_point(k, x);
        let (s2, t2) = quad_edge_point(k2, 1.0 - x);
        // The patch across runs the edge the other way (`x2 = 1 - x`).
        Some(
            sign(k) * self.mixed_derivative(i, s, t)?
                - sign(k2) * self.mixed_derivative(j, s2, t2)?,
        )
    }

    /// `d2/dsdt` of quad end cap `i` at own `(s, t)` (face points as `bezier_at` blends them).
    fn mixed_derivative(&self, i: usize, s: f64, t: f64) -> Option<DVec3> {
        let PatchShape::Gregory(g) = &self.patches[i].shape else {
            return None;
        };
        let GregoryPatch::Quad(q) = g.as_ref() else {
            return None;
        };
        let b = q.bezier_at(s, t);
        let (ds, dt) = (bernstein_deriv(s), bernstein_deriv(t));
        Some(eval_tensor(&b, &ds, &ds, &dt, &dt).0)
    }

    /// At `x` along edge `k` of patch `i` (from corner `k`), with patch `j` across it on its
    /// edge `k2`: (the edge's direction, the cross-edge derivative into `i`, into `j`).
    fn edge_derivatives(
        &self,
        i: usize,
        k: usize,
        x: f64,
        (j, k2): (usize, usize),
    ) -> (DVec3, DVec3, DVec3) {
        let (s, t) = quad_edge_point(k, x);
        let (_, ds, dt) = self.eval_own(i, s, t);
        let (tangent, d_own) = edge_frame(k, ds, dt);
        // The patch across runs the edge the other way: its edge k2 at 1 - x.
        let (s2, t2) = quad_edge_point(k2, 1.0 - x);
        let (_, ds2, dt2) = self.eval_own(j, s2, t2);
        let (_, d_across) = edge_frame(k2, ds2, dt2);
        (tangent, d_own, d_across)
    }

    /// Position and derivatives of patch `i` in its own `(s, t)`.
    fn eval_own(&self, i: usize, s: f64, t: f64) -> (DVec3, DVec3, DVec3) {
        match &self.patches[i].shape {
            PatchShape::BSpline(b) => {
                let x = b.eval(&self.positions, s, t);
                (x.position, x.du, x.dv)
            }
            PatchShape::Gregory(g) => {
                let x = g.eval(s, t);
                (x.position, x.du, x.dv)
            }
            PatchShape::SingleCrease(c) => {
                let x = c.eval(&self.positions, s, t);
                (x.position, x.du, x.dv)
            }
        }
    }

    /// Evaluates patch `i` at its own `(s, t)`, derivatives mapped to base parameters; an end
    /// cap's position with its positional fillet ([`Self::fillet_position`]; the derivatives
    /// are the patch's own).
    pub fn eval_patch(&self, i: usize, s: f64, t: f64) -> SurfacePoint {
        let (position, ds, dt) = self.eval_own(i, s, t);
        let position = position + self.fillet_position(i, s, t);
        self.to_base(i, position, ds, dt)
    }

    /// Patch `i`'s point with own derivatives `ds`, `dt`, derivatives mapped to base parameters.
    fn to_base(&self, i: usize, position: DVec3, ds: DVec3, dt: DVec3) -> SurfacePoint {
        let p = &self.patches[i];
        // (s, t) -> origin + s U + t V: d/du = (ds, dt) J^-1 with J = [U V].
        let (a, b) = (p.domain.u, p.domain.v);
        let det = a.perp_dot(b);
        let (su, tu) = (b.y / det, -a.y / det);
        let (sv, tv) = (-b.x / det, a.x / det);
        SurfacePoint {
            position,
            du: su * ds + tu * dt,
            dv: sv * ds + tv * dt,
            patch: i,
        }
    }

    /// The patch of `base_face` (sub-face `sub_face` for non-quads, `None` for quads) whose
    /// domain holds `(u, v)`, and the patch's own `(s, t)` there; the first in census order on
    /// shared domain edges. `None` when no patch covers the point (holes, out of range).
    pub fn locate(
        &self,
        base_face: u32,
        sub_face: Option<u32>,
        u: f64,
        v: f64,
    ) -> Option<(usize, f64, f64)> {
        const EPS: f64 = 1e-12;
        let x = DVec2::new(u, v);
        let own = self.by_base.get(base_face as usize)?;
        own.iter().find_map(|&i| {
            let i = i as usize;
            let d = &self.patches[i].domain;
            if d.sub_face != sub_face {
                return None;
            }
            let r = x - d.origin;
            let det = d.u.perp_dot(d.v);
            let s = r.perp_dot(d.v) / det;
            let t = d.u.perp_dot(r) / det;
            let inside = |c: f64| (-EPS..=1.0 + EPS).contains(&c);
            (inside(s) && inside(t)).then(|| (i, s.clamp(0.0, 1.0), t.clamp(0.0, 1.0)))
        })
    }

    /// Evaluates the surface at `(u, v)` of `base_face` (sub-face `sub_face` for non-quads):
    /// [`Self::locate`] then [`Self::eval_patch`].
    pub fn eval(
        &self,
        base_face: u32,
        sub_face: Option<u32>,
        u: f64,
        v: f64,
    ) -> Option<SurfacePoint> {
        let (i, s, t) = self.locate(base_face, sub_face, u, v)?;
        Some(self.eval_patch(i, s, t))
    }
}

/// What the surface's end caps are built from, once per surface: the census, the levels'
/// end-cap topologies and the exact limit masks' table.
type EndCapInputs<'a> = (
    &'a PatchCensus,
    &'a EndCapTopologies<'a>,
    &'a SharedVertexMasks,
);

/// Per end cap with lattice regions (`super::lattice_frames`, census order): the regions with
/// their nodes' exact limit normals over `positions`.
fn lattice_normals(
    refinement: &AdaptiveRefinement,
    (census, topologies, masks): EndCapInputs,
    positions: &[DVec3],
) -> HashMap<usize, Vec<LatticeNormals>> {
    let at = patch_index(refinement, census);
    let frames = LatticeFrames::new(refinement, census, topologies, &at, 0, masks);
    let apply = |w: &[(u32, f64)]| apply_terms(w, positions);
    let normal = |f: u32| {
        let [d1, d2] = frames.rows.get(f as usize)?;
        Some(apply(d1).cross(apply(d2)).normalize_or_zero())
    };
    (frames.regions.chunk_by(|a, b| a.patch == b.patch))
        .map(|regions| {
            let i = regions[0].patch as usize;
            let regions = regions
                .iter()
                .map(|r| LatticeNormals {
                    corner: r.corner as usize,
                    steps: r.steps,
                    cells: r.cells,
                    normals: r.frames.iter().map(|&f| normal(f)).collect(),
                })
                .collect();
            (i, regions)
        })
        .collect()
}

/// The end caps of `patches` (census order) on promoted creases: per quad end cap the end cap
/// across each promoted edge and the exact limit normal at each promoted corner.
fn promoted_caps(
    refinement: &AdaptiveRefinement,
    (_, topologies, masks): EndCapInputs,
    patches: &[SurfacePatch],
    positions: &[DVec3],
) -> HashMap<usize, PromotedCap> {
    let mut at: HashMap<(u32, u32), usize> = HashMap::new();
    for (i, p) in patches.iter().enumerate() {
        if matches!(p.shape, PatchShape::Gregory(_)) {
            at.insert((p.level, p.face), i);
        }
    }
    let mut out = HashMap::new();
    for (&(level, face), &i) in &at {
        let lev = &refinement.levels[level as usize];
        let (t, caps) = (lev.topology(), topologies.get(level));
        if t.face_size(face) != 4 {
            continue;
        }
        let mut cap = PromotedCap::default();
        let fv = t.face_vertices(face);
        for (k, &e) in t.face_edges(face).iter().enumerate() {
            let across = t.edge_faces(e).iter().copied().find(|&g| g != face);
            let across = across.and_then(|g| {
                let j = *at.get(&(level, g))?;
                let k2 = t.face_edges(g).iter().position(|&x| x == e)?;
                (t.face_size(g) == 4).then_some((j, k2))
            });
            if !caps.is_promoted_edge(e) {
                if across.is_some() && !is_sharp_edge(caps, e) {
                    cap.others[k] = across;
                    for (half, v) in [fv[k], fv[(k + 1) % 4]].into_iter().enumerate() {
                        let end = fillet_end(t, caps, v, e);
                        cap.fillet_ends[k][half] = end;
                        cap.ends[k][half] = end.map_or(0.0, |x| {
                            fillet_end_sharpness(fillet_end_code(x.sharpness()))
                        });
                    }
                }
                continue;
            }
            cap.edges[k] = across;
            cap.sharpness[k] = fillet_fine_sharpness(fillet_fine_code(t.edge_sharpness(e)));
        }
        for (k, &v) in t.face_vertices(face).iter().enumerate() {
            cap.irregular[k] = irregular_crease_vertex(t, caps, v);
            if promoted_vertex(t, caps, v) {
                cap.positional[k] = positional_fillet_end(t, caps, v, |g| {
                    t.face_size(g) == 4 && at.contains_key(&(level, g))
                });
                cap.corners[k] =
                    exact_corner_tangents_shared(lev, face, k, masks).map(|[du, dv]| {
                        du.apply(positions)
                            .cross(dv.apply(positions))
                            .normalize_or_zero()
                    });
                // Where the positional fillet fades out: the exact limit position there
                // (`super::exact_corners`, the GPU's frame).
                let quad_cap = |g| t.face_size(g) == 4 && at.contains_key(&(level, g));
                if let (true, PatchShape::Gregory(g)) = (
                    corner_offset_vertex(t, caps, v, quad_cap),
                    &patches[i].shape,
                ) {
                    let (a, b) = quad_edge_point(k, 0.0);
                    let sharpness = fillet_sharpness(corner_offset_code(t, caps, v));
                    cap.corner_offsets[k] = exact_corner_position(lev, face, k, masks)
                        .map(|p| (p.apply(positions) - g.eval(a, b).position, sharpness));
                }
            }
        }
        let offsets = cap.corner_offsets.iter().any(Option::is_some);
        if offsets
            || cap.edges.iter().any(Option::is_some)
            || cap.corners.iter().any(Option::is_some)
        {
            out.insert(i, cap);
        }
    }
    out
}
