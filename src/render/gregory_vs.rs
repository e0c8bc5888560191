//! The two-stage GPU Gregory construction (`--scheme gregory-vs`, Loop et al. 2009 §4.1-4.2).
//!
//! Stage 1, the vertex shader (`glsl/gregory_vs.vert`), runs once per control vertex of the
//! Gregory faces (indexed draw: the patch primitive is the face's 3 or 4 vertices) and computes
//! from the vertex's one-ring — read from a connectivity storage buffer (the paper's Fig. 7
//! textures: [`GregoryVertexTable`]) and the dynamic positions buffer — its limit position, one
//! edge point per ring edge and the transversal vectors `r` (§3.2-3.4; at boundary, crease and
//! corner vertices the sector rules of §4.6). Stage 2, the TCS (`glsl/gregory_vs_{quad,tri}.tesc`,
//! one invocation per output control point), picks each patch's corner and edge points with the
//! per-patch ring offsets (Fig. 8) and builds the face points with eq. 6; the shared TES
//! (`glsl/patch_gregory_{quad,tri}.tese`) evaluates.
//!
//! The per-vertex results travel as vertex-shader outputs, not through a storage buffer: the
//! TCS of a patch reads exactly its own corners' outputs, which the pipeline orders after the
//! vertex stage, whereas storage writes of one vertex invocation are not guaranteed visible to
//! another patch's TCS in the same draw. The price is the varyings budget: `4 + 6 n` floats for
//! a smooth vertex of valence `n`, `4 + 9 ne` for a boundary/crease/corner vertex with `ne` ring
//! edges, within the smaller of `maxVertexOutputComponents` and
//! `maxTessellationControlPerVertexInputComponents` minus one location for the built-ins (128 on
//! lavapipe: 31 vec4 slots, smooth valence <= 20, sectored ring <= 13 edges; the variant for
//! 64-component devices: 15 slots, 9 / 6). Faces with a corner over the budget stay on the CPU
//! path (the renderer says so on stderr).

use ash::vk;
use glam::DVec3;

use super::gregory_layout::{gregory_face_problem, GregoryLayout};
use super::layout::vec3_bytes;
use super::patch_pipeline::{patch_push_constants, push_patch_chunk};
use super::renderer::RenderDesc;
use crate::gpu::{
    patch_draw_chunks, Buffer, BufferBinding, Context, DescriptorBinding, DescriptorKind,
    DescriptorPool, GraphicsPipelineDesc, MemoryLocation, Pipeline, TargetFormat,
};
use crate::patch::gregory::is_supported_vertex;
use crate::patch::gregory::table::GregoryVertexTable;
use crate::topology::Topology;
use crate::{Error, Result};

/// Varyings budget of the vertex stage: vec4 slots per vertex and the largest valence they hold.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct VsBudget {
    /// vec4 output slots (31 or 15; selects the shader variant).
    pub slots: u32,
    /// Largest valence of a smooth vertex: `(4 * slots - 4) / 6`.
    pub max_valence: usize,
}

impl VsBudget {
    /// Largest number of ring edges of a boundary, crease or corner vertex (9 floats each):
    /// `(4 * slots - 4) / 9`.
    pub fn max_sectored_edges(&self) -> usize {
        ((4 * self.slots - 4) / 9) as usize
    }

    /// Whether vertex `v`'s per-vertex data fits the varyings.
    pub fn fits(&self, topo: &Topology, v: u32) -> bool {
        let (ne, smooth) = vertex_need(topo, v);
        if smooth {
            ne <= self.max_valence
        } else {
            ne <= self.max_sectored_edges()
        }
    }
}

/// The budget the device allows, or `None` when even 15 slots do not fit.
pub fn vs_budget(ctx: &Context) -> Option<VsBudget> {
    // SAFETY: valid instance and physical device owned by the context.
    let props = unsafe {
        ctx.instance()
            .get_physical_device_properties(ctx.physical_device())
    };
    let comps = props.limits.max_vertex_output_components.min(
        props
            .limits
            .max_tessellation_control_per_vertex_input_components,
    );
    // One location of the budget is taken by the built-in per-vertex block.
    [31u32, 15]
        .into_iter()
        .find(|&s| 4 * s + 4 <= comps)
        .map(|slots| VsBudget {
            slots,
            max_valence: ((4 * slots - 4) / 6) as usize,
        })
}

