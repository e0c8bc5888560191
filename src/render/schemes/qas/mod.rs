//! QAS (`--scheme qas`, Boubekeur and Schlick 2007): every triangle and quad drawn as a
//! quadratic position patch and a quadratic normal patch fitted to one Catmull-Clark step's
//! limit points ([`crate::patch::qas`]); faces of five or more sides stay on the exact CPU path.
//!
//! GPU data: set 0 binding 4 holds one 320-byte record per patch (`QasPatchRecord` in
//! `glsl/qas/qas.glsl`: face, kind, corner vertex ids, 9 position and 9 normal Bézier
//! coefficients), written by the host; animation re-applies the sparse limit stencils on the CPU
//! and rewrites the records (`update_positions`). The patch primitive has one point and no vertex
//! input (`qas.vert` is empty): the tessellation stages read the record of
//! `patch_base + gl_PrimitiveID`. Quads are drawn first, then triangles, each whole (the pass is
//! not split into sub-patches: a quadratic is cheap at any level).

use std::any::Any;
use std::sync::Arc;

use ash::vk;
use glam::DVec3;

use super::traits::{
    CaptureLayout, PassContext, PassPlan, PassTables, PatchPass, PatchScheme, PlanOptions,
    ReferencePatch, Refusal, RefusalReason,
};
use crate::gpu::{
    patches_per_draw_at_level, Buffer, BufferBinding, Context, DescriptorKind, DescriptorPool,
    Pipeline,
};
use crate::patch::qas::{QasKind, QasPoints, QasSurface};
use crate::render::pass::frames::single_normal_vertex;
use crate::render::pass::pipeline::{patch_pipeline, PatchShaders};
use crate::render::pass::shared::set0_layout;
use crate::render::pass::upload::{device_buffer, host_buffer};
use crate::render::pass::{
    bind_draw_state, record_patch_draws, NormalRule, PatchDraws, VertexFrames,
};
use crate::render::settings::{PatchLevelLimit, Spacing, TessMode};
use crate::topology::Topology;
use crate::Result;

/// The QAS pass in the registry.
pub static QAS: QasScheme = QasScheme;

/// Bytes of one `QasPatchRecord` (`glsl/qas/qas.glsl`).
pub const RECORD_BYTES: usize = 320;
/// Set-0 binding of the records.
const RECORDS_BINDING: u32 = 4;
/// Set-0 binding the shared frame block declares for B-spline records; bound to the QAS records
/// so the layout is complete (unused by the QAS stages).
const UNUSED_PATCH_INFO_BINDING: u32 = 1;

/// Takes every triangle and quad with a limit surface.
#[derive(Debug, Clone, Copy)]
pub struct QasScheme;

impl PatchScheme for QasScheme {
    fn name(&self) -> &'static str {
        "qas"
    }

    fn plan(&self, topo: &Arc<Topology>, candidates: &[u32], _: &PlanOptions) -> PassPlan {
        let (surface, refused) = QasSurface::build(topo, candidates);
        let refused = refused
            .into_iter()
            .map(|r| Refusal {
                face: r.face(),
                pass: self.name(),
                reason: RefusalReason::NotQas(r),
            })
            .collect();
        PassPlan {
            tables: (!surface.patches.is_empty())
                .then(|| Arc::new(QasTables::new(surface)) as Arc<dyn PassTables>),
            refused,
        }
    }
}

/// The QAS patches of a surface and their limit stencils.
#[derive(Debug, Clone)]
pub struct QasTables {
    /// Patches (quads first) and stencils.
    pub surface: Arc<QasSurface>,
    faces: Vec<u32>,
    quads: usize,
}

impl QasTables {
    /// Tables drawing `surface`'s patches.
    pub fn new(surface: QasSurface) -> QasTables {
        let faces = surface.patches.iter().map(|p| p.face).collect();
        let quads = surface
            .patches
            .iter()
            .filter(|p| p.kind == QasKind::Quad)
            .count();
        QasTables {
            surface: Arc::new(surface),
            faces,
            quads,
        }
    }

