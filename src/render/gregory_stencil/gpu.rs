//! GPU resources and draws of the stencil variant (paper §4.3): stencil blocks per connectivity
//! type, per-patch records, the ring index buffer (the patch primitive is the face's one-ring,
//! padded to one patch size per quad/triangle pipeline). Descriptor set 0 ([`frame_set_layout`])
//! binds the renderer's frame, vertex-limit and capture buffers and the shared TES tables
//! (`GregoryLayout`); set 1 holds the stencil data. Byte layouts mirror
//! `glsl/common/gregory_stencil.glsl`.

use ash::vk;

use glam::DVec3;

use crate::gpu::{
    patch_draw_chunks, Buffer, BufferBinding, Context, DescriptorBinding, DescriptorKind,
    DescriptorPool, GraphicsPipelineDesc, MemoryLocation, Pipeline, TargetFormat,
};
use crate::patch::gregory::stencil_table::{
    GregoryStencilTable as StencilTable, QUAD_EXTRA, QUAD_POINTS,
};
use crate::render::gregory_layout::GregoryLayout;
use crate::render::gregory_vs::SharedBuffers;
use crate::render::layout::{vec3_bytes, vec4_bytes};
use crate::render::patch_pipeline::{patch_push_constants, position_input, push_patch_chunk};
use crate::render::renderer::RenderDesc;
use crate::topology::Topology;
use crate::{Error, Result};

/// Rows per stencil block (a quad's 20 points + 8 neighbour edge points; triangles use 21).
pub const STENCIL_ROWS: usize = QUAD_POINTS + QUAD_EXTRA;
/// Columns per stencil block (`maxTessellationPatchSize` guaranteed by Vulkan).
pub const STENCIL_COLS: usize = 32;
/// Bytes of one `StencilRecord`.
pub const RECORD_BYTES: usize = 64;
/// Patch sizes the ring is padded to (one pipeline each).
const PATCH_SIZES: [u32; 3] = [16, 24, 32];

/// Descriptor set 0 of the Gregory pipelines (the shared TES contract, glsl/common/gregory.glsl):
/// 0 frame UBO, 1 regular-patch records (unused), 2 vertex limit positions, 3 TES capture,
/// 6 Gregory patch records, 7 B-spline edge grids, 8 control positions, 9 vertex normals.
pub fn frame_set_layout() -> Vec<DescriptorBinding> {
    let all = vk::ShaderStageFlags::VERTEX
        | vk::ShaderStageFlags::TESSELLATION_CONTROL
        | vk::ShaderStageFlags::TESSELLATION_EVALUATION
        | vk::ShaderStageFlags::FRAGMENT;
    let tess =
        vk::ShaderStageFlags::TESSELLATION_CONTROL | vk::ShaderStageFlags::TESSELLATION_EVALUATION;
    let tes = vk::ShaderStageFlags::TESSELLATION_EVALUATION;
    let b = |binding, kind, stages| DescriptorBinding {
        binding,
        kind,
        stages,
    };
    vec![
        b(0, DescriptorKind::UniformBuffer, all),
        b(1, DescriptorKind::StorageBuffer, tess),
        b(2, DescriptorKind::StorageBuffer, tess),
        b(3, DescriptorKind::StorageBuffer, tes),
        b(6, DescriptorKind::StorageBuffer, tes),
        b(7, DescriptorKind::StorageBuffer, tes),
        b(8, DescriptorKind::StorageBuffer, tes),
        b(9, DescriptorKind::StorageBuffer, tes),
    ]
}

/// Set 1: stencil weights, masks, per-patch records (TCS only).
fn stencil_set_layout() -> Vec<DescriptorBinding> {
    (0..3)
        .map(|binding| DescriptorBinding {
            binding,
            kind: DescriptorKind::StorageBuffer,
            stages: vk::ShaderStageFlags::TESSELLATION_CONTROL,
        })
        .collect()
}

/// Patches of one kind (quads or triangles), drawn with one pipeline.
#[derive(Debug, Clone)]
struct DrawGroup {
    triangle: bool,
    points: u32,
    first_record: u32,
    first_index: u32,
    count: u32,
    pipeline: Pipeline,
}

