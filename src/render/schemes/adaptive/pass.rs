//! The GPU pass of `--scheme adaptive`: per frame, the refinement kernels
//! ([`GpuRefiner`]) and the derived points ([`DerivedPoints`]: corner frames, end-cap control
//! points) before the render pass; then five draws reading the refined buffer: B-spline
//! patches of every level (`glsl/adaptive/patch_adaptive_bspline.*`), transition patches as
//! triangle fans (`patch_adaptive_transition.*`), single-crease patches whole and as fans
//! (`patch_adaptive_single_crease.*`, `patch_adaptive_sc_transition.*`) and Gregory end caps
//! (`patch_adaptive_endcap.*`). One set 0 serves the five pipelines. Above the patch level
//! limit a level's quads are drawn as sub-patches and its fan triangles as sub-triangles
//! ([`level_split`], `fan_sub_split`).

use ash::vk;
use glam::DVec3;

use super::derive::DerivedPoints;
use super::refine::GpuRefiner;
use crate::gpu::{Buffer, BufferBinding, Context, DescriptorKind, DescriptorPool, Pipeline};
use crate::patch::adaptive::records::{BSplineDraw, TransitionTriangle};
use crate::patch::adaptive::AdaptiveDrawTables;
use crate::render::pass::pipeline::{patch_pipeline, PatchShaders};
use crate::render::pass::shared::{
    set0_layout, CONTROL_POSITIONS_BINDING, VERTEX_LIMITS_BINDING, VERTEX_NORMALS_BINDING,
};
use crate::render::pass::upload::device_buffer;
use crate::render::pass::{bind_draw_state, record_patch_draws, PatchDraws, VertexFrames};
use crate::render::schemes::traits::PassContext;
use crate::render::schemes::{PassTables, PatchPass};
use crate::subdiv::tables::{KernelRange, RefinementTables};
use crate::Result;

/// The pass's own set-0 bindings (`glsl/common/frame.glsl`, `gregory/gregory.glsl`,
/// `adaptive/*.glsl`, `single_crease/single_crease.glsl`): B-spline and single-crease patch
/// records, Gregory records, Gregory grids, adaptive patch records, coarse edges, transition
/// triangles, per-record crease sharpness, end-cap lattice regions, then end-cap points.
const OWN_BINDINGS: [u32; 9] = [1, 6, 7, 10, 11, 12, 4, 16, 13];

/// One pipeline's patches: index buffer (control points or one dummy index per patch) and
/// the runs it is drawn in.
struct DrawGroup {
    /// What it draws (its pipeline's label).
    label: String,
    pipeline: Pipeline,
    /// Which of [`index_bytes`] it draws.
    table: usize,
    first_patch: u32,
    indices: Buffer,
    points: u32,
    vertices: Option<vk::Buffer>,
    /// Runs of consecutive patches drawn with one split ([`split_runs`], [`fan_runs`]).
    runs: Vec<Run>,
}

/// Consecutive patches (from `first`, `count` of them) drawn with push constant `split` (the
/// split of their level, [`level_split`]) as `sub_draws` sub-patches each.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Run {
    first: u32,
    count: u32,
    split: u32,
    sub_draws: u32,
}

/// Sub-patches per side of a level-`level` patch when level-0 patches are split `split` x
/// `split` (`TessSettings::split`): a level-k patch gets the uniform level / 2^k, so it needs
/// `split / 2^k`, at least 1.
pub fn level_split(split: u32, level: u32) -> u32 {
    split.checked_shr(level).unwrap_or(0).max(1)
}

/// Sub-triangles per side of a fan triangle of a level-`level` patch (`half`: on a half edge)
/// when level-0 patches are split `split` x `split`: s = [`level_split`] for a whole edge, s / 2
/// (at least 1) for a half edge, whose finer owner is split half as often; 1 when the level is
/// drawn whole (`glsl/adaptive/transition.glsl`, `fan_split`, derives the same from s).
fn fan_sub_split(split: u32, level: u32, half: bool) -> u32 {
    let s = level_split(split, level);
    if half {
        (s / 2).max(1)
    } else {
        s
    }
}

