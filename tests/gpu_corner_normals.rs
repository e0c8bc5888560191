//! The normals the GPU draws at patch corners against the exact per-face corner normal
//! (`LimitEvaluator` at the face corner, checked to be the limit of the face's own normals in
//! tests/limit_corners.rs): issue 10, part 2, "the GPU patches use the same corrected normals".
//! Every shared mesh with creases, corners or boundaries, drawn by both Gregory schemes (Gregory
//! and B-spline patch corners; measured: every corner within 4.7e-7 rad of the exact normal and
//! 2.2e-7 of the diagonal in position, 62 meshes); corners at vertices whose limit tangent plane
//! is degenerate (the valence-2 interior vertices) are counted apart.
//!
//! Not the adaptive scheme: its end caps smooth the semi-sharpness left at the isolation level
//! (as OpenSubdiv's end caps do), so their corners at vertices on creases sharper than the
//! isolation level are not the limit (measured at isolation 3: up to 0.60 rad and 1.8e-2 of the
//! diagonal on the rook and bishop, whose creases have sharpness 6).

mod common;

use std::collections::BTreeMap;

use common::capture::{capture, offscreen, uniform};
use common::gpu::{assert_validation_clean, context};
use common::meshes::{corpus_options, osd_names, osd_path};
use glam::DVec3;
use tessera::render::{surface_for_scheme, CaptureRecord, RenderDesc, Scheme, SchemeLimits};
use tessera::subdiv::eval::LimitEvaluator;
use tessera::topology::Topology;
use tessera::ControlMesh;

/// GPU vs exact corner normal (radians): f32 evaluation (measured 4.7e-7 at worst).
const TOLERANCE: f64 = 1e-5;
/// GPU vs exact corner position (fraction of the diagonal; measured 2.2e-7 at worst).
const POSITION_TOLERANCE: f64 = 1e-6;

/// `(sub-face, u, v)` of the exact evaluator and the base vertex at a captured domain corner, or
/// `None` for a point that is not at a corner of the base face.
fn corner_of(t: &Topology, r: &CaptureRecord) -> Option<(usize, f64, f64, u32)> {
    let (u, v) = (f64::from(r.u), f64::from(r.v));
    let at = |x: f64| x == 0.0 || x == 1.0;
    let fv = t.face_vertices(r.face);
    match (r.sub_face, fv.len()) {
        (Some(k), _) => (u == 0.0 && v == 0.0).then_some((k as usize, 0.0, 0.0, fv[k as usize])),
        (None, 4) if at(u) && at(v) => {
            let k = match (u == 0.0, v == 0.0) {
                (true, true) => 0,
                (false, true) => 1,
                (false, false) => 2,
                (true, false) => 3,
            };
            Some((0, u, v, fv[k]))
        }
        // Whole triangles: barycentric (b1, b2), corner k is sub-face k's (0, 0).
        (None, 3) => {
            let k = match (u, v) {
                (0.0, 0.0) => 0,
                (1.0, 0.0) => 1,
                (0.0, 1.0) => 2,
                _ => return None,
            };
            Some((k, 0.0, 0.0, fv[k]))
        }
        _ => None,
    }
}

/// A smooth interior vertex of valence 2 after decay: its tangent plane is degenerate.
fn degenerate(t: &Topology, v: u32) -> bool {
    !t.is_boundary_vertex(v)
        && t.vertex_faces(v).len() == 2
        && t.vertex_sharpness(v) == 0.0
        && t.vertex_edges(v)
            .iter()
            .all(|&e| t.edge_sharpness(e) == 0.0)
}

