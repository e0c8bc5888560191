//! Accuracy of the CPU Gregory construction against the exact Catmull-Clark limit
//! ([`LimitEvaluator`]), the measurement behind the paper's Table 3.
//!
//! Every face that gets a Gregory patch (and, unless asked otherwise, is not a regular B-spline
//! face) is sampled on a grid: quads at `(i/N, j/N)`, triangles at barycentric `(i/N, j/N)`
//! with `i + j <= N`. Each sample is compared with the exact surface
//! - by distance: the closest exact point, found from dense exact samples of the face and every
//!   face sharing a vertex with it, refined by Gauss-Newton projection steps;
//! - for quads also at equal `(u, v)` (a Gregory triangle is not parameterised like the three
//!   quads Catmull-Clark makes of a triangle, so triangles are measured by distance only);
//! - normals: the angle between the patch's (§4.4) normal and the exact normal at the closest
//!   point.
//!
//! Distances are reported as fractions of the control mesh's bounding-box diagonal.

use super::build::{check_face, gregory_patch, gregory_vertices_with, GregoryPatch};
pub use super::closest::{closest_exact, nearby_exact_samples, normal_angle, Located};
use super::tangents::GregoryTangents;
use crate::patch::regular::RegularPatch;
use crate::subdiv::eval::{GridSample, LimitEvaluator};
use crate::topology::Topology;
use crate::{ControlMesh, Result};
use glam::DVec3;
use rayon::prelude::*;

/// What to sample.
#[derive(Debug, Clone, Copy)]
pub struct AccuracyOptions {
    /// Grid resolution `N` per face.
    pub grid: usize,
    /// Also sample regular faces (which the renderer draws as exact B-splines).
    pub include_regular: bool,
}

impl Default for AccuracyOptions {
    fn default() -> Self {
        AccuracyOptions {
            grid: 8,
            include_regular: false,
        }
    }
}

/// Error figures of one mesh.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AccuracyReport {
    /// Faces sampled.
    pub faces: usize,
    /// Of which triangles.
    pub triangles: usize,
    /// Non-regular faces with a limit surface but no Gregory patch (not sampled).
    pub unsupported: usize,
    /// The first such face and why (see [`super::NotGregory`]).
    pub first_unsupported: Option<super::NotGregory>,
    /// Regular faces (sampled only with `include_regular`).
    pub regular: usize,
    /// Samples taken.
    pub samples: usize,
    /// Bounding-box diagonal of the control mesh.
    pub diagonal: f64,
    /// RMS distance to the exact surface / diagonal.
    pub rms_distance: f64,
    /// Maximum distance / diagonal.
    pub max_distance: f64,
    /// RMS error at equal `(u, v)` over quad samples / diagonal (0 without quads).
    pub rms_uv: f64,
    /// Maximum error at equal `(u, v)` / diagonal.
    pub max_uv: f64,
    /// RMS angle between patch and exact normals at the closest point (radians).
    pub rms_normal: f64,
    /// Maximum normal angle (radians).
    pub max_normal: f64,
}

/// Per-sample errors of one face: (distance, uv error or None, normal angle).
type FaceErrors = Vec<(f64, Option<f64>, f64)>;

/// One sample of a Gregory face with its measured error, for error maps (paper Fig. 11).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeatSample {
    /// Position on the Gregory patch.
    pub position: DVec3,
    /// The patch's unit normal (§4.4).
    pub normal: DVec3,
    /// Distance to the closest exact point, in model units.
    pub distance: f64,
}

/// The samples of one Gregory face, in `sample_params` order: quads row by row
/// (`(N+1)^2` samples, `i` along u inner), triangles row by row in `t` with `N + 1 - j` samples
/// in row `j`.
#[derive(Debug, Clone, PartialEq)]
pub struct FaceHeat {
    /// Base face.
    pub face: u32,
    /// Whether the face is a triangle (barycentric grid).
    pub triangle: bool,
    /// Grid resolution N.
    pub grid: usize,
    /// Samples.
    pub samples: Vec<HeatSample>,
}

/// Parameter points of a face's sample grid: `(u, v)` for quads, barycentric `(s, t)` for
/// triangles.
fn sample_params(n: usize, triangle: bool) -> Vec<(f64, f64)> {
    let nf = n as f64;
    (0..=n)
        .flat_map(|j| {
            let last = if triangle { n - j } else { n };
            (0..=last).map(move |i| (i as f64 / nf, j as f64 / nf))
        })
        .collect()
}

/// Measures the Gregory construction of `mesh` against its exact limit surface.
pub fn measure(mesh: &ControlMesh, options: &AccuracyOptions) -> Result<AccuracyReport> {
    Ok(sample(mesh, options, GregoryTangents::default(), false)?.0)
}

/// [`measure`] of the construction with the given edge tangents, with every sample and its
/// error when `keep_samples` (for error maps).
pub fn measure_tangents(
    mesh: &ControlMesh,
    options: &AccuracyOptions,
    tangents: GregoryTangents,
    keep_samples: bool,
) -> Result<(AccuracyReport, Vec<FaceHeat>)> {
    sample(mesh, options, tangents, keep_samples)
}

