//! `tessera error --scheme adaptive`: the GPU capture measured per patch type
//! (`render::accuracy::measure_gpu_with`). The exact types (B-spline patches of every level,
//! boundary, crease, transition fans) equal the limit at equal `(u, v)` to ≤ 1e-6 of the bbox
//! diagonal; the end caps approximate it and their error falls with the isolation level; the
//! overall line counts every point once.

mod common;

use tessera::mesh::ControlMesh;
use tessera::render::accuracy::{measure_gpu_with, GpuAccuracy};
use tessera::render::{PlanOptions, Scheme, SchemeLimits};

use common::gpu::{assert_validation_clean, context};
use common::meshes::{corpus_options, osd_path};

const EXACT: &[&str] = &["regular", "boundary", "crease", "transition"];

fn load(name: &str) -> ControlMesh {
    tessera::assets::load_mesh(osd_path(name).to_str().unwrap(), &corpus_options(name)).unwrap()
}

fn measure(ctx: &tessera::gpu::Context, m: &ControlMesh, isolation: u32) -> GpuAccuracy {
    let opts = PlanOptions::new(SchemeLimits::from_context(ctx)).with_isolation(isolation);
    let r = measure_gpu_with(ctx, m, Scheme::Adaptive, 4, &opts).unwrap();
    assert_validation_clean(ctx);
    r
}

#[test]
fn exact_types_equal_the_limit_per_type() {
    let Some(ctx) = context() else { return };
    for (name, isolation) in [
        ("catmark_cube", 2),
        ("catmark_nonquads", 2),
        ("catmark_cube_creases1", 2),
        ("catmark_car", 1),
    ] {
        let m = load(name);
        let r = measure(&ctx, &m, isolation);
        let total: usize = r.by_type.iter().map(|t| t.samples).sum();
        assert_eq!(total, r.report.samples, "{name}: every point has a type");
        assert_eq!(r.report.unsupported, 0, "{name}: nothing on the CPU path");
        assert!(
            r.by_type.iter().any(|t| t.kind == "gregory-quad"),
            "{name}: end caps measured"
        );
        for t in &r.by_type {
            assert!(t.samples > 0, "{name} {}", t.kind);
            assert!(t.levels.1 as u32 <= isolation, "{name} {}", t.kind);
            if EXACT.contains(&t.kind) {
                assert!(
                    t.max_uv <= 1e-6 && t.max_distance <= 1e-6,
                    "{name} iso {isolation} {}: max (u,v) {:.3e} max dist {:.3e}",
                    t.kind,
                    t.max_uv,
                    t.max_distance
                );
            }
        }
        let max = r.by_type.iter().map(|t| t.max_distance).fold(0.0, f64::max);
        assert_eq!(
            max, r.report.max_distance,
            "{name}: overall max is a type's max"
        );
    }
}

#[test]
fn end_cap_error_falls_with_isolation() {
    let Some(ctx) = context() else { return };
    let m = load("catmark_cube");
    let cap = |isolation| {
        let r = measure(&ctx, &m, isolation);
        let t = r
            .by_type
            .into_iter()
            .find(|t| t.kind == "gregory-quad")
            .unwrap();
        (t.rms_uv, t.rms_distance)
    };
    let (a, b) = (cap(1), cap(3));
    assert!(
        b.0 < 0.5 * a.0 && b.1 < 0.5 * a.1,
        "iso 1 {a:?}, iso 3 {b:?}"
    );
}
