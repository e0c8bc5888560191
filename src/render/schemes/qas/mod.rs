//! QAS (`--scheme qas`, Boubekeur and Schlick 2007): every face drawn as quadratic position
//! patches and quadratic normal patches fitted to one Catmull-Clark step's limit points
//! ([`crate::patch::qas`]): quads whole, triangles whole, n-gons (n ≥ 5) as a fan of quadratic
//! triangles around the face point.
//!
//! GPU data ([`super::records`]): set 0 binding 4 holds one 320-byte record per patch (`QasPatchRecord` in
//! `glsl/qas/qas.glsl`: face, kind, a fan's two sub-faces, corner vertex ids, 9 position and 9
//! normal Bézier coefficients), written by the host; animation re-applies the sparse limit
//! stencils on the CPU and rewrites the records (`update_positions`). Quads are drawn first,
//! then triangles and fan triangles (one pipeline), each whole (the pass is not split into
//! sub-patches: a quadratic is cheap at any level).
use std::any::Any;
use std::collections::HashMap;
use std::sync::Arc;

use glam::DVec3;

use super::records::{RecordGroup, RecordTables, RecordTablesPass};
use super::traits::{
    CaptureLayout, PassContext, PassPlan, PassTables, PatchPass, PatchScheme, PlanOptions,
    ReferencePatch, Refusal, RefusalReason,
};
use crate::patch::qas::{QasKind, QasPoints, QasSurface};
use crate::render::pass::frames::single_normal_vertex;
use crate::render::pass::{NormalRule, VertexFrames};
use crate::render::settings::{PatchLevelLimit, Spacing};
use crate::topology::Topology;
use crate::Result;

/// The QAS pass in the registry.
pub static QAS: QasScheme = QasScheme;

/// Bytes of one `QasPatchRecord` (`glsl/qas/qas.glsl`).
pub const RECORD_BYTES: usize = 320;

/// Takes every face with a limit surface.
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
    /// Sides of each n-gon drawn as a fan.
    fan_sides: HashMap<u32, u32>,
}

impl QasTables {
    /// Tables drawing `surface`'s patches.
    pub fn new(surface: QasSurface) -> QasTables {
        let mut faces: Vec<u32> = surface.patches.iter().map(|p| p.face).collect();
        faces.dedup();
        let quads = surface
            .patches
            .iter()
            .filter(|p| p.kind == QasKind::Quad)
            .count();
        let mut fan_sides = HashMap::new();
        for p in surface.patches.iter().filter(|p| p.kind == QasKind::Fan) {
            *fan_sides.entry(p.face).or_insert(0) += 1;
        }
        QasTables {
            surface: Arc::new(surface),
            faces,
            quads,
            fan_sides,
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
                QasKind::Fan => 2,
            };
            // A fan's sub-faces at its corners 1 and 2.
            let (sub, next) = match p.fan {
                Some(k) => (k, (k + 1) % self.fan_sides[&p.face]),
                None => (0, 0),
            };
            for w in [p.face, kind, sub, next].iter().chain(&p.corners) {
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

    /// The CPU construction at a captured n-gon point (sub-face `sub`, `(u, v)`): position and
    /// unit normal, or `None` if `face` is not drawn as a fan.
    pub fn sub_face_reference(
        &self,
        positions: &[DVec3],
        face: u32,
        sub: u32,
        u: f64,
        v: f64,
    ) -> Option<(DVec3, DVec3)> {
        let n = *self.fan_sides.get(&face)?;
        self.surface.eval_sub_face(positions, face, n, sub, u, v)
    }
}

impl RecordTables for QasTables {
    /// One Catmull-Clark step projected to the limit (the sparse rows over the control
    /// vertices), the fit, the records: CPU work per animation frame.
    fn records(&self, positions: &[DVec3]) -> Result<Vec<u8>> {
        Ok(self.record_bytes(&self.surface.points(positions)))
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

    fn corner_frames(&self, positions: &[DVec3], rule: NormalRule<'_>, frames: &mut VertexFrames) {
        let points = self.surface.points(positions);
        for p in &self.surface.patches {
            for (v, slot) in p.corner_vertices() {
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
            .flat_map(|p| p.corner_vertices())
            .map(|(v, _)| frames.limits[v as usize])
            .collect()
    }

    fn patch_level_limit(&self, _: Spacing) -> PatchLevelLimit {
        PatchLevelLimit::WHOLE
    }

    fn capture_layout(&self) -> CaptureLayout {
        CaptureLayout::FaceDomainOrBarycentric
    }

    /// Quads and triangles (their captured `(u, v)` are enough); `None` for n-gons, whose points
    /// need the sub-face ([`QasTables::sub_face_reference`] with the record's sub-face).
    fn reference(&self, positions: &[DVec3], face: u32) -> Option<ReferencePatch> {
        let i = self.surface.patches.iter().position(|p| p.face == face)?;
        if self.surface.patches[i].kind == QasKind::Fan {
            return None;
        }
        let c = self.surface.control_from(i, positions);
        Some(Box::new(move |u, v| c.eval(u, v)))
    }

    fn create_pass(&self, pc: &PassContext<'_>) -> Result<Box<dyn PatchPass>> {
        let count = self.surface.patches.len() as u32;
        let quads = self.quads as u32;
        let groups = [
            RecordGroup {
                tess_control: "qas_quad.tesc",
                tess_eval_stem: "patch_qas_quad",
                first: 0,
                count: quads,
            },
            RecordGroup {
                tess_control: "qas_tri.tesc",
                tess_eval_stem: "patch_qas_tri",
                first: quads,
                count: count - quads,
            },
        ];
        Ok(Box::new(RecordTablesPass::new(
            pc,
            "qas patches",
            self,
            &groups,
        )?))
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}
