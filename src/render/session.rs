//! A Gregory-only harness over [`OffscreenSession`]: the Gregory patches of a mesh with either
//! GPU variant, optionally with its regular B-spline patches, no CPU path. The harness of the
//! Gregory tests (GPU == CPU, watertightness, variant against variant) and of the per-pass
//! timings `tessera bench --variants` reports.

use glam::DVec3;
use image::RgbaImage;

use super::camera::{Camera, CameraSpec};
use super::offscreen::{OffscreenDesc, OffscreenSession};
use super::pass::CaptureRecord;
use super::plan::plan_passes;
use super::renderer::RenderDesc;
use super::schemes::{
    bspline, gregory_stencil, gregory_vs, PatchScheme, PlanOptions, SchemeLimits,
};
use crate::gpu::{Context, PipelineStats};
use crate::mesh::ControlMesh;
use crate::{Error, Result};

/// Which GPU construction builds the Gregory patches.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GregoryVariant {
    /// §4.3: one-ring patch primitive, precomputed stencils.
    Stencil,
    /// §4.1-4.2: per-vertex VS + per-corner TCS.
    TwoStage,
}

impl GregoryVariant {
    /// The variant's pass.
    pub fn pass(self) -> &'static dyn PatchScheme {
        match self {
            GregoryVariant::Stencil => &gregory_stencil::GREGORY_STENCIL,
            GregoryVariant::TwoStage => &gregory_vs::GREGORY_VS,
        }
    }
}

/// What a [`GregorySession`] draws.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SessionOptions {
    /// Construction variant.
    pub variant: GregoryVariant,
    /// Also draw the regular faces as B-spline patches.
    pub with_regular: bool,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
}

/// Timings and statistics of one frame.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GregoryFrameReport {
    /// GPU milliseconds of the Gregory pass (construction + evaluation).
    pub gregory_ms: f64,
    /// GPU milliseconds of the regular B-spline pass (0 without regular patches).
    pub regular_ms: f64,
    /// Pipeline statistics of the Gregory pass.
    pub gregory_stats: PipelineStats,
}

/// Offscreen target, Gregory patches (and optionally the regular patches) of one mesh.
pub struct GregorySession {
    session: OffscreenSession,
    gregory_faces: Vec<u32>,
    regular_count: usize,
    rejected: Vec<(u32, String)>,
    gregory_label: &'static str,
}

impl GregorySession {
    /// Plans the faces of `mesh` (regular / Gregory / refused by the variant), uploads them and
    /// frames the control mesh (camera `auto`).
    pub fn new(
        ctx: &Context,
        mesh: &ControlMesh,
        desc: &RenderDesc,
        opts: &SessionOptions,
    ) -> Result<GregorySession> {
        let limits = SchemeLimits::from_context(ctx);
        if opts.variant == GregoryVariant::TwoStage
            && gregory_vs::VsBudget::for_limits(&limits).is_none()
        {
            return Err(Error::Invalid(
                "the device cannot run the two-stage Gregory variant".into(),
            ));
        }
        let gregory = opts.variant.pass();
        // Regular faces go to the B-spline pass (dropped when not drawn), so the Gregory pass is
        // offered the irregular faces only.
        let mut surface = plan_passes(
            mesh,
            &[&bspline::BSPLINE, gregory],
            &PlanOptions::new(limits),
        )?;
        if !opts.with_regular {
            surface
                .parts
                .retain(|p| p.pass_name() != bspline::BSPLINE.name());
        }
        surface.fallback_faces.clear();
        let gregory_faces = surface
            .part(gregory.name())
            .map(|p| p.faces().to_vec())
            .unwrap_or_default();
        if gregory_faces.is_empty() {
            return Err(Error::Invalid(format!(
                "no face can be drawn by the {:?} Gregory variant",
                opts.variant
            )));
        }
        let rejected = surface
            .refusals
            .iter()
            .filter(|r| {
                r.pass == gregory.name() && matches!(mesh.face_size(r.face as usize), 3 | 4)
            })
            .map(|r| (r.face, r.to_string()))
            .collect();
        let regular_count = surface.regular_patches().len();
        let off = OffscreenDesc {
            width: opts.width,
            height: opts.height,
            ..OffscreenDesc::default()
        };
        let mut session = OffscreenSession::new(ctx, &surface, desc, &off, true)?;
        let (lo, hi) = mesh.bounding_box();
        session.set_camera(Camera::frame(
            CameraSpec::Auto,
            lo,
            hi,
            f64::from(opts.width) / f64::from(opts.height),
        ));
        let gregory_label = session.renderer().passes().last().map_or("", |p| p.label());
        Ok(GregorySession {
            session,
            gregory_faces,
            regular_count,
            rejected,
            gregory_label,
        })
    }

    /// Faces drawn as Gregory patches, in draw order.
    pub fn gregory_faces(&self) -> &[u32] {
        &self.gregory_faces
    }

    /// Number of regular B-spline patches drawn.
    pub fn regular_count(&self) -> usize {
        self.regular_count
    }

    /// Candidate Gregory faces the variant does not draw, with the reason.
    pub fn rejected(&self) -> &[(u32, String)] {
        &self.rejected
    }

    /// Animation: new control positions (same topology); stencils and tables stay.
    pub fn update_positions(&mut self, positions: &[DVec3]) -> Result<()> {
        self.session
            .renderer_mut()
            .update_positions(positions, None)
    }

    /// Renders one frame, waits, and returns the per-pass GPU times and statistics.
    pub fn frame(&mut self) -> Result<GregoryFrameReport> {
        let r = self
            .session
            .frame()?
            .ok_or_else(|| Error::Invalid("no timings returned".into()))?;
        Ok(GregoryFrameReport {
            gregory_ms: r.ms(self.gregory_label),
            regular_ms: r.ms("bspline patches"),
            gregory_stats: r.stats(self.gregory_label),
        })
    }

    /// The last frame's image.
    pub fn image(&self) -> Result<RgbaImage> {
        self.session.image()
    }

    /// The last frame's TES capture, in draw order (regular patches first when drawn).
    pub fn capture(&self) -> Result<Vec<CaptureRecord>> {
        self.session.capture()
    }
}