/// Runs of consecutive patches drawn alike: `keys` per patch in draw order, (split, sub-patches
/// per side).
fn runs_of(keys: impl Iterator<Item = (u32, u32)>) -> Vec<Run> {
    let mut runs: Vec<Run> = Vec::new();
    for (k, (split, n)) in keys.enumerate() {
        match runs.last_mut() {
            Some(r) if (r.split, r.sub_draws) == (split, n * n) => r.count += 1,
            _ => runs.push(Run {
                first: k as u32,
                count: 1,
                split,
                sub_draws: n * n,
            }),
        }
    }
    runs
}

/// Runs of consecutive quad patches with the same split (`levels` per patch in draw order),
/// each drawn as split x split sub-patches.
fn split_runs(levels: impl Iterator<Item = u32>, split: u32) -> Vec<Run> {
    runs_of(levels.map(|l| {
        let s = level_split(split, l);
        (s, s)
    }))
}

/// The draw order of fan triangles (`fans`: level and half-edge flag per triangle, table order)
/// and its runs: sorted, stably, by the level's split and [`fan_sub_split`], so one run draws
/// one number of sub-triangles; `order[k]` is the table index of the k-th drawn triangle.
fn fan_runs(fans: &[(u32, bool)], split: u32) -> (Vec<u32>, Vec<Run>) {
    let key = |&(level, half): &(u32, bool)| {
        (level_split(split, level), fan_sub_split(split, level, half))
    };
    let mut order: Vec<u32> = (0..fans.len() as u32).collect();
    order.sort_by_key(|&k| key(&fans[k as usize]));
    let runs = runs_of(order.iter().map(|&k| key(&fans[k as usize])));
    (order, runs)
}

/// Level and half-edge flag of every fan triangle: B-spline fans, then single-crease fans.
fn fan_levels(d: &AdaptiveDrawTables) -> [Vec<(u32, bool)>; 2] {
    let of = |draws: &[BSplineDraw], tris: &[TransitionTriangle]| -> Vec<(u32, bool)> {
        tris.iter()
            .map(|t| {
                let record = draws[t.patch as usize].record;
                (d.records[record as usize].level, t.half != 0)
            })
            .collect()
    };
    [
        of(&d.transition, &d.triangles),
        of(&d.single_crease_transition, &d.single_crease_triangles),
    ]
}

/// The fan triangles' draw orders and runs ([`fan_runs`]) of both fan groups.
type FanOrders = [(Vec<u32>, Vec<Run>); 2];

fn fan_orders(d: &AdaptiveDrawTables, split: u32) -> FanOrders {
    fan_levels(d).map(|fans| fan_runs(&fans, split))
}

/// `bytes`, records of `stride` bytes, in the order `order` (table indices).
fn permuted(bytes: &[u8], stride: usize, order: &[u32]) -> Vec<u8> {
    order
        .iter()
        .flat_map(|&k| &bytes[k as usize * stride..(k as usize + 1) * stride])
        .copied()
        .collect()
}

/// GPU resources of the adaptive scheme for one surface.
pub struct AdaptivePass {
    ctx: Context,
    refiner: GpuRefiner,
    derived: DerivedPoints,
    records: Vec<Buffer>,
    groups: Vec<DrawGroup>,
    _pool: DescriptorPool,
    /// Set 0 per frame slot.
    sets: Vec<vk::DescriptorSet>,
    /// The shared control positions per frame slot (level 0 of the refinement).
    control: Vec<vk::Buffer>,
    patches: u32,
    /// What [`PatchPass::update_tables`] must keep.
    layout: TableLayout,
    /// Finds the tables in what [`PatchPass::update_tables`] gets.
    tables_of: TablesOf,
    /// The level-0 patches' split the draws were recorded for (`TessSettings::split`).
    split: u32,
    /// Largest level of a drawn (sub-)patch (`PatchDraws::max_level`), that of a whole level-0
    /// patch for every run (an upper bound whatever the run's split): past
    /// `MAX_DOMAIN_POINTS_PER_DRAW` domain points in one draw lavapipe's triangles join wrong
    /// vertices. Binds the end caps (one index per patch, so 1,024 per draw by the index rule
    /// alone: the car's 1,248 end caps at level 8 made 82,944 points in one draw).
    max_level: f32,
}

