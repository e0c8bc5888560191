//! What the renderer draws: control positions, the regular B-spline patches, and the faces
//! evaluated on the CPU, gathered from a control mesh or given directly.

use glam::DVec3;

use super::fallback::{FallbackFace, FallbackMesh};
use super::gregory_layout::gregory_vertex_frame;
use super::layout::BSplinePatch;
use super::scheme::GregorySurface;

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
    /// Faces drawn as GPU Gregory patches and the variant (`--scheme`); `None`: none.
    pub gregory: Option<GregorySurface>,
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
        for q in self.fallback.positions.iter().chain(&self.gregory_points()) {
            lo = lo.min(*q);
            hi = hi.max(*q);
        }
        if lo.x > hi.x {
            return (DVec3::ZERO, DVec3::ZERO);
        }
        (lo, hi)
    }

    /// Limit positions of the corners of the Gregory faces (camera framing).
    pub fn gregory_points(&self) -> Vec<DVec3> {
        match &self.gregory {
            Some(g) => {
                let mut vs: Vec<u32> = g
                    .faces
                    .iter()
                    .flat_map(|&f| g.topology.face_vertices(f).iter().copied())
                    .filter(|&v| (v as usize) < self.positions.len())
                    .collect();
                vs.sort_unstable();
                vs.dedup();
                vs.into_iter()
                    .map(|v| gregory_vertex_frame(&g.topology, &self.positions, v).0)
                    .collect()
            }
            None => Vec::new(),
        }
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
