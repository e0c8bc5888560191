//! Accuracy of the GPU Gregory variants against the exact Catmull-Clark limit: the real pipeline
//! draws the mesh with a `--scheme`, the TES capture of every Gregory patch is measured as
//! [`crate::patch::gregory::accuracy`] measures the CPU construction (distance to the closest
//! exact point, equal-`(u, v)` error on quads, normal angle at the closest point), so the two
//! reports compare directly (`tessera error --scheme gregory-vs|gregory-stencil`).
//!
//! The adaptive scheme (`tessera error --scheme adaptive --isolation L`) draws every face and
//! tags each captured point with the patch that produced it: [`measure_gpu_with`] also reports
//! the error per patch type ([`TypeAccuracy`]); points of non-quad faces are in sub-face
//! domains and compared at equal `(u, v)` through `LimitEvaluator::eval(face, sub, u, v)`.

use std::collections::{BTreeMap, HashMap, HashSet};

use glam::DVec3;
use rayon::prelude::*;

use super::offscreen::{render_to_image, OffscreenDesc};
use super::pass::{capture_capacity_for, CaptureRecord};
use super::plan::plan_for_scheme_with;
use super::renderer::{resolve_tess, RenderDesc};
use super::schemes::adaptive::kind_name;
use super::schemes::bspline::BSPLINE;
use super::schemes::{PatchScheme, PlanOptions, Scheme, SchemeLimits};
use super::settings::TessSettings;
use super::surface::SurfaceData;
use crate::gpu::Context;
use crate::patch::gregory::accuracy::{
    closest_exact, nearby_exact_samples, normal_angle, AccuracyReport, Located,
};
use crate::patch::gregory::check_face;
use crate::patch::RegularPatch;
use crate::subdiv::eval::{GridSample, LimitEvaluator};
use crate::topology::Topology;
use crate::{ControlMesh, Error, Result};

/// Error of the captured points of one patch type (adaptive scheme), distances as fractions of
/// the bbox diagonal, angles in radians.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TypeAccuracy {
    /// Patch type (`kind_name`: `regular`, `boundary`, `crease`, `gregory-quad` (end caps),
    /// `single-crease`, `transition`).
    pub kind: &'static str,
    /// Captured points of this type.
    pub samples: usize,
    /// Refinement levels of the patches, lowest and highest.
    pub levels: (u8, u8),
    /// RMS distance to the closest exact point / diagonal.
    pub rms_distance: f64,
    /// Maximum distance / diagonal.
    pub max_distance: f64,
    /// RMS error at equal `(u, v)` (quads and sub-faces) / diagonal.
    pub rms_uv: f64,
    /// Maximum error at equal `(u, v)` / diagonal.
    pub max_uv: f64,
    /// RMS normal angle at the closest exact point.
    pub rms_normal: f64,
    /// Maximum normal angle.
    pub max_normal: f64,
}

/// [`measure_gpu_with`]'s result: the overall report and, for schemes that tag their captured
/// points with a patch type (adaptive), one line per type in `kind` order.
#[derive(Debug, Clone, Default)]
pub struct GpuAccuracy {
    /// Every measured point.
    pub report: AccuracyReport,
    /// Per patch type (empty for untagged schemes).
    pub by_type: Vec<TypeAccuracy>,
    /// Faces with a limit surface the scheme does not draw (the exact CPU path; not sampled).
    pub cpu_faces: usize,
    /// Why the first of them was refused by the scheme's last pass.
    pub first_refusal: Option<String>,
}

/// Sums of squares and maxima of one group of samples.
#[derive(Default, Clone, Copy)]
struct Sums {
    n: usize,
    nuv: usize,
    d2: f64,
    dmax: f64,
    uv2: f64,
    uvmax: f64,
    a2: f64,
    amax: f64,
    lo: u8,
    hi: u8,
}

impl Sums {
    fn add(&mut self, d: f64, uv: Option<f64>, a: f64) {
        self.n += 1;
        self.d2 += d * d;
        self.dmax = self.dmax.max(d);
        self.a2 += a * a;
        self.amax = self.amax.max(a);
        if let Some(e) = uv {
            self.nuv += 1;
            self.uv2 += e * e;
            self.uvmax = self.uvmax.max(e);
        }
    }

    fn level(&mut self, level: u8) {
        if self.n == 0 {
            (self.lo, self.hi) = (level, level);
        } else {
            (self.lo, self.hi) = (self.lo.min(level), self.hi.max(level));
        }
    }

    fn rms(sum: f64, n: usize) -> f64 {
        (sum / n.max(1) as f64).sqrt()
    }
}

/// Draws `mesh` with `scheme` at uniform level `grid` and measures the captured points of every
/// Gregory patch. Faces left to the CPU path count as unsupported.
pub fn measure_gpu(
    ctx: &Context,
    mesh: &ControlMesh,
    scheme: Scheme,
    grid: usize,
) -> Result<AccuracyReport> {
    let opts = PlanOptions::new(SchemeLimits::from_context(ctx));
    Ok(measure_gpu_with(ctx, mesh, scheme, grid, &opts)?.report)
}

