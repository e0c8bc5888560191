//! From a control mesh to [`SurfaceData`]: the faces with a limit surface are offered to the
//! scheme's passes in registry order ([`crate::render::schemes::REGISTRY`]); each takes what it
//! can and refuses the rest with a typed reason; what no pass takes is evaluated exactly on the
//! CPU ([`LimitEvaluator`]) on a grid matching the tessellation level.

use std::sync::Arc;

use super::fallback::{self, FallbackFace, FallbackMesh};
use super::schemes::{PatchScheme, PlanOptions, Refusal, Scheme, SchemeLimits};
use super::surface::SurfaceData;
use crate::mesh::ControlMesh;
use crate::patch::gregory::vertex_fit;
use crate::subdiv::eval::{LimitEvaluator, LimitSample};
use crate::topology::Topology;
use crate::Result;

/// Plans the faces of `mesh` for `passes` (no CPU evaluation yet): the parts, the faces left to
/// the CPU path (`fallback` empty) and every refusal (`SurfaceData::refusals`; the refusals of
/// the passes after the first are also logged at debug level, count and the first reasons). A
/// refusal of a pass that takes every face ([`PatchScheme::takes_every_face`]) is an error
/// naming the faces.
pub fn plan_passes(
    mesh: &ControlMesh,
    passes: &[&dyn PatchScheme],
    opts: &PlanOptions,
) -> Result<SurfaceData> {
    // `--gregory-tangents fitted`: the factors are fitted here, on the pose planned (the rest
    // pose), and frozen in the topology the tables are built from, when a pass reads them.
    let topo = Topology::new(mesh)?;
    let topo = match passes.iter().any(|p| p.reads_fitted_crease_factors()) {
        true => vertex_fit::for_tangents(mesh, topo, opts.gregory_tangents)?,
        false => topo,
    };
    let topo = Arc::new(topo);
    let mut surface = SurfaceData {
        positions: mesh.positions().to_vec(),
        topology: Some(topo.clone()),
        texcoords: mesh.uvs().cloned().map(Arc::new),
        ..SurfaceData::default()
    };
    let mut candidates = Vec::new();
    for f in 0..topo.face_count() as u32 {
        if topo.has_limit_surface(f) {
            candidates.push(f);
        } else {
            surface.skipped_faces += 1;
        }
    }
    for (k, pass) in passes.iter().enumerate() {
        let plan = pass.plan(&topo, &candidates, opts);
        if pass.takes_every_face() && !plan.refused.is_empty() {
            return Err(refusal_error(pass.name(), &plan.refused));
        }
        if let Some(t) = plan.tables {
            surface.parts.push(t);
        }
        candidates = plan.refused.iter().map(|r| r.face).collect();
        candidates.sort_unstable();
        // The first pass's refusals are the faces offered to the next (not failures).
        if k > 0 {
            log_refusals(pass.name(), &plan.refused, &candidates);
        }
        surface.refusals.extend(plan.refused);
    }
    surface.fallback_faces = candidates
        .iter()
        .map(|&face| FallbackFace::new(face, topo.face_size(face) as u32))
        .collect();
    Ok(surface)
}

fn refusal_error(pass: &str, refused: &[Refusal]) -> crate::Error {
    let first: Vec<String> = refused.iter().take(3).map(|r| r.to_string()).collect();
    crate::Error::Invalid(format!(
        "{pass}: {} faces cannot be drawn: {}{}",
        refused.len(),
        first.join("; "),
        if refused.len() > 3 { "; ..." } else { "" }
    ))
}

fn log_refusals(pass: &str, refused: &[super::schemes::Refusal], left: &[u32]) {
    if refused.is_empty() {
        return;
    }
    log::debug!(
        "{pass}: {} faces stay on the exact CPU path, e.g.: {}",
        left.len(),
        refused
            .iter()
            .take(3)
            .map(|r| r.to_string())
            .collect::<Vec<_>>()
            .join("; ")
    );
}

/// Which face is drawn how under `scheme`: [`plan_passes`] with the scheme's passes and the
/// default [`PlanOptions`].
pub fn plan_for_scheme(
    mesh: &ControlMesh,
    scheme: Scheme,
    limits: &SchemeLimits,
) -> Result<SurfaceData> {
    plan_passes(mesh, scheme.passes(), &PlanOptions::new(*limits))
}

/// As [`plan_for_scheme`] with explicit options (e.g. the isolation level).
pub fn plan_for_scheme_with(
    mesh: &ControlMesh,
    scheme: Scheme,
    opts: &PlanOptions,
) -> Result<SurfaceData> {
    plan_passes(mesh, scheme.passes(), opts)
}

/// Builds the surface of `mesh` for `scheme`: the faces its passes take as GPU patches, every
/// other face with a limit surface evaluated exactly on the CPU on a grid matching `level`.
pub fn surface_for_scheme(
    mesh: &ControlMesh,
    level: u32,
    scheme: Scheme,
    limits: &SchemeLimits,
) -> Result<SurfaceData> {
    surface_for_scheme_with(mesh, level, scheme, &PlanOptions::new(*limits))
}

/// As [`surface_for_scheme`] with explicit options (e.g. the isolation level).
pub fn surface_for_scheme_with(
    mesh: &ControlMesh,
    level: u32,
    scheme: Scheme,
    opts: &PlanOptions,
) -> Result<SurfaceData> {
    let mut surface = plan_for_scheme_with(mesh, scheme, opts)?;
    surface.fallback = cpu_faces(mesh, &surface.fallback_faces, level)?;
    Ok(surface)
}

/// Builds the surface of `mesh` with only regular faces on the GPU (`bspline-only`) and the
/// others evaluated exactly on the CPU at `level`. Needs no device.
pub fn surface_from_mesh(mesh: &ControlMesh, level: u32) -> Result<SurfaceData> {
    surface_for_scheme(mesh, level, Scheme::BsplineOnly, &SchemeLimits::NO_DEVICE)
}

/// As [`surface_from_mesh`], with the CPU-evaluated faces sampled at tessellation `level`
/// through `eval(face, sub, &[(u, v)]) -> [LimitSample]` (position, partials, unit normal).
pub fn surface_with<F>(mesh: &ControlMesh, level: u32, eval: F) -> Result<SurfaceData>
where
    F: Fn(u32, u32, &[(f64, f64)]) -> Result<Vec<LimitSample>> + Sync,
{
    let mut surface = plan_for_scheme(mesh, Scheme::BsplineOnly, &SchemeLimits::NO_DEVICE)?;
    surface.fallback = fallback::tessellate(&surface.fallback_faces, level, eval)?;
    Ok(surface)
}

/// The CPU-evaluated triangles of `faces` at `level` (exact limit, [`LimitEvaluator`]).
pub fn cpu_faces(mesh: &ControlMesh, faces: &[FallbackFace], level: u32) -> Result<FallbackMesh> {
    if faces.is_empty() {
        return Ok(FallbackMesh::default());
    }
    let ev = LimitEvaluator::new(mesh)?;
    fallback::tessellate(faces, level, |f, sub, uv| {
        ev.eval_points(f as usize, sub as usize, uv)
    })
}