/// Splits candidate Gregory faces into those this variant draws and those it cannot, with the
/// reason (the construction's limits, [`gregory_face_problem`], or a vertex over the varyings
/// budget).
pub fn select_faces(
    topo: &Topology,
    faces: &[u32],
    budget: VsBudget,
) -> (Vec<u32>, Vec<(u32, String)>) {
    let mut ok = Vec::new();
    let mut rejected = Vec::new();
    for &f in faces {
        if let Some(why) = gregory_face_problem(topo, f) {
            rejected.push((f, why));
            continue;
        }
        if let Some(&v) = topo
            .face_vertices(f)
            .iter()
            .find(|&&v| !budget.fits(topo, v))
        {
            rejected.push((
                f,
                format!(
                    "face {f}: vertex {v} has {} ring edges, over the two-stage variant's varyings budget ({} smooth, {} at boundaries/creases)",
                    topo.vertex_edges(v).len(),
                    budget.max_valence,
                    budget.max_sectored_edges()
                ),
            ));
            continue;
        }
        ok.push(f);
    }
    (ok, rejected)
}

/// Connectivity words (layout in `glsl/common/gregory_vs.glsl`): the per-vertex part of
/// [`GregoryVertexTable`] (paper Fig. 7: header `(offset, ne, nf, kind)` per vertex, far edge
/// vertices, sector words, face records) with the ring offsets made absolute.
pub fn connectivity_words(topo: &Topology) -> Vec<u32> {
    let t = GregoryVertexTable::new(topo, std::iter::empty());
    let base = t.vertices.len() as u32;
    let mut words = t.vertices;
    for h in words.chunks_exact_mut(4) {
        h[0] += base;
    }
    words.extend(t.ring);
    words
}

/// Ring edges of vertex `v` the varyings must hold, and whether it is smooth (6 floats per
/// edge) or sectored (9).
fn vertex_need(topo: &Topology, v: u32) -> (usize, bool) {
    let smooth = is_supported_vertex(topo, v);
    (topo.vertex_edges(v).len(), smooth)
}

/// Flag of the `sub_index` push constant: draw a triangle as sub-triangles
/// (`glsl/common/gregory.glsl` `TRI_SUB_MODE`).
pub const TRI_SUB_MODE: u32 = 0x8000_0000;

/// The shared buffers the two-stage pass binds but does not own (the surface renderer's).
#[derive(Clone, Copy)]
pub struct SharedBuffers<'a> {
    /// Frame uniforms (binding 0).
    pub frame: &'a Buffer,
    /// Vertex limit positions (binding 2), filled by [`super::gregory_layout::vertex_frames`].
    pub vertex_limits: &'a Buffer,
    /// TES capture (binding 3).
    pub capture: &'a Buffer,
}

/// GPU resources and pipelines of the two-stage Gregory patches of one surface.
pub struct GregoryVsPatches {
    ctx: Context,
    layout: GregoryLayout,
    split: u32,
    vertex_count: usize,
    _conn: Buffer,
    _corner_ring: Buffer,
    _patch_info: Buffer,
    _grids: Buffer,
    indices: Buffer,
    control_pos: Buffer,
    vertex_normals: Buffer,
    _pool: DescriptorPool,
    set: vk::DescriptorSet,
    quad_pipeline: Pipeline,
    tri_pipeline: Pipeline,
}

fn storage_stages() -> vk::ShaderStageFlags {
    vk::ShaderStageFlags::VERTEX
        | vk::ShaderStageFlags::TESSELLATION_CONTROL
        | vk::ShaderStageFlags::TESSELLATION_EVALUATION
}

/// Descriptor set 0 of the two-stage pipelines: 0 frame UBO, 1 (declared by frame.glsl, unused),
/// 2 vertex limits, 3 capture, 4 connectivity, 5 ring offsets, 6 patch records, 7 grids,
/// 8 control positions, 9 vertex normals.
fn set_layout() -> Vec<DescriptorBinding> {
    let mut v = vec![DescriptorBinding {
        binding: 0,
        kind: DescriptorKind::UniformBuffer,
        stages: storage_stages() | vk::ShaderStageFlags::FRAGMENT,
    }];
    for b in 1..10 {
        v.push(DescriptorBinding {
            binding: b,
            kind: DescriptorKind::StorageBuffer,
            stages: storage_stages(),
        });
    }
    v
}

fn host_buffer(ctx: &Context, bytes: &[u8], name: &str) -> Result<Buffer> {
    let mut b = Buffer::new(
        ctx,
        bytes.len().max(64) as u64,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::CpuToGpu,
        name,
    )?;
    b.write(0, bytes)?;
    Ok(b)
}

fn padded(mut bytes: Vec<u8>) -> Vec<u8> {
    if bytes.len() < 64 {
        bytes.resize(64, 0);
    }
    bytes
}

