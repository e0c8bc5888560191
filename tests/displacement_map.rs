//! Displacement from a map (`--displacement FILE.png`, `Displacement::Map`): every scheme moves
//! each TES point by `scale * (value - 0.5)` along its normal, `value` the map sampled at the
//! point's texture coordinate as the CPU mirror (`DisplacementMap::sample`, bilinear over texel
//! centres with wrap-around) computes it; the displaced surface stays bitwise watertight at
//! several levels on `embedded:mixed` (B-spline and Gregory or end-cap patches side by side)
//! with one shared `vt` per vertex; bad input (no `vt`, no map, a missing or corrupt file, a
//! map beyond the device's image size) is a typed error. The golden map `assets/
//! displacement_bumps.png` is [`bumps`] (checked here, rewritten with `TESSERA_UPDATE_GOLDEN=1`).

mod common;

use std::path::PathBuf;

use common::capture::{
    capture, image, offscreen, param_key, points_by_param, scheme_surface, uniform,
};
use common::golden::{check_golden, update_requested};
use common::gpu::{assert_validation_clean, context};
use common::meshes::{mesh, with_shared_uvs};
use common::watertight::assert_displacement_keeps_seams;
use glam::{DVec2, DVec3};
use tessera::mesh::ObjOptions;
use tessera::render::displace::DisplacementMap;
use tessera::render::{
    render_to_image, ColorBy, Displacement, OffscreenDesc, RenderDesc, Scheme, SurfaceData,
};
use tessera::{ControlMesh, Error};

const SCALE: f32 = 0.2;
/// Side of the golden map.
const BUMPS: u32 = 32;

/// The golden map: `BUMPS x BUMPS` 8-bit texels `round(127.5 + 127 sin(2 pi x) cos(4 pi y))` at
/// the texel centres `x = (i + 0.5) / w`, `y = (j + 0.5) / h`: smooth, periodic (so repeat
/// addressing has no seam), the full range of values.
fn bumps() -> Vec<u8> {
    let tau = std::f64::consts::TAU;
    let n = f64::from(BUMPS);
    (0..BUMPS)
        .flat_map(|j| {
            (0..BUMPS).map(move |i| {
                let (x, y) = ((f64::from(i) + 0.5) / n, (f64::from(j) + 0.5) / n);
                (127.5 + 127.0 * (tau * x).sin() * (2.0 * tau * y).cos()).round() as u8
            })
        })
        .collect()
}

fn asset() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/displacement_bumps.png")
}

fn bumps_map() -> DisplacementMap {
    DisplacementMap::from_u8(BUMPS, BUMPS, bumps()).unwrap()
}

/// `embedded:mixed` with one shared `vt` per vertex.
fn mixed_with_uvs() -> ControlMesh {
    ControlMesh::from_obj_str(
        &with_shared_uvs(&mesh("embedded:mixed")),
        "mixed-uv.obj",
        &ObjOptions::default(),
    )
    .unwrap()
}

fn desc(level: f32, scale: f32) -> RenderDesc {
    RenderDesc {
        tess: uniform(level),
        displacement: Displacement::Map { scale },
        ..RenderDesc::default()
    }
}

fn mapped(ctx: &tessera::gpu::Context, m: &ControlMesh, level: u32, scheme: Scheme) -> SurfaceData {
    let mut surface = scheme_surface(ctx, m, level, scheme);
    surface.set_displacement_map(bumps_map()).unwrap();
    surface
}

#[test]
fn golden_map_asset_is_the_documented_function() {
    let path = asset();
    if update_requested() {
        image::GrayImage::from_raw(BUMPS, BUMPS, bumps())
            .unwrap()
            .save(&path)
            .unwrap();
    }
    let loaded = DisplacementMap::load(&path).unwrap();
    assert_eq!(loaded.size(), (BUMPS, BUMPS));
    assert_eq!(loaded.texels(), bumps_map().texels());
    assert_eq!(loaded.source(), path.display().to_string());
}

#[test]
fn map_displaced_surface_is_watertight_for_every_scheme() {
    let Some(ctx) = context() else { return };
    let m = mixed_with_uvs();
    for scheme in Scheme::ALL {
        for level in [2.0, 5.0, 8.0] {
            let surface = mapped(&ctx, &m, level as u32, scheme);
            let what = format!("{scheme:?} level {level}");
            assert_displacement_keeps_seams(&ctx, &m, &surface, |s| desc(level, s), SCALE, &what);
        }
    }
    assert_validation_clean(&ctx);
}

