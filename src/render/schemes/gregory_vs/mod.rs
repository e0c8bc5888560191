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
//! path with a typed [`Refusal`] (logged when the surface is planned).

use std::any::Any;
use std::sync::Arc;

use ash::vk;
use glam::DVec3;

use super::gregory::{self, GregoryLayout, GregoryTesBuffers};
use super::traits::{
    PassContext, PassPlan, PassTables, PatchPass, PatchScheme, PlanOptions, ReferencePatch,
    Refusal, RefusalReason, SchemeLimits,
};
use crate::gpu::{Buffer, BufferBinding, Context, DescriptorKind, DescriptorPool, Pipeline};
use crate::patch::gregory::table::GregoryVertexTable;
use crate::patch::gregory::{is_supported_vertex, GregoryTangents};
use crate::render::pass::pipeline::{patch_pipeline, PatchShaders};
use crate::render::pass::shared::set0_layout;
use crate::render::pass::upload::{host_buffer, u32_bytes};
use crate::render::pass::{
    bind_draw_state, record_patch_draws, NormalRule, PatchDraws, VertexFrames,
};
use crate::render::settings::{PatchLevelLimit, Spacing};
use crate::topology::Topology;
use crate::{Error, Result};

/// The two-stage Gregory pass in the registry.
pub static GREGORY_VS: GregoryVsScheme = GregoryVsScheme;

/// Largest (sub-)patch level the two-stage pass is drawn at: its pass jumps ~13x in cost at
/// (sub-)patch levels >= 15 on Mesa 22.3 lavapipe (catmark_car, 460 Gregory quads: level 14
/// 71 ms, 15 941 ms; the stencil variant 63 / 72 ms), so higher levels are split.
pub const MAX_PATCH_LEVEL: f32 = 14.0;

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
    VsBudget::for_limits(&SchemeLimits::from_context(ctx))
}

impl VsBudget {
    /// The largest budget `limits` allow (31 or 15 vec4 slots), `None` below 64 components.
    pub fn for_limits(limits: &SchemeLimits) -> Option<VsBudget> {
        // One location of the budget is taken by the built-in per-vertex block.
        [31u32, 15]
            .into_iter()
            .find(|&s| 4 * s + 4 <= limits.max_vertex_varyings)
            .map(|slots| VsBudget {
                slots,
                max_valence: ((4 * slots - 4) / 6) as usize,
            })
    }
}

/// Splits candidate faces into those this variant draws and typed refusals: the
/// construction's limits ([`gregory::covered_faces`]) or a corner over the varyings budget.
pub fn select_faces(topo: &Topology, faces: &[u32], budget: VsBudget) -> (Vec<u32>, Vec<Refusal>) {
    let (covered, mut refused) = gregory::covered_faces(GREGORY_VS.name(), topo, faces);
    let mut ok = Vec::new();
    for f in covered {
        match topo
            .face_vertices(f)
            .iter()
            .find(|&&v| !budget.fits(topo, v))
        {
            Some(&v) => refused.push(Refusal {
                face: f,
                pass: GREGORY_VS.name(),
                reason: RefusalReason::VaryingsBudget {
                    vertex: v,
                    edges: topo.vertex_edges(v).len(),
                    max_smooth: budget.max_valence,
                    max_sectored: budget.max_sectored_edges(),
                },
            }),
            None => ok.push(f),
        }
    }
    (ok, refused)
}

/// Connectivity words (layout in `glsl/common/gregory_vs.glsl`): the per-vertex part of
/// [`GregoryVertexTable`] (paper Fig. 7: header `(offset, ne, nf, kind)` per vertex, far edge
/// vertices, sector words, face records) with the ring offsets made absolute.
pub fn connectivity_words(topo: &Topology, tangents: GregoryTangents) -> Vec<u32> {
    let t = GregoryVertexTable::with_tangents(topo, std::iter::empty(), tangents);
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

/// Set-0 binding of the per-vertex connectivity words.
const CONNECTIVITY_BINDING: u32 = 4;
/// Set-0 binding of the per-patch corner ring offsets.
const CORNER_RING_BINDING: u32 = 5;

/// Takes the triangles and quads the Gregory construction covers whose corners fit the
/// device's varyings budget.
#[derive(Debug, Clone, Copy)]
pub struct GregoryVsScheme;

impl PatchScheme for GregoryVsScheme {
    fn name(&self) -> &'static str {
        "gregory-vs"
    }

    fn reads_fitted_crease_factors(&self) -> bool {
        true
    }

    fn plan(&self, topo: &Arc<Topology>, candidates: &[u32], opts: &PlanOptions) -> PassPlan {
        let limits = &opts.limits;
        let Some(budget) = VsBudget::for_limits(limits) else {
            return PassPlan {
                tables: None,
                refused: candidates
                    .iter()
                    .map(|&face| Refusal {
                        face,
                        pass: self.name(),
                        reason: RefusalReason::Device(
                            "the device's varyings budget is below 64 components".into(),
                        ),
                    })
                    .collect(),
            };
        };
        let (ok, refused) = select_faces(topo, candidates, budget);
        PassPlan {
            tables: (!ok.is_empty()).then(|| {
                Arc::new(GregoryVsTables::new(
                    topo.clone(),
                    &ok,
                    budget,
                    opts.gregory_tangents,
                )) as Arc<dyn PassTables>
            }),
            refused,
        }
    }
}

