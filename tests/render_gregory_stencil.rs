//! Stencil-variant Gregory patches on the GPU (Loop et al. 2009, §4.3): TES-captured surface ==
//! CPU construction and evaluation, bitwise watertight positions and normals along every shared
//! Gregory/Gregory edge, validation-clean.

mod render_common;

use std::collections::{HashMap, HashSet};

use glam::DVec3;
use tessera::mesh::{ControlMesh, ControlMeshDesc, ObjOptions};
use tessera::patch::gregory::{gregory_patch_at, GregoryPatch};
use tessera::render::session::{GregorySession, GregoryVariant, SessionOptions};
use tessera::render::CaptureRecord;
use tessera::render::{
    compare_images, render_to_image, surface_for_scheme, ColorBy, CompareThreshold, OffscreenDesc,
    RenderDesc, Scheme, SchemeLimits, TessSettings,
};
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
    gregory: HashSet<u32>,
    drawn: HashSet<u32>,
    records: Vec<CaptureRecord>,
}

/// Draws the Gregory faces of `mesh` (with `variant`; plus its regular faces when
/// `with_regular`) at uniform `level` and captures the TES output.
fn run_with(
    mesh: &ControlMesh,
    level: f32,
    variant: GregoryVariant,
    with_regular: bool,
) -> Option<Run> {
    let ctx = render_common::context()?;
    let topo = Topology::new(mesh).unwrap();
    let desc = RenderDesc {
        tess: TessSettings {
            level,
            ..TessSettings::default()
        },
        capture_capacity: Some(topo.face_count() as u32 * 400),
        ..RenderDesc::default()
    };
    let opts = SessionOptions {
        variant,
        with_regular,
        width: 128,
        height: 128,
    };
    let mut s = GregorySession::new(&ctx, mesh, &desc, &opts).unwrap();
    s.frame().unwrap();
    let records = s.capture().unwrap();
    render_common::assert_validation_clean(&ctx);
    let gregory: HashSet<u32> = s.gregory_faces().iter().copied().collect();
    assert!(!gregory.is_empty());
    let drawn: HashSet<u32> = records.iter().map(|r| r.face).collect();
    assert!(gregory.is_subset(&drawn));
    Some(Run {
        topo,
        positions: mesh.positions().to_vec(),
        diag: mesh.bbox_diagonal(),
        gregory,
        drawn,
        records,
    })
}

