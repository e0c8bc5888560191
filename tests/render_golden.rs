//! Golden images: renders several meshes and modes offscreen and compares them with the PNGs in
//! `tests/golden/` by FLIP (tests/common/golden.rs: thresholds per golden, failure images,
//! `TESSERA_UPDATE_GOLDEN=1`); and a wrong render is rejected.

mod common;

use common::capture::{image, offscreen, uniform};
use common::golden::{check_golden, verify};
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

/// The comparison rejects wrong renders of `torus_patch_type`: another camera, the neutral
/// material instead of the patch-type colours, and (subtler: only the facets change) tessellation
/// level 4 instead of 6. The failure names the actual render and the FLIP map, both written.
#[test]
fn golden_rejects_wrong_renders() {
    let Some(ctx) = context() else { return };
    let turned = CameraSpec::Orbit {
        azimuth_deg: 5.0,
        elevation_deg: 30.0,
        distance: 9.0,
    };
    for (stem, wrong) in [
        (
            "perturbed_camera",
            torus_shaded(&ctx, 6.0, ColorBy::PatchType, turned),
        ),
        (
            "perturbed_colouring",
            torus_shaded(&ctx, 6.0, ColorBy::None, CameraSpec::Auto),
        ),
        (
            "perturbed_level4",
            torus_shaded(&ctx, 4.0, ColorBy::PatchType, CameraSpec::Auto),
        ),
    ] {
        let written = [".actual.png", ".flip.png"]
            .map(|ext| common::out_dir("golden-failures").join(format!("{stem}{ext}")));
        for path in &written {
            let _ = std::fs::remove_file(path);
        }
        let msg = match verify("torus_patch_type", &wrong, stem) {
            Ok(f) => panic!(
                "{stem}: accepted (FLIP mean {}, percentile {})",
                f.mean, f.at_percentile
            ),
            Err(msg) => msg,
        };
        for path in &written {
            assert!(path.is_file(), "{} not written", path.display());
            assert!(
                msg.contains(&path.display().to_string()),
                "{msg}\ndoes not name {}",
                path.display()
            );
        }
    }
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