/// The stencil blocks, masks, records and ring indices of `table` (patches in draw order),
/// rings padded to `size(triangle)`.
fn buffers_words(
    table: &StencilTable,
    size: impl Fn(bool) -> u32,
) -> (Vec<f32>, Vec<u32>, Vec<u32>, Vec<u32>) {
    let mut weights = vec![0f32; table.types.len() * STENCIL_ROWS * STENCIL_COLS];
    let mut masks = vec![0u32; table.types.len() * STENCIL_ROWS];
    for (t, ty) in table.types.iter().enumerate() {
        for (row, w) in ty.weights.chunks(ty.ring_len).enumerate() {
            let base = (t * STENCIL_ROWS + row) * STENCIL_COLS;
            weights[base..base + w.len()].copy_from_slice(w);
            masks[t * STENCIL_ROWS + row] = ty.masks[row];
        }
    }
    let mut records = Vec::with_capacity(table.patches.len() * RECORD_BYTES / 4);
    let mut indices = Vec::new();
    for p in &table.patches {
        records.extend([p.face, p.type_id, p.ring.len() as u32, 0]);
        records.extend(p.corners);
        // Summation order: ring slots by ascending global id, 4 slots per word (low byte first).
        let mut order = [0u32; STENCIL_COLS / 4];
        for (i, &k) in p.order.iter().enumerate() {
            order[i / 4] |= u32::from(k) << (8 * (i % 4));
        }
        records.extend(order);
        indices.extend(p.ring.iter().copied());
        let pad = size(p.triangle) as usize - p.ring.len();
        indices.extend(std::iter::repeat_n(p.ring[0], pad));
    }
    (weights, masks, records, indices)
}

/// Pads to a minimal non-empty buffer.
fn non_empty<T: Copy + Default>(mut v: Vec<T>) -> Vec<T> {
    if v.is_empty() {
        v.push(T::default());
    }
    v
}

fn host_buffer(
    ctx: &Context,
    bytes: &[u8],
    usage: vk::BufferUsageFlags,
    name: &str,
) -> Result<Buffer> {
    let mut b = Buffer::new(
        ctx,
        bytes.len().max(64) as u64,
        usage,
        MemoryLocation::CpuToGpu,
        name,
    )?;
    b.write(0, bytes)?;
    Ok(b)
}

/// Which faces the stencil variant draws, in draw order, and the shared TES tables for them.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StencilPlan {
    /// Stencils; `patches` in draw order (quads, then triangles), `rejected` the faces left to
    /// another path with the reason.
    pub table: StencilTable,
    /// Shared TES records (binding 6/7) for the same faces in the same order.
    pub layout: GregoryLayout,
}

impl StencilPlan {
    /// Stencils of `faces` (rings limited to `max_patch_size`, the device's
    /// `maxTessellationPatchSize`) and the shared layout of the accepted ones.
    pub fn new(topo: &Topology, faces: &[u32], max_patch_size: u32) -> StencilPlan {
        let mut table = StencilTable::build(topo, faces, max_patch_size as usize);
        // GregoryLayout's order: quads first, then triangles, each in input order.
        table.patches.sort_by_key(|p| p.triangle);
        let accepted: Vec<u32> = table.patches.iter().map(|p| p.face).collect();
        let layout = GregoryLayout::new(topo, &accepted);
        debug_assert_eq!(layout.faces, accepted);
        StencilPlan { table, layout }
    }
}

/// GPU resources and pipelines of the stencil-variant Gregory patches of one surface.
pub struct StencilPatches {
    ctx: Context,
    plan: StencilPlan,
    groups: Vec<DrawGroup>,
    split: u32,
    vertex_count: usize,
    _weights: Buffer,
    _masks: Buffer,
    _records: Buffer,
    _patch_info: Buffer,
    _grids: Buffer,
    indices: Buffer,
    control_pos: Buffer,
    vertex_normals: Buffer,
    _pool: DescriptorPool,
    set0: vk::DescriptorSet,
    set1: vk::DescriptorSet,
}

