//! Which GPU scheme draws the faces that are not regular B-spline patches (`--scheme`), and the
//! surface plan for it: Gregory patches (Loop et al. 2009) for the triangles and quads a variant
//! can take, the exact CPU fallback for every other face (with the reason on stderr).

use std::sync::Arc;

use super::fallback::{self, FallbackFace, FallbackMesh};
use super::gregory_layout::irregular_faces;
use super::gregory_stencil::StencilPlan;
use super::gregory_vs::{select_faces, vs_budget, VsBudget};
use super::scene::SurfacePlan;
use super::surface::SurfaceData;
use crate::gpu::Context;
use crate::mesh::ControlMesh;
use crate::subdiv::eval::LimitEvaluator;
use crate::topology::Topology;
use crate::{Error, Result};

/// GPU scheme for non-regular faces.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Scheme {
    /// Only regular faces on the GPU; every other face from the exact CPU reference.
    BsplineOnly,
    /// Two-stage Gregory construction: vertex shader + TCS (§4.1-4.2).
    GregoryVs,
    /// Stencil Gregory construction: precomputed one-ring weights in the TCS (§4.3).
    #[default]
    GregoryStencil,
}

impl Scheme {
    /// Every scheme.
    pub const ALL: [Scheme; 3] = [
        Scheme::BsplineOnly,
        Scheme::GregoryVs,
        Scheme::GregoryStencil,
    ];

    /// Command-line name.
    pub fn name(self) -> &'static str {
        match self {
            Scheme::BsplineOnly => "bspline-only",
            Scheme::GregoryVs => "gregory-vs",
            Scheme::GregoryStencil => "gregory-stencil",
        }
    }

    /// Parses a command-line name.
    pub fn parse(s: &str) -> Result<Scheme> {
        Self::ALL
            .into_iter()
            .find(|x| x.name() == s)
            .ok_or_else(|| {
                Error::Invalid(format!(
                    "scheme `{s}`: expected bspline-only, gregory-vs or gregory-stencil"
                ))
            })
    }
}

/// Device limits the Gregory variants are planned against.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SchemeLimits {
    /// Two-stage variant's varyings budget (`None`: the variant is unavailable).
    pub vs: Option<VsBudget>,
    /// `maxTessellationPatchSize` (stencil variant: largest face one-ring).
    pub max_patch_size: u32,
}

impl SchemeLimits {
    /// The limits of `ctx`'s device.
    pub fn from_context(ctx: &Context) -> SchemeLimits {
        SchemeLimits {
            vs: vs_budget(ctx),
            max_patch_size: ctx.info().limits.max_tessellation_patch_size,
        }
    }
}

/// The Gregory part of a surface: the variant and the faces it draws (in any order; the pass
/// orders them).
#[derive(Debug, Clone)]
pub struct GregorySurface {
    /// [`Scheme::GregoryVs`] or [`Scheme::GregoryStencil`].
    pub scheme: Scheme,
    /// Topology of the mesh (the GPU tables are built from it).
    pub topology: Arc<Topology>,
    /// Faces drawn as Gregory patches.
    pub faces: Vec<u32>,
}

/// Faces the variant of `scheme` accepts among `candidates`, and the others with the reason.
pub fn split_faces(
    topo: &Topology,
    candidates: &[u32],
    scheme: Scheme,
    limits: &SchemeLimits,
) -> (Vec<u32>, Vec<(u32, String)>) {
    match scheme {
        Scheme::BsplineOnly => (Vec::new(), Vec::new()),
        Scheme::GregoryVs => match limits.vs {
            Some(b) => select_faces(topo, candidates, b),
            None => (
                Vec::new(),
                candidates
                    .iter()
                    .map(|&f| {
                        (
                            f,
                            "the device's varyings budget is below 64 components".to_string(),
                        )
                    })
                    .collect(),
            ),
        },
        Scheme::GregoryStencil => {
            let plan = StencilPlan::new(topo, candidates, limits.max_patch_size);
            let rejected = plan
                .table
                .rejected
                .iter()
                .map(|r| (r.face, r.reason.clone()))
                .collect();
            (plan.layout.faces, rejected)
        }
    }
}

/// Builds the surface of `mesh` for `scheme`: regular faces as B-spline patches, the faces the
/// Gregory variant takes as Gregory patches, every other face with a limit surface evaluated
/// exactly on the CPU on a grid matching `level`. Faces left to the CPU although they are
/// triangles or quads are reported on stderr (count and the first reasons).
pub fn surface_for_scheme(
    mesh: &ControlMesh,
    level: u32,
    scheme: Scheme,
    limits: &SchemeLimits,
) -> Result<SurfaceData> {
    let (plan, gregory) = plan_for_scheme(mesh, scheme, limits)?;
    let fallback = cpu_faces(mesh, &plan.fallback_faces, level)?;
    Ok(SurfaceData {
        positions: mesh.positions().to_vec(),
        patches: plan.patches,
        fallback_faces: plan.fallback_faces,
        fallback,
        skipped_faces: plan.skipped_faces,
        gregory,
    })
}

/// Which face is drawn how under `scheme` (no CPU evaluation yet): [`surface_for_scheme`]
/// without the fallback triangles.
pub fn plan_for_scheme(
    mesh: &ControlMesh,
    scheme: Scheme,
    limits: &SchemeLimits,
) -> Result<(SurfacePlan, Option<GregorySurface>)> {
    let topo = Arc::new(Topology::new(mesh)?);
    let mut plan = SurfacePlan::new(&topo);
    let mut gregory = None;
    if scheme != Scheme::BsplineOnly {
        let candidates = irregular_faces(&topo);
        let (accepted, rejected) = split_faces(&topo, &candidates, scheme, limits);
        if !rejected.is_empty() {
            eprintln!(
                "{}: {} of {} irregular triangle/quad faces stay on the exact CPU path, e.g.:",
                scheme.name(),
                rejected.len(),
                candidates.len()
            );
            for (_, why) in rejected.iter().take(3) {
                eprintln!("  {why}");
            }
        }
        let set: std::collections::HashSet<u32> = accepted.iter().copied().collect();
        plan.fallback_faces.retain(|f| !set.contains(&f.face));
        if !accepted.is_empty() {
            gregory = Some(GregorySurface {
                scheme,
                topology: topo.clone(),
                faces: accepted,
            });
        }
    }
    Ok((plan, gregory))
}

/// The CPU-evaluated triangles of `faces` at `level` (exact limit, [`LimitEvaluator`]).
pub fn cpu_faces(mesh: &ControlMesh, faces: &[FallbackFace], level: u32) -> Result<FallbackMesh> {
    if faces.is_empty() {
        return Ok(FallbackMesh::default());
    }
    let ev = LimitEvaluator::new(mesh)?;
    fallback::tessellate(faces, level, |f, sub, uv| {
        Ok(ev
            .eval_points(f as usize, sub as usize, uv)?
            .into_iter()
            .map(|s| (s.position, s.normal))
            .collect())
    })
}
