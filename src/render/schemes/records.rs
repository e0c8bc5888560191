//! Passes of host-written per-patch records (QAS, ACC; Pm's fixed records): the CPU builds every
//! patch's coefficients into one record per patch (rewritten per animation frame unless they
//! do not depend on the positions, [`FixedRecords`]), the tessellation
//! stages read the record of `patch_base + gl_PrimitiveID` from set 0 binding 4; the patch
//! primitive has one point and no vertex input (`record_patch.vert`). Groups (one pipeline each,
//! e.g. quads then triangles) are drawn whole (not split into sub-patches) at levels up to
//! [`PassContext::largest_level`] of 1, which bounds the patches per draw
//! ([`crate::gpu::patch_draw_chunks`]).

use ash::vk;
use glam::DVec3;

use super::{PassContext, PatchPass};
use crate::gpu::{Buffer, BufferBinding, Context, DescriptorKind, DescriptorPool, Pipeline};
use crate::render::pass::pipeline::{patch_pipeline, PatchShaders};
use crate::render::pass::shared::set0_layout;
use crate::render::pass::upload::{device_buffer, host_buffer};
use crate::render::pass::VertexFrames;
use crate::render::pass::{bind_draw_state, record_patch_draws, PatchDraws};
use crate::Result;

/// Set-0 binding of the records.
pub const RECORDS_BINDING: u32 = 4;
/// Set-0 binding the shared frame block declares for B-spline records; bound to the records so
/// the layout is complete (unused by these stages).
const UNUSED_PATCH_INFO_BINDING: u32 = 1;

/// One pipeline's run of patches.
pub struct RecordGroup {
    /// Tessellation control shader.
    pub tess_control: &'static str,
    /// Evaluation-shader stem.
    pub tess_eval_stem: &'static str,
    /// First patch (record) of the run.
    pub first: u32,
    /// Patches in the run.
    pub count: u32,
}

/// GPU resources of a pass of host-written records.
pub struct RecordPass {
    ctx: Context,
    records: Buffer,
    indices: Buffer,
    _pool: DescriptorPool,
    /// Set 0 per frame slot (the shared bindings of that slot, the records).
    sets: Vec<vk::DescriptorSet>,
    groups: Vec<(Pipeline, u32, u32)>,
    /// Largest level of a patch (drawn whole; `PatchDraws::max_level`).
    max_level: f32,
    count: u32,
}

impl RecordPass {
    /// Uploads `records` (one per patch) and creates a pipeline per non-empty group.
    pub fn new(
        pc: &PassContext<'_>,
        label: &str,
        records: &[u8],
        groups: &[RecordGroup],
    ) -> Result<RecordPass> {
        let ctx = pc.ctx;
        let records = host_buffer(
            ctx,
            records,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            &format!("{label} records"),
        )?;
        let count: u32 = groups.iter().map(|g| g.count).sum();
        let indices = device_buffer(
            ctx,
            &vec![0u8; 4 * count as usize],
            vk::BufferUsageFlags::INDEX_BUFFER,
            &format!("{label} patch indices"),
        )?;
        let own = [UNUSED_PATCH_INFO_BINDING, RECORDS_BINDING];
        let mut pipelines = Vec::new();
        for g in groups.iter().filter(|g| g.count > 0) {
            let pipeline = patch_pipeline(
                ctx,
                pc.desc,
                pc.target,
                PatchShaders {
                    label: format!("{label} {}", g.tess_eval_stem),
                    vertex: "record_patch.vert".into(),
                    tess_control: g.tess_control.into(),
                    tess_eval_stem: g.tess_eval_stem,
                    points: 1,
                    position_input: false,
                    set_layouts: vec![set0_layout(&own)],
                },
            )?;
            pipelines.push((pipeline, g.first, g.count));
        }
        let layout = pipelines
            .first()
            .map(|p| p.0.set_layouts[0])
            .ok_or_else(|| {
                crate::Error::Invalid(format!("{label}: a record pass needs at least one patch"))
            })?;
        let n = pc.shared.slot_count() as u32;
        let pool = DescriptorPool::new(ctx, n, n * (5 + own.len() as u32), n)?;
        let sb = |binding| BufferBinding {
            binding,
            kind: DescriptorKind::StorageBuffer,
            buffer: &records,
        };
        let sets = pc.shared.set0_per_slot(
            ctx,
            &pool,
            layout,
            &[sb(UNUSED_PATCH_INFO_BINDING), sb(RECORDS_BINDING)],
        )?;
        Ok(RecordPass {
            ctx: ctx.clone(),
            records,
            indices,
            _pool: pool,
            sets,
            groups: pipelines,
            max_level: pc.largest_level(1),
            count,
        })
    }