impl StencilPatches {
    /// Uploads the stencils and shared tables of `plan` and creates the pipelines for targets
    /// of format `target`. `positions`: control positions (also the ring vertex buffer);
    /// `normals`: per-vertex limit normals ([`crate::render::gregory_layout::vertex_frames`]
    /// with `plan.layout`); `shared`: the renderer's frame, vertex-limit and capture buffers.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        ctx: &Context,
        plan: StencilPlan,
        positions: &[DVec3],
        normals: &[DVec3],
        shared: SharedBuffers<'_>,
        desc: &RenderDesc,
        target: TargetFormat,
    ) -> Result<StencilPatches> {
        if normals.len() != positions.len() {
            return Err(Error::Invalid(format!(
                "gregory-stencil: {} positions but {} normals",
                positions.len(),
                normals.len()
            )));
        }
        if let Some(p) = plan
            .table
            .patches
            .iter()
            .find(|p| p.ring.iter().any(|&v| v as usize >= positions.len()))
        {
            return Err(Error::Invalid(format!(
                "gregory-stencil: face {} uses a vertex beyond the {} positions",
                p.face,
                positions.len()
            )));
        }
        if desc.capture_capacity.is_some() {
            ctx.require(&[crate::gpu::Feature::VertexPipelineStoresAndAtomics])?;
        }
        let max_size = ctx.info().limits.max_tessellation_patch_size;
        let size_of = |tri: bool| {
            let longest = plan
                .table
                .patches
                .iter()
                .filter(|p| p.triangle == tri)
                .map(|p| p.ring.len() as u32)
                .max()
                .unwrap_or(1);
            PATCH_SIZES
                .iter()
                .copied()
                .find(|&s| s >= longest && s <= max_size)
                .unwrap_or(max_size)
        };
        let quads = plan.layout.quad_count;
        let total = plan.table.patches.len() as u32;
        let mut groups = Vec::new();
        for (tri, first, count, first_index) in [
            (false, 0, quads, 0),
            (true, quads, total - quads, quads * size_of(false)),
        ] {
            if count > 0 {
                groups.push(DrawGroup {
                    triangle: tri,
                    points: size_of(tri),
                    first_record: first,
                    first_index,
                    count,
                    pipeline: pipeline(ctx, desc, target, tri, size_of(tri))?,
                });
            }
        }
        let (w, m, r, ix) = buffers_words(&plan.table, size_of);
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let weights = ctx.upload_buffer(&non_empty(w), storage, "gregory stencil weights")?;
        let masks = ctx.upload_buffer(&non_empty(m), storage, "gregory stencil masks")?;
        let records = ctx.upload_buffer(&non_empty(r), storage, "gregory stencil records")?;
        let indices = ctx.upload_buffer(
            &non_empty(ix),
            vk::BufferUsageFlags::INDEX_BUFFER,
            "gregory stencil ring indices",
        )?;
        let patch_info = host_buffer(
            ctx,
            &plan.layout.patch_info_bytes(),
            storage,
            "gregory patch records",
        )?;
        let grids = host_buffer(
            ctx,
            &plan.layout.grid_bytes(),
            storage,
            "gregory edge grids",
        )?;
        let control_pos = host_buffer(
            ctx,
            &vec3_bytes(positions),
            storage | vk::BufferUsageFlags::VERTEX_BUFFER,
            "gregory control positions",
        )?;
        let vertex_normals =
            host_buffer(ctx, &vec4_bytes(normals), storage, "gregory vertex normals")?;
        let pool = DescriptorPool::new(ctx, 2, 10, 1)?;
        let (mut set0, mut set1) = (vk::DescriptorSet::null(), vk::DescriptorSet::null());
        if let Some(g) = groups.first() {
            set0 = pool.allocate(g.pipeline.set_layouts[0])?;
            set1 = pool.allocate(g.pipeline.set_layouts[1])?;
            let sb = |binding, buffer| BufferBinding {
                binding,
                kind: DescriptorKind::StorageBuffer,
                buffer,
            };
            ctx.write_buffer_descriptors(
                set0,
                &[
                    BufferBinding {
                        binding: 0,
                        kind: DescriptorKind::UniformBuffer,
                        buffer: shared.frame,
                    },
                    sb(1, &patch_info),
                    sb(2, shared.vertex_limits),
                    sb(3, shared.capture),
                    sb(6, &patch_info),
                    sb(7, &grids),
                    sb(8, &control_pos),
                    sb(9, &vertex_normals),
                ],
            );
            ctx.write_buffer_descriptors(set1, &[sb(0, &weights), sb(1, &masks), sb(2, &records)]);
        }
        Ok(StencilPatches {
            ctx: ctx.clone(),
            plan,
            groups,
            split: desc.tess.split(),
            vertex_count: positions.len(),
            _weights: weights,
            _masks: masks,
            _records: records,
            _patch_info: patch_info,
            _grids: grids,
            indices,
            control_pos,
            vertex_normals,
            _pool: pool,
            set0,
            set1,
        })
    }

    /// The stencils (patches in draw order) and the rejected faces.
    pub fn table(&self) -> &StencilTable {
        &self.plan.table
    }

    /// The shared TES tables (patch records in draw order).
    pub fn layout(&self) -> &GregoryLayout {
        &self.plan.layout
    }

    /// The drawn faces in draw order.
    pub fn faces(&self) -> &[u32] {
        &self.plan.layout.faces
    }

    /// Number of patches drawn.
    pub fn patch_count(&self) -> u32 {
        self.plan.table.patches.len() as u32
    }

    /// Animation: new control positions and vertex normals (same topology). The stencils stay;
    /// every patch is rebuilt by the TCS in the next frame. The caller updates the shared vertex
    /// limits. Call while no frame using these buffers is executing.
    pub fn update_positions(&mut self, positions: &[DVec3], normals: &[DVec3]) -> Result<()> {
        if positions.len() != self.vertex_count || normals.len() != self.vertex_count {
            return Err(Error::Invalid(format!(
                "gregory-stencil update: {} positions / {} normals, the surface has {} vertices",
                positions.len(),
                normals.len(),
                self.vertex_count
            )));
        }
        self.control_pos.write(0, &vec3_bytes(positions))?;
        self.vertex_normals.write(0, &vec4_bytes(normals))
    }

    /// Records the draws inside the caller's render pass: quads with the renderer's sub-patch
    /// split, triangles whole; chunked per [`patch_draw_chunks`], the chunk's first patch as push
    /// constant.
    pub fn record(&self, cmd: vk::CommandBuffer) {
        let dev = self.ctx.device();
        for g in &self.groups {
            // SAFETY: cmd is recording inside a render pass compatible with the pipeline's
            // target format; every bound resource outlives the submission (owned by self or
            // the renderer).
            unsafe {
                dev.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, g.pipeline.raw);
                dev.cmd_bind_descriptor_sets(
                    cmd,
                    vk::PipelineBindPoint::GRAPHICS,
                    g.pipeline.layout,
                    0,
                    &[self.set0, self.set1],
                    &[],
                );
                dev.cmd_bind_vertex_buffers(cmd, 0, &[self.control_pos.raw()], &[0]);
                dev.cmd_bind_index_buffer(cmd, self.indices.raw(), 0, vk::IndexType::UINT32);
                // Triangles are drawn whole (one draw per chunk) but told the quads' split, so
                // their edge levels and edge parameters match the split quads
                // (gregory_tri_edge_level / edge_ts in glsl/common/gregory.glsl).
                let subs = if g.triangle {
                    1
                } else {
                    self.split * self.split
                };
                let split = self.split;
                for (first, n) in patch_draw_chunks(g.count, g.points, true) {
                    let base = g.first_record + first;
                    for sub in 0..subs {
                        push_patch_chunk(dev, cmd, g.pipeline.layout, base, sub, split);
                        dev.cmd_draw_indexed(
                            cmd,
                            n * g.points,
                            1,
                            g.first_index + first * g.points,
                            0,
                            0,
                        );
                    }
                }
            }
        }
    }
}