/// [`measure`], also returning every sample with its error (for error maps).
pub fn measure_with_samples(
    mesh: &ControlMesh,
    options: &AccuracyOptions,
) -> Result<(AccuracyReport, Vec<FaceHeat>)> {
    sample(mesh, options, GregoryTangents::default(), true)
}

/// Samples every Gregory face of `mesh` (as [`measure`] chooses them) with its distance to the
/// exact surface, for an error map.
pub fn heat_samples(mesh: &ControlMesh, options: &AccuracyOptions) -> Result<Vec<FaceHeat>> {
    Ok(sample(mesh, options, GregoryTangents::default(), true)?.1)
}

/// Chooses the faces, samples them and summarises the errors; keeps the samples when asked.
fn sample(
    mesh: &ControlMesh,
    options: &AccuracyOptions,
    tangents: GregoryTangents,
    keep_samples: bool,
) -> Result<(AccuracyReport, Vec<FaceHeat>)> {
    let grid = options.grid.max(1);
    let topo = super::vertex_fit::for_tangents(mesh, Topology::new(mesh)?, tangents)?;
    let ev = LimitEvaluator::new(mesh)?;
    let positions = mesh.positions();
    let verts = gregory_vertices_with(&topo, positions, tangents);
    let mut report = AccuracyReport {
        diagonal: mesh.bbox_diagonal(),
        ..Default::default()
    };
    let mut chosen = Vec::new();
    for f in 0..topo.face_count() as u32 {
        if !topo.has_limit_surface(f) {
            continue;
        }
        if RegularPatch::gather(&topo, f).is_some() {
            report.regular += 1;
            if !options.include_regular {
                continue;
            }
        }
        match check_face(&topo, f) {
            Ok(()) => chosen.push(f),
            Err(e) => {
                report.unsupported += 1;
                report.first_unsupported.get_or_insert(e);
            }
        }
    }
    // Dense exact samples of every face, for the closest-point search.
    let dense: Vec<Option<Vec<GridSample>>> = ev.eval_all_grids(2 * grid)?;
    let sampled: Vec<(FaceErrors, FaceHeat)> = chosen
        .par_iter()
        .map(|&f| {
            let mut samples = Vec::new();
            let heat = keep_samples.then_some(&mut samples);
            let errors = face_errors(&topo, &ev, &verts, &dense, f, grid, heat)?;
            let face = FaceHeat {
                face: f,
                triangle: topo.face_size(f) == 3,
                grid,
                samples,
            };
            Ok((errors, face))
        })
        .collect::<Result<_>>()?;
    report.faces = chosen.len();
    report.triangles = chosen.iter().filter(|&&f| topo.face_size(f) == 3).count();
    let (mut sd, mut suv, mut sn, mut nuv) = (0.0, 0.0, 0.0, 0usize);
    for (d, uv, a) in sampled.iter().flat_map(|(e, _)| e) {
        report.samples += 1;
        sd += d * d;
        sn += a * a;
        report.max_distance = report.max_distance.max(*d);
        report.max_normal = report.max_normal.max(*a);
        if let Some(e) = uv {
            suv += e * e;
            nuv += 1;
            report.max_uv = report.max_uv.max(*e);
        }
    }
    let diag = report.diagonal.max(f64::MIN_POSITIVE);
    let count = report.samples.max(1) as f64;
    report.rms_distance = (sd / count).sqrt() / diag;
    report.max_distance /= diag;
    report.rms_uv = (suv / nuv.max(1) as f64).sqrt() / diag;
    report.max_uv /= diag;
    report.rms_normal = (sn / count).sqrt();
    let faces = if keep_samples {
        sampled.into_iter().map(|(_, h)| h).collect()
    } else {
        Vec::new()
    };
    Ok((report, faces))
}

/// Samples one face and measures every sample.
fn face_errors(
    topo: &Topology,
    ev: &LimitEvaluator,
    verts: &[Option<super::GregoryVertex<DVec3>>],
    dense: &[Option<Vec<GridSample>>],
    f: u32,
    grid: usize,
    mut heat: Option<&mut Vec<HeatSample>>,
) -> Result<FaceErrors> {
    let patch = gregory_patch(topo, verts, f).map_err(|e| crate::Error::Invalid(e.to_string()))?;
    let triangle = matches!(patch, GregoryPatch::Triangle(_));
    let params = sample_params(grid, triangle);
    let exact_uv = if triangle {
        Vec::new()
    } else {
        ev.eval_points(f as usize, 0, &params)?
    };
    let candidates = nearby_exact_samples(topo, dense, f);
    let mut out = Vec::with_capacity(params.len());
    for (k, &(u, v)) in params.iter().enumerate() {
        let g = patch.eval(u, v);
        let x = g.position;
        let close = closest_exact(ev, x, &candidates, f)?;
        let dist = (close.sample.position - x).length();
        let angle = normal_angle(g.normal(), close.sample.normal);
        let uv = (!triangle).then(|| (exact_uv[k].position - x).length());
        out.push((dist, uv, angle));
        if let Some(h) = heat.as_deref_mut() {
            h.push(HeatSample {
                position: x,
                normal: g.normal(),
                distance: dist,
            });
        }
    }
    Ok(out)
}
