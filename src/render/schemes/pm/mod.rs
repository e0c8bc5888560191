//! Pm-patches on the GPU (`--scheme pm`, Myles, Ni, Peters 2008), stencil variant: one patch
//! per facet of a closed tri/quad/pent mesh ([`crate::patch::pm`]): ordinary quads as bicubic
//! patches on the quad domain, polar triangles as singular bicubics on the triangle domain, and
//! every other facet as `m` quartic sectors, the triangle domain drawn once per sector. Facets
//! the construction refuses (more than five sides, boundaries, open fans, holes) stay on the
//! exact CPU path with a typed [`RefusalReason::NotPm`]. The mesh's sharpness tags become crease
//! scalars (eq. 14, [`crate::patch::pm::crease_scalar`]: `a = a_0 2^{-s}`, `0` when infinitely
//! sharp), untagged edges `a_0 = 2/3` or `--pm-crease-scalar` ([`PlanOptions::pm_crease_scalar`]).
//!
//! Every coefficient is a stencil row over the control vertices ([`tables`]): the TCS sums
//! weights × control positions (set 0 binding 8), so animation only re-uploads the control
//! positions (the renderer's shared buffers) and the vertex frames.
//!
//! Domains and captured parameters (`tessera sample`, `f u v ...`, then the patch type column):
//! - ordinary: quad domain, `(u, v)` of the face (corner 0 at `(0, 0)`, 1 at `(1, 0)`);
//! - polar: triangle domain with corners (facet corner `pole + 1`, `pole + 2`, pole) at
//!   barycentric `(w_0, w_1, w_2)`, evaluated at the singular bicubic's
//!   `(u, v) = (w_1 / (w_0 + w_1), w_2)`; captured as the barycentric weights of face corners
//!   1 and 2 (the public triangle contract);
//! - Pm sector `k`: triangle domain with corners (`v^k`, `v^{k+1}`, centre `b_004`), captured as
//!   `f:k s t`, `(s, t)` the barycentric weights of corner `k + 1` and of the centre
//!   ([`crate::patch::pm::PmPatch::sample`]'s sector parameters).
//!
//! Watertight: corners read the shared vertex frames (the Pm vertex point `v` and the normal of
//! its tangent plane), the centre of a Pm-patch its centre record, every edge its edge record
//! (outer edges and inner spokes alike), evaluated in the canonical direction with `precise`
//! arithmetic: positions and normals are bitwise equal on both sides.

pub mod tables;

use std::any::Any;
use std::sync::Arc;

use glam::DVec3;

pub use tables::{class_code, PmGpuTables};

use super::records::{FixedRecords, RecordGroup, RecordTablesPass};
use super::traits::{
    CaptureLayout, PassContext, PassPlan, PassTables, PatchPass, PatchScheme, PlanOptions,
    ReferencePatch, Refusal, RefusalReason,
};
use crate::patch::pm::{
    bicubic_sample, pm_facets, polar_as_bicubic, FacetClass, PmOptions, PmPatch, PmSample,
};
use crate::render::pass::{NormalRule, VertexFrames};
use crate::render::settings::{PatchLevelLimit, Spacing};
use crate::topology::Topology;
use crate::Result;

/// The Pm pass in the registry.
pub static PM: PmScheme = PmScheme;

/// Capture tag kinds of the Pm patch types (`CAPTURE_TAGGED | kind`, [`kind_name`]): ordinary,
/// polar, Pm `m = 3, 4, 5`, after the adaptive scheme's kinds.
pub const CAPTURE_KIND_BASE: u8 = 16;

/// Name of a Pm capture kind (`None` for other kinds).
pub fn kind_name(kind: u8) -> Option<&'static str> {
    match kind.checked_sub(CAPTURE_KIND_BASE)? {
        0 => Some("pm-ordinary"),
        1 => Some("pm-polar"),
        2 => Some("pm-3"),
        3 => Some("pm-4"),
        4 => Some("pm-5"),
        _ => None,
    }
}

/// Whether captured points of this kind are in a Pm patch's own triangle domain (polar, sector),
/// not comparable with the Catmull-Clark limit at equal `(u, v)`.
pub fn own_domain_kind(kind: u8) -> bool {
    kind > CAPTURE_KIND_BASE && kind_name(kind).is_some()
}

/// Takes the triangles, quads and pentagons of closed fans ([`crate::patch::pm::classify`]).
#[derive(Debug, Clone, Copy)]
pub struct PmScheme;

impl PatchScheme for PmScheme {
    fn name(&self) -> &'static str {
        "pm"
    }

    fn plan(&self, topo: &Arc<Topology>, candidates: &[u32], opts: &PlanOptions) -> PassPlan {
        let (tables, refused) = PmTables::plan(self.name(), topo, candidates, opts);
        PassPlan {
            tables: tables.map(|t| Arc::new(t) as Arc<dyn PassTables>),
            refused,
        }
    }
}

/// The Pm patches of a surface.
#[derive(Debug, Clone)]
pub struct PmTables {
    topo: Arc<Topology>,
    options: PmOptions,
    /// Faces, classes and the word buffer.
    pub gpu: Arc<PmGpuTables>,
}