/// The kernels' and draw tables inside tables of this scheme (`super::AdaptiveTables`, whose
/// `create_pass` gives it, so this module need not name the type), or `None` for another pass's.
pub type TablesOf = fn(&dyn PassTables) -> Option<(&RefinementTables, &AdaptiveDrawTables)>;

/// The layout a run-time table change must keep, since it rewrites the buffers in place (the
/// draws, dispatches and descriptor sets stay): patch and refined-point counts, the kernels'
/// table words and dispatch ranges, and the byte length of every other table.
#[derive(Debug, PartialEq, Eq)]
struct TableLayout {
    patches: usize,
    refined_points: u32,
    refinement: (usize, Vec<[KernelRange; 3]>),
    records: [usize; 8],
    indices: [usize; 5],
    rows: [usize; 4],
    /// The fan groups' draw runs.
    fan_runs: [Vec<Run>; 2],
}

impl TableLayout {
    /// The layout of draw tables `d` with `refined_points` refined points, the kernels' table
    /// words and dispatch ranges `refinement`, the byte tables built from them ([`record_bytes`],
    /// [`index_bytes`], `DerivedPoints::row_bytes` lengths) and the fan orders `fans`.
    fn new(
        d: &AdaptiveDrawTables,
        refined_points: u32,
        refinement: (usize, &[[KernelRange; 3]]),
        records: &[Vec<u8>; 8],
        indices: &[Vec<u8>; 5],
        rows: [usize; 4],
        fans: &FanOrders,
    ) -> TableLayout {
        TableLayout {
            patches: d.primitive_count(),
            refined_points,
            refinement: (refinement.0, refinement.1.to_vec()),
            records: records.each_ref().map(Vec::len),
            indices: indices.each_ref().map(Vec::len),
            rows,
            fan_runs: fans.each_ref().map(|(_, runs)| runs.clone()),
        }
    }
}

/// Labels of the record tables ([`record_bytes`]).
const RECORD_LABELS: [&str; 8] = [
    "adaptive b-spline records",
    "adaptive end-cap records",
    "adaptive end-cap grids",
    "adaptive patch records",
    "adaptive coarse edges",
    "adaptive transition fans",
    "adaptive crease sharpness",
    "adaptive end-cap lattice",
];

/// The record tables, bound at [`OWN_BINDINGS`]`[..8]`, fan triangles in the draw order of
/// `fans`.
fn record_bytes(d: &AdaptiveDrawTables, fans: &FanOrders) -> [Vec<u8>; 8] {
    [
        bspline_info_bytes(d),
        end_cap_info_bytes(d),
        d.end_cap_grid_bytes(),
        d.patch_record_bytes(),
        d.coarse_edge_bytes(),
        triangle_bytes(d, fans),
        d.sharpness_bytes(),
        d.end_cap_lattice_bytes(),
    ]
}

/// The index buffers of the five draw groups: B-spline patches, transition triangles,
/// single-crease patches, single-crease transition triangles (both in the draw order of
/// `fans`), end caps (one dummy index each).
fn index_bytes(d: &AdaptiveDrawTables, fans: &FanOrders) -> [Vec<u8>; 5] {
    [
        d.regular_index_bytes(),
        permuted(&d.triangle_index_bytes(), 64, &fans[0].0),
        d.single_crease_index_bytes(),
        permuted(&d.single_crease_triangle_index_bytes(), 64, &fans[1].0),
        vec![0u8; 4 * d.end_caps.len()],
    ]
}

/// `bytes` as a device-local storage or index buffer (16 zero bytes when empty: a binding needs
/// a buffer).
fn table_buffer(
    ctx: &Context,
    bytes: Vec<u8>,
    usage: vk::BufferUsageFlags,
    label: &str,
) -> Result<Buffer> {
    let bytes = if bytes.is_empty() {
        vec![0u8; 16]
    } else {
        bytes
    };
    device_buffer(ctx, &bytes, usage, label)
}