/// The GPU's displaced points against the CPU mirror at the captured texture coordinates.
/// Tolerance: lavapipe (llvmpipe) filters 8-bit unorm texels in 8-bit fixed point: the bilinear
/// weights have 8 sub-texel bits (an error of up to `largest_step / 256` over both axes) and the
/// filtered value is returned as a multiple of 1/255 (truncated: up to 1/255 off); with f32
/// rounding of `p + s d n` (1e-6 of the diagonal) the bound is `scale (1/255 + largest_step /
/// 256) + 1e-6 diagonal`. Measured: 0.98/255 of the scale at most (mostly the 8-bit result).
#[test]
fn map_displacement_matches_the_cpu_mirror() {
    let Some(ctx) = context() else { return };
    let m = mixed_with_uvs();
    let diag = m.bbox_diagonal();
    let map = bumps_map();
    let bound = f64::from(SCALE) * (1.0 / 255.0 + map.largest_step() / 256.0) + 1e-6 * diag;
    for scheme in Scheme::ALL {
        let surface = mapped(&ctx, &m, 5, scheme);
        let run = |scale| capture(&ctx, &surface, &desc(5.0, scale), &offscreen(64, 64), false);
        let plain = points_by_param(&run(0.0).records);
        let (mut worst, mut largest, mut n) = (0.0f64, 0.0f64, 0);
        for r in run(SCALE).records {
            let Some(Some([p, nrm])) = plain.get(&param_key(&r)) else {
                continue;
            };
            assert_eq!(&r.normal, nrm, "{scheme:?}: the map keeps the normal");
            let p = DVec3::from(p.map(f64::from));
            let want = map.displaced(
                p,
                DVec3::from(nrm.map(f64::from)),
                DVec2::from(r.texcoord.map(f64::from)),
                f64::from(SCALE),
            );
            let got = DVec3::from(r.position.map(f64::from));
            worst = worst.max((got - want).length());
            largest = largest.max((got - p).length());
            n += 1;
        }
        eprintln!(
            "{scheme:?}: {n} points, largest deviation from the CPU mirror {worst:.2e} (bound \
             {bound:.2e}), largest move {largest:.4}"
        );
        assert!(n > 100, "{scheme:?}: only {n} points compared");
        assert!(
            worst <= bound,
            "{scheme:?}: {worst:e} from the CPU mirror (bound {bound:e})"
        );
        // The map spans [0, 1]: the points really moved (by up to scale / 2).
        assert!(
            largest > 0.3 * f64::from(SCALE),
            "{scheme:?}: largest move {largest}"
        );
    }
    assert_validation_clean(&ctx);
}

#[test]
fn bad_maps_and_meshes_without_texture_coordinates_are_refused() {
    // A mesh without `vt`.
    let plain = tessera::render::plan_for_scheme(
        &mesh("embedded:mixed"),
        Scheme::BsplineOnly,
        &tessera::render::SchemeLimits::NO_DEVICE,
    )
    .unwrap();
    let mut s = plain.clone();
    let e = s.set_displacement_map(bumps_map()).unwrap_err();
    assert!(matches!(e, Error::MissingTexCoords { .. }), "{e}");
    assert!(e.to_string().contains("texture coordinates"), "{e}");
    // Files: missing, not an image.
    let dir = std::env::temp_dir().join(format!("tessera-dispmap-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let missing = dir.join("missing.png");
    let e = DisplacementMap::load(&missing).unwrap_err();
    assert!(matches!(e, Error::Io { .. }), "{e}");
    assert!(e.to_string().contains("missing.png"), "{e}");
    let corrupt = dir.join("corrupt.png");
    let mut bytes = std::fs::read(asset()).unwrap();
    bytes.truncate(40);
    std::fs::write(&corrupt, &bytes).unwrap();
    let e = DisplacementMap::load(&corrupt).unwrap_err();
    assert!(matches!(e, Error::Image { .. }), "{e}");
    assert!(e.to_string().contains("corrupt.png"), "{e}");
    let text = dir.join("text.png");
    std::fs::write(&text, "v 0 0 0\n").unwrap();
    let e = DisplacementMap::load(&text).unwrap_err();
    assert!(e.to_string().contains("text.png"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
    // Texels that do not fill the size.
    let e = DisplacementMap::from_u8(4, 4, vec![0; 15]).unwrap_err();
    assert!(matches!(e, Error::SizeMismatch { .. }), "{e}");

    let Some(ctx) = context() else { return };
    let m = mixed_with_uvs();
    let refused = |surface: &SurfaceData| {
        render_to_image(&ctx, surface, &desc(2.0, 0.1), &offscreen(32, 32), false).unwrap_err()
    };
    // Map mode without a map on the surface.
    let surface = scheme_surface(&ctx, &m, 2, Scheme::BsplineOnly);
    let e = refused(&surface);
    assert!(e.to_string().contains("set_displacement_map"), "{e}");
    // A surface whose texture coordinates were dropped after the map was set.
    let mut dropped = mapped(&ctx, &m, 2, Scheme::BsplineOnly);
    dropped.texcoords = None;
    let e = refused(&dropped);
    assert!(matches!(e, Error::MissingTexCoords { .. }), "{e}");
    // Wider than the device allows.
    let max = ctx.info().limits.max_image_dimension_2d;
    let mut wide = scheme_surface(&ctx, &m, 2, Scheme::BsplineOnly);
    wide.set_displacement_map(
        DisplacementMap::from_u8(max + 1, 1, vec![0; max as usize + 1]).unwrap(),
    )
    .unwrap();
    let e = refused(&wide);
    let msg = e.to_string();
    assert!(
        msg.contains(&format!("{} x 1", max + 1)) && msg.contains(&max.to_string()),
        "{msg}"
    );
    assert_validation_clean(&ctx);
}

/// `embedded:mixed` displaced by the bumps map (scale 0.3, level 16), seen from the side so the
/// silhouette shows the bumps (the shading normal is the limit surface's).
#[test]
fn golden_map_displacement() {
    let Some(ctx) = context() else { return };
    let m = mixed_with_uvs();
    let surface = mapped(&ctx, &m, 16, Scheme::GregoryStencil);
    let render = RenderDesc {
        color_by: ColorBy::PatchType,
        ..desc(16.0, 0.3)
    };
    let off = OffscreenDesc {
        ..offscreen(256, 256)
    };
    check_golden(
        "map_displacement_mixed",
        &image(&ctx, &surface, &render, &off),
    );
    assert_validation_clean(&ctx);
}
