//! GPU resources and draws of the stencil variant (paper §4.3): stencil blocks per connectivity
//! type, per-patch records, the ring index buffer (the patch primitive is the face's one-ring,
//! padded to one patch size per quad/triangle pipeline). Set 0 holds the shared bindings
//! ([`crate::render::pass::shared`]) and the shared Gregory TES tables ([`GregoryLayout`]); set 1
//! the stencil data. Byte layouts mirror `glsl/gregory_stencil/`.

use std::any::Any;
use std::sync::Arc;

use ash::vk;
use glam::DVec3;

use super::gregory::{self, GregoryLayout, GregoryTesBuffers};
use super::traits::{
    PassContext, PassPlan, PassTables, PatchPass, PatchScheme, PlanOptions, ReferencePatch,
    Refusal, RefusalReason,
};
use crate::gpu::{
    Buffer, BufferBinding, Context, DescriptorBinding, DescriptorKind, DescriptorPool, Pipeline,
};
use crate::patch::gregory::stencil::{NoStencil, MAX_RING};
use crate::patch::gregory::stencil_table::{
    GregoryStencilTable as StencilTable, QUAD_EXTRA, QUAD_POINTS,
};
use crate::patch::gregory::GregoryTangents;
use crate::render::pass::pipeline::{patch_pipeline, PatchShaders};
use crate::render::pass::shared::set0_layout;
use crate::render::pass::upload::{device_buffer, f32_bytes, u32_bytes};
use crate::render::pass::{
    bind_draw_state, record_patch_draws, NormalRule, PatchDraws, VertexFrames,
};
use crate::render::settings::{PatchLevelLimit, Spacing};
use crate::topology::Topology;
use crate::{Error, Result};

/// The stencil Gregory pass in the registry.
pub static GREGORY_STENCIL: GregoryStencilScheme = GregoryStencilScheme;

/// Rows per stencil block (a quad's 20 points + 8 neighbour edge points; triangles use 21).
pub const STENCIL_ROWS: usize = QUAD_POINTS + QUAD_EXTRA;
/// Columns per stencil block (`maxTessellationPatchSize` guaranteed by Vulkan).
pub const STENCIL_COLS: usize = 32;
/// Bytes of one `StencilRecord`.
pub const RECORD_BYTES: usize = 64;
/// Patch sizes the ring is padded to (one pipeline each).
const PATCH_SIZES: [u32; 3] = [16, 24, 32];

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
    /// Stencils of the faces among `faces` the construction covers (rings limited to
    /// `max_patch_size`, the device's `maxTessellationPatchSize`) and the shared layout of the
    /// accepted ones.
    pub fn new(
        topo: &Topology,
        faces: &[u32],
        max_patch_size: u32,
        tangents: GregoryTangents,
    ) -> StencilPlan {
        let (covered, _) = gregory::covered_faces(GREGORY_STENCIL.name(), topo, faces);
        let mut table = StencilTable::build_with(topo, &covered, max_patch_size as usize, tangents);
        // GregoryLayout's order: quads first, then triangles, each in input order.
        table.patches.sort_by_key(|p| p.triangle);
        let accepted: Vec<u32> = table.patches.iter().map(|p| p.face).collect();
        let layout = GregoryLayout::new(topo, &accepted, tangents);
        debug_assert_eq!(layout.faces, accepted);
        StencilPlan { table, layout }
    }
}

/// Takes the triangles and quads the Gregory construction covers whose one-ring fits the
/// device's largest patch primitive.
#[derive(Debug, Clone, Copy)]
pub struct GregoryStencilScheme;

