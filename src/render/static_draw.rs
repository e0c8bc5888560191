//! The static baseline of a tessellated frame (issue 8: GPU time "beside the static draw of the
//! same triangles"): every face with a limit surface tessellated once on the CPU at the frame's
//! uniform level (the exact limit, [`crate::subdiv::eval::LimitEvaluator`], on the grid a whole
//! uniform patch of that level has: 2 level² triangles per quad or sub-quad), uploaded as one
//! static vertex + index buffer and drawn by the plain vertex/fragment pipeline of the CPU path
//! (`glsl/surface/mesh.vert`), timed by its timestamps in a frame of its own. No tessellation
//! stage runs: what the tessellated frame costs beyond this is the price of tessellating on the
//! GPU every frame.

use super::bench::timed_frames;
use super::fallback::FallbackMesh;
use super::offscreen::{OffscreenDesc, OffscreenSession, CPU_PATH_LABEL};
use super::plan::{cpu_faces, plan_passes};
use super::renderer::RenderDesc;
use super::schemes::{PlanOptions, SchemeLimits};
use super::surface::SurfaceData;
use crate::gpu::Context;
use crate::mesh::ControlMesh;
use crate::{Error, Result};

/// The static triangles of a mesh at one uniform level.
pub struct StaticDraw {
    surface: SurfaceData,
}

impl StaticDraw {
    /// Every face of `mesh` with a limit surface (holes skipped, as every scheme skips them) at
    /// uniform level `level` (at least 1).
    pub fn new(mesh: &ControlMesh, level: u32) -> Result<StaticDraw> {
        let opts = PlanOptions::new(SchemeLimits::NO_DEVICE);
        let mut surface = plan_passes(mesh, &[], &opts)?;
        surface.fallback = cpu_faces(mesh, &surface.fallback_faces, level.max(1))?;
        Ok(StaticDraw { surface })
    }

    /// Triangles drawn.
    pub fn triangles(&self) -> usize {
        self.surface.fallback.indices.len() / 3
    }

    /// The triangles (positions, normals, indices).
    pub fn mesh(&self) -> &FallbackMesh {
        &self.surface.fallback
    }

    /// The surface to draw: no patch pass, every face on the static path.
    pub fn surface(&self) -> &SurfaceData {
        &self.surface
    }

    /// Median GPU milliseconds of drawing the triangles over `frames` frames (after one warm-up
    /// frame) with `render`'s raster state into a target of `desc`.
    pub fn time(
        &self,
        ctx: &Context,
        render: &RenderDesc,
        desc: &OffscreenDesc,
        frames: u32,
    ) -> Result<f64> {
        if frames == 0 {
            return Err(Error::Invalid("static draw: at least one frame".into()));
        }
        let mut session = OffscreenSession::new(ctx, &self.surface, render, desc, true)?;
        timed_frames(&mut session, frames, CPU_PATH_LABEL)
    }
}