    /// The GPU records of every patch for limit points `points` ([`RECORD_BYTES`] each).
    pub fn record_bytes(&self, points: &QasPoints) -> Vec<u8> {
        let mut out = Vec::with_capacity(self.surface.patches.len() * RECORD_BYTES);
        for (i, p) in self.surface.patches.iter().enumerate() {
            let c = self.surface.control(i, points);
            let kind = match p.kind {
                QasKind::Quad => 0u32,
                QasKind::Triangle => 1,
            };
            for w in [p.face, kind, 0, 0].iter().chain(&p.corners) {
                out.extend_from_slice(&w.to_le_bytes());
            }
            for (coeffs, w) in [(&c.position, 1.0f32), (&c.normal, 0.0)] {
                for x in coeffs {
                    for f in x.as_vec3().to_array().into_iter().chain([w]) {
                        out.extend_from_slice(&f.to_le_bytes());
                    }
                }
            }
        }
        out
    }
}

impl PassTables for QasTables {
    fn pass_name(&self) -> &'static str {
        QAS.name()
    }

    fn faces(&self) -> &[u32] {
        &self.faces
    }

    fn patch_count(&self) -> usize {
        self.surface.patches.len()
    }

    fn control_points_per_patch(&self) -> Option<f64> {
        // Position and normal coefficients: 18 per quad, 12 per triangle.
        let n = self.surface.patches.len().max(1) as f64;
        let sum: usize = self
            .surface
            .patches
            .iter()
            .map(|p| 2 * p.kind.points())
            .sum();
        Some(sum as f64 / n)
    }

    fn corner_frames(&self, positions: &[DVec3], rule: NormalRule<'_>, frames: &mut VertexFrames) {
        let points = self.surface.points(positions);
        for p in &self.surface.patches {
            for (k, &slot) in p.corner_slots().iter().enumerate() {
                let v = p.corners[k];
                if frames.is_set(v) {
                    continue;
                }
                let shared = match rule {
                    NormalRule::Topology(topo) => single_normal_vertex(topo, v),
                    NormalRule::PatchSides => false,
                };
                frames.set(
                    v,
                    points.positions[p.points[slot] as usize],
                    points.normals[p.normals[slot] as usize],
                    shared,
                );
            }
        }
    }

    fn framing_points(&self, frames: &VertexFrames) -> Vec<DVec3> {
        self.surface
            .patches
            .iter()
            .flat_map(|p| p.corners)
            .map(|v| frames.limits[v as usize])
            .collect()
    }

    fn patch_level_limit(&self, _: Spacing) -> PatchLevelLimit {
        PatchLevelLimit {
            max_patch_level: f32::INFINITY,
            splittable: false,
        }
    }

    fn capture_layout(&self) -> CaptureLayout {
        CaptureLayout::FaceDomainOrBarycentric
    }

    fn reference(&self, positions: &[DVec3], face: u32) -> Option<ReferencePatch> {
        let i = self.surface.patches.iter().position(|p| p.face == face)?;
        let c = self.surface.control_from(i, positions);
        Some(Box::new(move |u, v| c.eval(u, v)))
    }

    fn create_pass(&self, pc: &PassContext<'_>) -> Result<Box<dyn PatchPass>> {
        Ok(Box::new(QasPass::new(pc, self)?))
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}

/// GPU resources of the QAS pass.
pub struct QasPass {
    ctx: Context,
    tables: QasTables,
    records: Buffer,
    indices: Buffer,
    _pool: DescriptorPool,
    set: vk::DescriptorSet,
    /// Quad pipeline, first patch and patch count, then triangles.
    groups: Vec<(Pipeline, u32, u32)>,
    /// Patches per draw ([`patches_per_draw_at_level`] of the largest level drawn).
    per_draw: u32,
}

