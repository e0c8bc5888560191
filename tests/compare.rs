//! `tessera compare`: every scheme in the table, each row's figures the same as the dedicated
//! measurements give alone (`tessera error`'s GPU accuracy, the renderer's memory and patch
//! counts), seams found and checked, and a contact sheet with one panel per scheme.

mod common;

use common::gpu::{assert_validation_clean, context};
use tessera::render::accuracy::measure_gpu_with;
use tessera::render::compare::{compare_scheme, error_map, exact_reference, CompareDesc};
use tessera::render::heatmap::{heat_class, HEAT_CLASS_BASE};
use tessera::render::{
    plan_for_scheme_with, OffscreenDesc, OffscreenSession, PlanOptions, RenderDesc, Scheme,
    SchemeLimits, TessSettings,
};

fn desc(ctx: &tessera::gpu::Context) -> CompareDesc {
    CompareDesc {
        tess: 6.0,
        frames: 1,
        width: 96,
        height: 72,
        plan: PlanOptions::new(SchemeLimits::from_context(ctx)).with_isolation(2),
    }
}

/// Each row agrees with the measurements made alone: the Gregory and adaptive rows' largest
/// distance is `tessera error`'s (regular B-spline points are exact to ~1e-8, far below the
/// Gregory maximum; the adaptive scheme measures every point in both), patch and CPU-face counts
/// are the plan's, memory is the renderer's; seams are watertight.
#[test]
fn rows_match_the_dedicated_measurements() {
    let Some(ctx) = context() else { return };
    let mesh = tessera::assets::EmbeddedMesh::Mixed.load().unwrap();
    let desc = desc(&ctx);
    let exact = exact_reference(&mesh, &desc).unwrap();
    for scheme in Scheme::ALL {
        let c = compare_scheme(&ctx, &mesh, &exact, scheme, &desc).unwrap();
        let r = &c.row;
        let surface = plan_for_scheme_with(&mesh, scheme, &desc.plan).unwrap();
        assert_eq!(r.patches, surface.patch_count(), "{scheme}");
        assert_eq!(r.cpu_faces, surface.fallback_faces.len(), "{scheme}");
        assert_eq!(r.samples, c.points.len());
        assert!(r.samples > 0 && r.seams.pairs > 0, "{scheme}: {r:?}");
        assert!(r.seams.watertight(), "{scheme}: {:?}", r.seams);
        assert!(r.frame_ms > 0.0, "{scheme}");
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
        let session = OffscreenSession::new(&ctx, &surface, &render, &off, false).unwrap();
        assert_eq!(r.memory_bytes, session.renderer().memory_bytes().total());
        if scheme != Scheme::BsplineOnly {
            let alone = measure_gpu_with(&ctx, &mesh, scheme, 6, &desc.plan).unwrap();
            let rel =
                (r.max_distance - alone.report.max_distance).abs() / alone.report.max_distance;
            assert!(
                rel < 1e-9,
                "{scheme}: {} vs {}",
                r.max_distance,
                alone.report.max_distance
            );
            if scheme == Scheme::Adaptive {
                assert_eq!(r.samples, alone.report.samples);
                assert!((r.rms_distance - alone.report.rms_distance).abs() < 1e-15);
            }
        } else {
            // Only regular faces on the GPU: exact B-spline patches.
            assert!(r.max_distance < 1e-6, "{}", r.max_distance);
            assert!(r.cpu_faces > 0);
        }
    }
    assert_validation_clean(&ctx);
}

/// The error maps of two schemes on one scale (the Gregory scheme's largest error): the Gregory
/// map reaches red, the far more accurate adaptive map stays near blue.
#[test]
fn error_maps_share_one_scale() {
    let Some(ctx) = context() else { return };
    let mesh = tessera::assets::EmbeddedMesh::Mixed.load().unwrap();
    let desc = desc(&ctx);
    let exact = exact_reference(&mesh, &desc).unwrap();
    let gregory = compare_scheme(&ctx, &mesh, &exact, Scheme::GregoryStencil, &desc).unwrap();
    let adaptive = compare_scheme(&ctx, &mesh, &exact, Scheme::Adaptive, &desc).unwrap();
    let grid = 4;
    let map_grid = exact.ev.eval_all_grids(grid).unwrap();
    let scale = gregory.row.max_distance * mesh.bbox_diagonal();
    let hot = |points: &[tessera::render::accuracy::MeasuredPoint]| {
        let map = error_map(&mesh, &map_grid, grid, points, scale).unwrap();
        assert!(map.surface.parts.is_empty());
        let classes = &map.surface.fallback.classes;
        assert!(!classes.is_empty());
        classes.iter().map(|c| c - HEAT_CLASS_BASE).max().unwrap()
    };
    // Each grid sample takes the error of the nearest captured point: the worst point lands on a
    // grid sample only approximately, so well above half scale; no sample exceeds its scheme's
    // largest error on the shared scale.
    let class = |c: &tessera::render::compare::SchemeComparison| {
        heat_class(c.row.max_distance * mesh.bbox_diagonal(), scale) - HEAT_CLASS_BASE
    };
    assert!(hot(&gregory.points) > 512);
    assert!(hot(&gregory.points) <= class(&gregory));
    assert!(
        class(&adaptive) < class(&gregory) / 4,
        "{}",
        class(&adaptive)
    );
    assert!(hot(&adaptive.points) <= class(&adaptive));
    assert_validation_clean(&ctx);
}