impl PatchScheme for GregoryStencilScheme {
    fn name(&self) -> &'static str {
        "gregory-stencil"
    }

    fn reads_fitted_crease_factors(&self) -> bool {
        true
    }

    fn plan(&self, topo: &Arc<Topology>, candidates: &[u32], opts: &PlanOptions) -> PassPlan {
        let limits = &opts.limits;
        let (covered, mut refused) = gregory::covered_faces(self.name(), topo, candidates);
        let plan = StencilPlan::new(topo, &covered, limits.max_patch_size, opts.gregory_tangents);
        refused.extend(plan.table.skipped.iter().map(|s| Refusal {
            face: s.face(),
            pass: self.name(),
            reason: match *s {
                NoStencil::NotGregory(e) => RefusalReason::NotGregory(e),
                NoStencil::TooLarge { ring, .. } => RefusalReason::RingTooLarge {
                    ring,
                    max: MAX_RING,
                },
                NoStencil::OverLimit { ring, limit, .. } => {
                    RefusalReason::RingTooLarge { ring, max: limit }
                }
            },
        }));
        PassPlan {
            tables: (!plan.layout.faces.is_empty()).then(|| {
                Arc::new(GregoryStencilTables {
                    topology: topo.clone(),
                    plan,
                }) as Arc<dyn PassTables>
            }),
            refused,
        }
    }
}

/// CPU tables of the stencil pass.
#[derive(Debug, Clone)]
pub struct GregoryStencilTables {
    /// Topology of the surface.
    pub topology: Arc<Topology>,
    /// Stencils and shared layout, in draw order.
    pub plan: StencilPlan,
}

impl PassTables for GregoryStencilTables {
    fn pass_name(&self) -> &'static str {
        GREGORY_STENCIL.name()
    }

    fn faces(&self) -> &[u32] {
        &self.plan.layout.faces
    }

    fn patch_count(&self) -> usize {
        self.plan.layout.faces.len()
    }

    fn corner_frames(&self, positions: &[DVec3], _: NormalRule<'_>, frames: &mut VertexFrames) {
        gregory::corner_frames(&self.topology, &self.plan.layout, positions, frames);
    }

    fn framing_points(&self, frames: &VertexFrames) -> Vec<DVec3> {
        gregory::framing_points(&self.plan.layout, frames)
    }

    fn patch_level_limit(&self, spacing: Spacing) -> PatchLevelLimit {
        gregory::level_limit(&self.plan.layout, spacing, f32::INFINITY)
    }

    fn capture_layout(&self) -> super::traits::CaptureLayout {
        super::traits::CaptureLayout::FaceDomainOrBarycentric
    }

    fn reference(&self, positions: &[DVec3], face: u32) -> Option<ReferencePatch> {
        gregory::reference(&self.topology, &self.plan.layout, positions, face)
    }

    fn create_pass(&self, pc: &PassContext<'_>) -> Result<Box<dyn PatchPass>> {
        Ok(Box::new(GregoryStencilPass::new(pc, &self.plan)?))
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}

/// GPU resources and pipelines of the stencil-variant Gregory patches of one surface.
pub struct GregoryStencilPass {
    ctx: Context,
    groups: Vec<DrawGroup>,
    count: u32,
    split: u32,
    /// Largest level of a quad sub-patch and of a (whole) triangle (`PatchDraws::max_level`).
    max_levels: [f32; 2],
    positions: Vec<vk::Buffer>,
    _weights: Buffer,
    _masks: Buffer,
    _records: Buffer,
    _tes: GregoryTesBuffers,
    indices: Buffer,
    _pool: DescriptorPool,
    /// Set 0 per frame slot.
    set0: Vec<vk::DescriptorSet>,
    set1: vk::DescriptorSet,
}

