//! Pm-patches on the GPU, vertex-stage variant (`--scheme pm-vs`): the paper's own GPU
//! construction (Myles, Ni, Peters 2008 §6.1; there a DX10 vertex shader and a geometry shader
//! with stream-out). Stage 1, the vertex shader (`glsl/pm_vs/pm_vs.vert`), runs once per control
//! vertex of the drawn facets and computes from its one-ring — read from a connectivity storage
//! buffer (the paper's index texture `I` with start index and valence per vertex, and the crease
//! scalars `a_j`: [`connectivity_words`]) and the dynamic control positions — the per-vertex
//! quantities of §5.1: `v`, the face points `f_j`, `t_1`, `t_2` and `n` (eq. 13-15). Stage 2, the
//! TCS (`glsl/pm_vs/pm_vs_{bicubic,polar,sector}.tesc`), assembles each patch from its corners'
//! data with the per-facet ring indices `j_k` ([`patch_words`]): eq. (16)-(22), Fig. 11. Both
//! stages are the arithmetic of [`crate::patch::pm`] (`pm_vertex`, `facet_corner`, `construct`),
//! whose module docs derive every formula; `tests/scheme_pm.rs` checks the GPU against it.
//!
//! Evaluation is the stencil variant's ([`super::pm`]): the same TES files over the same word
//! buffer, so domain edges (outer edges and inner spokes), corners and Pm centres are evaluated
//! from the shared edge and centre records and stay bitwise equal with every neighbour, while the
//! interior of each patch comes from the coefficients the TCS assembled. The patch primitive is
//! the facet's vertices in facet order (3, 4 or 5 control points; one draw run per patch type and
//! side count), a Pm facet drawn once per sector as in `pm`.
//!
//! Varyings: `4 + 6 + 3 n` floats per vertex of valence `n` in 31 vec4 slots (one location of
//! the 128-component budget is left to the built-in block): valence <= [`MAX_VALENCE`]. Facets
//! with a corner above it are refused ([`RefusalReason::VaryingsBudget`]) and stay on the CPU
//! path, as on devices whose budget is below 128 components.

use std::any::Any;
use std::sync::Arc;

use ash::vk;
use glam::DVec3;

use super::pm::PmTables;
use super::records::record_run;
use super::traits::{
    CaptureLayout, PassContext, PassPlan, PassTables, PatchPass, PatchScheme, PlanOptions,
    ReferencePatch, Refusal, RefusalReason,
};
use crate::gpu::{Buffer, BufferBinding, Context, DescriptorKind, DescriptorPool, Pipeline};
use crate::patch::pm::{corner_slots, far_vertices, FacetClass, PmOptions};
use crate::render::pass::pipeline::{patch_pipeline, PatchShaders};
use crate::render::pass::shared::set0_layout;
use crate::render::pass::upload::{device_buffer, host_buffer, u32_bytes};
use crate::render::pass::{NormalRule, PatchDraws, VertexFrames};
use crate::render::settings::{PatchLevelLimit, Spacing};
use crate::topology::Topology;
use crate::Result;

/// The vertex-stage Pm pass in the registry.
pub static PM_VS: PmVsScheme = PmVsScheme;

/// vec4 output slots of the vertex stage (`PMVS_SLOTS` in `glsl/pm_vs/pm_vs.glsl`).
pub const SLOTS: u32 = 31;
/// Largest valence the varyings hold: `(4 SLOTS - 10) / 3` (`v`, `n`, `t_1`, `t_2`, `f_j`).
pub const MAX_VALENCE: usize = ((4 * SLOTS - 10) / 3) as usize;
/// Words per patch in the per-patch buffer (`PMVS_PATCH_WORDS`).
pub const PATCH_WORDS: usize = 12;

/// Set-0 binding the shared frame block declares for B-spline records (bound to the words).
const UNUSED_PATCH_INFO_BINDING: u32 = 1;
/// Set-0 binding of the Pm word buffer (`glsl/pm/pm.glsl`).
const WORDS_BINDING: u32 = 4;
/// Set-0 binding of the per-vertex connectivity.
const CONNECTIVITY_BINDING: u32 = 5;
/// Set-0 binding of the per-patch words.
const PATCH_BINDING: u32 = 6;