/// The `PatchInfo` records of binding 1: regular B-spline patches, B-spline transition patches,
/// whole single-crease patches, single-crease transition patches.
fn bspline_info_bytes(d: &AdaptiveDrawTables) -> Vec<u8> {
    let mut bytes = d.regular_info_bytes();
    bytes.extend(d.transition_info_bytes());
    bytes.extend(d.single_crease_info_bytes());
    bytes
}

/// The transition triangles (binding 12), B-spline fans then single-crease fans, each in the
/// draw order of `fans`, with their patch index into [`bspline_info_bytes`].
fn triangle_bytes(d: &AdaptiveDrawTables, fans: &FanOrders) -> Vec<u8> {
    let offset = d.regular.len() as u32;
    let bytes = rewrite_word(d.triangle_bytes(), 16, 0, |w| w + offset);
    let mut out = permuted(&bytes, 16, &fans[0].0);
    let offset = (d.regular.len() + d.transition.len() + d.single_crease.len()) as u32;
    let bytes = rewrite_word(d.single_crease_triangle_bytes(), 16, 0, |w| w + offset);
    out.extend(permuted(&bytes, 16, &fans[1].0));
    out
}

/// The end caps' `GregoryPatchInfo` records (binding 6) with `pad1` (word 3) the first of their
/// points in the end-cap point buffer (rows counted from `end_cap_first_row`).
fn end_cap_info_bytes(d: &AdaptiveDrawTables) -> Vec<u8> {
    rewrite_word(d.end_cap_info_bytes(), 32, 3, |w| w - d.end_cap_first_row)
}

/// `bytes` with word `word` of every `stride`-byte record replaced by `f` of it.
fn rewrite_word(mut bytes: Vec<u8>, stride: usize, word: usize, f: impl Fn(u32) -> u32) -> Vec<u8> {
    for record in bytes.chunks_exact_mut(stride) {
        let at = &mut record[4 * word..4 * word + 4];
        let w = u32::from_le_bytes([at[0], at[1], at[2], at[3]]);
        at.copy_from_slice(&f(w).to_le_bytes());
    }
    bytes
}

