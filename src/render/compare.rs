//! Every scheme on one mesh, measured one way (`tessera compare`): what each draws, how close it
//! is to the exact Catmull-Clark limit, what it costs on the GPU, whether its seams are
//! watertight and how far its normals jump across patch edges where the limit is smooth; plus an
//! error map per scheme on one shared colour scale. This is the table the Gregory paper's
//! Table 3 (ACC vs Pm vs Gregory) and the QAS paper's speed claim are read against.

use std::collections::HashMap;

use glam::DVec3;

use super::accuracy::{capture_whole_patches, ExactReference, MeasuredPoint};
use super::bench::median;
use super::continuity::ContinuityReport;
use super::heatmap::{heat_only_surface, HeatSurface};
use super::offscreen::{OffscreenDesc, OffscreenSession};
use super::plan::plan_for_scheme_with;
use super::renderer::RenderDesc;
use super::schemes::{PlanOptions, Scheme};
use super::seams::SeamReport;
use super::settings::TessSettings;
use super::CPU_PATH_LABEL;
use crate::gpu::Context;
use crate::patch::gregory::accuracy::{FaceHeat, HeatSample};
use crate::subdiv::eval::GridSample;
use crate::{ControlMesh, Error, Result};

/// Two captured points closer than this fraction of the bbox diagonal are one seam point.
pub const SEAM_TOLERANCE: f64 = 1e-6;

/// How every scheme is run.
#[derive(Debug, Clone)]
pub struct CompareDesc {
    /// Uniform tessellation level of the capture and the timed frames.
    pub tess: f32,
    /// Timed frames (after one warm-up frame); the median is reported.
    pub frames: u32,
    /// Image size of the timed frames.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Planning options (device limits, the adaptive scheme's isolation and single-crease).
    pub plan: PlanOptions,
}

/// One scheme's line of the comparison. Distances are fractions of the bbox diagonal, angles
/// radians, over every point the GPU patches emitted (faces on the CPU path are exact and not
/// sampled).
#[derive(Debug, Clone)]
pub struct SchemeRow {
    /// The scheme.
    pub scheme: Scheme,
    /// Patches drawn (every pass, sub-patches not counted).
    pub patches: usize,
    /// Faces evaluated on the CPU path.
    pub cpu_faces: usize,
    /// Captured points measured.
    pub samples: usize,
    /// RMS distance to the closest exact point.
    pub rms_distance: f64,
    /// Largest distance.
    pub max_distance: f64,
    /// RMS normal angle against the exact normal at the closest point.
    pub rms_normal: f64,
    /// Largest normal angle.
    pub max_normal: f64,
    /// Median GPU milliseconds per frame: compute pre-passes + patch draws + CPU-path triangles.
    pub frame_ms: f64,
    /// Of which compute pre-passes (construction or refinement on the GPU).
    pub compute_ms: f64,
    /// GPU buffer memory of the surface (shared buffers, every pass, CPU-path triangles).
    pub memory_bytes: u64,
    /// Seams between the GPU patches.
    pub seams: SeamReport,
    /// Tangent-plane continuity of the patches' constructions across shared smooth edges.
    pub continuity: ContinuityReport,
}

/// A row and the measured points it was computed from (for the error map).
#[derive(Debug, Clone)]
pub struct SchemeComparison {
    /// The table line.
    pub row: SchemeRow,
    /// Every captured point with its error.
    pub points: Vec<MeasuredPoint>,
}

/// The exact reference every scheme of a comparison at `desc.tess` is measured against (built
/// once per mesh).
pub fn exact_reference(mesh: &ControlMesh, desc: &CompareDesc) -> Result<ExactReference> {
    ExactReference::new(mesh, desc.tess.round().max(1.0) as usize)
}