impl PmTables {
    /// The tables of the facets among `candidates` the construction takes (`None` when none),
    /// crease scalars from the sharpness tags and `--pm-crease-scalar` (eq. 14), and the
    /// refusals, attributed to pass `pass`.
    pub fn plan(
        pass: &'static str,
        topo: &Arc<Topology>,
        candidates: &[u32],
        opts: &PlanOptions,
    ) -> (Option<PmTables>, Vec<Refusal>) {
        let options = PmOptions::default().with_crease_tags(topo, opts.pm_crease_scalar);
        let (tables, refused) = PmGpuTables::build(topo, candidates, &options);
        let refused = refused
            .into_iter()
            .map(|e| Refusal {
                face: e.face(),
                pass,
                reason: RefusalReason::NotPm(e),
            })
            .collect();
        let tables = (!tables.faces.is_empty()).then(|| PmTables {
            topo: topo.clone(),
            options,
            gpu: Arc::new(tables),
        });
        (tables, refused)
    }

    /// The topology.
    pub fn topology(&self) -> &Arc<Topology> {
        &self.topo
    }

    /// The construction's settings (crease scalars).
    pub fn options(&self) -> &PmOptions {
        &self.options
    }

    /// The CPU construction of every drawn facet for control positions `positions`.
    pub fn patches(&self, positions: &[DVec3]) -> Vec<(u32, PmPatch)> {
        let all = pm_facets(&self.topo, positions, &self.options);
        self.gpu
            .faces
            .iter()
            .filter_map(|&f| all[f as usize].clone().ok().map(|p| (f, p)))
            .collect()
    }

    /// The class of a drawn face.
    pub fn class(&self, face: u32) -> Option<FacetClass> {
        let i = self.gpu.faces.iter().position(|&f| f == face)?;
        Some(self.gpu.classes[i])
    }
}

/// The CPU reference of a captured point of `patch` (parameters as the module docs say):
/// `sub_face` is the sector of a Pm-patch.
pub fn reference_sample(patch: &PmPatch, sub_face: Option<u32>, u: f64, v: f64) -> PmSample {
    match patch {
        PmPatch::Bicubic(_) | PmPatch::Pm(_) => patch.sample(sub_face.unwrap_or(0) as usize, u, v),
        PmPatch::Polar { h, pole } => {
            // Face-corner barycentric weights to the singular bicubic's (u, v).
            let w = [1.0 - u - v, u, v];
            let (wa, wb, wp) = (w[(pole + 1) % 3], w[(pole + 2) % 3], w[*pole]);
            if wp >= 1.0 {
                return patch.sample(0, 0.0, 1.0);
            }
            bicubic_sample(&polar_as_bicubic(h), wb / (wa + wb), wp)
        }
    }
}

impl PassTables for PmTables {
    fn pass_name(&self) -> &'static str {
        PM.name()
    }

    fn faces(&self) -> &[u32] {
        &self.gpu.faces
    }

    fn patch_count(&self) -> usize {
        self.gpu.patch_count()
    }

    fn corner_frames(&self, positions: &[DVec3], _: NormalRule<'_>, frames: &mut VertexFrames) {
        // Every Pm corner is interior with one tangent plane: always a shared normal.
        for (v, p, n) in self.gpu.corner_frames(&self.topo, positions, &self.options) {
            frames.set(v, p, n, true);
        }
    }

    fn framing_points(&self, frames: &VertexFrames) -> Vec<DVec3> {
        self.gpu
            .corners
            .iter()
            .map(|&(v, _, _)| frames.limits[v as usize])
            .collect()
    }

    fn patch_level_limit(&self, _: Spacing) -> PatchLevelLimit {
        PatchLevelLimit::WHOLE
    }

    fn capture_layout(&self) -> CaptureLayout {
        CaptureLayout::SubFaces
    }

    /// Ordinary and polar facets (their captured `(u, v)` are enough); `None` for Pm-patches,
    /// whose points need the sector ([`reference_sample`] with the record's sub-face).
    fn reference(&self, positions: &[DVec3], face: u32) -> Option<ReferencePatch> {
        if matches!(self.class(face)?, FacetClass::Pm { .. }) {
            return None;
        }
        let patch = pm_facets(&self.topo, positions, &self.options)
            .swap_remove(face as usize)
            .ok()?;
        Some(Box::new(move |u, v| {
            let s = reference_sample(&patch, None, u, v);
            (s.position, s.normal)
        }))
    }

    fn create_pass(&self, pc: &PassContext<'_>) -> Result<Box<dyn PatchPass>> {
        let [bicubic, polar, sectors] = self.gpu.counts;
        let groups = [
            RecordGroup {
                tess_control: "pm_bicubic.tesc",
                tess_eval_stem: "patch_pm_bicubic",
                first: 0,
                count: bicubic,
            },
            RecordGroup {
                tess_control: "pm_polar.tesc",
                tess_eval_stem: "patch_pm_polar",
                first: bicubic,
                count: polar,
            },
            RecordGroup {
                tess_control: "pm_sector.tesc",
                tess_eval_stem: "patch_pm_sector",
                first: bicubic + polar,
                count: sectors,
            },
        ];
        let bytes: Vec<u8> = self
            .gpu
            .words
            .iter()
            .flat_map(|w| w.to_le_bytes())
            .collect();
        // The TCS applies the fixed stencil rows to the shared control positions.
        Ok(Box::new(RecordTablesPass::new(
            pc,
            "pm patches",
            &FixedRecords(bytes.into()),
            &groups,
        )?))
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}
