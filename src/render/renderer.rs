//! [`SurfaceRenderer`]: GPU resources of one surface and the draw calls, recorded into the
//! caller's command buffer inside its render pass.

use ash::vk;
use glam::DVec3;

use super::fallback::FallbackMesh;
use super::gregory_pass::{surface_vertex_frames, GregoryPass, GregoryPassPlan};
use super::gregory_vs::SharedBuffers;
use super::layout::{self, BSplinePatch};
use super::patch_pipeline::{patch_push_constants, position_input, push_patch_chunk};
use super::settings::{ColorBy, FrameUniforms, Spacing, TessSettings, FRAME_UNIFORM_BYTES};
use super::surface::SurfaceData;
use crate::gpu::{
    patch_draw_chunks, Buffer, BufferBinding, Context, DescriptorBinding, DescriptorKind,
    DescriptorPool, GraphicsPipelineDesc, MemoryLocation, Pipeline, TargetFormat, VertexAttribute,
    VertexBinding,
};
use crate::{Error, Result};

/// Bytes of one capture record (`CaptureRecord` in `glsl/common/capture.glsl`).
pub const CAPTURE_RECORD_BYTES: usize = 36;
/// Bytes before the first capture record (count, capacity, two pad words).
pub const CAPTURE_HEADER_BYTES: usize = 16;
/// Bytes per fallback vertex: position (3 f32), normal (3 f32), class (u32).
const FALLBACK_VERTEX_BYTES: usize = 28;

/// How a surface is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderDesc {
    /// Tessellation levels, mode and spacing.
    pub tess: TessSettings,
    /// Draw triangle edges only (polygon mode LINE).
    pub wireframe: bool,
    /// Surface colouring.
    pub color_by: ColorBy,
    /// Cull back faces (closed surfaces only; open ones show both sides otherwise).
    pub cull_back_faces: bool,
    /// Record every TES invocation into the capture buffer (`Some(capacity)` in records).
    pub capture_capacity: Option<u32>,
}

impl Default for RenderDesc {
    fn default() -> Self {
        RenderDesc {
            tess: TessSettings::default(),
            wireframe: false,
            color_by: ColorBy::None,
            cull_back_faces: false,
            capture_capacity: None,
        }
    }
}

/// One captured TES invocation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CaptureRecord {
    /// Base-mesh face.
    pub face: u32,
    /// Face parameter u.
    pub u: f32,
    /// Face parameter v.
    pub v: f32,
    /// Position.
    pub position: [f32; 3],
    /// Unit normal.
    pub normal: [f32; 3],
}

/// GPU resources of one surface plus its pipelines for one render-target format.
pub struct SurfaceRenderer {
    ctx: Context,
    desc: RenderDesc,
    patches: Vec<BSplinePatch>,
    vertex_count: usize,
    patch_count: u32,
    split: u32,
    fallback_index_count: u32,
    positions: Buffer,
    vertex_limits: Buffer,
    vertex_normals: Buffer,
    gregory: Option<GregoryPass>,
    frame: Buffer,
    capture: Buffer,
    _patch_info: Buffer,
    patch_indices: Buffer,
    fallback_vertices: Buffer,
    fallback_indices: Buffer,
    _pool: DescriptorPool,
    set: vk::DescriptorSet,
    patch_pipeline: Pipeline,
    fallback_pipeline: Pipeline,
}

fn set_layout() -> Vec<DescriptorBinding> {
    let all = vk::ShaderStageFlags::VERTEX
        | vk::ShaderStageFlags::TESSELLATION_CONTROL
        | vk::ShaderStageFlags::TESSELLATION_EVALUATION
        | vk::ShaderStageFlags::FRAGMENT;
    let tess =
        vk::ShaderStageFlags::TESSELLATION_CONTROL | vk::ShaderStageFlags::TESSELLATION_EVALUATION;
    vec![
        DescriptorBinding {
            binding: 0,
            kind: DescriptorKind::UniformBuffer,
            stages: all,
        },
        DescriptorBinding {
            binding: 1,
            kind: DescriptorKind::StorageBuffer,
            stages: tess,
        },
        DescriptorBinding {
            binding: 2,
            kind: DescriptorKind::StorageBuffer,
            stages: tess,
        },
        DescriptorBinding {
            binding: 3,
            kind: DescriptorKind::StorageBuffer,
            stages: vk::ShaderStageFlags::TESSELLATION_EVALUATION,
        },
        // Vertex limit normals (patch corners; glsl/common/gregory.glsl).
        DescriptorBinding {
            binding: 9,
            kind: DescriptorKind::StorageBuffer,
            stages: vk::ShaderStageFlags::TESSELLATION_EVALUATION,
        },
    ]
}