#[test]
fn gpu_corner_normals_are_the_exact_corner_normals() {
    let Some(ctx) = context() else { return };
    let mut worst: BTreeMap<&str, (f64, String)> = BTreeMap::new();
    let (mut judged, mut skipped, mut meshes) = (0usize, 0usize, 0usize);
    let mut failures = Vec::new();
    let mut pos_worst: BTreeMap<&str, f64> = BTreeMap::new();
    for name in osd_names() {
        let Ok(mesh) = ControlMesh::from_obj_file(osd_path(&name), &corpus_options(&name)) else {
            continue;
        };
        let ev = LimitEvaluator::new(&mesh).unwrap();
        let t = ev.level().topology();
        let featured = t.edge_sharpnesses().iter().any(|&s| s > 0.0)
            || t.vertex_sharpnesses().iter().any(|&s| s > 0.0);
        if !featured {
            continue;
        }
        meshes += 1;
        for scheme in [Scheme::GregoryStencil, Scheme::GregoryVs] {
            let limits = SchemeLimits::from_context(&ctx);
            let surface = surface_for_scheme(&mesh, 2, scheme, &limits).unwrap();
            let render = RenderDesc {
                tess: uniform(2.0),
                ..RenderDesc::default()
            };
            let records = capture(&ctx, &surface, &render, &offscreen(64, 64), false).records;
            for r in &records {
                let Some((sub, u, v, vertex)) = corner_of(t, r) else {
                    continue;
                };
                if degenerate(t, vertex) {
                    skipped += 1;
                    continue;
                }
                let exact_point = ev.eval(r.face as usize, sub, u, v).unwrap();
                let exact = exact_point.normal;
                let gp = DVec3::from(r.position.map(f64::from));
                let perr = (gp - exact_point.position).length() / mesh.bbox_diagonal();
                let pe = pos_worst.entry(scheme.name()).or_insert(0.0f64);
                *pe = pe.max(perr);
                let gpu = DVec3::from(r.normal.map(f64::from));
                let angle = gpu.cross(exact).length().atan2(gpu.dot(exact));
                judged += 1;
                let label = scheme.name();
                let e = worst.entry(label).or_insert((0.0, String::new()));
                if angle > e.0 {
                    *e = (angle, format!("{name} face {} vertex {vertex}", r.face));
                }
                if angle > TOLERANCE || perr > POSITION_TOLERANCE {
                    failures.push(format!(
                        "{label}: {name} face {} sub {sub} ({u}, {v}) vertex {vertex}: {angle:.2e} \
                         rad, {perr:.2e} of the diagonal",
                        r.face
                    ));
                }
            }
        }
    }
    eprintln!(
        "{meshes} meshes, {judged} corner points judged, {skipped} at degenerate vertices; worst \
         {worst:?}; positions {pos_worst:?}"
    );
    assert_validation_clean(&ctx);
    assert!(
        meshes >= 60 && judged > 1000,
        "{meshes} meshes, {judged} corners"
    );
    failures.sort();
    failures.dedup();
    assert!(
        failures.is_empty(),
        "{} corner points off the exact corner normal or position, e.g.\n{}",
        failures.len(),
        failures[..failures.len().min(40)].join("\n")
    );
}

/// The adaptive scheme's end caps at crease sectors of one face (both edges on the crease curve,
/// collinear tangents) take their corner normal from the face points there: every base-face
/// corner point within 1e-4 rad of the exact corner normal (measured <= 8.7e-6; a +z fallback
/// put one cube_creases2 corner at 3.14 rad before).
#[test]
fn adaptive_corners_at_one_face_crease_sectors() {
    let Some(ctx) = context() else { return };
    let limits = SchemeLimits::from_context(&ctx);
    for name in [
        "catmark_edgeonly",
        "catmark_tent",
        "catmark_cube_creases2",
        "catmark_dart_edgeonly",
    ] {
        let mesh = ControlMesh::from_obj_file(osd_path(name), &corpus_options(name)).unwrap();
        let ev = LimitEvaluator::new(&mesh).unwrap();
        let t = ev.level().topology();
        let surface = surface_for_scheme(&mesh, 2, Scheme::Adaptive, &limits).unwrap();
        let render = RenderDesc {
            tess: uniform(2.0),
            ..RenderDesc::default()
        };
        let records = capture(&ctx, &surface, &render, &offscreen(64, 64), false).records;
        let (mut worst, mut judged) = (0.0f64, 0);
        for r in &records {
            let Some((sub, u, v, vertex)) = corner_of(t, r) else {
                continue;
            };
            if degenerate(t, vertex) {
                continue;
            }
            let exact = ev.eval(r.face as usize, sub, u, v).unwrap().normal;
            let gpu = DVec3::from(r.normal.map(f64::from));
            worst = worst.max(gpu.cross(exact).length().atan2(gpu.dot(exact)));
            judged += 1;
        }
        eprintln!("{name}: {judged} adaptive corner points, worst {worst:.2e} rad");
        assert!(judged > 0 && worst <= 1e-4, "{name}: {worst:e} rad");
    }
    assert_validation_clean(&ctx);
}
