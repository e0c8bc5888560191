//! GPU resources and draws of the stencil variant (paper §4.3): stencil blocks per connectivity
//! type, per-patch records, the ring index buffer, and one pipeline per (quad/triangle, patch
//! size). Descriptor set 0 is the surface renderer's (frame uniforms, vertex limits, capture;
//! [`frame_set_layout`]); set 1 holds the stencil data. Byte layouts mirror
//! `glsl/common/gregory_stencil.glsl`.

use ash::vk;

use super::table::{StencilTable, QUAD_EXTRA, QUAD_POINTS};
use crate::gpu::{
    patch_draw_chunks, Buffer, BufferBinding, Context, DescriptorBinding, DescriptorKind,
    DescriptorPool, GraphicsPipelineDesc, Pipeline, PushConstants, TargetFormat, VertexAttribute,
    VertexBinding,
};
use crate::render::renderer::RenderDesc;
use crate::topology::Topology;
use crate::Result;

/// Rows per stencil block (a quad's 20 points + 8 neighbour edge points; triangles use 21).
pub const STENCIL_ROWS: usize = QUAD_POINTS + QUAD_EXTRA;
/// Columns per stencil block (`maxTessellationPatchSize` guaranteed by Vulkan).
pub const STENCIL_COLS: usize = 32;
/// Bytes of one `StencilRecord`.
pub const RECORD_BYTES: usize = 32;
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

/// Patches of one kind and patch size, drawn with one pipeline.
#[derive(Debug, Clone)]
struct DrawGroup {
    triangle: bool,
    points: u32,
    first_record: u32,
    count: u32,
    pipeline: Pipeline,
}