impl GregoryStencilPass {
    fn new(pc: &PassContext<'_>, plan: &StencilPlan) -> Result<GregoryStencilPass> {
        let ctx = pc.ctx;
        if let Some(p) = plan
            .table
            .patches
            .iter()
            .find(|p| p.ring.iter().any(|&v| v as usize >= pc.positions.len()))
        {
            return Err(Error::Invalid(format!(
                "gregory-stencil: face {} uses a vertex beyond the {} positions",
                p.face,
                pc.positions.len()
            )));
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
                    pipeline: pipeline(pc, tri, size_of(tri))?,
                });
            }
        }
        let (w, m, r, ix) = buffers_words(&plan.table, size_of);
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let weights = device_buffer(ctx, &f32_bytes(&w), storage, "gregory stencil weights")?;
        let masks = device_buffer(ctx, &u32_bytes(&m), storage, "gregory stencil masks")?;
        let records = device_buffer(ctx, &u32_bytes(&r), storage, "gregory stencil records")?;
        let indices = device_buffer(
            ctx,
            &u32_bytes(&ix),
            vk::BufferUsageFlags::INDEX_BUFFER,
            "gregory stencil ring indices",
        )?;
        let tes = GregoryTesBuffers::new(ctx, &plan.layout)?;
        let n = pc.shared.slot_count() as u32;
        let pool = DescriptorPool::new(ctx, n + 1, 9 * n + 3, n)?;
        let (mut set0, mut set1) = (Vec::new(), vk::DescriptorSet::null());
        if let Some(g) = groups.first() {
            set0 =
                pc.shared
                    .set0_per_slot(ctx, &pool, g.pipeline.set_layouts[0], &tes.bindings())?;
            set1 = pool.allocate(g.pipeline.set_layouts[1])?;
            let sb = |binding, buffer| BufferBinding {
                binding,
                kind: DescriptorKind::StorageBuffer,
                buffer,
            };
            ctx.write_buffer_descriptors(set1, &[sb(0, &weights), sb(1, &masks), sb(2, &records)]);
        }
        Ok(GregoryStencilPass {
            ctx: ctx.clone(),
            groups,
            count: total,
            split: pc.desc.tess.split(),
            max_levels: [pc.largest_level(pc.desc.tess.split()), pc.largest_level(1)],
            positions: (0..n as usize).map(|k| pc.shared.positions(k)).collect(),
            _weights: weights,
            _masks: masks,
            _records: records,
            _tes: tes,
            indices,
            _pool: pool,
            set0,
            set1,
        })
    }
}

impl PatchPass for GregoryStencilPass {
    fn label(&self) -> &'static str {
        "gregory patches"
    }

    fn memory_bytes(&self) -> u64 {
        self._weights.size()
            + self._masks.size()
            + self._records.size()
            + self._tes.memory_bytes()
            + self.indices.size()
    }

    fn patch_count(&self) -> u32 {
        self.count
    }

    /// Quads with the renderer's sub-patch split, triangles whole but told the quads' split, so
    /// their edge levels and edge parameters match the split quads (`gregory_tri_edge_level` /
    /// `edge_ts` in `glsl/gregory/`).
    fn record(&self, cmd: vk::CommandBuffer, slot: usize) {
        let dev = self.ctx.device();
        for g in &self.groups {
            bind_draw_state(
                dev,
                cmd,
                &g.pipeline,
                &[self.set0[slot], self.set1],
                Some(self.positions[slot]),
                self.indices.raw(),
            );
            let draws = PatchDraws {
                first_patch: g.first_record,
                first_index: g.first_index,
                count: g.count,
                points: g.points,
                sub_draws: if g.triangle {
                    1
                } else {
                    self.split * self.split
                },
                sub_flag: 0,
                max_level: self.max_levels[usize::from(g.triangle)],
            };
            record_patch_draws(dev, cmd, &g.pipeline, &draws, self.split);
        }
    }

    fn update_positions(&mut self, _: &[DVec3], _: &VertexFrames) -> Result<()> {
        // The TCS sums the shared control positions with the fixed stencils.
        Ok(())
    }
}

fn pipeline(pc: &PassContext<'_>, triangle: bool, points: u32) -> Result<Pipeline> {
    let shape = if triangle { "tri" } else { "quad" };
    patch_pipeline(
        pc.ctx,
        pc.desc,
        pc.target,
        PatchShaders {
            label: format!("gregory stencil {shape} patches, {points} ring points"),
            vertex: "gregory_stencil.vert".into(),
            tess_control: format!("gregory_stencil_{shape}.tesc"),
            tess_eval_stem: if triangle {
                "patch_gregory_tri"
            } else {
                "patch_gregory_quad"
            },
            points,
            position_input: true,
            set_layouts: vec![
                set0_layout(&[
                    gregory::UNUSED_PATCH_INFO_BINDING,
                    gregory::PATCH_RECORDS_BINDING,
                    gregory::GRIDS_BINDING,
                ]),
                stencil_set_layout(),
            ],
        },
    )
}