/// CPU tables of the two-stage pass: the shared Gregory layout, the varyings budget (selects
/// the shader variant) and the per-vertex connectivity (paper Fig. 7).
#[derive(Debug, Clone)]
pub struct GregoryVsTables {
    /// Topology of the surface.
    pub topology: Arc<Topology>,
    /// Patches in draw order.
    pub layout: GregoryLayout,
    /// Varyings budget the shaders are built for.
    pub budget: VsBudget,
}

impl GregoryVsTables {
    /// Tables for `faces` (accepted by [`select_faces`] with `budget`, which must not exceed the
    /// device's [`vs_budget`]; the 15-slot variant can be tested on devices allowing 31).
    pub fn new(
        topology: Arc<Topology>,
        faces: &[u32],
        budget: VsBudget,
        tangents: GregoryTangents,
    ) -> GregoryVsTables {
        let layout = GregoryLayout::new(&topology, faces, tangents);
        GregoryVsTables {
            topology,
            layout,
            budget,
        }
    }
}

impl PassTables for GregoryVsTables {
    fn pass_name(&self) -> &'static str {
        GREGORY_VS.name()
    }

    fn faces(&self) -> &[u32] {
        &self.layout.faces
    }

    fn patch_count(&self) -> usize {
        self.layout.faces.len()
    }

    fn corner_frames(&self, positions: &[DVec3], _: NormalRule<'_>, frames: &mut VertexFrames) {
        gregory::corner_frames(&self.topology, &self.layout, positions, frames);
    }

    fn framing_points(&self, frames: &VertexFrames) -> Vec<DVec3> {
        gregory::framing_points(&self.layout, frames)
    }

    fn patch_level_limit(&self, spacing: Spacing) -> PatchLevelLimit {
        gregory::level_limit(&self.layout, spacing, MAX_PATCH_LEVEL)
    }

    fn capture_layout(&self) -> super::traits::CaptureLayout {
        super::traits::CaptureLayout::FaceDomainOrBarycentric
    }

    fn reference(&self, positions: &[DVec3], face: u32) -> Option<ReferencePatch> {
        gregory::reference(&self.topology, &self.layout, positions, face)
    }

    fn create_pass(&self, pc: &PassContext<'_>) -> Result<Box<dyn PatchPass>> {
        Ok(Box::new(GregoryVsPass::new(pc, self)?))
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}

/// Flag of the `sub_index` push constant: draw a triangle as sub-triangles
/// (`glsl/gregory/` `TRI_SUB_MODE`).
pub const TRI_SUB_MODE: u32 = 0x8000_0000;

/// GPU resources and pipelines of the two-stage Gregory patches of one surface.
pub struct GregoryVsPass {
    ctx: Context,
    quads: u32,
    tris: u32,
    split: u32,
    /// Largest level of a sub-patch or sub-triangle (`PatchDraws::max_level`).
    max_level: f32,
    _conn: Buffer,
    _corner_ring: Buffer,
    _tes: GregoryTesBuffers,
    indices: Buffer,
    _pool: DescriptorPool,
    /// Set 0 per frame slot.
    sets: Vec<vk::DescriptorSet>,
    quad_pipeline: Pipeline,
    tri_pipeline: Pipeline,
}