    /// Patches drawn.
    pub fn patch_count(&self) -> u32 {
        self.count
    }

    /// Bytes of the records and indices.
    pub fn memory_bytes(&self) -> u64 {
        self.records.size() + self.indices.size()
    }

    /// Rewrites the records (same count; animation). One buffer serves every frame slot, so
    /// as [`PatchPass::update_positions`] says, no frame using it may be executing.
    pub fn write_records(&mut self, bytes: &[u8]) -> Result<()> {
        self.records.write(0, bytes)
    }

    /// Records the draws of every group of frame slot `slot` inside the caller's render pass.
    pub fn record(&self, cmd: vk::CommandBuffer, slot: usize) {
        let dev = self.ctx.device();
        for (pipeline, first, count) in &self.groups {
            let run = PatchDraws::whole(*first, *first, *count, 1, self.max_level);
            let draw_state = (&[self.sets[slot]][..], self.indices.raw());
            record_run(dev, cmd, pipeline, draw_state, &run);
        }
    }
}

/// Binds `pipeline` with `draw_state` (descriptor sets, index buffer) and records the patches
/// of `run` (drawn whole) with [`record_patch_draws`].
pub fn record_run(
    dev: &ash::Device,
    cmd: vk::CommandBuffer,
    pipeline: &Pipeline,
    draw_state: (&[vk::DescriptorSet], vk::Buffer),
    run: &PatchDraws,
) {
    bind_draw_state(dev, cmd, pipeline, draw_state.0, None, draw_state.1);
    record_patch_draws(dev, cmd, pipeline, run, 1);
}

/// Tables whose patches are drawn as records: the record bytes for control positions.
pub trait RecordTables: Clone + 'static {
    /// One record per patch, in draw order, for control positions `positions`.
    fn records(&self, positions: &[DVec3]) -> Result<Vec<u8>>;

    /// Whether the records change with the control positions (true: animation rewrites them;
    /// false: the stages read the positions themselves, e.g. through stencil rows).
    fn follow_positions(&self) -> bool {
        true
    }
}

/// Records that do not depend on the control positions (stencil rows and indices the stages
/// apply to the shared control positions, as Pm's): written once.
#[derive(Debug, Clone)]
pub struct FixedRecords(pub std::sync::Arc<[u8]>);

impl RecordTables for FixedRecords {
    fn records(&self, _: &[DVec3]) -> Result<Vec<u8>> {
        Ok(self.0.to_vec())
    }

    fn follow_positions(&self) -> bool {
        false
    }
}

/// The pass of a scheme drawn from records: its tables and the GPU resources; animation
/// rebuilds the records on the CPU.
pub struct RecordTablesPass<T> {
    label: &'static str,
    tables: T,
    pass: RecordPass,
}

impl<T: RecordTables> RecordTablesPass<T> {
    /// The pass of `tables` for the positions of `pc`, one pipeline per group.
    pub fn new(
        pc: &PassContext<'_>,
        label: &'static str,
        tables: &T,
        groups: &[RecordGroup],
    ) -> Result<Self> {
        let records = tables.records(pc.positions)?;
        Ok(RecordTablesPass {
            label,
            tables: tables.clone(),
            pass: RecordPass::new(pc, label, &records, groups)?,
        })
    }
}

impl<T: RecordTables> PatchPass for RecordTablesPass<T> {
    fn label(&self) -> &'static str {
        self.label
    }

    fn patch_count(&self) -> u32 {
        self.pass.patch_count()
    }

    fn memory_bytes(&self) -> u64 {
        self.pass.memory_bytes()
    }

    fn record(&self, cmd: vk::CommandBuffer, slot: usize) {
        self.pass.record(cmd, slot);
    }

    fn update_positions(&mut self, positions: &[DVec3], _: &VertexFrames) -> Result<()> {
        if !self.tables.follow_positions() {
            return Ok(());
        }
        let bytes = self.tables.records(positions)?;
        self.pass.write_records(&bytes)
    }
}
