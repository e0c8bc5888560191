//! Tangent-plane continuity of a scheme's patches, measured from their CPU constructions (the
//! references the GPU reproduces): across every smooth edge two GPU-drawn quads share, the angle
//! between the two patches' geometric normals a small parameter step inside each side.
//!
//! The drawn normals cannot show a G1 defect: every scheme evaluates shared edges from shared
//! data, so both sides draw the same normal there ([`super::seams::SeamReport`]), and QAS draws
//! a separate, continuous normal patch. The geometric normal (central differences of the
//! reference positions) just inside each side shows what the construction does: no more than
//! the limit's own turn for exact patches, a little more for Gregory patches (G1 only
//! approximately), much more for QAS (only C0). The same angle of the exact limit at the same
//! two points is reported beside it, so a scheme's figure reads against it. Edges with any
//! sharpness are left out (a semi-sharp crease turns the limit's normal fast across it).

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::schemes::ReferencePatch;
use super::surface::SurfaceData;
use crate::patch::gregory::accuracy::normal_angle;
use crate::subdiv::eval::LimitEvaluator;
use crate::topology::{is_sharp_edge, Topology};

/// Parameter step inside each face (fraction of its edge length).
pub const INSET: f64 = 1e-4;
/// Half-width of the central differences of the geometric normal (parameter units).
const STEP: f64 = 1e-5;
/// Points per shared edge (at `t = (k + ½) / SAMPLES_PER_EDGE`).
pub const SAMPLES_PER_EDGE: usize = 8;

/// What [`ContinuityReport::new`] measured.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ContinuityReport {
    /// Smooth edges between two GPU-drawn quads measured.
    pub edges: usize,
    /// Point pairs measured.
    pub samples: usize,
    /// Largest angle between the two patches' normals (radians).
    pub max_jump: f64,
    /// RMS of that angle.
    pub rms_jump: f64,
    /// Largest angle between the exact limit's normals at the same two points (the floor).
    pub max_exact_jump: f64,
}

/// Face parameters of edge `k` of a quad (0: v = 0, 1: u = 1, 2: v = 1, 3: u = 0, each from
/// corner k to k + 1) at `t`, stepped `inset` towards the face's inside.
fn quad_edge_point(k: usize, t: f64, inset: f64) -> DVec2 {
    match k {
        0 => DVec2::new(t, inset),
        1 => DVec2::new(1.0 - inset, t),
        2 => DVec2::new(1.0 - t, 1.0 - inset),
        _ => DVec2::new(inset, 1.0 - t),
    }
}

/// The normal of `patch`'s positions at `p` by central differences.
fn geometric_normal(patch: &ReferencePatch, p: DVec2) -> DVec3 {
    let at = |u: f64, v: f64| patch(u, v).0;
    let du = at(p.x + STEP, p.y) - at(p.x - STEP, p.y);
    let dv = at(p.x, p.y + STEP) - at(p.x, p.y - STEP);
    du.cross(dv).normalize_or_zero()
}

/// The two faces of an edge and the point pairs measured across it.
type EdgePairs = (u32, u32, Vec<(DVec2, DVec2)>);

/// The two faces of edge `e` and the point pairs measured across it (face parameters a step
/// inside each side, at the same places along the edge), if `e` is an interior edge without
/// sharpness between two quads.
fn edge_pairs(topo: &Topology, e: u32) -> Option<EdgePairs> {
    let faces = topo.edge_faces(e);
    let (f, g) = (*faces.first()?, *faces.get(1)?);
    if is_sharp_edge(topo, e) || topo.edge_sharpness(e) > 0.0 {
        return None;
    }
    let local = |face: u32| {
        (topo.face_size(face) == 4)
            .then(|| topo.face_edges(face).iter().position(|&x| x == e))
            .flatten()
    };
    let (kf, kg) = (local(f)?, local(g)?);
    let pairs = (0..SAMPLES_PER_EDGE)
        .map(|s| {
            let t = (s as f64 + 0.5) / SAMPLES_PER_EDGE as f64;
            // The two faces run the shared edge in opposite directions.
            (
                quad_edge_point(kf, t, INSET),
                quad_edge_point(kg, 1.0 - t, INSET),
            )
        })
        .collect();
    Some((f, g, pairs))
}

/// Per edge of `topo`: the largest angle between the exact limit's normals at the point pairs
/// [`ContinuityReport::new`] measures there (`None` where it measures none). It depends on the
/// mesh only, so `tessera compare` computes it once for every scheme
/// ([`super::accuracy::ExactReference::turns`]).
pub fn exact_turns(topo: &Topology, exact: &LimitEvaluator) -> Vec<Option<f64>> {
    (0..topo.edge_count() as u32)
        .into_par_iter()
        .map(|e| {
            let (f, g, pairs) = edge_pairs(topo, e)?;
            let mut turn = 0.0f64;
            for (a, b) in pairs {
                let ea = exact.eval(f as usize, 0, a.x, a.y);
                let eb = exact.eval(g as usize, 0, b.x, b.y);
                if let (Ok(ea), Ok(eb)) = (ea, eb) {
                    turn = turn.max(normal_angle(ea.normal, eb.normal));
                }
            }
            Some(turn)
        })
        .collect()
}

impl ContinuityReport {
    /// Measures `surface` (its GPU parts' references over `surface.positions`) across every
    /// interior, non-sharp edge whose two faces are quads drawn by GPU passes; `turns` are the
    /// limit's own turns there ([`exact_turns`] of the same mesh).
    pub fn new(surface: &SurfaceData, topo: &Topology, turns: &[Option<f64>]) -> Self {
        let mut refs: Vec<Option<ReferencePatch>> = (0..topo.face_count()).map(|_| None).collect();
        for part in &surface.parts {
            let quads: Vec<u32> = part
                .faces()
                .iter()
                .copied()
                .filter(|&f| topo.face_size(f) == 4)
                .collect();
            for (f, r) in quads
                .iter()
                .zip(part.references(&surface.positions, &quads))
            {
                refs[*f as usize] = r;
            }
        }
        let mut report = ContinuityReport::default();
        let mut sum = 0.0;
        for e in 0..topo.edge_count() as u32 {
            let Some((f, g, pairs)) = edge_pairs(topo, e) else {
                continue;
            };
            let (Some(rf), Some(rg)) = (&refs[f as usize], &refs[g as usize]) else {
                continue;
            };
            report.edges += 1;
            if let Some(turn) = turns[e as usize] {
                report.max_exact_jump = report.max_exact_jump.max(turn);
            }
            for (a, b) in pairs {
                let jump = normal_angle(geometric_normal(rf, a), geometric_normal(rg, b));
                report.samples += 1;
                report.max_jump = report.max_jump.max(jump);
                sum += jump * jump;
            }
        }
        report.rms_jump = (sum / report.samples.max(1) as f64).sqrt();
        report
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edge_points_run_corner_to_corner_inside() {
        let corners = [
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(0.0, 1.0),
        ];
        for k in 0..4 {
            assert_eq!(quad_edge_point(k, 0.0, 0.0), corners[k]);
            assert_eq!(quad_edge_point(k, 1.0, 0.0), corners[(k + 1) % 4]);
            let p = quad_edge_point(k, 0.5, 0.25);
            assert!(p.min_element() >= 0.25 && p.max_element() <= 0.75);
        }
    }
}
