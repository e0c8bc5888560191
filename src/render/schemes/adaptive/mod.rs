//! Feature-adaptive subdivision on the GPU (`--scheme adaptive`; Köbler 2013 ch. 3-4, after
//! Nießner, Loop, Meyer, DeRose 2012): every face of the mesh refined around its features to the
//! isolation level by compute kernels, then drawn as exact B-spline patches at the level where
//! it became regular, transition patches where a finer neighbour meets it, and Gregory end caps
//! for what is still irregular at the isolation level. No face goes to the CPU path: a face the
//! scheme cannot build is an error naming it.
//!
//! CPU side: [`crate::subdiv::adaptive`] (refinement, census), [`crate::subdiv::tables`]
//! (kernels' tables), [`crate::patch::adaptive`] (patches, draw tables, CPU surface). GPU side:
//! [`refine`] (refinement kernels), [`derive`](mod@derive) (corner frames and end-cap points), [`pass`]
//! (draws).

pub mod derive;
pub mod pass;
pub mod refine;

use std::any::Any;
use std::sync::Arc;

use glam::DVec3;

use super::traits::{
    CaptureLayout, PassContext, PassPlan, PassTables, PatchPass, PatchScheme, PlanOptions,
    ReferencePatch, Refusal, RefusalReason,
};
use crate::mesh::Crease;
use crate::patch::adaptive::{AdaptiveDrawTables, AdaptiveSurface};
use crate::patch::gregory::GregoryTangents;
use crate::render::pass::{NormalRule, VertexFrames};
use crate::render::settings::{PatchLevelLimit, Spacing};
use crate::subdiv::adaptive::{AdaptiveOptions, AdaptiveRefinement};
use crate::subdiv::tables::RefinementTables;
use crate::subdiv::Level;
use crate::topology::Topology;
use crate::Result;

/// The name of a captured patch kind (`KIND_*` of `glsl/adaptive/adaptive.glsl`: the
/// [`crate::subdiv::adaptive::PatchType`] codes, end caps as `gregory-quad`, then
/// `transition`), as `tessera sample` writes it.
pub fn kind_name(kind: u8) -> &'static str {
    match kind {
        0 => "regular",
        1 => "boundary",
        2 => "crease",
        3 => "gregory-quad",
        4 => "single-crease",
        5 => "transition",
        k => super::pm::kind_name(k).unwrap_or("unknown"),
    }
}

/// The adaptive scheme's only pass, in the registry.
pub static ADAPTIVE: AdaptiveScheme = AdaptiveScheme;

/// Takes every face with a limit surface (or fails naming one it cannot build).
#[derive(Debug, Clone, Copy)]
pub struct AdaptiveScheme;

impl PatchScheme for AdaptiveScheme {
    fn name(&self) -> &'static str {
        "adaptive"
    }

    fn takes_every_face(&self) -> bool {
        true
    }

    fn plan(&self, topo: &Arc<Topology>, candidates: &[u32], opts: &PlanOptions) -> PassPlan {
        match AdaptiveTables::new(topo, candidates, opts) {
            Ok(t) => PassPlan {
                tables: Some(Arc::new(t)),
                refused: Vec::new(),
            },
            Err((face, why)) => PassPlan {
                tables: None,
                refused: vec![Refusal {
                    face,
                    pass: self.name(),
                    reason: RefusalReason::Adaptive(why),
                }],
            },
        }
    }
}

/// The CPU tables of the adaptive scheme for one topology.
#[derive(Debug)]
pub struct AdaptiveTables {
    faces: Vec<u32>,
    /// The refinement (levels, sparse topologies).
    pub adaptive: AdaptiveRefinement,
    /// The kernels' subdivision tables.
    pub refinement: RefinementTables,
    /// What the draws read.
    pub draw: AdaptiveDrawTables,
    /// Edge-tangent lengths of the end caps' Gregory construction.
    pub tangents: GregoryTangents,
}

impl AdaptiveTables {
    /// Refines `topo` to `opts.isolation` (stopping at single-crease patches with
    /// `opts.single_crease`) and builds the tables; on failure the face that cannot be drawn and
    /// why.
    pub fn new(
        topo: &Arc<Topology>,
        faces: &[u32],
        opts: &PlanOptions,
    ) -> std::result::Result<AdaptiveTables, (u32, String)> {
        let options = AdaptiveOptions {
            isolation: opts.isolation,
            single_crease: opts.single_crease,
            end_cap_sharpness: opts.end_cap_sharpness,
            lattice_normals: opts.lattice_normals,
        };
        Self::build((**topo).clone(), faces, options, opts.gregory_tangents)
    }

    /// [`Self::new`] from the base topology, the refinement options and the end caps'
    /// edge-tangent lengths.
    fn build(
        topo: Topology,
        faces: &[u32],
        options: AdaptiveOptions,
        tangents: GregoryTangents,
    ) -> std::result::Result<AdaptiveTables, (u32, String)> {
        let first = faces.first().copied().unwrap_or(0);
        let base = Level::from_topology(topo);
        let adaptive =
            AdaptiveRefinement::from_level(base, options).map_err(|e| (first, e.to_string()))?;
        let refinement =
            RefinementTables::adaptive(&adaptive).map_err(|e| (first, e.to_string()))?;
        let draw = AdaptiveDrawTables::with_tangents(&adaptive, tangents)
            .map_err(|e| (e.base_face(), e.to_string()))?;
        Ok(AdaptiveTables {
            faces: faces.to_vec(),
            adaptive,
            refinement,
            draw,
            tangents,
        })
    }