/// The stencil blocks, masks, records and ring indices of `table`, records ordered by
/// `order` (indices into `table.patches`), rings padded to `sizes[i]`.
fn buffers_bytes(
    table: &StencilTable,
    order: &[usize],
    sizes: &[u32],
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
    let mut records = Vec::with_capacity(order.len() * RECORD_BYTES / 4);
    let mut indices = Vec::new();
    for (&i, &size) in order.iter().zip(sizes) {
        let p = &table.patches[i];
        records.extend([p.face, p.type_id, p.ring.len() as u32, 0]);
        records.extend(p.corners);
        indices.extend(p.ring.iter().copied());
        indices.extend(std::iter::repeat_n(p.ring[0], size as usize - p.ring.len()));
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

/// The stencil-variant Gregory patches of one surface, ready to record.
pub struct StencilPatches {
    ctx: Context,
    table: StencilTable,
    groups: Vec<DrawGroup>,
    split: u32,
    _weights: Buffer,
    _masks: Buffer,
    _records: Buffer,
    indices: Buffer,
    _pool: DescriptorPool,
    set: vk::DescriptorSet,
}

impl StencilPatches {
    /// Builds the stencils of `faces` (see [`StencilTable::build`]; rings are limited by the
    /// device's `maxTessellationPatchSize`) and the pipelines for targets of format `target`.
    /// Faces the variant cannot take are in [`Self::table`]`.rejected`; the caller draws them
    /// another way.
    pub fn new(
        ctx: &Context,
        topo: &Topology,
        faces: &[u32],
        desc: &RenderDesc,
        target: TargetFormat,
    ) -> Result<StencilPatches> {
        let max_ring = ctx.info().limits.max_tessellation_patch_size as usize;
        let table = StencilTable::build(topo, faces, max_ring);
        Self::from_table(ctx, table, desc, target)
    }

    /// As [`Self::new`] from a prepared table.
    pub fn from_table(
        ctx: &Context,
        table: StencilTable,
        desc: &RenderDesc,
        target: TargetFormat,
    ) -> Result<StencilPatches> {
        let max_size = ctx.info().limits.max_tessellation_patch_size;
        let size_of = |len: usize| {
            PATCH_SIZES
                .iter()
                .copied()
                .find(|&s| s as usize >= len && s <= max_size)
                .unwrap_or(max_size)
        };
        // Group by (triangle, padded size).
        let mut order: Vec<usize> = (0..table.patches.len()).collect();
        order.sort_by_key(|&i| {
            let p = &table.patches[i];
            (p.triangle, size_of(p.ring.len()), i)
        });
        let sizes: Vec<u32> = order
            .iter()
            .map(|&i| size_of(table.patches[i].ring.len()))
            .collect();
        let mut groups = Vec::new();
        let mut start = 0usize;
        while start < order.len() {
            let tri = table.patches[order[start]].triangle;
            let mut end = start;
            while end < order.len()
                && table.patches[order[end]].triangle == tri
                && sizes[end] == sizes[start]
            {
                end += 1;
            }
            groups.push(DrawGroup {
                triangle: tri,
                points: sizes[start],
                first_record: start as u32,
                count: (end - start) as u32,
                pipeline: pipeline(ctx, desc, target, tri, sizes[start])?,
            });
            start = end;
        }
        let (w, m, r, ix) = buffers_bytes(&table, &order, &sizes);
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let weights = ctx.upload_buffer(&non_empty(w), storage, "gregory stencil weights")?;
        let masks = ctx.upload_buffer(&non_empty(m), storage, "gregory stencil masks")?;
        let records = ctx.upload_buffer(&non_empty(r), storage, "gregory stencil records")?;
        let indices = ctx.upload_buffer(
            &non_empty(ix),
            vk::BufferUsageFlags::INDEX_BUFFER,
            "gregory stencil ring indices",
        )?;
        let pool = DescriptorPool::new(ctx, 1, 3, 0)?;
        let set = match groups.first() {
            Some(g) => {
                let set = pool.allocate(g.pipeline.set_layouts[1])?;
                let sb = |binding, buffer| BufferBinding {
                    binding,
                    kind: DescriptorKind::StorageBuffer,
                    buffer,
                };
                ctx.write_buffer_descriptors(
                    set,
                    &[sb(0, &weights), sb(1, &masks), sb(2, &records)],
                );
                set
            }
            None => vk::DescriptorSet::null(),
        };
        // Keep the table in record order, so `patch_base + gl_PrimitiveID` indexes it.
        let mut table = table;
        let mut sorted: Vec<_> = order.iter().map(|&i| table.patches[i].clone()).collect();
        std::mem::swap(&mut table.patches, &mut sorted);
        Ok(StencilPatches {
            ctx: ctx.clone(),
            table,
            groups,
            split: desc.tess.split(),
            _weights: weights,
            _masks: masks,
            _records: records,
            indices,
            _pool: pool,
            set,
        })
    }

    /// The stencils (patches in draw order) and the rejected faces.
    pub fn table(&self) -> &StencilTable {
        &self.table
    }

    /// The Vulkan handle of set 0's layout ([`frame_set_layout`]), for allocating a frame set;
    /// `None` when there is nothing to draw.
    pub fn frame_set_layout_handle(&self) -> Option<vk::DescriptorSetLayout> {
        self.groups.first().map(|g| g.pipeline.set_layouts[0])
    }

    /// The drawn faces in draw order (quads first, then triangles): the order of the shared
    /// TES's patch records (`GregoryLayout::new(topo, &faces())`, binding 6).
    pub fn faces(&self) -> Vec<u32> {
        self.table.patches.iter().map(|p| p.face).collect()
    }

    /// Number of patches drawn.
    pub fn patch_count(&self) -> u32 {
        self.table.patches.len() as u32
    }

    /// Records the draws inside the caller's render pass. `frame_set` is a set 0 of
    /// [`frame_set_layout`] (the surface renderer's); `positions` the control-vertex buffer
    /// (tightly packed f32 xyz), which the caller may update between frames (animation: the
    /// stencils do not change).
    pub fn record(
        &self,
        cmd: vk::CommandBuffer,
        frame_set: vk::DescriptorSet,
        positions: vk::Buffer,
    ) {
        let dev = self.ctx.device();
        let stages = vk::ShaderStageFlags::TESSELLATION_CONTROL
            | vk::ShaderStageFlags::TESSELLATION_EVALUATION;
        for g in &self.groups {
            // SAFETY: cmd is recording inside a render pass compatible with the pipeline's
            // target format; every bound resource outlives the submission (owned by self or
            // the caller).
            unsafe {
                dev.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, g.pipeline.raw);
                dev.cmd_bind_descriptor_sets(
                    cmd,
                    vk::PipelineBindPoint::GRAPHICS,
                    g.pipeline.layout,
                    0,
                    &[frame_set, self.set],
                    &[],
                );
                dev.cmd_bind_vertex_buffers(cmd, 0, &[positions], &[0]);
                dev.cmd_bind_index_buffer(cmd, self.indices.raw(), 0, vk::IndexType::UINT32);
                // The shared triangle TES has no sub-domains: triangles are drawn whole.
                let split = if g.triangle { 1 } else { self.split };
                for (first, n) in patch_draw_chunks(g.count, g.points, true) {
                    let base = g.first_record + first;
                    for sub in 0..split * split {
                        let mut pc = [0u8; 12];
                        for (k, w) in [base, sub, split].iter().enumerate() {
                            pc[4 * k..4 * k + 4].copy_from_slice(&w.to_le_bytes());
                        }
                        dev.cmd_push_constants(cmd, g.pipeline.layout, stages, 0, &pc);
                        dev.cmd_draw_indexed(
                            cmd,
                            n * g.points,
                            1,
                            self.first_index(g, first),
                            0,
                            0,
                        );
                    }
                }
            }
        }
    }

    /// First index of patch `first` of group `g` in the ring index buffer.
    fn first_index(&self, g: &DrawGroup, first: u32) -> u32 {
        let before: u32 = self
            .groups
            .iter()
            .take_while(|h| h.first_record < g.first_record)
            .map(|h| h.count * h.points)
            .sum();
        before + first * g.points
    }
}

/// Shared TES of the Gregory patches (glsl/patch_gregory_{quad,tri}.tese and variants).
fn tese_name(desc: &RenderDesc, triangle: bool) -> String {
    format!(
        "patch_gregory_{}_{}{}.tese",
        if triangle { "tri" } else { "quad" },
        desc.tess.spacing.shader_suffix(),
        if desc.capture_capacity.is_some() {
            "_capture"
        } else {
            ""
        }
    )
}

fn pipeline_desc(desc: &RenderDesc, triangle: bool, points: u32) -> GraphicsPipelineDesc {
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
        vertex_bindings: vec![VertexBinding {
            binding: 0,
            stride: 12,
            per_instance: false,
        }],
        vertex_attributes: vec![VertexAttribute {
            location: 0,
            binding: 0,
            format: vk::Format::R32G32B32_SFLOAT,
            offset: 0,
        }],
        topology: vk::PrimitiveTopology::PATCH_LIST,
        patch_control_points: points,
        polygon_mode: if desc.wireframe {
            vk::PolygonMode::LINE
        } else {
            vk::PolygonMode::FILL
        },
        cull_mode: if desc.cull_back_faces {
            vk::CullModeFlags::BACK
        } else {
            vk::CullModeFlags::NONE
        },
        front_face: vk::FrontFace::COUNTER_CLOCKWISE,
        depth_test: true,
        depth_write: true,
        set_layouts: vec![frame_set_layout(), stencil_set_layout()],
        push_constants: Some(PushConstants {
            stages: vk::ShaderStageFlags::TESSELLATION_CONTROL
                | vk::ShaderStageFlags::TESSELLATION_EVALUATION,
            size: 12,
        }),
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
