//! A self-contained offscreen session that draws the Gregory patches of a mesh with either GPU
//! variant, optionally together with its regular B-spline patches (no CPU fallback): the
//! harness of the stencil tests (GPU == CPU, watertightness, variant against variant) and of
//! the per-pass timings `tessera bench` reports. It owns the buffers a surface renderer shares
//! with the Gregory pass (frame uniforms, vertex limits, capture).

use ash::vk;
use glam::DVec3;
use image::RgbaImage;

use super::gpu::{StencilPatches, StencilPlan};
use crate::gpu::{
    Buffer, Context, GpuTimer, MemoryLocation, PipelineStats, RenderTarget, StatsQuery,
};
use crate::mesh::ControlMesh;
use crate::patch::gregory::gregory_faces;
use crate::render::camera::{Camera, CameraSpec};
use crate::render::gregory_layout::{vertex_frames, GregoryLayout};
use crate::render::gregory_vs::{select_faces, vs_budget, GregoryVsPatches, SharedBuffers};
use crate::render::layout::{vec4_bytes, BSplinePatch};
use crate::render::renderer::{CaptureRecord, RenderDesc, SurfaceRenderer};
use crate::render::scene::SurfacePlan;
use crate::render::settings::{FrameUniforms, FRAME_UNIFORM_BYTES};
use crate::render::surface::SurfaceData;
use crate::topology::Topology;
use crate::{Error, Result};

/// Which GPU construction builds the Gregory patches.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GregoryVariant {
    /// §4.3: one-ring patch primitive, precomputed stencils (this module).
    Stencil,
    /// §4.1-4.2: per-vertex VS + per-corner TCS (`render::gregory_vs`).
    TwoStage,
}

/// What a [`GregorySession`] draws.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SessionOptions {
    /// Construction variant.
    pub variant: GregoryVariant,
    /// Also draw the regular faces as B-spline patches (the regular pipeline of
    /// [`SurfaceRenderer`]), sharing the vertex limit positions with the Gregory pass.
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

enum Patches {
    Stencil(StencilPatches),
    TwoStage(GregoryVsPatches),
}

impl Patches {
    fn record(&self, cmd: vk::CommandBuffer) {
        match self {
            Patches::Stencil(p) => p.record(cmd),
            Patches::TwoStage(p) => p.record(cmd),
        }
    }

    fn layout(&self) -> &GregoryLayout {
        match self {
            Patches::Stencil(p) => p.layout(),
            Patches::TwoStage(p) => p.layout(),
        }
    }

    fn update(&mut self, positions: &[DVec3], normals: &[DVec3]) -> Result<()> {
        match self {
            Patches::Stencil(p) => p.update_positions(positions, normals),
            Patches::TwoStage(p) => p.update_positions(positions, normals),
        }
    }
}

/// Offscreen target, Gregory patches (and optionally the regular patches) of one mesh.
pub struct GregorySession {
    ctx: Context,
    topo: Topology,
    target: RenderTarget,
    patches: Patches,
    regular: Option<SurfaceRenderer>,
    regular_patches: Vec<BSplinePatch>,
    rejected: Vec<(u32, String)>,
    desc: RenderDesc,
    camera: Camera,
    size: (u32, u32),
    limits: Buffer,
    frame: Buffer,
    capture: Buffer,
    timer: GpuTimer,
    stats: StatsQuery,
}

/// Capture header bytes (count, capacity, 2 pad words) and record bytes (capture.glsl).
const CAPTURE_HEADER: usize = 16;
const CAPTURE_RECORD: usize = 36;

fn host_buffer(
    ctx: &Context,
    bytes: &[u8],
    usage: vk::BufferUsageFlags,
    loc: MemoryLocation,
    name: &str,
) -> Result<Buffer> {
    let mut b = Buffer::new(ctx, bytes.len().max(64) as u64, usage, loc, name)?;
    b.write(0, bytes)?;
    Ok(b)
}