/// Pads empty data to a minimal non-empty buffer (shaders never read the padding).
fn non_empty(mut bytes: Vec<u8>) -> Vec<u8> {
    if bytes.len() < 64 {
        bytes.resize(64, 0);
    }
    bytes
}

fn host_buffer(
    ctx: &Context,
    bytes: &[u8],
    usage: vk::BufferUsageFlags,
    name: &str,
) -> Result<Buffer> {
    let mut b = Buffer::new(
        ctx,
        bytes.len() as u64,
        usage,
        MemoryLocation::CpuToGpu,
        name,
    )?;
    b.write(0, bytes)?;
    Ok(b)
}

fn fallback_vertex_bytes(mesh: &FallbackMesh) -> Vec<u8> {
    let mut out = Vec::with_capacity(mesh.positions.len() * FALLBACK_VERTEX_BYTES);
    for ((p, n), c) in mesh.positions.iter().zip(&mesh.normals).zip(&mesh.classes) {
        for x in p
            .as_vec3()
            .to_array()
            .into_iter()
            .chain(n.as_vec3().to_array())
        {
            out.extend_from_slice(&x.to_le_bytes());
        }
        out.extend_from_slice(&c.to_le_bytes());
    }
    out
}

impl SurfaceRenderer {
    /// Uploads `surface` and creates the pipelines for render targets of format `target`.
    pub fn new(
        ctx: &Context,
        surface: &SurfaceData,
        desc: &RenderDesc,
        target: TargetFormat,
    ) -> Result<SurfaceRenderer> {
        surface.validate()?;
        let mut desc_local = *desc;
        let (tess, note) = effective_tess(surface, &desc.tess);
        if let Some(n) = note {
            eprintln!("note: {n}");
        }
        desc_local.tess = tess;
        let desc = &desc_local;
        if desc.wireframe {
            ctx.require(&[crate::gpu::Feature::FillModeNonSolid])?;
        }
        if !surface.patches.is_empty() || surface.gregory.is_some() {
            ctx.require(&[crate::gpu::Feature::TessellationShader])?;
        }
        if desc.capture_capacity.is_some() {
            ctx.require(&[crate::gpu::Feature::VertexPipelineStoresAndAtomics])?;
        }
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let plan = surface
            .gregory
            .as_ref()
            .map(|g| GregoryPassPlan::new(ctx, g));
        let (limits, normals) =
            surface_vertex_frames(&surface.positions, &surface.patches, plan.as_ref());
        let positions = host_buffer(
            ctx,
            &non_empty(layout::vec3_bytes(&surface.positions)),
            vk::BufferUsageFlags::VERTEX_BUFFER,
            "control positions",
        )?;
        let vertex_limits = host_buffer(
            ctx,
            &non_empty(layout::vec4_bytes(&limits)),
            storage,
            "vertex limit positions",
        )?;
        let vertex_normals = host_buffer(
            ctx,
            &non_empty(layout::vec4_bytes(&normals)),
            storage,
            "vertex limit normals",
        )?;
        let frame = host_buffer(
            ctx,
            &[0u8; FRAME_UNIFORM_BYTES],
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            "frame uniforms",
        )?;
        let capacity = desc.capture_capacity.unwrap_or(0);
        let mut capture_bytes =
            vec![0u8; CAPTURE_HEADER_BYTES + CAPTURE_RECORD_BYTES * capacity as usize];
        capture_bytes[4..8].copy_from_slice(&capacity.to_le_bytes());
        let capture = Buffer::new(
            ctx,
            capture_bytes.len() as u64,
            storage,
            MemoryLocation::GpuToCpu,
            "tes capture",
        )?;
        let mut capture = capture;
        capture.write(0, &capture_bytes)?;
        let patch_info = ctx.upload_buffer(
            &non_empty(layout::patch_info_bytes(&surface.patches)),
            storage,
            "patch info",
        )?;
        let patch_indices = ctx.upload_buffer(
            &non_empty(layout::patch_index_bytes(&surface.patches)),
            vk::BufferUsageFlags::INDEX_BUFFER,
            "patch control-vertex indices",
        )?;
        let fallback_vertices = host_buffer(
            ctx,
            &non_empty(fallback_vertex_bytes(&surface.fallback)),
            vk::BufferUsageFlags::VERTEX_BUFFER,
            "cpu-evaluated vertices",
        )?;
        let fallback_index_bytes: Vec<u8> = surface
            .fallback
            .indices
            .iter()
            .flat_map(|i| i.to_le_bytes())
            .collect();
        let fallback_indices = ctx.upload_buffer(
            &non_empty(fallback_index_bytes),
            vk::BufferUsageFlags::INDEX_BUFFER,
            "cpu-evaluated indices",
        )?;

        let (patch_pipeline, fallback_pipeline) = Self::pipelines(ctx, desc, target)?;
        let gregory = match plan {
            Some(plan) => Some(GregoryPass::new(
                ctx,
                plan,
                &surface.positions,
                &normals,
                SharedBuffers {
                    frame: &frame,
                    vertex_limits: &vertex_limits,
                    capture: &capture,
                },
                desc,
                target,
            )?),
            None => None,
        };
        let pool = DescriptorPool::new(ctx, 1, 4, 1)?;
        let set = pool.allocate(patch_pipeline.set_layouts[0])?;
        ctx.write_buffer_descriptors(
            set,
            &[
                BufferBinding {
                    binding: 0,
                    kind: DescriptorKind::UniformBuffer,
                    buffer: &frame,
                },
                BufferBinding {
                    binding: 1,
                    kind: DescriptorKind::StorageBuffer,
                    buffer: &patch_info,
                },
                BufferBinding {
                    binding: 2,
                    kind: DescriptorKind::StorageBuffer,
                    buffer: &vertex_limits,
                },
                BufferBinding {
                    binding: 3,
                    kind: DescriptorKind::StorageBuffer,
                    buffer: &capture,
                },
                BufferBinding {
                    binding: 9,
                    kind: DescriptorKind::StorageBuffer,
                    buffer: &vertex_normals,
                },
            ],
        );
        Ok(SurfaceRenderer {
            ctx: ctx.clone(),
            desc: *desc,
            patches: surface.patches.clone(),
            vertex_count: surface.positions.len(),
            split: desc.tess.split(),
            patch_count: surface.patches.len() as u32,
            fallback_index_count: surface.fallback.indices.len() as u32,
            positions,
            vertex_limits,
            vertex_normals,
            gregory,
            frame,
            capture,
            _patch_info: patch_info,
            patch_indices,
            fallback_vertices,
            fallback_indices,
            _pool: pool,
            set,
            patch_pipeline,
            fallback_pipeline,
        })
    }

