//! Golden images: renders several meshes and modes offscreen and compares them with the PNGs in
//! `tests/golden/` (tests/common/golden.rs: threshold, failure images,
//! `TESSERA_UPDATE_GOLDEN=1`).

mod common;

use common::capture::{image, offscreen, uniform};
use common::golden::check_golden;
use common::gpu::{assert_validation_clean, context};
use common::surfaces::{open_grid, torus};
use image::RgbaImage;
use tessera::gpu::Context;
use tessera::render::{
    CameraSpec, ColorBy, OffscreenDesc, RenderDesc, Spacing, SurfaceData, TessMode, TessSettings,
};

fn render(ctx: &Context, s: &SurfaceData, r: RenderDesc, camera: CameraSpec) -> RgbaImage {
    let off = OffscreenDesc {
        camera,
        ..offscreen(256, 192)
    };
    image(ctx, s, &r, &off)
}

/// The torus of `torus_patch_type` shaded at `level`, coloured by `color_by`.
fn torus_shaded(ctx: &Context, level: f32, color_by: ColorBy, camera: CameraSpec) -> RgbaImage {
    let shaded = RenderDesc {
        tess: uniform(level),
        color_by,
        ..RenderDesc::default()
    };
    render(ctx, &torus(12, 8, 2.0, 0.7), shaded, camera)
}

#[test]
fn golden_synthetic_regular() {
    let Some(ctx) = context() else { return };
    let t = torus(12, 8, 2.0, 0.7);
    let g = open_grid(6, 5);
    check_golden(
        "torus_patch_type",
        &torus_shaded(&ctx, 6.0, ColorBy::PatchType, CameraSpec::Auto),
    );
    let wire = RenderDesc {
        tess: uniform(3.0),
        wireframe: true,
        ..RenderDesc::default()
    };
    check_golden("torus_wireframe", &render(&ctx, &t, wire, CameraSpec::Auto));
    let adaptive = RenderDesc {
        tess: TessSettings {
            mode: TessMode::Adaptive,
            pixels_per_edge: 10.0,
            spacing: Spacing::FractionalOdd,
            ..TessSettings::default()
        },
        wireframe: true,
        ..RenderDesc::default()
    };
    let cam = CameraSpec::Orbit {
        azimuth_deg: 20.0,
        elevation_deg: 40.0,
        distance: 11.0,
    };
    check_golden(
        "open_grid_adaptive_wireframe",
        &render(&ctx, &g, adaptive, cam),
    );
    assert_validation_clean(&ctx);
}

#[test]
fn golden_embedded_meshes() {
    use tessera::assets::EmbeddedMesh;
    use tessera::render::surface_from_mesh;
    let Some(ctx) = context() else { return };
    let load = |m: EmbeddedMesh, lvl: u32| surface_from_mesh(&m.load().unwrap(), lvl).unwrap();
    let shaded = |l: f32, color_by| RenderDesc {
        tess: uniform(l),
        color_by,
        ..RenderDesc::default()
    };
    let mixed = load(EmbeddedMesh::Mixed, 6);
    for (name, surface, color_by) in [
        ("mixed_patch_type", &mixed, ColorBy::PatchType),
        ("open_shaded", &load(EmbeddedMesh::Open, 6), ColorBy::None),
        (
            "creased_patch_type",
            &load(EmbeddedMesh::Creased, 6),
            ColorBy::PatchType,
        ),
    ] {
        check_golden(
            name,
            &render(&ctx, surface, shaded(6.0, color_by), CameraSpec::Auto),
        );
    }
    let mixed4 = load(EmbeddedMesh::Mixed, 4);
    let wire = RenderDesc {
        tess: uniform(4.0),
        wireframe: true,
        ..RenderDesc::default()
    };
    check_golden(
        "mixed_wireframe",
        &render(&ctx, &mixed4, wire, CameraSpec::Auto),
    );
    let adaptive = RenderDesc {
        tess: TessSettings {
            mode: TessMode::Adaptive,
            pixels_per_edge: 8.0,
            spacing: Spacing::FractionalEven,
            ..TessSettings::default()
        },
        wireframe: true,
        color_by: ColorBy::PatchType,
        ..RenderDesc::default()
    };
    check_golden(
        "mixed_adaptive_wireframe",
        &render(&ctx, &mixed4, adaptive, CameraSpec::Auto),
    );
    assert_validation_clean(&ctx);
}