impl AdaptivePass {
    /// Uploads the kernels' tables `refinement` and the draw tables `d` and creates the
    /// pipelines; `tables_of` finds both in new tables of the same scheme (run-time changes).
    pub fn new(
        pc: &PassContext<'_>,
        refinement: &RefinementTables,
        d: &AdaptiveDrawTables,
        tables_of: TablesOf,
    ) -> Result<AdaptivePass> {
        let ctx = pc.ctx;
        let refiner = GpuRefiner::new(ctx, refinement, pc.positions)?;
        let derived = DerivedPoints::new(ctx, d, refiner.points())?;
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let index = vk::BufferUsageFlags::INDEX_BUFFER;
        let split = pc.desc.tess.split();
        let fans = fan_orders(d, split);
        let record_bytes = record_bytes(d, &fans);
        let index_bytes = index_bytes(d, &fans);
        let layout = TableLayout::new(
            d,
            refiner.total_vertices(),
            refiner.table_layout(),
            &record_bytes,
            &index_bytes,
            derived.row_lens(),
            &fans,
        );
        let records = record_bytes
            .into_iter()
            .zip(RECORD_LABELS)
            .map(|(bytes, label)| table_buffer(ctx, bytes, storage, label))
            .collect::<Result<Vec<_>>>()?;
        let set0 = set0_layout(&OWN_BINDINGS);
        let shaders =
            |label: &str, vertex: &str, stem: &'static str, points, position_input| PatchShaders {
                label: label.into(),
                vertex: vertex.into(),
                tess_control: format!("{stem}.tesc"),
                tess_eval_stem: stem,
                points,
                position_input,
                set_layouts: vec![set0.clone()],
            };
        let points = Some(refiner.points().raw());
        let level_of = |record: u32| d.records[record as usize].level;
        let quad_levels: [Vec<u32>; 3] = [
            d.regular.iter().map(|p| level_of(p.record)).collect(),
            d.single_crease.iter().map(|p| level_of(p.record)).collect(),
            d.end_caps.iter().map(|p| level_of(p.record)).collect(),
        ];
        let mut groups = Vec::new();
        let bspline_records = (d.regular.len() + d.transition.len()) as u32;
        for (table, (indices, (first_patch, count, s, vertices))) in index_bytes
            .into_iter()
            .zip([
                (
                    0,
                    d.regular.len() as u32,
                    shaders(
                        "adaptive b-spline",
                        "patch_bspline.vert",
                        "patch_adaptive_bspline",
                        16,
                        true,
                    ),
                    points,
                ),
                (
                    0,
                    d.triangles.len() as u32,
                    shaders(
                        "adaptive transition",
                        "patch_bspline.vert",
                        "patch_adaptive_transition",
                        16,
                        true,
                    ),
                    points,
                ),
                (
                    bspline_records,
                    d.single_crease.len() as u32,
                    shaders(
                        "adaptive single-crease",
                        "patch_bspline.vert",
                        "patch_adaptive_single_crease",
                        16,
                        true,
                    ),
                    points,
                ),
                (
                    d.triangles.len() as u32,
                    d.single_crease_triangles.len() as u32,
                    shaders(
                        "adaptive single-crease transition",
                        "patch_bspline.vert",
                        "patch_adaptive_sc_transition",
                        16,
                        true,
                    ),
                    points,
                ),
                (
                    0,
                    d.end_caps.len() as u32,
                    shaders(
                        "adaptive end caps",
                        "patch_adaptive_endcap.vert",
                        "patch_adaptive_endcap",
                        1,
                        false,
                    ),
                    None,
                ),
            ])
            .enumerate()
        {
            if count == 0 {
                continue;
            }
            let points = s.points;
            let quads = match table {
                0 => Some(&quad_levels[0]),
                2 => Some(&quad_levels[1]),
                4 => Some(&quad_levels[2]),
                _ => None,
            };
            let runs = match (quads, table) {
                (Some(levels), _) => split_runs(levels.iter().copied(), split),
                (None, 1) => fans[0].1.clone(),
                (None, _) => fans[1].1.clone(),
            };
            groups.push(DrawGroup {
                label: s.label.clone(),
                pipeline: patch_pipeline(ctx, pc.desc, pc.target, s)?,
                table,
                first_patch,
                indices: table_buffer(ctx, indices, index, "adaptive indices")?,
                points,
                vertices,
                runs,
            });
        }
        let n = pc.shared.slot_count() as u32;
        let pool = DescriptorPool::new(ctx, n, 16 * n, n)?;
        let set0 = match groups.first() {
            Some(g) => g.pipeline.set_layouts[0],
            None => {
                return Err(crate::Error::Invalid(
                    "adaptive scheme: no patch to draw".into(),
                ))
            }
        };
        let sb = |binding, buffer| BufferBinding {
            binding,
            kind: DescriptorKind::StorageBuffer,
            buffer,
        };
        let mut own: Vec<BufferBinding<'_>> = OWN_BINDINGS[..8]
            .iter()
            .zip(&records)
            .map(|(&b, buf)| sb(b, buf))
            .collect();
        own.push(sb(13, derived.end_cap_points()));
        own.push(sb(CONTROL_POSITIONS_BINDING, refiner.points()));
        own.push(sb(VERTEX_LIMITS_BINDING, derived.limits()));
        own.push(sb(VERTEX_NORMALS_BINDING, derived.normals()));
        let sets = pc.shared.set0_per_slot(ctx, &pool, set0, &own)?;
        Ok(AdaptivePass {
            ctx: ctx.clone(),
            split,
            layout,
            tables_of,
            max_level: pc.largest_level(1),
            patches: d.primitive_count() as u32,
            refiner,
            derived,
            records,
            groups,
            _pool: pool,
            sets,
            control: (0..n as usize).map(|k| pc.shared.positions(k)).collect(),
        })
    }

    /// The refinement (tests read its points back).
    pub fn refiner(&self) -> &GpuRefiner {
        &self.refiner
    }

    /// The derived points (tests read the frames back).
    pub fn derived(&self) -> &DerivedPoints {
        &self.derived
    }

    /// Bytes of GPU memory held by the pass (tables, refined and derived points).
    pub fn memory_bytes(&self) -> u64 {
        self.refiner.memory_bytes()
            + self.derived.memory_bytes()
            + self.records.iter().map(Buffer::size).sum::<u64>()
            + self.groups.iter().map(|g| g.indices.size()).sum::<u64>()
    }
}