impl GregorySession {
    /// Plans the faces of `mesh` (regular / Gregory / rejected by the variant), uploads them and
    /// frames the control mesh (camera `auto`).
    pub fn new(
        ctx: &Context,
        mesh: &ControlMesh,
        desc: &RenderDesc,
        opts: &SessionOptions,
    ) -> Result<GregorySession> {
        ctx.require(&[crate::gpu::Feature::TessellationShader])?;
        let topo = Topology::new(mesh)?;
        let positions = mesh.positions();
        let target = RenderTarget::new(ctx, opts.width, opts.height, 1)?;
        let candidates = gregory_faces(&topo);
        let regular_patches = if opts.with_regular {
            SurfacePlan::new(&topo).patches
        } else {
            Vec::new()
        };
        enum Planned {
            Stencil(StencilPlan),
            TwoStage(GregoryLayout),
        }
        let (planned, rejected) = match opts.variant {
            GregoryVariant::Stencil => {
                let plan = StencilPlan::new(
                    &topo,
                    &candidates,
                    ctx.info().limits.max_tessellation_patch_size,
                );
                let rejected = plan
                    .table
                    .rejected
                    .iter()
                    .map(|r| (r.face, r.reason.clone()))
                    .collect();
                (Planned::Stencil(plan), rejected)
            }
            GregoryVariant::TwoStage => {
                let budget = vs_budget(ctx).ok_or_else(|| {
                    Error::Invalid("the device cannot run the two-stage Gregory variant".into())
                })?;
                let (ok, rejected) = select_faces(&topo, &candidates, budget);
                (Planned::TwoStage(GregoryLayout::new(&topo, &ok)), rejected)
            }
        };
        let layout = match &planned {
            Planned::Stencil(p) => &p.layout,
            Planned::TwoStage(l) => l,
        };
        if layout.faces.is_empty() {
            return Err(Error::Invalid(format!(
                "no face can be drawn by the {:?} Gregory variant",
                opts.variant
            )));
        }
        let (lim, nrm) = vertex_frames(&topo, positions, &regular_patches, layout);
        let loc = MemoryLocation::CpuToGpu;
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let limits = host_buffer(ctx, &vec4_bytes(&lim), storage, loc, "vertex limits")?;
        let frame = host_buffer(
            ctx,
            &[0; FRAME_UNIFORM_BYTES],
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            loc,
            "frame uniforms",
        )?;
        let capacity = desc.capture_capacity.unwrap_or(0);
        let mut cap = vec![0u8; CAPTURE_HEADER + CAPTURE_RECORD * capacity as usize];
        cap[4..8].copy_from_slice(&capacity.to_le_bytes());
        let capture = host_buffer(ctx, &cap, storage, MemoryLocation::GpuToCpu, "tes capture")?;
        let shared = SharedBuffers {
            frame: &frame,
            vertex_limits: &limits,
            capture: &capture,
        };
        let patches = match planned {
            Planned::Stencil(plan) => Patches::Stencil(StencilPatches::new(
                ctx,
                plan,
                positions,
                &nrm,
                shared,
                desc,
                target.format(),
            )?),
            Planned::TwoStage(layout) => Patches::TwoStage(GregoryVsPatches::new(
                ctx,
                &topo,
                layout,
                positions,
                &nrm,
                shared,
                desc,
                target.format(),
            )?),
        };
        let regular = if regular_patches.is_empty() {
            None
        } else {
            let surface = SurfaceData {
                positions: positions.to_vec(),
                patches: regular_patches.clone(),
                ..SurfaceData::default()
            };
            Some(SurfaceRenderer::new(ctx, &surface, desc, target.format())?)
        };
        let (lo, hi) = mesh.bounding_box();
        let camera = Camera::frame(
            CameraSpec::Auto,
            lo,
            hi,
            f64::from(opts.width) / f64::from(opts.height),
        );
        Ok(GregorySession {
            ctx: ctx.clone(),
            topo,
            target,
            patches,
            regular,
            regular_patches,
            rejected,
            desc: *desc,
            camera,
            size: (opts.width, opts.height),
            limits,
            frame,
            capture,
            timer: GpuTimer::new(ctx, 2)?,
            stats: StatsQuery::new(ctx)?,
        })
    }

    /// Faces drawn as Gregory patches, in draw order.
    pub fn gregory_faces(&self) -> &[u32] {
        &self.patches.layout().faces
    }

    /// Number of regular B-spline patches drawn.
    pub fn regular_count(&self) -> usize {
        self.regular_patches.len()
    }

    /// Candidate Gregory faces the variant does not draw, with the reason.
    pub fn rejected(&self) -> &[(u32, String)] {
        &self.rejected
    }

