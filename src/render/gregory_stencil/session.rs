//! A self-contained offscreen session that draws only the stencil-variant Gregory patches of a
//! mesh (no regular patches, no fallback): the harness of the stencil tests and of timings of
//! the Gregory pass alone. It owns the buffers a surface renderer would share (frame uniforms,
//! vertex limits, capture). Edges next to regular faces are evaluated from the B-spline grid as
//! in the full renderer, even though the regular faces themselves are not drawn.

use ash::vk;
use glam::DVec3;
use image::RgbaImage;

use super::gpu::{StencilPatches, StencilPlan};
use crate::gpu::{
    Buffer, Context, GpuTimer, MemoryLocation, PipelineStats, RenderTarget, StatsQuery,
};
use crate::render::camera::{Camera, CameraSpec};
use crate::render::gregory_layout::vertex_frames;
use crate::render::gregory_vs::SharedBuffers;
use crate::render::layout::vec4_bytes;
use crate::render::renderer::{CaptureRecord, RenderDesc};
use crate::render::settings::{FrameUniforms, FRAME_UNIFORM_BYTES};
use crate::topology::Topology;
use crate::{Error, Result};

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

/// Timings and statistics of one stencil frame.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StencilFrameReport {
    /// GPU milliseconds of the Gregory pass (construction in the TCS + evaluation).
    pub gpu_ms: f64,
    /// Pipeline statistics of the pass.
    pub stats: PipelineStats,
}

/// Offscreen target + stencil patches + the buffers a renderer would share with them.
pub struct StencilSession {
    ctx: Context,
    topo: Topology,
    target: RenderTarget,
    patches: StencilPatches,
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

impl StencilSession {
    /// Builds the stencils of `faces` of `topo` and a `width x height` target framing the
    /// control mesh (camera `auto`).
    pub fn new(
        ctx: &Context,
        topo: Topology,
        positions: &[DVec3],
        faces: &[u32],
        desc: &RenderDesc,
        width: u32,
        height: u32,
    ) -> Result<StencilSession> {
        ctx.require(&[crate::gpu::Feature::TessellationShader])?;
        let target = RenderTarget::new(ctx, width, height, 1)?;
        let plan = StencilPlan::new(&topo, faces, ctx.info().limits.max_tessellation_patch_size);
        if plan.table.patches.is_empty() {
            return Err(Error::Invalid(
                "no face can be drawn by the stencil variant".into(),
            ));
        }
        let (lim, nrm) = vertex_frames(&topo, positions, &[], &plan.layout);
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
        let patches =
            StencilPatches::new(ctx, plan, positions, &nrm, shared, desc, target.format())?;
        let (lo, hi) = bbox(positions);
        let camera = Camera::frame(
            CameraSpec::Auto,
            lo,
            hi,
            f64::from(width) / f64::from(height),
        );
        Ok(StencilSession {
            ctx: ctx.clone(),
            topo,
            target,
            patches,
            desc: *desc,
            camera,
            size: (width, height),
            limits,
            frame,
            capture,
            timer: GpuTimer::new(ctx, 1)?,
            stats: StatsQuery::new(ctx)?,
        })
    }

    /// The stencil patches (table, rejected faces).
    pub fn patches(&self) -> &StencilPatches {
        &self.patches
    }

    /// Animation: new control positions, same topology. The positions, vertex limits and
    /// normals are rewritten; the stencils stay.
    pub fn update_positions(&mut self, positions: &[DVec3]) -> Result<()> {
        if positions.len() != self.topo.vertex_count() {
            return Err(Error::Invalid(format!(
                "update_positions: got {} positions, the mesh has {} vertices",
                positions.len(),
                self.topo.vertex_count()
            )));
        }
        let (lim, nrm) = vertex_frames(&self.topo, positions, &[], self.patches.layout());
        self.limits.write(0, &vec4_bytes(&lim))?;
        self.patches.update_positions(positions, &nrm)
    }

    /// Renders one frame, waits, and returns its GPU time and statistics.
    pub fn frame(&mut self) -> Result<StencilFrameReport> {
        let t = self.desc.tess;
        let uniforms = FrameUniforms {
            view_proj: self.camera.view_proj(),
            eye: self.camera.eye.as_vec3(),
            viewport: [self.size.0 as f32, self.size.1 as f32],
            tess: t,
            max_level: self.ctx.info().limits.max_tessellation_generation_level as f32,
            light_dir: (self.camera.eye - self.camera.target).normalize().as_vec3(),
            color_by: self.desc.color_by,
        };
        self.frame.write(0, &uniforms.to_bytes())?;
        if self.desc.capture_capacity.is_some() {
            self.capture.write(0, &[0u32])?;
        }
        let (target, patches) = (&self.target, &self.patches);
        let timer = &mut self.timer;
        let stats = &self.stats;
        self.ctx.submit_once(|dev, cmd| {
            timer.reset(cmd);
            stats.reset(cmd);
            target.begin(dev, cmd, [0.02, 0.025, 0.035, 1.0]);
            let i = timer.begin(cmd, "gregory stencil patches")?;
            stats.begin(cmd);
            patches.record(cmd);
            stats.end(cmd);
            timer.end(cmd, i)?;
            target.end(dev, cmd);
            let barrier = vk::MemoryBarrier::default()
                .src_access_mask(vk::AccessFlags::SHADER_WRITE)
                .dst_access_mask(vk::AccessFlags::HOST_READ);
            // SAFETY: recording outside the render pass.
            unsafe {
                dev.cmd_pipeline_barrier(
                    cmd,
                    vk::PipelineStageFlags::TESSELLATION_EVALUATION_SHADER,
                    vk::PipelineStageFlags::HOST,
                    vk::DependencyFlags::empty(),
                    &[barrier],
                    &[],
                    &[],
                );
            }
            Ok(())
        })?;
        Ok(StencilFrameReport {
            gpu_ms: self.timer.results()?.iter().map(|(_, ms)| ms).sum(),
            stats: self.stats.results()?,
        })
    }

    /// The last frame's image.
    pub fn image(&self) -> Result<RgbaImage> {
        self.target.read_rgba(&self.ctx)
    }

    /// The last frame's TES capture.
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
        Ok((0..count as usize)
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
            .collect())
    }
}

fn bbox(points: &[DVec3]) -> (DVec3, DVec3) {
    points.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    )
}