    fn pipelines(
        ctx: &Context,
        desc: &RenderDesc,
        target: TargetFormat,
    ) -> Result<(Pipeline, Pipeline)> {
        let (polygon_mode, cull_mode) = (desc.polygon_mode(), desc.cull_mode());
        let tese = desc.tese_name("patch_bspline");
        let (vertex_bindings, vertex_attributes) = position_input();
        let patch = GraphicsPipelineDesc {
            label: format!("bspline patches ({tese})"),
            vertex: "patch_bspline.vert".into(),
            tess_control: Some("patch_bspline.tesc".into()),
            tess_eval: Some(tese),
            fragment: "shade.frag".into(),
            vertex_bindings,
            vertex_attributes,
            topology: vk::PrimitiveTopology::PATCH_LIST,
            patch_control_points: 16,
            polygon_mode,
            cull_mode,
            front_face: vk::FrontFace::COUNTER_CLOCKWISE,
            depth_test: true,
            depth_write: true,
            set_layouts: vec![set_layout()],
            push_constants: Some(patch_push_constants()),
        };
        let fallback = GraphicsPipelineDesc {
            label: "cpu-evaluated triangles".into(),
            vertex: "mesh.vert".into(),
            tess_control: None,
            tess_eval: None,
            fragment: "shade.frag".into(),
            vertex_bindings: vec![VertexBinding {
                binding: 0,
                stride: FALLBACK_VERTEX_BYTES as u32,
                per_instance: false,
            }],
            vertex_attributes: vec![
                VertexAttribute {
                    location: 0,
                    binding: 0,
                    format: vk::Format::R32G32B32_SFLOAT,
                    offset: 0,
                },
                VertexAttribute {
                    location: 1,
                    binding: 0,
                    format: vk::Format::R32G32B32_SFLOAT,
                    offset: 12,
                },
                VertexAttribute {
                    location: 2,
                    binding: 0,
                    format: vk::Format::R32_UINT,
                    offset: 24,
                },
            ],
            topology: vk::PrimitiveTopology::TRIANGLE_LIST,
            patch_control_points: 0,
            polygon_mode,
            cull_mode,
            front_face: vk::FrontFace::COUNTER_CLOCKWISE,
            depth_test: true,
            depth_write: true,
            set_layouts: vec![set_layout()],
            push_constants: None,
        };
        let p = ctx.graphics_pipeline_for(&patch, target)?;
        let f = ctx.graphics_pipeline_for(&fallback, target)?;
        Ok((p, f))
    }

