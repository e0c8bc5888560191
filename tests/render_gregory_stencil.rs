//! Stencil-variant Gregory patches on the GPU (Loop et al. 2009, §4.3): TES-captured surface ==
//! CPU construction and evaluation, bitwise watertight positions and normals along every shared
//! Gregory/Gregory edge, validation-clean.

mod render_common;

use std::collections::{HashMap, HashSet};

use glam::DVec3;
use tessera::mesh::{ControlMesh, ControlMeshDesc, ObjOptions};
use tessera::patch::gregory::{gregory_patch, gregory_vertices, GregoryPatch};
use tessera::render::gregory_stencil::{gregory_faces, StencilSession};
use tessera::render::renderer::CaptureRecord;
use tessera::render::{RenderDesc, TessSettings};
use tessera::topology::Topology;

fn osd(name: &str) -> ControlMesh {
    let path = format!(
        "{}/../shared/meshes/osd/{name}.obj",
        env!("CARGO_MANIFEST_DIR")
    );
    ControlMesh::from_obj_file(&path, &ObjOptions::default()).unwrap()
}

/// A closed mixed mesh: a triangular prism whose bottom is a fan of three triangles (valences
/// 3 and 4 with triangles in the rings), written for this test.
fn prism() -> ControlMesh {
    let positions = vec![
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 0.1, 0.0),
        DVec3::new(0.4, 0.9, 0.1),
        DVec3::new(0.0, 0.0, 1.0),
        DVec3::new(1.1, 0.0, 1.2),
        DVec3::new(0.5, 1.0, 1.0),
        DVec3::new(0.5, 0.35, -0.4),
    ];
    let face_vertices = vec![
        3, 4, 5, 0, 1, 4, 3, 1, 2, 5, 4, 2, 0, 3, 5, 1, 0, 6, 2, 1, 6, 0, 2, 6,
    ];
    ControlMesh::new(ControlMeshDesc {
        positions,
        face_sizes: vec![3, 4, 4, 4, 3, 3, 3],
        face_vertices,
        ..Default::default()
    })
    .unwrap()
}

struct Run {
    topo: Topology,
    positions: Vec<DVec3>,
    diag: f64,
    drawn: HashSet<u32>,
    records: Vec<CaptureRecord>,
}

/// Draws every stencil face of `mesh` at uniform `level` and captures the TES output.
fn run(mesh: &ControlMesh, level: f32) -> Option<Run> {
    let ctx = render_common::context()?;
    let topo = Topology::new(mesh).unwrap();
    let faces = gregory_faces(&topo);
    let desc = RenderDesc {
        tess: TessSettings {
            level,
            ..TessSettings::default()
        },
        capture_capacity: Some(faces.len() as u32 * 400),
        ..RenderDesc::default()
    };
    let mut s = StencilSession::new(
        &ctx,
        Topology::new(mesh).unwrap(),
        mesh.positions(),
        &faces,
        &desc,
        128,
        128,
    )
    .unwrap();
    s.frame().unwrap();
    let records = s.capture().unwrap();
    render_common::assert_validation_clean(&ctx);
    let drawn: HashSet<u32> = s.patches().table().patches.iter().map(|p| p.face).collect();
    assert!(!drawn.is_empty());
    Some(Run {
        topo,
        positions: mesh.positions().to_vec(),
        diag: mesh.bbox_diagonal(),
        drawn,
        records,
    })
}

/// Which face edge (corner k -> k+1) a captured point lies on, if any (corners excluded).
fn edge_of(triangle: bool, r: &CaptureRecord) -> Option<usize> {
    let (u, v) = (r.u, r.v);
    if triangle {
        // (u, v) are the barycentric weights of corners 1 and 2.
        let w0 = 1.0 - u - v;
        let on = [v == 0.0, w0.abs() < 1e-6, u == 0.0];
        (on.iter().filter(|x| **x).count() == 1).then(|| on.iter().position(|x| *x).unwrap())
    } else {
        let on = [v == 0.0, u == 1.0, v == 1.0, u == 0.0];
        (on.iter().filter(|x| **x).count() == 1).then(|| on.iter().position(|x| *x).unwrap())
    }
}