/// Takes the facets `pm` takes whose corners fit the varyings.
#[derive(Debug, Clone, Copy)]
pub struct PmVsScheme;

impl PatchScheme for PmVsScheme {
    fn name(&self) -> &'static str {
        "pm-vs"
    }

    fn plan(&self, topo: &Arc<Topology>, candidates: &[u32], opts: &PlanOptions) -> PassPlan {
        let over = |f: u32| {
            topo.face_vertices(f)
                .iter()
                .copied()
                .find(|&v| topo.vertex_edges(v).len() > MAX_VALENCE)
        };
        let mut refused = Vec::new();
        let mut ok = Vec::new();
        for &face in candidates {
            if opts.limits.max_vertex_varyings < 4 * SLOTS + 4 {
                refused.push(Refusal {
                    face,
                    pass: self.name(),
                    reason: RefusalReason::Device(format!(
                        "the device's varyings budget ({} components) is below the vertex stage's {}",
                        opts.limits.max_vertex_varyings,
                        4 * SLOTS + 4
                    )),
                });
            } else if let Some(vertex) = over(face) {
                refused.push(Refusal {
                    face,
                    pass: self.name(),
                    reason: RefusalReason::VaryingsBudget {
                        vertex,
                        edges: topo.vertex_edges(vertex).len(),
                        max_smooth: MAX_VALENCE,
                        max_sectored: MAX_VALENCE,
                    },
                });
            } else {
                ok.push(face);
            }
        }
        let (tables, more) = PmTables::plan(self.name(), topo, &ok, opts);
        refused.extend(more);
        refused.sort_by_key(|r| r.face);
        PassPlan {
            tables: tables.map(|pm| Arc::new(PmVsTables::new(pm)) as Arc<dyn PassTables>),
            refused,
        }
    }
}

/// One draw run: patches of one type (and side count) with their pipeline's shaders.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Run {
    /// Tessellation control shader.
    pub tess_control: &'static str,
    /// Evaluation-shader stem (the stencil variant's).
    pub tess_eval_stem: &'static str,
    /// Control points per patch (the facet's vertices).
    pub points: u32,
    /// First patch (record) of the run.
    pub first_patch: u32,
    /// First index of the run.
    pub first_index: u32,
    /// Patches in the run.
    pub count: u32,
}

/// CPU tables of the vertex-stage pass: the stencil variant's tables (faces, word buffer with
/// the edge and centre records, reference) and the two stages' inputs.
#[derive(Debug, Clone)]
pub struct PmVsTables {
    /// The facets, classes, word buffer and CPU construction (shared with `pm`).
    pub pm: PmTables,
    /// Per-vertex connectivity ([`connectivity_words`]).
    pub connectivity: Vec<u32>,
    /// Per-patch words ([`patch_words`]).
    pub patches: Vec<u32>,
    /// Index buffer: each patch's facet vertices in facet order.
    pub indices: Vec<u32>,
    /// Draw runs in record order.
    pub runs: Vec<Run>,
}

impl PmVsTables {
    /// The stages' inputs for the facets of `pm`.
    pub fn new(pm: PmTables) -> PmVsTables {
        let topo = pm.topology().clone();
        let (patches, indices, runs) = patch_words(&topo, &pm);
        let connectivity = connectivity_words(&topo, &pm.gpu.faces, pm.options());
        PmVsTables {
            pm,
            connectivity,
            patches,
            indices,
            runs,
        }
    }
}

/// The connectivity words of the vertex stage (layout in `glsl/pm_vs/pm_vs.glsl`): a header
/// `(offset, n, κ_n bits, 0)` per vertex (`n = 0` for vertices of no drawn facet), then per used
/// vertex 4 words per facet of its ring (spoke end, far-vertex offset and count, crease scalar
/// bits of the spoke), then the far-vertex lists.
pub fn connectivity_words(topo: &Topology, faces: &[u32], options: &PmOptions) -> Vec<u32> {
    let nv = topo.vertex_count();
    let mut used = vec![false; nv];
    for &f in faces {
        for &v in topo.face_vertices(f) {
            used[v as usize] = true;
        }
    }
    let ring_words: usize = (0..nv)
        .filter(|&v| used[v])
        .map(|v| 4 * topo.vertex_edges(v as u32).len())
        .sum();
    let far_base = 4 * nv + ring_words;
    let mut header = vec![0u32; 4 * nv];
    let mut ring = Vec::with_capacity(ring_words);
    let mut far = Vec::new();
    for v in (0..nv as u32).filter(|&v| used[v as usize]) {
        let edges = topo.vertex_edges(v);
        let n = edges.len();
        let h = 4 * v as usize;
        header[h] = (4 * nv + ring.len()) as u32;
        header[h + 1] = n as u32;
        header[h + 2] = (options.tangent_scale.kappa(n) as f32).to_bits();
        for (j, &e) in edges.iter().enumerate() {
            let fv = far_vertices(topo, v, j);
            ring.extend([
                topo.other_vertex(e, v),
                (far_base + far.len()) as u32,
                fv.len() as u32,
                (options.edge_crease(e) as f32).to_bits(),
            ]);
            far.extend(fv);
        }
    }
    header.extend(ring);
    header.extend(far);
    header
}