    /// The render description.
    pub fn desc(&self) -> &RenderDesc {
        &self.desc
    }

    /// Number of regular patches drawn through the tessellation stages.
    pub fn patch_count(&self) -> u32 {
        self.patch_count
    }

    /// Number of Gregory patches drawn through the tessellation stages.
    pub fn gregory_patch_count(&self) -> u32 {
        self.gregory.as_ref().map_or(0, |g| g.patch_count())
    }

    /// Number of CPU-evaluated triangles.
    pub fn fallback_triangle_count(&self) -> u32 {
        self.fallback_index_count / 3
    }

    /// Animation: new control positions (same topology). The vertex limit positions the
    /// tessellation factors and patch corners use are recomputed. `fallback`, when given,
    /// replaces the CPU-evaluated triangles (same count). Call only while no submitted frame
    /// that uses this renderer is still executing.
    pub fn update_positions(
        &mut self,
        positions: &[DVec3],
        fallback: Option<&FallbackMesh>,
    ) -> Result<()> {
        if positions.len() != self.vertex_count {
            return Err(Error::Invalid(format!(
                "update_positions: got {} positions, the surface has {} vertices",
                positions.len(),
                self.vertex_count
            )));
        }
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(Error::Invalid(format!(
                "update_positions: vertex {i} has a non-finite coordinate"
            )));
        }
        self.positions.write(0, &layout::vec3_bytes(positions))?;
        let (limits, normals) = match &self.gregory {
            Some(g) => g.vertex_frames(positions, &self.patches),
            None => surface_vertex_frames(positions, &self.patches, None),
        };
        self.vertex_limits.write(0, &layout::vec4_bytes(&limits))?;
        self.vertex_normals
            .write(0, &layout::vec4_bytes(&normals))?;
        if let Some(g) = &mut self.gregory {
            g.update_positions(positions, &normals)?;
        }
        if let Some(mesh) = fallback {
            if mesh.indices.len() as u32 != self.fallback_index_count {
                return Err(Error::Invalid(format!(
                    "update_positions: fallback mesh has {} indices, expected {}",
                    mesh.indices.len(),
                    self.fallback_index_count
                )));
            }
            let vb = fallback_vertex_bytes(mesh);
            if vb.len() as u64 > self.fallback_vertices.size() {
                return Err(Error::Invalid(
                    "update_positions: fallback mesh has more vertices than before".into(),
                ));
            }
            self.fallback_vertices.write(0, &vb)?;
        }
        Ok(())
    }

    /// Writes the frame uniforms. Call before submitting the command buffer that [`Self::record`]
    /// filled, while no earlier frame of this renderer is still executing.
    pub fn set_frame(&mut self, frame: &FrameUniforms) -> Result<()> {
        let mut f = *frame;
        f.max_level = f
            .max_level
            .min(self.ctx.info().limits.max_tessellation_generation_level as f32)
            .max(1.0);
        self.frame.write(0, &f.to_bytes())
    }

    /// Records the tessellated draws (inside the caller's render pass): regular patches, then
    /// the Gregory patches.
    pub fn record_patches(&self, cmd: vk::CommandBuffer) {
        self.record_regular(cmd);
        if let Some(g) = &self.gregory {
            g.record(cmd);
        }
    }

    /// Records the regular-patch draw (inside the caller's render pass).
    pub fn record_regular(&self, cmd: vk::CommandBuffer) {
        if self.patch_count == 0 {
            return;
        }
        let dev = self.ctx.device();
        // SAFETY: cmd is recording inside a render pass compatible with the pipeline's format;
        // every bound resource lives as long as self.
        unsafe {
            dev.cmd_bind_pipeline(
                cmd,
                vk::PipelineBindPoint::GRAPHICS,
                self.patch_pipeline.raw,
            );
            dev.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::GRAPHICS,
                self.patch_pipeline.layout,
                0,
                &[self.set],
                &[],
            );
            dev.cmd_bind_vertex_buffers(cmd, 0, &[self.positions.raw()], &[0]);
            dev.cmd_bind_index_buffer(cmd, self.patch_indices.raw(), 0, vk::IndexType::UINT32);
            // Mesa 22.3 lavapipe gives wrong control points to patches past the first 64
            // sixteen-point patches of one indexed draw (gpu::draw); gl_PrimitiveID restarts per
            // draw, so the chunk's first patch index is a push constant.
            let split = self.split;
            for (base, n) in patch_draw_chunks(self.patch_count, 16, true) {
                for sub in 0..split * split {
                    push_patch_chunk(dev, cmd, self.patch_pipeline.layout, base, sub, split);
                    dev.cmd_draw_indexed(cmd, n * 16, 1, base * 16, 0, 0);
                }
            }
        }
    }

    /// Records the CPU-evaluated triangles (inside the caller's render pass).
    pub fn record_fallback(&self, cmd: vk::CommandBuffer) {
        if self.fallback_index_count == 0 {
            return;
        }
        let dev = self.ctx.device();
        // SAFETY: as in record_patches.
        unsafe {
            dev.cmd_bind_pipeline(
                cmd,
                vk::PipelineBindPoint::GRAPHICS,
                self.fallback_pipeline.raw,
            );
            dev.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::GRAPHICS,
                self.fallback_pipeline.layout,
                0,
                &[self.set],
                &[],
            );
            dev.cmd_bind_vertex_buffers(cmd, 0, &[self.fallback_vertices.raw()], &[0]);
            dev.cmd_bind_index_buffer(cmd, self.fallback_indices.raw(), 0, vk::IndexType::UINT32);
            dev.cmd_draw_indexed(cmd, self.fallback_index_count, 1, 0, 0, 0);
        }
    }

    /// Records everything (patches, then CPU-evaluated triangles).
    pub fn record(&self, cmd: vk::CommandBuffer) {
        self.record_patches(cmd);
        self.record_fallback(cmd);
    }

    /// Resets the capture counter (host write; call between frames, before submitting).
    pub fn reset_capture(&mut self) -> Result<()> {
        self.capture.write(0, &[0u32])
    }

    /// Reads the captured TES invocations of the last finished frame. Errors if the capture
    /// buffer overflowed (more invocations than its capacity) or capture is off.
    pub fn read_capture(&self) -> Result<Vec<CaptureRecord>> {
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
        let f = |w: u32| f32::from_bits(w);
        let recs = (0..count as usize)
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
        Ok(recs)
    }
}