/// As [`measure_gpu`] with explicit planning options (the adaptive scheme's isolation level),
/// plus the error per captured patch type.
pub fn measure_gpu_with(
    ctx: &Context,
    mesh: &ControlMesh,
    scheme: Scheme,
    grid: usize,
    opts: &PlanOptions,
) -> Result<GpuAccuracy> {
    if scheme.passes().iter().all(|p| p.name() == BSPLINE.name()) {
        return Err(Error::Invalid(format!(
            "{scheme} draws no Gregory patches to measure"
        )));
    }
    let topo = Topology::new(mesh)?;
    let mut surface = plan_for_scheme_with(mesh, scheme, opts)?;
    let faces: Vec<u32> = surface.irregular_gpu_faces();
    let mut report = AccuracyReport {
        diagonal: mesh.bbox_diagonal(),
        ..Default::default()
    };
    let drawn_here: HashSet<u32> = faces.iter().copied().collect();
    for f in 0..topo.face_count() as u32 {
        if !topo.has_limit_surface(f) {
            continue;
        }
        if RegularPatch::gather(&topo, f).is_some() && !drawn_here.contains(&f) {
            report.regular += 1;
        } else if !drawn_here.contains(&f) {
            report.unsupported += 1;
            if let Err(e) = check_face(&topo, f) {
                report.first_unsupported.get_or_insert(e);
            }
        }
    }
    let cpu_faces = surface.fallback_faces.len();
    // The last pass's word on the first CPU face (earlier passes refuse it for their own reasons).
    let first_refusal = surface.fallback_faces.first().and_then(|first| {
        (surface.refusals.iter())
            .rfind(|r| r.face == first.face)
            .map(ToString::to_string)
    });
    report.faces = faces.len();
    report.triangles = faces.iter().filter(|&&f| topo.face_size(f) == 3).count();
    if faces.is_empty() {
        return Ok(GpuAccuracy {
            report,
            by_type: Vec::new(),
            cpu_faces,
            first_refusal,
        });
    }
    surface.fallback_faces.clear();
    let records = capture_whole_patches(ctx, &surface, grid.max(1) as f32)?;
    let records: Vec<CaptureRecord> = records
        .into_iter()
        .filter(|r| drawn_here.contains(&r.face))
        .collect();
    let measured = ExactReference::with_topology(topo, mesh, grid)?.measure(&records)?;
    let mut all = Sums::default();
    let mut types: BTreeMap<u8, Sums> = BTreeMap::new();
    for m in &measured {
        let (r, d, uv, a) = (&m.record, m.distance, m.uv_error, m.normal_angle);
        all.add(d, uv, a);
        if let Some(p) = r.patch {
            let t = types.entry(p.kind).or_default();
            t.level(p.level);
            t.add(d, uv, a);
        }
    }
    let diag = report.diagonal.max(f64::MIN_POSITIVE);
    report.samples = all.n;
    report.rms_distance = Sums::rms(all.d2, all.n) / diag;
    report.max_distance = all.dmax / diag;
    report.rms_uv = Sums::rms(all.uv2, all.nuv) / diag;
    report.max_uv = all.uvmax / diag;
    report.rms_normal = Sums::rms(all.a2, all.n);
    report.max_normal = all.amax;
    let by_type = types
        .into_iter()
        .map(|(kind, s)| TypeAccuracy {
            kind: kind_name(kind),
            samples: s.n,
            levels: (s.lo, s.hi),
            rms_distance: Sums::rms(s.d2, s.n) / diag,
            max_distance: s.dmax / diag,
            rms_uv: Sums::rms(s.uv2, s.nuv) / diag,
            max_uv: s.uvmax / diag,
            rms_normal: Sums::rms(s.a2, s.n),
            max_normal: s.amax,
        })
        .collect();
    Ok(GpuAccuracy {
        report,
        by_type,
        cpu_faces,
        first_refusal,
    })
}

/// One captured point measured against the exact limit (model units, radians).
#[derive(Debug, Clone, Copy)]
pub struct MeasuredPoint {
    /// The captured point.
    pub record: CaptureRecord,
    /// Distance to the closest exact point.
    pub distance: f64,
    /// Distance to the exact point at the same `(face, sub-face, u, v)` (quads and sub-faces;
    /// `None` for a scheme's own triangle domains).
    pub uv_error: Option<f64>,
    /// Angle between the captured normal and the exact normal at the closest point.
    pub normal_angle: f64,
    /// The exact unit normal at the closest point.
    pub exact_normal: DVec3,
}

/// The exact limit captured points are measured against, built once per mesh and sampling:
/// its topology, its evaluator and a dense sampling (`2 grid` per face side) the projections
/// start from, so that several captures of one mesh (`tessera compare`) share them.
pub struct ExactReference {
    /// Topology of the mesh.
    pub topo: Topology,
    /// Its exact evaluator.
    pub ev: LimitEvaluator,
    dense: Vec<Option<Vec<GridSample>>>,
    turns: std::sync::OnceLock<Vec<Option<f64>>>,
}