/// Shared TES of the Gregory patches (glsl/patch_gregory_{quad,tri}.tese and variants).
fn tese_name(desc: &RenderDesc, triangle: bool) -> String {
    desc.tese_name(if triangle {
        "patch_gregory_tri"
    } else {
        "patch_gregory_quad"
    })
}

fn pipeline_desc(desc: &RenderDesc, triangle: bool, points: u32) -> GraphicsPipelineDesc {
    let (vertex_bindings, vertex_attributes) = position_input();
    GraphicsPipelineDesc {
        label: format!(
            "gregory stencil {} patches, {points} ring points",
            if triangle { "triangle" } else { "quad" }
        ),
        vertex: "gregory_stencil.vert".into(),
        tess_control: Some(
            if triangle {
                "gregory_stencil_tri.tesc"
            } else {
                "gregory_stencil_quad.tesc"
            }
            .into(),
        ),
        tess_eval: Some(tese_name(desc, triangle)),
        fragment: "shade.frag".into(),
        vertex_bindings,
        vertex_attributes,
        topology: vk::PrimitiveTopology::PATCH_LIST,
        patch_control_points: points,
        polygon_mode: desc.polygon_mode(),
        cull_mode: desc.cull_mode(),
        front_face: vk::FrontFace::COUNTER_CLOCKWISE,
        depth_test: true,
        depth_write: true,
        set_layouts: vec![frame_set_layout(), stencil_set_layout()],
        push_constants: Some(patch_push_constants()),
    }
}

fn pipeline(
    ctx: &Context,
    desc: &RenderDesc,
    target: TargetFormat,
    triangle: bool,
    points: u32,
) -> Result<Pipeline> {
    ctx.graphics_pipeline_for(&pipeline_desc(desc, triangle, points), target)
}