/// The tessellation settings a [`SurfaceRenderer`] actually uses for `surface` (and a note when
/// they differ from `tess`): the two-stage Gregory variant splits patches from level 15 on (its
/// pass jumps ~13x in cost at (sub-)patch levels >= 15 on Mesa 22.3 lavapipe: catmark_car, 460
/// Gregory quads, level 14 71 ms, 15 941 ms; the stencil variant 63 / 72 ms); with fractional
/// spacing and Gregory triangles nothing is split (sub-patch edges cannot meet a whole triangle's
/// edge point for point). Size capture buffers with it ([`capture_capacity_for`]).
pub fn effective_tess(
    surface: &SurfaceData,
    tess: &TessSettings,
) -> (TessSettings, Option<&'static str>) {
    let mut t = *tess;
    let mut note = None;
    if surface
        .gregory
        .as_ref()
        .is_some_and(|g| g.scheme == super::scheme::Scheme::GregoryVs)
        && t.max_patch_level > 14.0
    {
        t.max_patch_level = 14.0;
    }
    let has_triangles = surface
        .gregory
        .as_ref()
        .is_some_and(|g| g.faces.iter().any(|&f| g.topology.face_size(f) == 3));
    if has_triangles && t.spacing != Spacing::Equal && t.split() > 1 {
        note = Some(
            "fractional spacing with Gregory triangles: patches are not split into sub-patches \
             (--max-patch-level ignored)",
        );
        t.max_patch_level = f32::INFINITY;
    }
    (t, note)
}

/// Capture capacity (records) sufficient for `tess` (uniform) over `patches` patches: per
/// (sub-)patch at most `(ceil(level / split) + 2)^2` domain points.
pub fn capture_capacity_for(patches: usize, tess: &TessSettings) -> u32 {
    let split = u64::from(tess.split());
    let sub = tess.level.max(1.0) / split as f32;
    let n = (sub.ceil() as u64) + if tess.spacing == Spacing::Equal { 1 } else { 2 };
    (patches as u64 * split * split * n * n).min(u64::from(u32::MAX / 64)) as u32
}