fn run(mesh: &ControlMesh, level: f32) -> Option<Run> {
    run_with(mesh, level, GregoryVariant::Stencil, false)
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
    let mut patches = HashMap::new();
    let (mut max_p, mut max_n, mut max_edge_n) = (0f64, 0f64, 0f64);
    for rec in r.records.iter().filter(|x| r.gregory.contains(&x.face)) {
        let patch = *patches
            .entry(rec.face)
            .or_insert_with(|| gregory_patch_at(&r.topo, &r.positions, rec.face).unwrap());
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

#[test]
fn car_with_regular_patches_is_watertight() {
    // Gregory/Gregory, Gregory/B-spline and B-spline/B-spline edges all bitwise equal.
    let mesh = osd("catmark_car");
    let Some(r) = run_with(&mesh, 6.0, GregoryVariant::Stencil, true) else {
        return;
    };
    assert!(r.drawn.len() > r.gregory.len());
    let (p, _, _) = check_against_cpu(&r, 2e-3);
    let mut mixed = 0;
    for &f in &r.gregory {
        let fv = r.topo.face_vertices(f);
        for k in 0..fv.len() {
            let e = r.topo.find_edge(fv[k], fv[(k + 1) % fv.len()]).unwrap();
            if r.topo
                .edge_faces(e)
                .iter()
                .any(|g| r.drawn.contains(g) && !r.gregory.contains(g))
            {
                mixed += 1;
            }
        }
    }
    assert!(mixed > 0, "no Gregory/B-spline edge in the test");
    let m = check_watertight(&r);
    eprintln!(
        "catmark_car with regular patches: {} Gregory + {} regular faces, {mixed} Gregory/B-spline \
         edges, {m} edge points bitwise equal, max Gregory position error {p:.2e} of the diagonal",
        r.gregory.len(),
        r.drawn.len() - r.gregory.len()
    );
}

/// Captured points keyed by (face, u bits, v bits).
fn by_param(r: &Run) -> HashMap<(u32, u32, u32), &CaptureRecord> {
    r.records
        .iter()
        .map(|x| ((x.face, x.u.to_bits(), x.v.to_bits()), x))
        .collect()
}

#[test]
fn stencil_and_two_stage_variants_agree() {
    for (name, mesh) in [
        ("catmark_car", osd("catmark_car")),
        ("prism", prism()),
        ("catmark_smoothtris0", osd("catmark_smoothtris0")),
    ] {
        let Some(a) = run_with(&mesh, 6.0, GregoryVariant::Stencil, true) else {
            return;
        };
        let b = run_with(&mesh, 6.0, GregoryVariant::TwoStage, true).unwrap();
        let (ma, mb) = (by_param(&a), by_param(&b));
        let (mut max_p, mut max_n, mut corner_or_grid_bitwise, mut common) = (0f64, 0f64, 0, 0);
        for (key, x) in &ma {
            if !a.gregory.contains(&key.0) || !b.gregory.contains(&key.0) {
                continue;
            }
            let y = mb[key];
            common += 1;
            let px = DVec3::from(x.position.map(f64::from));
            let py = DVec3::from(y.position.map(f64::from));
            let nx = DVec3::from(x.normal.map(f64::from));
            let ny = DVec3::from(y.normal.map(f64::from));
            max_p = max_p.max((px - py).length() / a.diag);
            max_n = max_n.max(nx.angle_between(ny));
            if x.position == y.position && x.normal == y.normal {
                corner_or_grid_bitwise += 1;
            }
        }
        assert!(common > 0);
        assert!(
            max_p <= 1e-5,
            "{name}: variants differ by {max_p:e} of the diagonal"
        );
        assert!(
            max_n <= 1e-3,
            "{name}: variant normals differ by {max_n} rad"
        );
        eprintln!(
            "{name}: {common} common points, stencil vs two-stage max position difference \
             {max_p:.2e} of the diagonal, max normal difference {max_n:.2e} rad, \
             {corner_or_grid_bitwise} bitwise equal"
        );
    }
}

fn embedded(name: &str) -> ControlMesh {
    tessera::assets::EmbeddedMesh::from_name(name)
        .unwrap()
        .load()
        .unwrap()
}

/// Renders `mesh` through the integrated renderer with `scheme`, coloured by patch type.
fn patch_type_image(
    ctx: &tessera::gpu::Context,
    mesh: &ControlMesh,
    scheme: Scheme,
) -> image::RgbaImage {
    let surface = surface_for_scheme(mesh, 8, scheme, &SchemeLimits::from_context(ctx)).unwrap();
    let desc = RenderDesc {
        tess: TessSettings {
            level: 8.0,
            ..TessSettings::default()
        },
        color_by: ColorBy::PatchType,
        ..RenderDesc::default()
    };
    let off = OffscreenDesc {
        width: 256,
        height: 256,
        ..OffscreenDesc::default()
    };
    render_to_image(ctx, &surface, &desc, &off, false)
        .unwrap()
        .image
}

/// Golden images coloured by patch type (regular gold, irregular quad purple, triangle green,
/// the paper's Fig. 1) drawn with gregory-stencil: quad-only (catmark_cube), mixed tri/quad
/// (embedded `mixed`), boundary (embedded `open`, whose boundary faces stay on the exact CPU
/// path until the boundary construction lands); the boundary mesh also with gregory-vs
/// (its mixed and cube goldens are in tests/render_gregory_vs.rs). `TESSERA_UPDATE_GOLDEN=1`
/// rewrites them (look at them before committing).
#[test]
fn golden_patch_type() {
    let Some(ctx) = render_common::context() else {
        return;
    };
    let dir = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/golden");
    let threshold = CompareThreshold {
        channel_tolerance: 32,
        max_differing_fraction: 0.01,
    };
    for (name, mesh, scheme) in [
        (
            "gregory_stencil_cube_patch_type",
            osd("catmark_cube"),
            Scheme::GregoryStencil,
        ),
        (
            "gregory_stencil_mixed_patch_type",
            embedded("mixed"),
            Scheme::GregoryStencil,
        ),
        (
            "gregory_stencil_open_patch_type",
            embedded("open"),
            Scheme::GregoryStencil,
        ),
        (
            "gregory_vs_open_patch_type",
            embedded("open"),
            Scheme::GregoryVs,
        ),
    ] {
        let img = patch_type_image(&ctx, &mesh, scheme);
        let path = dir.join(format!("{name}.png"));
        if std::env::var("TESSERA_UPDATE_GOLDEN").as_deref() == Ok("1") {
            img.save(&path).unwrap();
            eprintln!("updated {}", path.display());
            continue;
        }
        let expected = image::open(&path)
            .unwrap_or_else(|e| {
                panic!(
                    "{}: {e} (TESSERA_UPDATE_GOLDEN=1 creates it)",
                    path.display()
                )
            })
            .to_rgba8();
        let report = compare_images(&expected, &img, &threshold).unwrap();
        if !report.passes(&threshold) {
            let out = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
                .parent()
                .unwrap()
                .join("golden-failures");
            std::fs::create_dir_all(&out).unwrap();
            let a = out.join(format!("{name}.actual.png"));
            let d = out.join(format!("{name}.diff.png"));
            img.save(&a).unwrap();
            report.diff_image.save(&d).unwrap();
            panic!(
                "golden {name}: {} of {} pixels differ (max {}); expected {}, actual {}, diff {}",
                report.differing,
                report.total,
                report.max_channel_diff,
                path.display(),
                a.display(),
                d.display()
            );
        }
    }
    render_common::assert_validation_clean(&ctx);
}

/// A closed spindle: apex fans of `n` triangles at both ends and a band of `n` quads between two
/// rings of `n` vertices.
fn spindle(n: u32) -> ControlMesh {
    let mut positions = Vec::new();
    for (z, r) in [(0.5, 1.0), (-0.5, 1.1)] {
        for i in 0..n {
            let a = std::f64::consts::TAU * f64::from(i) / f64::from(n);
            positions.push(DVec3::new(r * a.cos(), r * a.sin(), z));
        }
    }
    positions.push(DVec3::new(0.0, 0.0, 1.6)); // top apex 2n
    positions.push(DVec3::new(0.0, 0.0, -1.5)); // bottom apex 2n + 1
    let (top, bottom) = (2 * n, 2 * n + 1);
    let mut face_vertices = Vec::new();
    let mut face_sizes = Vec::new();
    for i in 0..n {
        let j = (i + 1) % n;
        face_vertices.extend([i, j, top]);
        face_vertices.extend([n + j, n + i, bottom]);
        face_vertices.extend([n + i, n + j, j, i]);
        face_sizes.extend([3, 3, 4]);
    }
    ControlMesh::new(ControlMeshDesc {
        positions,
        face_sizes,
        face_vertices,
        ..Default::default()
    })
    .unwrap()
}

#[test]
fn rings_over_the_patch_size_limit_go_to_the_cpu_path() {
    let Some(ctx) = render_common::context() else {
        return;
    };
    let n = 40;
    let mesh = spindle(n);
    let limits = SchemeLimits::from_context(&ctx);
    assert!(
        limits.max_patch_size <= 32 + 8,
        "test assumes a small patch size limit"
    );
    let surface = surface_for_scheme(&mesh, 6, Scheme::GregoryStencil, &limits).unwrap();
    // The fan triangles have one-rings of n + 2 > 32 vertices: CPU path; the band quads fit.
    let gregory = surface.irregular_gpu_faces();
    assert_eq!(gregory.len(), n as usize);
    assert!(gregory.iter().all(|&f| f % 3 == 2), "only band quads");
    assert_eq!(surface.fallback_faces.len(), 2 * n as usize);
    let desc = RenderDesc {
        tess: TessSettings {
            level: 6.0,
            ..TessSettings::default()
        },
        color_by: ColorBy::PatchType,
        ..RenderDesc::default()
    };
    let off = OffscreenDesc {
        width: 128,
        height: 128,
        ..OffscreenDesc::default()
    };
    let img = render_to_image(&ctx, &surface, &desc, &off, false)
        .unwrap()
        .image;
    // Something was drawn (the background is uniform).
    let bg = *img.get_pixel(0, 0);
    assert!(img.pixels().filter(|p| **p != bg).count() > 1000);
    render_common::assert_validation_clean(&ctx);
}

#[test]
fn split_quads_meet_whole_triangles() {
    let Some(ctx) = render_common::context() else {
        return;
    };
    let mesh = prism();
    for (level, max_patch) in [(12.0, 6.0), (12.0, 3.0), (10.0, 5.0), (24.0, 16.0)] {
        let desc = RenderDesc {
            tess: TessSettings {
                level,
                max_patch_level: max_patch,
                ..TessSettings::default()
            },
            capture_capacity: Some(20000),
            ..RenderDesc::default()
        };
        let opts = SessionOptions {
            variant: GregoryVariant::Stencil,
            with_regular: false,
            width: 64,
            height: 64,
        };
        let mut s = GregorySession::new(&ctx, &mesh, &desc, &opts).unwrap();
        s.frame().unwrap();
        let records = s.capture().unwrap();
        let topo = Topology::new(&mesh).unwrap();
        let r = Run {
            topo,
            positions: mesh.positions().to_vec(),
            diag: mesh.bbox_diagonal(),
            gregory: s.gregory_faces().iter().copied().collect(),
            drawn: s.gregory_faces().iter().copied().collect(),
            records,
        };
        let m = check_watertight(&r);
        eprintln!("level {level} split at {max_patch}: {m} edge points bitwise equal");
    }
    render_common::assert_validation_clean(&ctx);
}

#[test]
fn boundary_and_crease_meshes() {
    // §4.6 boundary construction (G1) through the stencil: GPU == CPU, bitwise watertight
    // (Gregory/Gregory and Gregory/B-spline), validation-clean.
    let mut meshes = vec![("open".to_string(), embedded("open"))];
    for name in [
        "catmark_gregory_test0",
        "catmark_gregory_test1",
        "catmark_gregory_test2",
        "catmark_gregory_test5",
        "catmark_gregory_test6",
        "catmark_nonquads",
        "catmark_car",
    ] {
        meshes.push((name.to_string(), osd(name)));
    }
    for (name, mesh) in &meshes {
        let Some(r) = run_with(mesh, 6.0, GregoryVariant::Stencil, true) else {
            return;
        };
        let (p, n, en) = check_against_cpu(&r, 2e-3);
        let m = check_watertight(&r);
        eprintln!(
            "{name}: {} Gregory + {} regular faces, max position error {p:.2e} of the diagonal, \
             interior normals {n:.2e} rad, edge normals {en:.2e} rad from the CPU patch, {m} edge \
             points bitwise equal",
            r.gregory.len(),
            r.drawn.len() - r.gregory.len()
        );
    }
}
