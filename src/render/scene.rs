//! From a control mesh to [`SurfaceData`]: regular faces become B-spline patches
//! ([`RegularPatch::gather`]); every other face with a limit surface is evaluated on the CPU.

use glam::DVec3;

use super::fallback::{self, FallbackFace, PatchClass};
use super::layout::BSplinePatch;
use super::surface::SurfaceData;
use crate::mesh::ControlMesh;
use crate::patch::RegularPatch;
use crate::subdiv::eval::LimitEvaluator;
use crate::topology::Topology;
use crate::Result;

impl From<&RegularPatch> for BSplinePatch {
    fn from(p: &RegularPatch) -> Self {
        BSplinePatch {
            face: p.face,
            cvs: p.cvs,
            boundary_mask: p.boundary_mask,
        }
    }
}

/// Which face is drawn how.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SurfacePlan {
    /// Regular faces (B-spline patches on the GPU).
    pub patches: Vec<BSplinePatch>,
    /// Faces with a limit surface but no GPU scheme yet.
    pub fallback_faces: Vec<FallbackFace>,
    /// Holes and faces without a limit surface.
    pub skipped_faces: usize,
}

impl SurfacePlan {
    /// Sorts the faces of `topo`.
    pub fn new(topo: &Topology) -> SurfacePlan {
        let mut plan = SurfacePlan::default();
        for f in 0..topo.face_count() as u32 {
            if !topo.has_limit_surface(f) {
                plan.skipped_faces += 1;
            } else if let Some(p) = RegularPatch::gather(topo, f) {
                plan.patches.push(BSplinePatch::from(&p));
            } else {
                let n = topo.face_size(f) as u32;
                plan.fallback_faces.push(FallbackFace {
                    face: f,
                    corners: n,
                    class: if n == 3 {
                        PatchClass::Triangle
                    } else {
                        PatchClass::Irregular
                    },
                });
            }
        }
        plan
    }
}

/// Builds the surface of `mesh` with the CPU-evaluated faces sampled at tessellation `level`
/// through `eval(face, sub, &[(u, v)]) -> [(position, unit normal)]`.
pub fn surface_with<F>(mesh: &ControlMesh, level: u32, eval: F) -> Result<SurfaceData>
where
    F: Fn(u32, u32, &[(f64, f64)]) -> Result<Vec<(DVec3, DVec3)>> + Sync,
{
    let topo = Topology::new(mesh)?;
    let plan = SurfacePlan::new(&topo);
    let fallback = fallback::tessellate(&plan.fallback_faces, level, eval)?;
    Ok(SurfaceData {
        positions: mesh.positions().to_vec(),
        patches: plan.patches,
        fallback_faces: plan.fallback_faces,
        fallback,
        skipped_faces: plan.skipped_faces,
        gregory: None,
    })
}

/// Builds the surface of `mesh`: regular faces as GPU patches, every other face with a limit
/// surface evaluated exactly on the CPU ([`LimitEvaluator`]) on a grid matching `level`.
pub fn surface_from_mesh(mesh: &ControlMesh, level: u32) -> Result<SurfaceData> {
    let topo = Topology::new(mesh)?;
    let plan = SurfacePlan::new(&topo);
    let fallback = if plan.fallback_faces.is_empty() {
        super::fallback::FallbackMesh::default()
    } else {
        let ev = LimitEvaluator::new(mesh)?;
        fallback::tessellate(&plan.fallback_faces, level, |f, sub, uv| {
            Ok(ev
                .eval_points(f as usize, sub as usize, uv)?
                .into_iter()
                .map(|s| (s.position, s.normal))
                .collect())
        })?
    };
    Ok(SurfaceData {
        positions: mesh.positions().to_vec(),
        patches: plan.patches,
        fallback_faces: plan.fallback_faces,
        fallback,
        skipped_faces: plan.skipped_faces,
        gregory: None,
    })
}