impl ExactReference {
    /// The reference of `mesh` for captures at level `grid`.
    pub fn new(mesh: &ControlMesh, grid: usize) -> Result<ExactReference> {
        Self::with_topology(Topology::new(mesh)?, mesh, grid)
    }

    /// [`Self::new`] with the topology of `mesh` already built.
    pub fn with_topology(
        topo: Topology,
        mesh: &ControlMesh,
        grid: usize,
    ) -> Result<ExactReference> {
        let ev = LimitEvaluator::new(mesh)?;
        let dense = ev.eval_all_grids(2 * grid.max(1))?;
        Ok(ExactReference {
            topo,
            ev,
            dense,
            turns: std::sync::OnceLock::new(),
        })
    }

    /// The limit's own normal turn across each edge the continuity reading measures
    /// ([`super::continuity::exact_turns`]), computed on first use and kept for every scheme.
    pub fn turns(&self) -> &[Option<f64>] {
        self.turns
            .get_or_init(|| super::continuity::exact_turns(&self.topo, &self.ev))
    }

    /// Measures captured points (faces in parallel): the closest exact point among the dense
    /// samples of the face and its neighbours, refined by projection, and the equal-`(u, v)`
    /// point where the record is in a quad or sub-face domain. Points come back grouped by
    /// face, ascending.
    pub fn measure(&self, records: &[CaptureRecord]) -> Result<Vec<MeasuredPoint>> {
        let mut by_face: HashMap<u32, Vec<&CaptureRecord>> = HashMap::new();
        for r in records {
            by_face.entry(r.face).or_default().push(r);
        }
        let mut face_list: Vec<(u32, Vec<&CaptureRecord>)> = by_face.into_iter().collect();
        face_list.sort_unstable_by_key(|(f, _)| *f);
        let measured: Vec<Vec<MeasuredPoint>> = face_list
            .par_iter()
            .map(|(f, recs)| {
                let candidates: Vec<Located> = nearby_exact_samples(&self.topo, &self.dense, *f);
                recs.iter()
                    .map(|&r| measure_point(&self.ev, &self.topo, &candidates, r))
                    .collect::<Result<Vec<_>>>()
            })
            .collect::<Result<_>>()?;
        Ok(measured.into_iter().flatten().collect())
    }
}

/// [`ExactReference::measure`] for one record of face `r.face` with its face's exact candidates.
fn measure_point(
    ev: &LimitEvaluator,
    topo: &Topology,
    candidates: &[Located],
    r: &CaptureRecord,
) -> Result<MeasuredPoint> {
    let f = r.face;
    let x = DVec3::from(r.position.map(f64::from));
    let n = DVec3::from(r.normal.map(f64::from));
    let c = closest_exact(ev, x, candidates, f)?;
    let (mut d, mut exact_normal) = ((c.sample.position - x).length(), c.sample.normal);
    // Equal (u, v): quads in their own domain, other faces per sub-face.
    // Pm polar and sector points are in the patch's own triangle domain.
    let own_domain = r
        .patch
        .is_some_and(|p| super::schemes::pm::own_domain_kind(p.kind));
    let sub = match r.sub_face {
        _ if own_domain => None,
        Some(k) => Some(k as usize),
        None if topo.face_size(f) == 4 => Some(0),
        None => None,
    };
    let uv_error = match sub {
        Some(k) => {
            let e = ev.eval(f as usize, k, f64::from(r.u), f64::from(r.v))?;
            let uv = (e.position - x).length();
            // The equal-(u, v) point is an exact point too: the projection can stop in a
            // local minimum (seen near the car's creases).
            if uv < d {
                (d, exact_normal) = (uv, e.normal);
            }
            Some(uv)
        }
        None => None,
    };
    Ok(MeasuredPoint {
        record: *r,
        distance: d,
        uv_error,
        normal_angle: normal_angle(n, exact_normal),
        exact_normal,
    })
}

/// The TES capture of every GPU patch of `surface` at uniform `level`, patches drawn whole (not
/// split into sub-patches), into a small offscreen target.
pub fn capture_whole_patches(
    ctx: &Context,
    surface: &SurfaceData,
    level: f32,
) -> Result<Vec<CaptureRecord>> {
    let tess = TessSettings {
        level,
        max_patch_level: f32::INFINITY,
        ..TessSettings::default()
    };
    let render = RenderDesc {
        tess,
        capture_capacity: Some(capture_capacity_for(
            surface.patch_count(),
            &resolve_tess(ctx, surface, &tess),
        )),
        ..RenderDesc::default()
    };
    let off = OffscreenDesc {
        width: 64,
        height: 64,
        ..OffscreenDesc::default()
    };
    Ok(render_to_image(ctx, surface, &render, &off, false)?
        .capture
        .unwrap_or_default())
}