impl GregoryVsPass {
    fn new(pc: &PassContext<'_>, t: &GregoryVsTables) -> Result<GregoryVsPass> {
        let (ctx, topo, layout, budget) = (pc.ctx, &*t.topology, &t.layout, t.budget);
        if let Some(device) = vs_budget(ctx) {
            if budget.slots > device.slots {
                return Err(Error::Invalid(format!(
                    "gregory-vs: budget of {} slots exceeds the device's {}",
                    budget.slots, device.slots
                )));
            }
        } else {
            return Err(Error::Invalid(
                "the device's varyings budget is below 64 components: no two-stage Gregory variant"
                    .into(),
            ));
        }
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
        if pc.positions.len() != topo.vertex_count() {
            return Err(Error::Invalid(format!(
                "gregory-vs: {} positions for {} vertices",
                pc.positions.len(),
                topo.vertex_count()
            )));
        }
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let conn = host_buffer(
            ctx,
            &u32_bytes(&connectivity_words(topo, t.layout.tangents)),
            storage,
            "gregory-vs connectivity",
        )?;
        let corner_ring = host_buffer(
            ctx,
            &layout.corner_ring_bytes(),
            storage,
            "gregory-vs ring offsets",
        )?;
        let tes = GregoryTesBuffers::new(ctx, layout)?;
        let indices = crate::render::pass::upload::device_buffer(
            ctx,
            &layout.corner_index_bytes(),
            vk::BufferUsageFlags::INDEX_BUFFER,
            "gregory-vs corner indices",
        )?;
        let quad_pipeline = pipeline(pc, budget, true)?;
        let tri_pipeline = pipeline(pc, budget, false)?;
        let n = pc.shared.slot_count() as u32;
        let pool = DescriptorPool::new(ctx, n, 10 * n, n)?;
        let sb = |binding, buffer| BufferBinding {
            binding,
            kind: DescriptorKind::StorageBuffer,
            buffer,
        };
        let mut own = tes.bindings().to_vec();
        own.extend([
            sb(CONNECTIVITY_BINDING, &conn),
            sb(CORNER_RING_BINDING, &corner_ring),
        ]);
        let sets = pc
            .shared
            .set0_per_slot(ctx, &pool, quad_pipeline.set_layouts[0], &own)?;
        Ok(GregoryVsPass {
            ctx: ctx.clone(),
            quads: layout.quad_count,
            tris: layout.patch_count() - layout.quad_count,
            split: pc.desc.tess.split(),
            max_level: pc.largest_level(pc.desc.tess.split()),
            _conn: conn,
            _corner_ring: corner_ring,
            _tes: tes,
            indices,
            _pool: pool,
            sets,
            quad_pipeline,
            tri_pipeline,
        })
    }
}

fn pipeline(pc: &PassContext<'_>, budget: VsBudget, quads: bool) -> Result<Pipeline> {
    let suffix = if budget.slots == 31 { "" } else { "_16" };
    let shape = if quads { "quad" } else { "tri" };
    patch_pipeline(
        pc.ctx,
        pc.desc,
        pc.target,
        PatchShaders {
            label: format!("gregory-vs {shape} patches"),
            vertex: format!("gregory_vs{suffix}.vert"),
            tess_control: format!("gregory_vs_{shape}{suffix}.tesc"),
            tess_eval_stem: if quads {
                "patch_gregory_quad"
            } else {
                "patch_gregory_tri"
            },
            points: if quads { 4 } else { 3 },
            position_input: false,
            set_layouts: vec![set0_layout(&[
                gregory::UNUSED_PATCH_INFO_BINDING,
                CONNECTIVITY_BINDING,
                CORNER_RING_BINDING,
                gregory::PATCH_RECORDS_BINDING,
                gregory::GRIDS_BINDING,
            ])],
        },
    )
}

impl PatchPass for GregoryVsPass {
    fn label(&self) -> &'static str {
        "gregory patches"
    }

    fn memory_bytes(&self) -> u64 {
        self._conn.size()
            + self._corner_ring.size()
            + self._tes.memory_bytes()
            + self.indices.size()
    }

    fn patch_count(&self) -> u32 {
        self.quads + self.tris
    }

    /// Quads in sub-patch splits like the regular patches, triangles in as many sub-triangles
    /// (sub index | [`TRI_SUB_MODE`]), their edges on the split quads' lattice.
    fn record(&self, cmd: vk::CommandBuffer, slot: usize) {
        let dev = self.ctx.device();
        let subs = self.split * self.split;
        for (pipe, draws) in [
            (
                &self.quad_pipeline,
                PatchDraws {
                    first_patch: 0,
                    first_index: 0,
                    count: self.quads,
                    points: 4,
                    sub_draws: subs,
                    sub_flag: 0,
                    max_level: self.max_level,
                },
            ),
            (
                &self.tri_pipeline,
                PatchDraws {
                    first_patch: self.quads,
                    first_index: 4 * self.quads,
                    count: self.tris,
                    points: 3,
                    sub_draws: subs,
                    sub_flag: TRI_SUB_MODE,
                    max_level: self.max_level,
                },
            ),
        ] {
            if draws.count == 0 {
                continue;
            }
            bind_draw_state(dev, cmd, pipe, &[self.sets[slot]], None, self.indices.raw());
            record_patch_draws(dev, cmd, pipe, &draws, self.split);
        }
    }

    fn update_positions(&mut self, _: &[DVec3], _: &VertexFrames) -> Result<()> {
        // The vertex stage reads the shared control positions and normals.
        Ok(())
    }
}
