//! Accuracy of the GPU Gregory variants against the exact Catmull-Clark limit: the real pipeline
//! draws the mesh with a `--scheme`, the TES capture of every Gregory patch is measured as
//! [`crate::patch::gregory::accuracy`] measures the CPU construction (distance to the closest
//! exact point, equal-`(u, v)` error on quads, normal angle at the closest point), so the two
//! reports compare directly (`tessera error --scheme gregory-vs|gregory-stencil`).

use std::collections::HashSet;

use glam::DVec3;

use super::offscreen::{render_to_image, OffscreenDesc};
use super::pass::capture_capacity_for;
use super::plan::plan_for_scheme;
use super::renderer::{resolve_tess, RenderDesc};
use super::schemes::bspline::BSPLINE;
use super::schemes::{PatchScheme, Scheme, SchemeLimits};
use super::settings::TessSettings;
use crate::gpu::Context;
use crate::patch::gregory::accuracy::{
    closest_exact, nearby_exact_samples, normal_angle, AccuracyReport,
};
use crate::patch::gregory::check_face;
use crate::patch::RegularPatch;
use crate::subdiv::eval::{GridSample, LimitEvaluator};
use crate::topology::Topology;
use crate::{ControlMesh, Error, Result};

/// Draws `mesh` with `scheme` at uniform level `grid` and measures the captured points of every
/// Gregory patch. Faces left to the CPU path count as unsupported.
pub fn measure_gpu(
    ctx: &Context,
    mesh: &ControlMesh,
    scheme: Scheme,
    grid: usize,
) -> Result<AccuracyReport> {
    if scheme.passes().iter().all(|p| p.name() == BSPLINE.name()) {
        return Err(Error::Invalid(format!(
            "{scheme} draws no Gregory patches to measure"
        )));
    }
    let topo = Topology::new(mesh)?;
    let mut surface = plan_for_scheme(mesh, scheme, &SchemeLimits::from_context(ctx))?;
    let faces: Vec<u32> = surface.irregular_gpu_faces();
    let mut report = AccuracyReport {
        diagonal: mesh.bbox_diagonal(),
        ..Default::default()
    };
    for f in 0..topo.face_count() as u32 {
        if !topo.has_limit_surface(f) {
            continue;
        }
        if RegularPatch::gather(&topo, f).is_some() {
            report.regular += 1;
        } else if !faces.contains(&f) {
            report.unsupported += 1;
            if let Err(e) = check_face(&topo, f) {
                report.first_unsupported.get_or_insert(e);
            }
        }
    }
    report.faces = faces.len();
    report.triangles = faces.iter().filter(|&&f| topo.face_size(f) == 3).count();
    if faces.is_empty() {
        return Ok(report);
    }
    surface.fallback_faces.clear();
    let tess = TessSettings {
        level: grid.max(1) as f32,
        max_patch_level: f32::INFINITY,
        ..TessSettings::default()
    };
    let render = RenderDesc {
        tess,
        capture_capacity: Some(capture_capacity_for(
            surface.patch_count(),
            &resolve_tess(ctx, &surface, &tess),
        )),
        ..RenderDesc::default()
    };
    let off = OffscreenDesc {
        width: 64,
        height: 64,
        ..OffscreenDesc::default()
    };
    let records = render_to_image(ctx, &surface, &render, &off, false)?
        .capture
        .unwrap_or_default();
    let ev = LimitEvaluator::new(mesh)?;
    let dense: Vec<Option<Vec<GridSample>>> = ev.eval_all_grids(2 * grid.max(1))?;
    let drawn: HashSet<u32> = faces.iter().copied().collect();
    let (mut sd, mut suv, mut sn, mut nuv) = (0.0, 0.0, 0.0, 0usize);
    for r in records.iter().filter(|r| drawn.contains(&r.face)) {
        let x = DVec3::from(r.position.map(f64::from));
        let n = DVec3::from(r.normal.map(f64::from));
        let f = r.face;
        let candidates = nearby_exact_samples(&topo, &dense, f);
        let c = closest_exact(&ev, x, &candidates, f)?;
        let d = (c.sample.position - x).length();
        let a = normal_angle(n, c.sample.normal);
        report.samples += 1;
        sd += d * d;
        sn += a * a;
        report.max_distance = report.max_distance.max(d);
        report.max_normal = report.max_normal.max(a);
        if topo.face_size(f) == 4 {
            let e = (ev
                .eval(f as usize, 0, f64::from(r.u), f64::from(r.v))?
                .position
                - x)
                .length();
            suv += e * e;
            nuv += 1;
            report.max_uv = report.max_uv.max(e);
        }
    }
    let diag = report.diagonal.max(f64::MIN_POSITIVE);
    let count = report.samples.max(1) as f64;
    report.rms_distance = (sd / count).sqrt() / diag;
    report.max_distance /= diag;
    report.rms_uv = (suv / nuv.max(1) as f64).sqrt() / diag;
    report.max_uv /= diag;
    report.rms_normal = (sn / count).sqrt();
    Ok(report)
}