/// The per-patch words (layout in `glsl/pm_vs/pm_vs.glsl`), the index buffer and the draw runs,
/// in the record order of `pm`'s word buffer (bicubic, polar, Pm sectors by side count).
pub fn patch_words(topo: &Topology, pm: &PmTables) -> (Vec<u32>, Vec<u32>, Vec<Run>) {
    let mut words = Vec::new();
    let mut indices = Vec::new();
    let mut runs: Vec<Run> = Vec::new();
    let mut patch = 0u32;
    for (&f, &class) in pm.gpu.faces.iter().zip(&pm.gpu.classes) {
        let fv = topo.face_vertices(f);
        let (tess_control, tess_eval_stem, count) = match class {
            FacetClass::Ordinary => ("pm_vs_bicubic.tesc", "patch_pm_bicubic", 1),
            FacetClass::Polar { .. } => ("pm_vs_polar.tesc", "patch_pm_polar", 1),
            FacetClass::Pm { m } => ("pm_vs_sector.tesc", "patch_pm_sector", m),
        };
        let mut w = [0u32; PATCH_WORDS];
        for (k, &v) in fv.iter().enumerate() {
            let c = corner_slots(topo, f, k);
            w[k] = v;
            w[5 + k] = [c.slot, c.f_next, c.f_prev, c.next_spoke, c.prev_spoke]
                .iter()
                .enumerate()
                .fold(0, |acc, (i, &x)| acc | (x as u32) << (6 * i));
        }
        if let FacetClass::Polar { pole } = class {
            // Eq. (19): the spokes' scalars, edge `pole` (pole to a) and edge `pole + 2` (b to pole).
            let crease = |k: usize| pm.options().edge_crease(topo.face_edges(f)[k]) as f32;
            w[10] = crease(pole).to_bits();
            w[11] = crease((pole + 2) % 3).to_bits();
        }
        let points = fv.len() as u32;
        for _ in 0..count {
            words.extend(w);
            match runs.last_mut() {
                Some(r) if r.tess_control == tess_control && r.points == points => r.count += 1,
                _ => runs.push(Run {
                    tess_control,
                    tess_eval_stem,
                    points,
                    first_patch: patch,
                    first_index: indices.len() as u32,
                    count: 1,
                }),
            }
            indices.extend_from_slice(fv);
            patch += 1;
        }
    }
    (words, indices, runs)
}

impl PassTables for PmVsTables {
    fn pass_name(&self) -> &'static str {
        PM_VS.name()
    }

    fn faces(&self) -> &[u32] {
        self.pm.faces()
    }

    fn patch_count(&self) -> usize {
        self.pm.patch_count()
    }

    fn corner_frames(&self, positions: &[DVec3], rule: NormalRule<'_>, frames: &mut VertexFrames) {
        self.pm.corner_frames(positions, rule, frames);
    }

    fn framing_points(&self, frames: &VertexFrames) -> Vec<DVec3> {
        self.pm.framing_points(frames)
    }

    fn patch_level_limit(&self, spacing: Spacing) -> PatchLevelLimit {
        self.pm.patch_level_limit(spacing)
    }

    fn capture_layout(&self) -> CaptureLayout {
        self.pm.capture_layout()
    }

    fn reference(&self, positions: &[DVec3], face: u32) -> Option<ReferencePatch> {
        self.pm.reference(positions, face)
    }

    fn create_pass(&self, pc: &PassContext<'_>) -> Result<Box<dyn PatchPass>> {
        Ok(Box::new(PmVsPass::new(pc, self)?))
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}