#[test]
fn cli_prints_every_scheme_and_writes_the_sheet() {
    let dir = std::env::temp_dir().join(format!("tessera-compare-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let sheet = dir.join("sheet.png");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_tessera"))
        .args(["compare", "embedded:mixed", "--tess", "4", "--frames", "1"])
        .args([
            "--size",
            "64x48",
            "--csv",
            "--sheet",
            sheet.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let rows: Vec<&str> = text.lines().skip(1).collect();
    let names: Vec<&str> = rows.iter().map(|l| l.split(',').next().unwrap()).collect();
    let all: Vec<&str> = Scheme::ALL.iter().map(|s| s.name()).collect();
    assert_eq!(names, all, "{text}");
    let columns = text.lines().next().unwrap().split(',').count();
    assert!(
        rows.iter().all(|l| l.split(',').count() == columns),
        "{text}"
    );
    let img = image::open(&sheet).unwrap();
    // One 64 x 48 panel per scheme in a near-square grid (3 x 2 for six schemes).
    let n = Scheme::ALL.len() as u32;
    let columns = (1..=n).find(|c| c * c >= n).unwrap();
    assert_eq!(
        (img.width(), img.height()),
        (64 * columns, 48 * n.div_ceil(columns))
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// The continuity column measures the constructions: exact B-spline patches turn no more across
/// a shared smooth edge than the limit itself does at the same two points (both f64 on the CPU),
/// Gregory quads no more either (G1 across their edges), QAS far more (C0: its geometric normal
/// jumps, measured up to 2.4 rad on the car, though its separate normal patch is continuous) and
/// ACC's geometry patches (C0 at extraordinary vertices, 0.60 rad on the car; its tangent patches
/// shade them continuously, but this reads the geometry) more than the limit. Meshes:
/// the car (all quads) and `embedded:mixed`.
#[test]
fn continuity_reads_each_construction() {
    use tessera::render::continuity::{exact_turns, ContinuityReport};
    use tessera::render::{plan_for_scheme, Scheme, SchemeLimits};
    use tessera::subdiv::eval::LimitEvaluator;
    use tessera::topology::Topology;
    for name in ["catmark_car", "embedded:mixed"] {
        let m = common::meshes::mesh(name);
        let topo = Topology::new(&m).unwrap();
        let ev = LimitEvaluator::new(&m).unwrap();
        let turns = exact_turns(&topo, &ev);
        let report = |scheme| {
            let surface = plan_for_scheme(&m, scheme, &SchemeLimits::NO_DEVICE).unwrap();
            let r = ContinuityReport::new(&surface, &topo, &turns);
            eprintln!("{name} {scheme:?}: {r:?}");
            r
        };
        let bspline = report(Scheme::BsplineOnly);
        assert!(bspline.edges > 0);
        assert!(
            bspline.max_jump <= 1.01 * bspline.max_exact_jump + 1e-7,
            "{name}: exact patches turn more than the limit"
        );
        let qas = report(Scheme::Qas);
        assert!(
            qas.max_jump > 10.0 * qas.max_exact_jump,
            "{name}: QAS looks G1"
        );
        // Gregory quads meet each other and B-spline patches tangent-continuously, to the
        // limit's own turn at the two points (measured: car 1.06e-3 both, 269 edges more).
        let gregory = report(Scheme::GregoryStencil);
        assert!(gregory.edges >= bspline.edges);
        assert!(gregory.max_jump <= 1.01 * gregory.max_exact_jump + 1e-7);
        assert!(gregory.max_jump < qas.max_jump);
        // ACC draws extraordinary quads only on the car (mixed: interior regular quads alone).
        let acc = report(Scheme::Acc);
        if name == "catmark_car" {
            assert!(acc.max_jump > 10.0 * acc.max_exact_jump);
        }
    }
}