fn vec4_bytes(points: &[DVec3]) -> Vec<u8> {
    super::layout::vec4_bytes(points)
}

impl GregoryVsPatches {
    /// Uploads the tables for the faces in `layout` (made from faces [`select_faces`] accepted)
    /// and creates the pipelines for targets of format `target`. `normals`: per-vertex limit
    /// normals (from [`super::gregory_layout::vertex_frames`]).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        ctx: &Context,
        topo: &Topology,
        layout: GregoryLayout,
        positions: &[DVec3],
        normals: &[DVec3],
        shared: SharedBuffers<'_>,
        desc: &RenderDesc,
        target: TargetFormat,
    ) -> Result<GregoryVsPatches> {
        let budget = vs_budget(ctx).ok_or_else(|| {
            Error::Invalid(
                "the device's varyings budget is below 64 components: no two-stage Gregory variant"
                    .into(),
            )
        })?;
        Self::with_budget(
            ctx, topo, layout, positions, normals, shared, desc, target, budget,
        )
    }

    /// As [`Self::new`] with an explicit varyings budget (at most the device's [`vs_budget`]):
    /// the 15-slot shader variant can be tested on devices that allow 31. Errors if a patch
    /// corner's valence exceeds `budget.max_valence`.
    #[allow(clippy::too_many_arguments)]
    pub fn with_budget(
        ctx: &Context,
        topo: &Topology,
        layout: GregoryLayout,
        positions: &[DVec3],
        normals: &[DVec3],
        shared: SharedBuffers<'_>,
        desc: &RenderDesc,
        target: TargetFormat,
        budget: VsBudget,
    ) -> Result<GregoryVsPatches> {
        if let Some((f, v)) = layout.faces.iter().find_map(|&f| {
            topo.face_vertices(f)
                .iter()
                .find(|&&v| !budget.fits(topo, v))
                .map(|&v| (f, v))
        }) {
            return Err(Error::Invalid(format!(
                "gregory-vs: face {f}: vertex {v} has {} ring edges, over the varyings budget",
                topo.vertex_edges(v).len()
            )));
        }
        if positions.len() != topo.vertex_count() || normals.len() != positions.len() {
            return Err(Error::Invalid(format!(
                "gregory-vs: {} positions / {} normals for {} vertices",
                positions.len(),
                normals.len(),
                topo.vertex_count()
            )));
        }
        if desc.capture_capacity.is_some() {
            ctx.require(&[crate::gpu::Feature::VertexPipelineStoresAndAtomics])?;
        }
        let conn_words = connectivity_words(topo);
        let conn = host_buffer(
            ctx,
            &padded(conn_words.iter().flat_map(|w| w.to_le_bytes()).collect()),
            "gregory-vs connectivity",
        )?;
        let corner_ring = host_buffer(
            ctx,
            &padded(layout.corner_ring_bytes()),
            "gregory-vs ring offsets",
        )?;
        let patch_info = host_buffer(
            ctx,
            &padded(layout.patch_info_bytes()),
            "gregory patch records",
        )?;
        let grids = host_buffer(ctx, &padded(layout.grid_bytes()), "gregory edge grids")?;
        let control_pos = host_buffer(
            ctx,
            &padded(vec3_bytes(positions)),
            "gregory control positions",
        )?;
        let vertex_normals =
            host_buffer(ctx, &padded(vec4_bytes(normals)), "gregory vertex normals")?;
        let indices = ctx.upload_buffer(
            &padded(layout.corner_index_bytes()),
            vk::BufferUsageFlags::INDEX_BUFFER,
            "gregory-vs corner indices",
        )?;
        let quad_pipeline = Self::pipeline(ctx, desc, target, budget, true)?;
        let tri_pipeline = Self::pipeline(ctx, desc, target, budget, false)?;
        let pool = DescriptorPool::new(ctx, 1, 9, 1)?;
        let set = pool.allocate(quad_pipeline.set_layouts[0])?;
        let bind = |binding, buffer| BufferBinding {
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
                    buffer: shared.frame,
                },
                bind(1, &patch_info),
                bind(2, shared.vertex_limits),
                bind(3, shared.capture),
                bind(4, &conn),
                bind(5, &corner_ring),
                bind(6, &patch_info),
                bind(7, &grids),
                bind(8, &control_pos),
                bind(9, &vertex_normals),
            ],
        );
        Ok(GregoryVsPatches {
            ctx: ctx.clone(),
            layout,
            split: desc.tess.split(),
            vertex_count: positions.len(),
            _conn: conn,
            _corner_ring: corner_ring,
            _patch_info: patch_info,
            _grids: grids,
            indices,
            control_pos,
            vertex_normals,
            _pool: pool,
            set,
            quad_pipeline,
            tri_pipeline,
        })
    }

    fn pipeline(
        ctx: &Context,
        desc: &RenderDesc,
        target: TargetFormat,
        budget: VsBudget,
        quads: bool,
    ) -> Result<Pipeline> {
        let suffix = if budget.slots == 31 { "" } else { "_16" };
        let shape = if quads { "quad" } else { "tri" };
        let tese = desc.tese_name(&format!("patch_gregory_{shape}"));
        let p = GraphicsPipelineDesc {
            label: format!("gregory-vs {shape} patches ({tese})"),
            vertex: format!("gregory_vs{suffix}.vert"),
            tess_control: Some(format!("gregory_vs_{shape}{suffix}.tesc")),
            tess_eval: Some(tese),
            fragment: "shade.frag".into(),
            vertex_bindings: vec![],
            vertex_attributes: vec![],
            topology: vk::PrimitiveTopology::PATCH_LIST,
            patch_control_points: if quads { 4 } else { 3 },
            polygon_mode: desc.polygon_mode(),
            cull_mode: desc.cull_mode(),
            front_face: vk::FrontFace::COUNTER_CLOCKWISE,
            depth_test: true,
            depth_write: true,
            set_layouts: vec![set_layout()],
            push_constants: Some(patch_push_constants()),
        };
        ctx.graphics_pipeline_for(&p, target)
    }

    /// The patch tables.
    pub fn layout(&self) -> &GregoryLayout {
        &self.layout
    }

    /// Number of patches (quads + triangles).
    pub fn patch_count(&self) -> u32 {
        self.layout.patch_count()
    }

    /// Animation: new control positions and vertex normals (same topology); every patch is
    /// rebuilt on the GPU in the next frame. The caller updates the shared vertex limits.
    pub fn update_positions(&mut self, positions: &[DVec3], normals: &[DVec3]) -> Result<()> {
        if positions.len() != self.vertex_count || normals.len() != self.vertex_count {
            return Err(Error::Invalid(format!(
                "gregory-vs update: {} positions / {} normals, the surface has {} vertices",
                positions.len(),
                normals.len(),
                self.vertex_count
            )));
        }
        self.control_pos.write(0, &vec3_bytes(positions))?;
        self.vertex_normals.write(0, &vec4_bytes(normals))?;
        Ok(())
    }

    /// Records the Gregory patch draws (inside the caller's render pass): quads in sub-patch
    /// splits like the regular patches, triangles in as many sub-triangles; chunked per
    /// [`crate::gpu::patch_draw_chunks`], the chunk's first patch as push constant.
    pub fn record(&self, cmd: vk::CommandBuffer) {
        let dev = self.ctx.device();
        let quads = self.layout.quad_count;
        let tris = self.layout.patch_count() - quads;
        for (pipe, count, quad) in [
            (&self.quad_pipeline, quads, true),
            (&self.tri_pipeline, tris, false),
        ] {
            if count == 0 {
                continue;
            }
            let points = if quad { 4 } else { 3 };
            // SAFETY: cmd records inside a render pass of the pipeline's format; every bound
            // resource lives as long as self.
            unsafe {
                dev.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipe.raw);
                dev.cmd_bind_descriptor_sets(
                    cmd,
                    vk::PipelineBindPoint::GRAPHICS,
                    pipe.layout,
                    0,
                    &[self.set],
                    &[],
                );
                dev.cmd_bind_index_buffer(cmd, self.indices.raw(), 0, vk::IndexType::UINT32);
            }
            // Triangles as split^2 sub-triangles (sub index | TRI_SUB_MODE, gregory.glsl
            // tri_domain_point), their edges on the split quads' lattice.
            let (split, subs) = (self.split, self.split * self.split);
            let sub_flag = if quad { 0 } else { TRI_SUB_MODE };
            for (first, n) in patch_draw_chunks(count, points, true) {
                let (base, first_index) = if quad {
                    (first, 4 * first)
                } else {
                    (quads + first, 4 * quads + 3 * first)
                };
                for sub in 0..subs {
                    push_patch_chunk(dev, cmd, pipe.layout, base, sub | sub_flag, split);
                    // SAFETY: as above.
                    unsafe { dev.cmd_draw_indexed(cmd, n * points, 1, first_index, 0, 0) };
                }
            }
        }
    }
}
