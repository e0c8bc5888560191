//! Golden images: renders several meshes and modes offscreen and compares them with the PNGs in
//! `tests/golden/` (per-pixel tolerance + maximum fraction of differing pixels, see
//! [`THRESHOLD`]). On mismatch the actual and difference images are written to
//! `target/golden-failures/` and named in the failure. `TESSERA_UPDATE_GOLDEN=1` rewrites the
//! goldens instead of comparing (look at them before committing).

mod render_common;

use std::path::PathBuf;

use image::RgbaImage;
use render_common::{assert_validation_clean, context, open_grid, torus};
use tessera::gpu::Context;
use tessera::render::{
    compare_images, render_to_image, CameraSpec, ColorBy, CompareThreshold, OffscreenDesc,
    RenderDesc, Spacing, SurfaceData, TessMode, TessSettings,
};

/// A pixel differs when a channel differs by more than 32/255; at most 1% may differ
/// (rasterisation differences along silhouettes between drivers).
const THRESHOLD: CompareThreshold = CompareThreshold {
    channel_tolerance: 32,
    max_differing_fraction: 0.01,
};

const W: u32 = 256;
const H: u32 = 192;

fn golden_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/golden")
}

fn failure_dir() -> PathBuf {
    // CARGO_TARGET_TMPDIR is <target>/tmp.
    PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .parent()
        .map(|p| p.join("golden-failures"))
        .unwrap_or_else(|| PathBuf::from("target/golden-failures"))
}

/// Compares `actual` with `tests/golden/<name>.png` (or rewrites it).
fn check_golden(name: &str, actual: &RgbaImage) {
    let path = golden_dir().join(format!("{name}.png"));
    if std::env::var("TESSERA_UPDATE_GOLDEN").as_deref() == Ok("1") {
        std::fs::create_dir_all(golden_dir()).unwrap();
        actual.save(&path).unwrap();
        eprintln!("updated {}", path.display());
        return;
    }
    let expected = match image::open(&path) {
        Ok(i) => i.to_rgba8(),
        Err(e) => panic!(
            "golden {} unreadable ({e}); run with TESSERA_UPDATE_GOLDEN=1 to create it",
            path.display()
        ),
    };
    let report = compare_images(&expected, actual, &THRESHOLD).unwrap();
    if !report.passes(&THRESHOLD) {
        let dir = failure_dir();
        std::fs::create_dir_all(&dir).unwrap();
        let a = dir.join(format!("{name}.actual.png"));
        let d = dir.join(format!("{name}.diff.png"));
        actual.save(&a).unwrap();
        report.diff_image.save(&d).unwrap();
        panic!(
            "golden {name}: {} of {} pixels ({:.3}%) differ by more than {} (max diff {}), allowed \
             {:.3}%\n  expected: {}\n  actual:   {}\n  diff:     {}",
            report.differing,
            report.total,
            100.0 * report.differing_fraction(),
            THRESHOLD.channel_tolerance,
            report.max_channel_diff,
            100.0 * THRESHOLD.max_differing_fraction,
            path.display(),
            a.display(),
            d.display()
        );
    }
}

fn render(ctx: &Context, s: &SurfaceData, r: RenderDesc, camera: CameraSpec) -> RgbaImage {
    let desc = OffscreenDesc {
        width: W,
        height: H,
        camera,
        ..OffscreenDesc::default()
    };
    render_to_image(ctx, s, &r, &desc, false).unwrap().image
}

fn level(level: f32) -> TessSettings {
    TessSettings {
        level,
        ..TessSettings::default()
    }
}

#[test]
fn golden_synthetic_regular() {
    let Some(ctx) = context() else { return };
    let t = torus(12, 8, 2.0, 0.7);
    let g = open_grid(6, 5);
    let shaded = RenderDesc {
        tess: level(6.0),
        color_by: ColorBy::PatchType,
        ..RenderDesc::default()
    };
    check_golden(
        "torus_patch_type",
        &render(&ctx, &t, shaded, CameraSpec::Auto),
    );
    let wire = RenderDesc {
        tess: level(3.0),
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
        tess: level(l),
        color_by,
        ..RenderDesc::default()
    };
    let mixed = load(EmbeddedMesh::Mixed, 6);
    check_golden(
        "mixed_patch_type",
        &render(
            &ctx,
            &mixed,
            shaded(6.0, ColorBy::PatchType),
            CameraSpec::Auto,
        ),
    );
    check_golden(
        "open_shaded",
        &render(
            &ctx,
            &load(EmbeddedMesh::Open, 6),
            shaded(6.0, ColorBy::None),
            CameraSpec::Auto,
        ),
    );
    check_golden(
        "creased_patch_type",
        &render(
            &ctx,
            &load(EmbeddedMesh::Creased, 6),
            shaded(6.0, ColorBy::PatchType),
            CameraSpec::Auto,
        ),
    );
    let mixed4 = load(EmbeddedMesh::Mixed, 4);
    let wire = RenderDesc {
        tess: level(4.0),
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
