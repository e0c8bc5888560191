//! A self-contained offscreen session that draws only the stencil-variant Gregory patches of a
//! mesh (no regular patches, no fallback): the harness of the stencil tests and of
//! `tessera bench --scheme gregory-stencil` timings of the Gregory pass alone. It fills the
//! shared descriptor set 0 itself (frame uniforms, vertex limit positions and normals, patch
//! records, control positions, capture); every edge is treated as Gregory/Gregory (flags 0).

use ash::vk;
use glam::DVec3;
use image::RgbaImage;

use super::gpu::StencilPatches;
use crate::gpu::{
    Buffer, BufferBinding, Context, DescriptorKind, DescriptorPool, GpuTimer, MemoryLocation,
    PipelineStats, RenderTarget, StatsQuery,
};
use crate::patch::gregory::{vertex_ring, GregoryVertex};
use crate::render::camera::{Camera, CameraSpec};
use crate::render::renderer::{CaptureRecord, RenderDesc};
use crate::render::settings::{FrameUniforms, FRAME_UNIFORM_BYTES};
use crate::topology::Topology;
use crate::{Error, Result};

/// Limit position and unit limit normal of interior vertex `v` (§3.2-3.3: the normal of the
/// tangent plane spanned by the limit tangents along ring edges 0 and 1).
pub fn vertex_limit_frame(topo: &Topology, positions: &[DVec3], v: u32) -> (DVec3, DVec3) {
    let g = GregoryVertex::interior(&vertex_ring(topo, positions, v));
    let n = (g.e[0] - g.p).cross(g.e[1] - g.p).normalize_or_zero();
    (g.p, n)
}

fn f32_bytes(v: impl IntoIterator<Item = f32>) -> Vec<u8> {
    v.into_iter().flat_map(|x| x.to_le_bytes()).collect()
}

fn u32_bytes(v: impl IntoIterator<Item = u32>) -> Vec<u8> {
    v.into_iter().flat_map(|x| x.to_le_bytes()).collect()
}

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