/// Draws `mesh` with `scheme`: captures and measures every TES point at `desc.tess` (patches
/// not split) against `exact` ([`exact_reference`]), then times `desc.frames` frames with the
/// renderer's default settings.
pub fn compare_scheme(
    ctx: &Context,
    mesh: &ControlMesh,
    exact: &ExactReference,
    scheme: Scheme,
    desc: &CompareDesc,
) -> Result<SchemeComparison> {
    let surface = plan_for_scheme_with(mesh, scheme, &desc.plan)?;
    let diagonal = mesh.bbox_diagonal().max(f64::MIN_POSITIVE);
    let points = if surface.patch_count() == 0 {
        Vec::new()
    } else {
        let records = capture_whole_patches(ctx, &surface, desc.tess)?;
        exact.measure(&records)?
    };
    let n = points.len().max(1) as f64;
    let rms = |f: fn(&MeasuredPoint) -> f64| {
        (points.iter().fold(0.0, |a, m| a + f(m).powi(2)) / n).sqrt()
    };
    let max = |f: fn(&MeasuredPoint) -> f64| points.iter().map(f).fold(0.0, f64::max);
    let (frame_ms, compute_ms, memory_bytes) = time_frames(ctx, &surface, desc)?;
    let row = SchemeRow {
        scheme,
        patches: surface.patch_count(),
        cpu_faces: surface.fallback_faces.len(),
        samples: points.len(),
        rms_distance: rms(|m| m.distance) / diagonal,
        max_distance: max(|m| m.distance) / diagonal,
        rms_normal: rms(|m| m.normal_angle),
        max_normal: max(|m| m.normal_angle),
        frame_ms,
        compute_ms,
        memory_bytes,
        seams: SeamReport::new(&points, SEAM_TOLERANCE * diagonal),
        continuity: ContinuityReport::new(&surface, &exact.topo, exact.turns()),
    };
    Ok(SchemeComparison { row, points })
}

/// Median frame and compute milliseconds over `desc.frames` timed frames, and the surface's
/// GPU memory.
fn time_frames(
    ctx: &Context,
    surface: &super::SurfaceData,
    desc: &CompareDesc,
) -> Result<(f64, f64, u64)> {
    let render = RenderDesc {
        tess: TessSettings {
            level: desc.tess,
            ..TessSettings::default()
        },
        ..RenderDesc::default()
    };
    let off = OffscreenDesc {
        width: desc.width,
        height: desc.height,
        ..OffscreenDesc::default()
    };
    let mut session = OffscreenSession::new(ctx, surface, &render, &off, true)?;
    let memory = session.renderer().memory_bytes().total();
    session.frame()?;
    let (mut frame, mut compute) = (Vec::new(), Vec::new());
    for _ in 0..desc.frames.max(1) {
        let r = session
            .frame()?
            .ok_or_else(|| Error::Invalid("compare: no GPU timings returned".into()))?;
        compute.push(r.compute_ms());
        frame.push(r.compute_ms() + r.patch_ms() + r.ms(CPU_PATH_LABEL));
    }
    Ok((median(&mut frame), median(&mut compute), memory))
}

/// The error map of one scheme: every face of `mesh` drawn from `exact`, its exact limit on a
/// `grid` per (sub-)face ([`crate::subdiv::eval::LimitEvaluator::eval_all_grids`], evaluated once for all
/// schemes),
/// each sample coloured by the distance of the scheme's captured point of the same face nearest
/// to it (faces without captured points are on the exact CPU path: 0), on the shared `scale`
/// (model units shown as full red).
pub fn error_map(
    mesh: &ControlMesh,
    exact: &[Option<Vec<GridSample>>],
    grid: usize,
    points: &[MeasuredPoint],
    scale: f64,
) -> Result<HeatSurface> {
    let mut by_face: HashMap<u32, Vec<&MeasuredPoint>> = HashMap::new();
    for m in points {
        by_face.entry(m.record.face).or_default().push(m);
    }
    let mut heat = Vec::new();
    for (f, samples) in exact.iter().enumerate() {
        let Some(samples) = samples else { continue };
        let captured = by_face.get(&(f as u32)).map(Vec::as_slice).unwrap_or(&[]);
        for sub in samples.chunks((grid + 1) * (grid + 1)) {
            let samples = sub
                .iter()
                .map(|g| HeatSample {
                    position: g.sample.position,
                    normal: g.sample.normal,
                    distance: nearest_distance(captured, g.sample.position),
                })
                .collect();
            heat.push(FaceHeat {
                face: f as u32,
                triangle: false,
                grid,
                samples,
            });
        }
    }
    heat_only_surface(mesh, &heat, scale)
}

/// The error of the captured point nearest to `x` (0 without captured points).
fn nearest_distance(captured: &[&MeasuredPoint], x: DVec3) -> f64 {
    captured
        .iter()
        .map(|m| {
            let p = DVec3::from(m.record.position.map(f64::from));
            (p.distance_squared(x), m.distance)
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map_or(0.0, |(_, d)| d)
}
