//! `tessera error --heatmap`: the error map (paper Fig. 11) is rendered through the real
//! pipeline, validation-clean, with the colours the errors call for.

mod common;

use common::capture::{image, offscreen};
use common::gpu::{assert_validation_clean, context};
use tessera::render::heatmap::{heat_surface, HEAT_CLASS_BASE, HEAT_STEPS};
use tessera::render::{ColorBy, RenderDesc};

#[test]
fn error_map_shows_exact_faces_blue_and_the_worst_error_red() {
    let Some(ctx) = context() else { return };
    let mesh = tessera::assets::EmbeddedMesh::Mixed.load().unwrap();
    let heat = heat_surface(&mesh, 6, 6, None).unwrap();
    assert!(heat
        .surface
        .fallback
        .classes
        .contains(&(HEAT_CLASS_BASE + HEAT_STEPS)));
    let render = RenderDesc {
        color_by: ColorBy::Error,
        ..RenderDesc::default()
    };
    let img = image(&ctx, &heat.surface, &render, &offscreen(160, 120));
    assert_validation_clean(&ctx);
    // Mostly-blue pixels (exact or nearly) and some red-dominated ones (the worst errors).
    let blue = img.pixels().filter(|p| p[2] > 120 && p[0] < 60).count();
    let red = img.pixels().filter(|p| p[0] > 120 && p[2] < 60).count();
    assert!(blue > 1000, "blue pixels: {blue}");
    assert!(red > 0, "no red pixels");
}

#[test]
fn error_cli_writes_the_map() {
    if context().is_none() {
        return;
    }
    let out = common::out_dir("render_heatmap").join("heat.png");
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_tessera"))
        .args([
            "error",
            "embedded:open",
            "--grid",
            "4",
            "--size",
            "96x72",
            "--heatmap",
        ])
        .arg(&out)
        .status()
        .unwrap();
    assert!(status.success());
    let img = image::open(&out).unwrap().to_rgba8();
    assert_eq!(img.dimensions(), (96, 72));
    let _ = std::fs::remove_file(&out);
}