    /// These tables with the sharpness of each edge of `creases` replaced (run-time creases,
    /// [`crate::render::SurfaceRenderer::set_sharpness`]): refined and tabulated again from the
    /// new base topology, at the same isolation, single-crease and tangent settings. Whether the GPU
    /// pass can take them without re-planning (the same faces refined to the same levels) is
    /// its [`PatchPass::update_tables`]'s decision. Errors name the crease or the face.
    pub fn with_sharpness(&self, creases: &[Crease]) -> Result<AdaptiveTables> {
        let topo = self.adaptive.levels[0].topology().with_creases(creases)?;
        let options = AdaptiveOptions {
            isolation: self.adaptive.isolation,
            single_crease: self.adaptive.single_crease,
            end_cap_sharpness: self.adaptive.end_cap_sharpness,
            lattice_normals: self.adaptive.lattice_normals,
        };
        Self::build(topo, &self.faces, options, self.tangents)
            .map_err(|(f, why)| crate::Error::Invalid(format!("face {f}: {why}")))
    }

    /// Patch primitives drawn: whole B-spline, single-crease and end-cap patches, one per
    /// transition triangle.
    pub fn primitive_count(&self) -> usize {
        self.draw.primitive_count()
    }

    /// Bytes of GPU memory of the patch data (what [`pass::AdaptivePass`] uploads and derives,
    /// staging and index padding aside): the draw tables ([`AdaptiveDrawTables::memory_bytes`]),
    /// the kernels' tables, the refined points (12 bytes each), the frames (two vec4 per
    /// slot) and the end-cap points (a vec4 per end-cap row).
    pub fn gpu_memory_bytes(&self) -> usize {
        let d = &self.draw;
        d.memory_bytes()
            + self.refinement.gpu_tables().bytes()
            + 12 * self.refinement.total_vertices as usize
            + 32 * d.frame_count()
            + 16 * (d.rows.len() - d.end_cap_first_row as usize)
    }

    /// The CPU surface of these tables over control `positions` (the reference the GPU
    /// reproduces).
    pub fn cpu_surface(&self, positions: &[DVec3]) -> Result<AdaptiveSurface> {
        AdaptiveSurface::with_tangents(&self.adaptive, positions, self.tangents)
            .map_err(|e| crate::Error::Invalid(e.to_string()))
    }
}

impl PassTables for AdaptiveTables {
    fn pass_name(&self) -> &'static str {
        ADAPTIVE.name()
    }

    fn faces(&self) -> &[u32] {
        &self.faces
    }

    fn patch_count(&self) -> usize {
        self.primitive_count()
    }

    fn corner_frames(&self, _: &[DVec3], _: NormalRule<'_>, _: &mut VertexFrames) {
        // The corner frames are computed on the GPU from the refined points every frame
        // (derive.rs); the shared per-vertex frames are not read by this pass.
    }

    fn framing_points(&self, frames: &VertexFrames) -> Vec<DVec3> {
        // The limit surface lies in the convex hull of the control points.
        let topo = self.adaptive.levels[0].topology();
        let mut points: Vec<DVec3> = self
            .faces
            .iter()
            .flat_map(|&f| {
                topo.face_vertices(f)
                    .iter()
                    .map(|&v| frames.limits[v as usize])
            })
            .collect();
        points.dedup();
        points
    }

    /// A level-k patch gets the uniform level / 2^k, so only patches whose own level exceeds
    /// the limit are split, into `split / 2^k` per side (`pass::level_split`); a transition
    /// fan's triangles into as many sub-triangles per side, half as many on a half edge, with
    /// every edge on its owner's lattice. The lattices need equal spacing: fractional spacing
    /// is drawn unsplit.
    fn patch_level_limit(&self, spacing: Spacing) -> PatchLevelLimit {
        PatchLevelLimit {
            max_patch_level: f32::INFINITY,
            splittable: spacing == Spacing::Equal,
        }
    }

    fn capture_layout(&self) -> CaptureLayout {
        CaptureLayout::SubFaces
    }

    fn reference(&self, positions: &[DVec3], face: u32) -> Option<ReferencePatch> {
        self.references(positions, &[face]).pop().flatten()
    }

    fn references(&self, positions: &[DVec3], faces: &[u32]) -> Vec<Option<ReferencePatch>> {
        let topo = self.adaptive.levels[0].topology();
        let surface = self.cpu_surface(positions).ok().map(Arc::new);
        faces
            .iter()
            .map(|&face| {
                let surface = surface.clone().filter(|_| topo.face_size(face) == 4)?;
                let patch: ReferencePatch =
                    Box::new(move |u, v| match surface.eval(face, None, u, v) {
                        Some(p) => (p.position, p.du.cross(p.dv).normalize_or_zero()),
                        None => (DVec3::NAN, DVec3::ZERO),
                    });
                Some(patch)
            })
            .collect()
    }

    fn create_pass(&self, pc: &PassContext<'_>) -> Result<Box<dyn PatchPass>> {
        Ok(Box::new(pass::AdaptivePass::new(
            pc,
            &self.refinement,
            &self.draw,
            |tables| {
                let t = tables.as_any().downcast_ref::<AdaptiveTables>()?;
                Some((&t.refinement, &t.draw))
            },
        )?))
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}