/// The GPU resources of the vertex-stage Pm pass.
pub struct PmVsPass {
    ctx: Context,
    buffers: [Buffer; 3],
    indices: Buffer,
    _pool: DescriptorPool,
    /// Set 0 per frame slot.
    sets: Vec<vk::DescriptorSet>,
    runs: Vec<(Pipeline, Run)>,
    /// Largest level of a patch (drawn whole; `PatchDraws::max_level`).
    max_level: f32,
    count: u32,
}

impl PmVsPass {
    fn new(pc: &PassContext<'_>, t: &PmVsTables) -> Result<PmVsPass> {
        let ctx = pc.ctx;
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let words = host_buffer(ctx, &u32_bytes(&t.pm.gpu.words), storage, "pm-vs words")?;
        let conn = host_buffer(
            ctx,
            &u32_bytes(&t.connectivity),
            storage,
            "pm-vs connectivity",
        )?;
        let patches = host_buffer(ctx, &u32_bytes(&t.patches), storage, "pm-vs patches")?;
        let indices = device_buffer(
            ctx,
            &u32_bytes(&t.indices),
            vk::BufferUsageFlags::INDEX_BUFFER,
            "pm-vs indices",
        )?;
        let own = [
            UNUSED_PATCH_INFO_BINDING,
            WORDS_BINDING,
            CONNECTIVITY_BINDING,
            PATCH_BINDING,
        ];
        let mut runs = Vec::new();
        for r in t.runs.iter().filter(|r| r.count > 0) {
            let pipeline = patch_pipeline(
                ctx,
                pc.desc,
                pc.target,
                PatchShaders {
                    label: format!("pm-vs {} ({} points)", r.tess_eval_stem, r.points),
                    vertex: "pm_vs.vert".into(),
                    tess_control: r.tess_control.into(),
                    tess_eval_stem: r.tess_eval_stem,
                    points: r.points,
                    position_input: false,
                    set_layouts: vec![set0_layout(&own)],
                },
            )?;
            runs.push((pipeline, *r));
        }
        let layout = runs.first().map(|p| p.0.set_layouts[0]).ok_or_else(|| {
            crate::Error::Invalid("pm-vs: the pass needs at least one patch".into())
        })?;
        let n = pc.shared.slot_count() as u32;
        let pool = DescriptorPool::new(ctx, n, n * (5 + own.len() as u32), n)?;
        let sb = |binding, buffer| BufferBinding {
            binding,
            kind: DescriptorKind::StorageBuffer,
            buffer,
        };
        let sets = pc.shared.set0_per_slot(
            ctx,
            &pool,
            layout,
            &[
                sb(UNUSED_PATCH_INFO_BINDING, &words),
                sb(WORDS_BINDING, &words),
                sb(CONNECTIVITY_BINDING, &conn),
                sb(PATCH_BINDING, &patches),
            ],
        )?;
        Ok(PmVsPass {
            ctx: ctx.clone(),
            buffers: [words, conn, patches],
            indices,
            _pool: pool,
            sets,
            runs,
            max_level: pc.largest_level(1),
            count: t.pm.patch_count() as u32,
        })
    }
}

impl PatchPass for PmVsPass {
    fn label(&self) -> &'static str {
        "pm-vs patches"
    }

    fn patch_count(&self) -> u32 {
        self.count
    }

    fn memory_bytes(&self) -> u64 {
        self.buffers.iter().map(|b| b.size()).sum::<u64>() + self.indices.size()
    }

    fn record(&self, cmd: vk::CommandBuffer, slot: usize) {
        let dev = self.ctx.device();
        for (pipeline, r) in &self.runs {
            let run = PatchDraws::whole(
                r.first_patch,
                r.first_index,
                r.count,
                r.points,
                self.max_level,
            );
            let draw_state = (&[self.sets[slot]][..], self.indices.raw());
            record_run(dev, cmd, pipeline, draw_state, &run);
        }
    }

    fn update_positions(&mut self, _: &[DVec3], _: &VertexFrames) -> Result<()> {
        // The vertex stage reads the shared control positions; the words do not depend on them.
        Ok(())
    }
}
