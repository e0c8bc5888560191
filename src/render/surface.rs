//! What the renderer draws: control positions, the regular B-spline patches, and the faces
//! evaluated on the CPU, gathered from a control mesh or given directly.

use glam::DVec3;

use super::fallback::{FallbackFace, FallbackMesh};
use super::layout::BSplinePatch;

/// A surface ready for the GPU.
#[derive(Debug, Clone, Default)]
pub struct SurfaceData {
    /// Control-vertex positions (f64; converted to f32 on upload).
    pub positions: Vec<DVec3>,
    /// Regular faces as bicubic B-spline patches (tessellated on the GPU).
    pub patches: Vec<BSplinePatch>,
    /// Faces with a limit surface but no GPU scheme yet (evaluated on the CPU).
    pub fallback_faces: Vec<FallbackFace>,
    /// The CPU-evaluated triangles of `fallback_faces` at the current tessellation level.
    pub fallback: FallbackMesh,
    /// Faces that are not drawn at all (holes, faces without a limit surface).
    pub skipped_faces: usize,
}

impl SurfaceData {
    /// Bounding box `(min, max)` of the limit corners of the patches and the fallback triangles
    /// (what is drawn, up to the bulge of patch interiors); `(0, 0)` when empty.
    pub fn bounding_box(&self) -> (DVec3, DVec3) {
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for p in &self.patches {
            for q in p.corner_limits(&self.positions) {
                lo = lo.min(q);
                hi = hi.max(q);
            }
        }
        for q in &self.fallback.positions {
            lo = lo.min(*q);
            hi = hi.max(*q);
        }
        if lo.x > hi.x {
            return (DVec3::ZERO, DVec3::ZERO);
        }
        (lo, hi)
    }

    /// Checks that every patch control vertex exists.
    pub fn validate(&self) -> crate::Result<()> {
        let n = self.positions.len();
        for p in &self.patches {
            if let Some(v) = p.cvs.iter().find(|v| **v as usize >= n) {
                return Err(crate::Error::Invalid(format!(
                    "patch of face {} uses vertex {v}, mesh has {n} vertices",
                    p.face
                )));
            }
        }
        Ok(())
    }
}
