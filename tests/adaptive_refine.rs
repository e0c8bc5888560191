//! The compute refinement of the adaptive scheme (`render::schemes::adaptive::refine`, Köbler
//! 2013, section 4.3) on the GPU equals the CPU f64 refinement, uniform to depth 2 and 3 and
//! feature-adaptive (`RefinementTables::adaptive`), before and after new control points;
//! validation clean.

mod common;

use common::gpu::{assert_validation_clean, context};
use common::levels::{worst_adaptive_error, worst_level_error};
use common::meshes::mesh;
use glam::DVec3;
use tessera::gpu::Context;
use tessera::render::schemes::adaptive::refine::GpuRefiner;
use tessera::subdiv::adaptive::AdaptiveRefinement;
use tessera::subdiv::tables::RefinementTables;
use tessera::subdiv::Level;

/// Car, creases (semi-sharp, fractional, infinitely sharp, corner), boundaries and corners,
/// n-gons, Chaikin creases, holes.
const MESHES: [&str; 9] = [
    "catmark_car",
    "embedded:creased",
    "embedded:open",
    "catmark_edgecorner",
    "catmark_nonquads",
    "catmark_chaikin0",
    "catmark_chaikin1",
    "catmark_chaikin2",
    "catmark_hole_test2",
];

/// Tolerance relative to the bbox diagonal (the kernels compute in f32).
const TOLERANCE: f64 = 1e-6;

/// Runs the recorded refinement once and reads the buffer of every level back.
fn run(ctx: &Context, refiner: &GpuRefiner) -> Vec<DVec3> {
    ctx.submit_once(|dev, cmd| {
        refiner.record(dev, cmd);
        Ok(())
    })
    .unwrap();
    refiner.read_points(ctx).unwrap()
}

/// A deterministic deformation (an animation frame).
fn deform(points: &[DVec3], t: f64) -> Vec<DVec3> {
    points
        .iter()
        .enumerate()
        .map(|(i, p)| *p + DVec3::new((i as f64 * 0.7 + t).sin(), (i as f64 * 1.3).cos(), t) * 0.05)
        .collect()
}

#[test]
fn gpu_refinement_equals_cpu_refinement() {
    let Some(ctx) = context() else { return };
    for name in MESHES {
        let m = mesh(name);
        let level = Level::from_mesh(&m).unwrap();
        for depth in [2, 3] {
            let tables = RefinementTables::uniform(&level, depth).unwrap();
            let mut refiner = GpuRefiner::new(&ctx, &tables, m.positions()).unwrap();
            let worst = worst_level_error(&m, m.positions(), &tables, &run(&ctx, &refiner));
            let moved = deform(m.positions(), 0.3);
            refiner.update_control_points(&moved).unwrap();
            let animated = worst_level_error(&m, &moved, &tables, &run(&ctx, &refiner));
            eprintln!(
                "{name} depth {depth}: {} points, worst {worst:.2e}, animated {animated:.2e} of \
                 the diagonal",
                tables.total_vertices
            );
            assert!(worst <= TOLERANCE, "{name} depth {depth}: {worst:e}");
            assert!(
                animated <= TOLERANCE,
                "{name} depth {depth} animated: {animated:e}"
            );
        }
    }
    assert_validation_clean(&ctx);
}

#[test]
fn gpu_adaptive_refinement_equals_cpu_refinement() {
    let Some(ctx) = context() else { return };
    let cases = [
        ("catmark_car", 2),
        ("catmark_car", 4),
        ("catmark_cube_creases1", 4),
        ("catmark_pole64", 3),
    ];
    for (name, isolation) in cases {
        let m = mesh(name);
        let refinement =
            AdaptiveRefinement::new(&Level::from_mesh(&m).unwrap(), isolation).unwrap();
        let tables = RefinementTables::adaptive(&refinement).unwrap();
        let mut refiner = GpuRefiner::new(&ctx, &tables, m.positions()).unwrap();
        let worst = worst_adaptive_error(&refinement, m.positions(), &run(&ctx, &refiner));
        let moved = deform(m.positions(), 0.3);
        refiner.update_control_points(&moved).unwrap();
        let animated = worst_adaptive_error(&refinement, &moved, &run(&ctx, &refiner));
        eprintln!(
            "{name} isolation {isolation}: {} points, {} table bytes, worst {worst:.2e}, \
             animated {animated:.2e} of the diagonal",
            tables.total_vertices,
            tables.gpu_tables().bytes()
        );
        assert!(
            worst <= TOLERANCE,
            "{name} isolation {isolation}: {worst:e}"
        );
        assert!(
            animated <= TOLERANCE,
            "{name} isolation {isolation} animated: {animated:e}"
        );
    }
    assert_validation_clean(&ctx);
}

/// GPU milliseconds of the whole refinement (timestamps) of the car at depths 1-4, median of 9
/// runs. `cargo test --release --test adaptive_refine -- --ignored --nocapture`.
#[test]
#[ignore = "timing print, not a check"]
fn gpu_refinement_timing() {
    let Some(ctx) = context() else { return };
    let m = mesh("catmark_car");
    let level = Level::from_mesh(&m).unwrap();
    for depth in 1..=4 {
        let tables = RefinementTables::uniform(&level, depth).unwrap();
        let refiner = GpuRefiner::new(&ctx, &tables, m.positions()).unwrap();
        let mut timer = tessera::gpu::GpuTimer::new(&ctx, 1).unwrap();
        let mut ms: Vec<f64> = (0..9)
            .map(|_| {
                ctx.submit_once(|dev, cmd| {
                    timer.reset(cmd);
                    let pass = timer.begin(cmd, "refine")?;
                    refiner.record(dev, cmd);
                    timer.end(cmd, pass)
                })
                .unwrap();
                timer.results().unwrap()[0].1
            })
            .collect();
        ms.sort_by(f64::total_cmp);
        eprintln!(
            "catmark_car depth {depth}: {} points, {:.3} ms (median GPU), {} KiB",
            tables.total_vertices,
            ms[4],
            refiner.memory_bytes() / 1024
        );
    }
    assert_validation_clean(&ctx);
}
