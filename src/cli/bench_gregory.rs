//! `tessera bench --variants`: the Gregory faces of a mesh drawn every way at each level (the
//! paper's Table 1 comparison of the two GPU variants, plus the exact CPU path and the regular
//! B-spline pass), each pass timed alone.

use tessera::gpu::Context;
use tessera::mesh::ControlMesh;
use tessera::render::bench::bench_paths;
use tessera::Result;

/// Prints the comparison table for `levels`.
pub fn run_variants(
    ctx: &Context,
    mesh: &ControlMesh,
    levels: &[f32],
    frames: u32,
    size: (u32, u32),
    max_patch_level: f32,
) -> Result<()> {
    println!(
        "Gregory pass alone, median GPU ms of {frames} frames (construction + evaluation); \
         cpu: exact evaluation of the same faces (wall-clock ms) + GPU ms to draw them"
    );
    println!(
        "{:>6} {:>8} {:>11} {:>11} {:>11} {:>10} {:>10} {:>9} {:>9} {:>11}",
        "level",
        "gregory",
        "TES invoc.",
        "stencil ms",
        "2-stage ms",
        "winner",
        "cpu eval",
        "cpu draw",
        "regular",
        "regular ms"
    );
    let rows = bench_paths(ctx, mesh, levels, frames, size, max_patch_level)?;
    for r in &rows {
        let winner = if r.stencil_ms < r.two_stage_ms {
            "stencil"
        } else {
            "two-stage"
        };
        let count = if r.gregory_patches == r.two_stage_patches {
            r.gregory_patches.to_string()
        } else {
            format!("{}/{}", r.gregory_patches, r.two_stage_patches)
        };
        println!(
            "{:>6} {:>8} {:>11} {:>11.3} {:>11.3} {:>10} {:>10.1} {:>9.3} {:>9} {:>11.3}",
            r.level,
            count,
            r.tes_invocations,
            r.stencil_ms,
            r.two_stage_ms,
            winner,
            r.cpu_eval_ms,
            r.cpu_draw_ms,
            r.regular_patches,
            r.regular_ms
        );
    }
    Ok(())
}