impl PatchPass for AdaptivePass {
    fn label(&self) -> &'static str {
        "adaptive patches"
    }

    fn patch_count(&self) -> u32 {
        self.patches
    }

    fn memory_bytes(&self) -> u64 {
        AdaptivePass::memory_bytes(self)
    }

    fn record_compute(&self, cmd: vk::CommandBuffer, slot: usize) {
        let dev = self.ctx.device();
        self.refiner.record_from(dev, cmd, self.control[slot]);
        self.derived.record(dev, cmd);
    }

    fn record(&self, cmd: vk::CommandBuffer, slot: usize) {
        for k in 0..self.groups.len() {
            self.record_group(cmd, slot, k);
        }
    }

    fn draw_groups(&self) -> Vec<String> {
        self.groups.iter().map(|g| g.label.clone()).collect()
    }

    fn record_group(&self, cmd: vk::CommandBuffer, slot: usize, group: usize) {
        let Some(g) = self.groups.get(group) else {
            return;
        };
        let dev = self.ctx.device();
        bind_draw_state(
            dev,
            cmd,
            &g.pipeline,
            &[self.sets[slot]],
            g.vertices,
            g.indices.raw(),
        );
        for r in &g.runs {
            let draws = PatchDraws {
                first_patch: g.first_patch + r.first,
                first_index: r.first * g.points,
                count: r.count,
                points: g.points,
                sub_draws: r.sub_draws,
                sub_flag: 0,
                max_level: self.max_level,
            };
            record_patch_draws(dev, cmd, &g.pipeline, &draws, r.split);
        }
    }

    fn update_positions(&mut self, _: &[DVec3], _: &VertexFrames) -> Result<()> {
        // Only the control points cross the bus (the shared positions of each frame slot,
        // copied into level 0 by `record_compute`); refinement and frames run on the GPU.
        Ok(())
    }

    /// New tables of the same layout (new crease sharpness that refines the same faces to the
    /// same levels, `AdaptiveTables::with_sharpness`): every table is rewritten in
    /// place; pipelines, draws and descriptor sets stay. Another layout is an error naming
    /// what changed, and nothing is written.
    fn update_tables(&mut self, tables: &dyn PassTables) -> Result<()> {
        let (kernels, d) = (self.tables_of)(tables)
            .ok_or_else(|| crate::Error::Invalid("adaptive pass: tables of another pass".into()))?;
        let fans = fan_orders(d, self.split);
        let records = record_bytes(d, &fans);
        let indices = index_bytes(d, &fans);
        let rows = DerivedPoints::row_bytes(d);
        let refinement = kernels.gpu_tables();
        let layout = TableLayout::new(
            d,
            kernels.total_vertices,
            (refinement.words.len(), &refinement.steps),
            &records,
            &indices,
            rows.each_ref().map(Vec::len),
            &fans,
        );
        if layout != self.layout {
            return Err(crate::Error::Invalid(format!(
                "the new sharpness changes the adaptive refinement ({} -> {} patches, {} -> {} \
                 refined points, {} -> {} stencil-row terms): plan the surface again with the new \
                 creases",
                self.layout.patches,
                layout.patches,
                self.layout.refined_points,
                layout.refined_points,
                self.layout.rows[1] / 4,
                layout.rows[1] / 4,
            )));
        }
        let ctx = &self.ctx;
        self.refiner.rewrite_tables(ctx, &refinement)?;
        self.derived.rewrite_rows(ctx, &rows)?;
        for ((buffer, bytes), label) in self.records.iter().zip(&records).zip(RECORD_LABELS) {
            ctx.rewrite_buffer(buffer, bytes, label)?;
        }
        for g in &self.groups {
            ctx.rewrite_buffer(&g.indices, &indices[g.table], "adaptive indices")?;
        }
        Ok(())
    }
}