/// GPU position == CPU Gregory patch at the captured parameter within 1e-5 of the bbox
/// diagonal; interior normals within `normal_tol` rad. Returns (max position error / diag,
/// max interior normal angle, max edge normal angle).
fn check_against_cpu(r: &Run, normal_tol: f64) -> (f64, f64, f64) {
    let verts = gregory_vertices(&r.topo, &r.positions);
    let mut patches = HashMap::new();
    let (mut max_p, mut max_n, mut max_edge_n) = (0f64, 0f64, 0f64);
    for rec in &r.records {
        assert!(
            r.drawn.contains(&rec.face),
            "capture from undrawn face {}",
            rec.face
        );
        let patch = *patches
            .entry(rec.face)
            .or_insert_with(|| gregory_patch(&r.topo, &verts, rec.face).unwrap());
        let (u, v) = (f64::from(rec.u), f64::from(rec.v));
        let (pt, tri) = match patch {
            GregoryPatch::Quad(q) => (q.eval(u, v), false),
            GregoryPatch::Triangle(t) => (t.eval(u, v), true),
        };
        let gp = DVec3::from(rec.position.map(f64::from));
        let gn = DVec3::from(rec.normal.map(f64::from));
        let err = (gp - pt.position).length() / r.diag;
        assert!(
            err <= 1e-5,
            "face {} at ({u}, {v}): GPU {gp} CPU {} (error {err:e} of the diagonal)",
            rec.face,
            pt.position
        );
        max_p = max_p.max(err);
        let angle = gn.angle_between(pt.normal());
        if edge_of(tri, rec).is_none() && u > 0.0 && v > 0.0 && (tri || (u < 1.0 && v < 1.0)) {
            assert!(
                angle <= normal_tol,
                "face {} at ({u}, {v}): normal off by {angle} rad",
                rec.face
            );
            max_n = max_n.max(angle);
        } else {
            max_edge_n = max_edge_n.max(angle);
        }
    }
    (max_p, max_n, max_edge_n)
}

/// A captured point on a face edge: face, position and normal bits.
type EdgePoint = (u32, [u32; 6]);

/// Along every edge shared by two drawn faces, every point one side emits has a point on the
/// other side with bitwise equal position and normal. Returns the number of matched points.
fn check_watertight(r: &Run) -> usize {
    let mut on_edge: HashMap<(u32, u32), Vec<EdgePoint>> = HashMap::new();
    for rec in &r.records {
        let fv = r.topo.face_vertices(rec.face);
        let Some(k) = edge_of(fv.len() == 3, rec) else {
            continue;
        };
        let (a, b) = (fv[k], fv[(k + 1) % fv.len()]);
        let bits = [
            rec.position[0].to_bits(),
            rec.position[1].to_bits(),
            rec.position[2].to_bits(),
            rec.normal[0].to_bits(),
            rec.normal[1].to_bits(),
            rec.normal[2].to_bits(),
        ];
        on_edge
            .entry((a.min(b), a.max(b)))
            .or_default()
            .push((rec.face, bits));
    }
    let mut matched = 0;
    let mut edges = 0;
    for ((a, b), pts) in &on_edge {
        let e = r.topo.find_edge(*a, *b).unwrap();
        let faces = r.topo.edge_faces(e);
        if faces.len() != 2 || !faces.iter().all(|f| r.drawn.contains(f)) {
            continue;
        }
        edges += 1;
        let side = |f: u32| -> HashSet<[u32; 6]> {
            pts.iter()
                .filter(|(g, _)| *g == f)
                .map(|(_, b)| *b)
                .collect()
        };
        let (s0, s1) = (side(faces[0]), side(faces[1]));
        assert!(!s0.is_empty(), "edge {a}-{b}: no points captured");
        assert_eq!(
            s0, s1,
            "edge {a}-{b} (faces {} / {}): points differ bitwise",
            faces[0], faces[1]
        );
        matched += s0.len();
    }
    assert!(edges > 0, "no shared edge checked");
    matched
}

fn gpu_matches_cpu_and_is_watertight(mesh: &ControlMesh, name: &str) {
    for level in [5.0, 8.0] {
        let Some(r) = run(mesh, level) else { return };
        let (p, n, en) = check_against_cpu(&r, 2e-3);
        // Edge normals come from both patches' cross-edge derivatives (or the B-spline grid next
        // to regular faces), so they differ slightly from either patch's own normal.
        assert!(en <= 0.1, "{name}: edge normal off by {en} rad");
        let m = check_watertight(&r);
        eprintln!(
            "{name} tess {level}: {} points, max position error {p:.2e} of the diagonal, \
             max interior normal error {n:.2e} rad, max edge/corner normal deviation from the \
             CPU patch normal {en:.2e} rad, {m} edge points bitwise equal on both sides",
            r.records.len()
        );
    }
}

#[test]
fn cube_quads() {
    gpu_matches_cpu_and_is_watertight(&osd("catmark_cube"), "catmark_cube");
}

#[test]
fn prism_triangles_and_quads() {
    gpu_matches_cpu_and_is_watertight(&prism(), "prism");
}

#[test]
fn smoothtris_triangles() {
    gpu_matches_cpu_and_is_watertight(&osd("catmark_smoothtris0"), "catmark_smoothtris0");
}

#[test]
fn gregory_test8_and_car() {
    // The car: 452 stencil patches in several draw chunks (lavapipe patch-list size rule).
    gpu_matches_cpu_and_is_watertight(&osd("catmark_gregory_test8"), "catmark_gregory_test8");
    gpu_matches_cpu_and_is_watertight(&osd("catmark_car"), "catmark_car");
}
