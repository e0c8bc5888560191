//! ACC (`--scheme acc`, Loop and Schaefer 2008 §3): every smooth interior quad with quad rings
//! drawn as its bicubic geometry patch ([`crate::patch::acc`]) with the paper's pair of tangent
//! patches for its normals ([`crate::patch::acc::tangent`]); every other face stays on the exact
//! CPU path. Normals: inside a patch `U × V` of its tangent patches; on an edge, from the edge's
//! canonical frame ([`AccEdgeFrame`]), which both faces hold with the same bits, so the normal
//! field is continuous and edge normals are shared.
//!
//! GPU data ([`super::records`]): one 1120-byte record per patch (`AccPatchRecord` in
//! `glsl/acc/acc.glsl`): face, colour class, corner vertex ids, the 16 Bézier points, the 12 + 12
//! tangent-patch vectors and the 4 edge frames, built on the CPU and rewritten per animation
//! frame.

use std::any::Any;
use std::sync::Arc;

use glam::DVec3;

use super::records::{RecordGroup, RecordTables, RecordTablesPass};
use super::traits::{
    PassContext, PassPlan, PassTables, PatchPass, PatchScheme, PlanOptions, ReferencePatch,
    Refusal, RefusalReason,
};
use crate::patch::acc::tangent::TangentBuilder;
use crate::patch::acc::{acc_patch, check_face, AccEdgeFrame};
use crate::render::pass::frames::single_normal_vertex;
use crate::render::pass::{NormalRule, VertexFrames};
use crate::render::settings::{PatchLevelLimit, Spacing};
use crate::topology::Topology;
use crate::Result;

/// The ACC pass in the registry.
pub static ACC: AccScheme = AccScheme;

/// Bytes of one `AccPatchRecord`.
pub const RECORD_BYTES: usize = 1120;

/// Colour classes (`glsl/common/frame.glsl`): regular quads (valence-4 corners) and the others.
const CLASS_REGULAR: u32 = 0;
const CLASS_IRREGULAR: u32 = 1;

/// Corner slots of the Bézier grid, corners 0-3.
const CORNER_SLOTS: [usize; 4] = [0, 3, 15, 12];

/// Takes smooth interior quads with quad rings ([`check_face`]).
#[derive(Debug, Clone, Copy)]
pub struct AccScheme;

impl PatchScheme for AccScheme {
    fn name(&self) -> &'static str {
        "acc"
    }

    fn plan(&self, topo: &Arc<Topology>, candidates: &[u32], _: &PlanOptions) -> PassPlan {
        let mut faces = Vec::new();
        let mut refused = Vec::new();
        for &f in candidates {
            match check_face(topo, f) {
                Ok(()) => faces.push(f),
                Err(e) => refused.push(Refusal {
                    face: f,
                    pass: self.name(),
                    reason: RefusalReason::NotAcc(e),
                }),
            }
        }
        PassPlan {
            tables: (!faces.is_empty()).then(|| {
                Arc::new(AccTables {
                    topo: topo.clone(),
                    faces,
                }) as Arc<dyn PassTables>
            }),
            refused,
        }
    }
}

/// The ACC faces of a surface.
#[derive(Debug, Clone)]
pub struct AccTables {
    topo: Arc<Topology>,
    faces: Vec<u32>,
}

impl RecordTables for AccTables {
    /// The GPU records of every patch for control positions `p` ([`RECORD_BYTES`] each): the
    /// masks applied on the CPU.
    fn records(&self, p: &[DVec3]) -> Result<Vec<u8>> {
        let mut out = Vec::with_capacity(self.faces.len() * RECORD_BYTES);
        let mut tangents = TangentBuilder::new(&self.topo, p);
        for &f in &self.faces {
            let bad = |e: crate::patch::acc::NotAcc| crate::Error::Invalid(e.to_string());
            let patch = acc_patch(&self.topo, p, f).map_err(bad)?;
            let tangent = tangents.patches(f).map_err(bad)?;
            let frames: Vec<AccEdgeFrame> = (0..4).map(|k| tangents.edge_frame(f, k)).collect();
            let fv = self.topo.face_vertices(f);
            let regular = fv.iter().all(|&v| self.topo.vertex_faces(v).len() == 4);
            let class = if regular {
                CLASS_REGULAR
            } else {
                CLASS_IRREGULAR
            };
            for w in [f, class, 0, 0].iter().chain(fv) {
                out.extend_from_slice(&w.to_le_bytes());
            }
            let vectors = patch
                .bezier
                .iter()
                .chain(&tangent.u)
                .chain(&tangent.v)
                .chain(frames.iter().flat_map(|e| e.versal.iter().chain(&e.cross)));
            for x in vectors {
                for c in x.as_vec3().to_array().into_iter().chain([1.0]) {
                    out.extend_from_slice(&c.to_le_bytes());
                }
            }
        }
        Ok(out)
    }
}

impl PassTables for AccTables {
    fn pass_name(&self) -> &'static str {
        ACC.name()
    }

    fn faces(&self) -> &[u32] {
        &self.faces
    }

    fn patch_count(&self) -> usize {
        self.faces.len()
    }

    fn corner_frames(&self, positions: &[DVec3], rule: NormalRule<'_>, frames: &mut VertexFrames) {
        let mut tangents = TangentBuilder::new(&self.topo, positions);
        for &f in &self.faces {
            let Ok(patch) = acc_patch(&self.topo, positions, f) else {
                continue;
            };
            let fv = self.topo.face_vertices(f);
            for k in 0..4 {
                if frames.is_set(fv[k]) {
                    continue;
                }
                let shared = match rule {
                    NormalRule::Topology(topo) => single_normal_vertex(topo, fv[k]),
                    NormalRule::PatchSides => false,
                };
                frames.set(
                    fv[k],
                    patch.bezier[CORNER_SLOTS[k]],
                    tangents.corner_normal(f, k),
                    shared,
                );
            }
        }
    }

    fn framing_points(&self, frames: &VertexFrames) -> Vec<DVec3> {
        self.faces
            .iter()
            .flat_map(|&f| self.topo.face_vertices(f).to_vec())
            .map(|v| frames.limits[v as usize])
            .collect()
    }

    fn patch_level_limit(&self, _: Spacing) -> PatchLevelLimit {
        PatchLevelLimit::WHOLE
    }

    fn reference(&self, positions: &[DVec3], face: u32) -> Option<ReferencePatch> {
        self.faces.contains(&face).then_some(())?;
        let patch = acc_patch(&self.topo, positions, face).ok()?;
        let tangent = TangentBuilder::new(&self.topo, positions)
            .patches(face)
            .ok()?;
        Some(Box::new(move |u, v| {
            (patch.eval(u, v).0, tangent.normal(u, v))
        }))
    }

    fn create_pass(&self, pc: &PassContext<'_>) -> Result<Box<dyn PatchPass>> {
        let groups = [RecordGroup {
            tess_control: "acc.tesc",
            tess_eval_stem: "patch_acc",
            first: 0,
            count: self.faces.len() as u32,
        }];
        Ok(Box::new(RecordTablesPass::new(
            pc,
            "acc patches",
            self,
            &groups,
        )?))
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}