impl QasPass {
    fn new(pc: &PassContext<'_>, tables: &QasTables) -> Result<QasPass> {
        let ctx = pc.ctx;
        let points = tables.surface.points(pc.positions);
        let records = host_buffer(
            ctx,
            &tables.record_bytes(&points),
            vk::BufferUsageFlags::STORAGE_BUFFER,
            "qas patch records",
        )?;
        let count = tables.surface.patches.len();
        let indices = device_buffer(
            ctx,
            &vec![0u8; 4 * count],
            vk::BufferUsageFlags::INDEX_BUFFER,
            "qas patch indices",
        )?;
        let own = [UNUSED_PATCH_INFO_BINDING, RECORDS_BINDING];
        let mut groups = Vec::new();
        let tris = (count - tables.quads) as u32;
        for (shape, n, first) in [
            ("quad", tables.quads as u32, 0u32),
            ("tri", tris, tables.quads as u32),
        ] {
            if n == 0 {
                continue;
            }
            let pipeline = patch_pipeline(
                ctx,
                pc.desc,
                pc.target,
                PatchShaders {
                    label: format!("qas {shape} patches"),
                    vertex: "qas.vert".into(),
                    tess_control: format!("qas_{shape}.tesc"),
                    tess_eval_stem: if shape == "quad" {
                        "patch_qas_quad"
                    } else {
                        "patch_qas_tri"
                    },
                    points: 1,
                    position_input: false,
                    set_layouts: vec![set0_layout(&own)],
                },
            )?;
            groups.push((pipeline, first, n));
        }
        let pool = DescriptorPool::new(ctx, 1, 4 + own.len() as u32, 1)?;
        let set = pool.allocate(groups[0].0.set_layouts[0])?;
        let sb = |binding| BufferBinding {
            binding,
            kind: DescriptorKind::StorageBuffer,
            buffer: &records,
        };
        pc.shared.write_set0(
            ctx,
            set,
            &[sb(UNUSED_PATCH_INFO_BINDING), sb(RECORDS_BINDING)],
        );
        Ok(QasPass {
            ctx: ctx.clone(),
            tables: tables.clone(),
            records,
            indices,
            _pool: pool,
            set,
            groups,
            per_draw: patches_per_draw_at_level(largest_level(pc)),
        })
    }
}

/// The largest level a patch edge or interior can get: the uniform level, or in screen-space
/// mode the device's largest level.
fn largest_level(pc: &PassContext<'_>) -> f32 {
    match pc.desc.tess.mode {
        TessMode::Uniform => pc.desc.tess.level,
        _ => pc.ctx.info().limits.max_tessellation_generation_level as f32,
    }
}

impl PatchPass for QasPass {
    fn label(&self) -> &'static str {
        "qas patches"
    }

    fn patch_count(&self) -> u32 {
        self.tables.surface.patches.len() as u32
    }

    fn memory_bytes(&self) -> u64 {
        self.records.size() + self.indices.size()
    }

    fn record(&self, cmd: vk::CommandBuffer) {
        let dev = self.ctx.device();
        for (pipeline, first, count) in &self.groups {
            bind_draw_state(dev, cmd, pipeline, &[self.set], None, self.indices.raw());
            // Runs below lavapipe's domain-point budget per draw; record_patch_draws further
            // chunks each run by its index count.
            let mut done = 0;
            while done < *count {
                let n = self.per_draw.min(*count - done);
                let draws = PatchDraws {
                    first_patch: first + done,
                    first_index: first + done,
                    count: n,
                    points: 1,
                    sub_draws: 1,
                    sub_flag: 0,
                };
                record_patch_draws(dev, cmd, pipeline.layout, &draws, 1);
                done += n;
            }
        }
    }

    fn update_positions(&mut self, positions: &[DVec3], _: &VertexFrames) -> Result<()> {
        // One Catmull-Clark step projected to the limit, as sparse rows over the control
        // vertices, then the fit: CPU work, records rewritten.
        let points = self.tables.surface.points(positions);
        self.records.write(0, &self.tables.record_bytes(&points))
    }
}