    /// Animation: new control positions (same topology). Per-vertex limit data, the Gregory
    /// pass's positions and the regular pass are updated; stencils and tables stay.
    pub fn update_positions(&mut self, positions: &[DVec3]) -> Result<()> {
        if positions.len() != self.topo.vertex_count() {
            return Err(Error::Invalid(format!(
                "update_positions: got {} positions, the mesh has {} vertices",
                positions.len(),
                self.topo.vertex_count()
            )));
        }
        let (lim, nrm) = vertex_frames(
            &self.topo,
            positions,
            &self.regular_patches,
            self.patches.layout(),
        );
        self.limits.write(0, &vec4_bytes(&lim))?;
        if let Some(r) = self.regular.as_mut() {
            r.update_positions(positions, None)?;
        }
        self.patches.update(positions, &nrm)
    }

    /// Renders one frame, waits, and returns the per-pass GPU times and statistics.
    pub fn frame(&mut self) -> Result<GregoryFrameReport> {
        let uniforms = FrameUniforms {
            view_proj: self.camera.view_proj(),
            eye: self.camera.eye.as_vec3(),
            viewport: [self.size.0 as f32, self.size.1 as f32],
            tess: self.desc.tess,
            max_level: self.ctx.info().limits.max_tessellation_generation_level as f32,
            light_dir: (self.camera.eye - self.camera.target).normalize().as_vec3(),
            color_by: self.desc.color_by,
        };
        self.frame.write(0, &uniforms.to_bytes())?;
        if let Some(r) = self.regular.as_mut() {
            r.set_frame(&uniforms)?;
            if self.desc.capture_capacity.is_some() {
                r.reset_capture()?;
            }
        }
        if self.desc.capture_capacity.is_some() {
            self.capture.write(0, &[0u32])?;
        }
        let (target, patches, regular) = (&self.target, &self.patches, &self.regular);
        let timer = &mut self.timer;
        let stats = &self.stats;
        self.ctx.submit_once(|dev, cmd| {
            timer.reset(cmd);
            stats.reset(cmd);
            target.begin(dev, cmd, [0.02, 0.025, 0.035, 1.0]);
            let i = timer.begin(cmd, "gregory patches")?;
            stats.begin(cmd);
            patches.record(cmd);
            stats.end(cmd);
            timer.end(cmd, i)?;
            if let Some(r) = regular {
                let i = timer.begin(cmd, "regular patches")?;
                r.record_patches(cmd);
                timer.end(cmd, i)?;
            }
            target.end(dev, cmd);
            crate::gpu::tes_writes_to_host(dev, cmd);
            Ok(())
        })?;
        let passes = self.timer.results()?;
        let ms = |label: &str| {
            passes
                .iter()
                .find(|(l, _)| l == label)
                .map_or(0.0, |(_, ms)| *ms)
        };
        Ok(GregoryFrameReport {
            gregory_ms: ms("gregory patches"),
            regular_ms: ms("regular patches"),
            gregory_stats: self.stats.results()?,
        })
    }

    /// The last frame's image.
    pub fn image(&self) -> Result<RgbaImage> {
        self.target.read_rgba(&self.ctx)
    }

    /// The last frame's TES capture: Gregory patches, then regular patches.
    pub fn capture(&self) -> Result<Vec<CaptureRecord>> {
        let Some(capacity) = self.desc.capture_capacity else {
            return Err(Error::Invalid(
                "capture is not enabled in RenderDesc".into(),
            ));
        };
        let words: Vec<u32> = self.capture.read()?;
        let count = words[0];
        if count > capacity {
            return Err(Error::Invalid(format!(
                "TES capture overflow: {count} invocations, capacity {capacity}"
            )));
        }
        let f = f32::from_bits;
        let mut out: Vec<CaptureRecord> = (0..count as usize)
            .map(|k| {
                let r = &words[4 + 9 * k..4 + 9 * k + 9];
                CaptureRecord {
                    face: r[0],
                    u: f(r[1]),
                    v: f(r[2]),
                    position: [f(r[3]), f(r[4]), f(r[5])],
                    normal: [f(r[6]), f(r[7]), f(r[8])],
                }
            })
            .collect();
        if let Some(r) = &self.regular {
            out.extend(r.read_capture()?);
        }
        Ok(out)
    }
}