/// Offscreen target + stencil patches + their own set 0.
pub struct StencilSession {
    ctx: Context,
    topo: Topology,
    target: RenderTarget,
    patches: StencilPatches,
    desc: RenderDesc,
    camera: Camera,
    size: (u32, u32),
    positions: Buffer,
    limits: Buffer,
    normals: Buffer,
    frame: Buffer,
    capture: Buffer,
    _info: Buffer,
    _grid: Buffer,
    _dummy: Buffer,
    _pool: DescriptorPool,
    set: vk::DescriptorSet,
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
        if desc.capture_capacity.is_some() {
            ctx.require(&[crate::gpu::Feature::VertexPipelineStoresAndAtomics])?;
        }
        let target = RenderTarget::new(ctx, width, height, 1)?;
        let patches = StencilPatches::new(ctx, &topo, faces, desc, target.format())?;
        let loc = MemoryLocation::CpuToGpu;
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let pos_bytes = f32_bytes(positions.iter().flat_map(|p| p.as_vec3().to_array()));
        let positions_buf = host_buffer(
            ctx,
            &pos_bytes,
            vk::BufferUsageFlags::VERTEX_BUFFER | storage,
            loc,
            "stencil session control positions",
        )?;
        let nv = topo.vertex_count();
        let limits = host_buffer(ctx, &vec![0; nv * 16], storage, loc, "vertex limits")?;
        let normals = host_buffer(ctx, &vec![0; nv * 16], storage, loc, "vertex normals")?;
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
        let info = host_buffer(
            ctx,
            &u32_bytes(patches.table().patches.iter().flat_map(|p| {
                [
                    p.face,
                    0,
                    0,
                    0,
                    p.corners[0],
                    p.corners[1],
                    p.corners[2],
                    p.corners[3],
                ]
            })),
            storage,
            loc,
            "gregory patch info",
        )?;
        let grid = host_buffer(ctx, &[0; 64], storage, loc, "gregory grids (unused)")?;
        let dummy = host_buffer(ctx, &[0; 64], storage, loc, "regular patches (unused)")?;
        let pool = DescriptorPool::new(ctx, 1, 7, 1)?;
        let set = match patches.frame_set_layout_handle() {
            Some(layout) => pool.allocate(layout)?,
            None => {
                return Err(Error::Invalid(
                    "no face can be drawn by the stencil variant".into(),
                ))
            }
        };
        let sb = |binding, buffer| BufferBinding {
            binding,
            kind: DescriptorKind::StorageBuffer,
            buffer,
        };
        ctx.write_buffer_descriptors(
            set,
            &[
                BufferBinding {
                    binding: 0,
                    kind: DescriptorKind::UniformBuffer,
                    buffer: &frame,
                },
                sb(1, &dummy),
                sb(2, &limits),
                sb(3, &capture),
                sb(6, &info),
                sb(7, &grid),
                sb(8, &positions_buf),
                sb(9, &normals),
            ],
        );
        let (lo, hi) = bbox(positions);
        let camera = Camera::frame(
            CameraSpec::Auto,
            lo,
            hi,
            f64::from(width) / f64::from(height),
        );
        let mut s = StencilSession {
            ctx: ctx.clone(),
            topo,
            target,
            patches,
            desc: *desc,
            camera,
            size: (width, height),
            positions: positions_buf,
            limits,
            normals,
            frame,
            capture,
            _info: info,
            _grid: grid,
            _dummy: dummy,
            _pool: pool,
            set,
            timer: GpuTimer::new(ctx, 1)?,
            stats: StatsQuery::new(ctx)?,
        };
        s.write_vertex_data(positions)?;
        Ok(s)
    }

    fn write_vertex_data(&mut self, positions: &[DVec3]) -> Result<()> {
        let nv = self.topo.vertex_count();
        let mut lim = vec![0f32; nv * 4];
        let mut nrm = vec![0f32; nv * 4];
        let mut done = vec![false; nv];
        for p in &self.patches.table().patches {
            for &v in &p.corners {
                if std::mem::replace(&mut done[v as usize], true) {
                    continue;
                }
                let (l, n) = vertex_limit_frame(&self.topo, positions, v);
                let i = v as usize * 4;
                lim[i..i + 4].copy_from_slice(&l.as_vec3().extend(1.0).to_array());
                nrm[i..i + 4].copy_from_slice(&n.as_vec3().extend(0.0).to_array());
            }
        }
        self.limits.write(0, &f32_bytes(lim))?;
        self.normals.write(0, &f32_bytes(nrm))
    }

    /// The stencil patches (table, rejected faces).
    pub fn patches(&self) -> &StencilPatches {
        &self.patches
    }

    /// Animation: new control positions, same topology. Only the positions and the per-vertex
    /// limit data are rewritten; the stencils stay.
    pub fn update_positions(&mut self, positions: &[DVec3]) -> Result<()> {
        if positions.len() != self.topo.vertex_count() {
            return Err(Error::Invalid(format!(
                "update_positions: got {} positions, the mesh has {} vertices",
                positions.len(),
                self.topo.vertex_count()
            )));
        }
        let bytes = f32_bytes(positions.iter().flat_map(|p| p.as_vec3().to_array()));
        self.positions.write(0, &bytes)?;
        self.write_vertex_data(positions)
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
        let (target, patches, set, pos) =
            (&self.target, &self.patches, self.set, self.positions.raw());
        let timer = &mut self.timer;
        let stats = &self.stats;
        self.ctx.submit_once(|dev, cmd| {
            timer.reset(cmd);
            stats.reset(cmd);
            target.begin(dev, cmd, [0.02, 0.025, 0.035, 1.0]);
            let i = timer.begin(cmd, "gregory stencil patches")?;
            stats.begin(cmd);
            patches.record(cmd, set, pos);
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
