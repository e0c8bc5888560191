//! Patch culling (`RenderDesc::cull_patches`, `glsl/common/cull.glsl`): patches whose control
//! hull lies outside the view frustum get zero tessellation levels in the control stages. The
//! image must not change (bitwise), the patches in view must keep their levels, and the
//! pipeline statistics must show the evaluation-stage invocations saved.

mod common;

use common::capture::{scheme_surface, uniform};
use common::gpu::{assert_validation_clean, context};
use common::meshes::{mesh, CUBE_FACES};
use glam::DVec3;
use image::RgbaImage;
use tessera::gpu::{Context, PipelineStats};
use tessera::mesh::{ControlMesh, ControlMeshDesc};
use tessera::render::{
    render_to_image, CameraSpec, Displacement, OffscreenDesc, RenderDesc, Scheme, SurfaceData,
};

/// One frame with and without culling: (image, patch-pass statistics).
fn draw(
    ctx: &Context,
    surface: &SurfaceData,
    render: &RenderDesc,
    off: &OffscreenDesc,
    cull: bool,
) -> (RgbaImage, PipelineStats) {
    let render = RenderDesc {
        cull_patches: cull,
        ..*render
    };
    let out = render_to_image(ctx, surface, &render, off, true).expect("render");
    (out.image, out.report.expect("statistics").patch_stats)
}

/// Axis-aligned cubes [-1, 1]^3 (faces wound outward) centred at `centres`.
fn cubes(centres: &[DVec3]) -> ControlMesh {
    let mut desc = ControlMeshDesc::default();
    for (k, c) in centres.iter().enumerate() {
        for i in 0..8 {
            let bit = |b: u32| if i & (1 << b) == 0 { -1.0 } else { 1.0 };
            desc.positions.push(*c + DVec3::new(bit(0), bit(1), bit(2)));
        }
        for f in CUBE_FACES {
            desc.face_sizes.push(4);
            desc.face_vertices
                .extend(f.iter().map(|v| v + 8 * k as u32));
        }
    }
    ControlMesh::new(desc).expect("cubes")
}

fn orbit(azimuth_deg: f64, elevation_deg: f64, distance: f64) -> CameraSpec {
    CameraSpec::Orbit {
        azimuth_deg,
        elevation_deg,
        distance,
    }
}

fn offscreen(camera: CameraSpec) -> OffscreenDesc {
    OffscreenDesc {
        width: 160,
        height: 120,
        camera,
        ..OffscreenDesc::default()
    }
}

/// Three cubes in a row, the camera close in front of the middle one (the orbit centre): the
/// outer two lie far outside the frustum and must be culled; every patch of the middle one
/// straddles a frustum plane (the front one all four sides, the sides the left/right or
/// top/bottom planes) or lies inside, and must be drawn at its own levels. The expected counts
/// come from drawing the middle cube alone without culling.
#[test]
fn patches_outside_are_culled_and_straddling_ones_kept() {
    let Some(ctx) = context() else { return };
    let off = offscreen(orbit(0.0, 0.0, 2.2));
    let render = RenderDesc {
        tess: uniform(6.0),
        ..RenderDesc::default()
    };
    let row = cubes(&[
        DVec3::new(-20.0, 0.0, 0.0),
        DVec3::ZERO,
        DVec3::new(20.0, 0.0, 0.0),
    ]);
    let alone = cubes(&[DVec3::ZERO]);
    let row_surface = scheme_surface(&ctx, &row, 6, Scheme::GregoryStencil);
    let alone_surface = scheme_surface(&ctx, &alone, 6, Scheme::GregoryStencil);
    assert_eq!(row_surface.patch_count(), 18);
    assert!(row_surface.fallback_faces.is_empty());

    let (_, middle) = draw(&ctx, &alone_surface, &render, &off, false);
    let (_, middle_culled) = draw(&ctx, &alone_surface, &render, &off, true);
    let (full_image, full) = draw(&ctx, &row_surface, &render, &off, false);
    let (culled_image, culled) = draw(&ctx, &row_surface, &render, &off, true);
    eprintln!(
        "TES invocations: middle cube {}, row {} without culling, {} with",
        middle.tes_invocations, full.tes_invocations, culled.tes_invocations
    );
    assert!(middle.tes_invocations > 0);
    // Straddling patches are kept at their levels.
    assert_eq!(middle_culled.tes_invocations, middle.tes_invocations);
    // Patches outside are culled: only the middle cube is evaluated.
    assert_eq!(full.tes_invocations, 3 * middle.tes_invocations);
    assert_eq!(culled.tes_invocations, middle.tes_invocations);
    // Every patch still reaches the control stage.
    assert_eq!(culled.tcs_patches, full.tcs_patches);
    assert!(full_image == culled_image, "culling changed the image");
    assert_validation_clean(&ctx);
}

/// The hull is grown by |displacement scale|: a cube just outside the frustum whose displaced
/// surface could reach into it is kept.
#[test]
fn displacement_grows_the_bound() {
    let Some(ctx) = context() else { return };
    // The orbit looks at the bounding-box centre, between the cubes. Eye (0, -2.2, 0), half
    // angles 22.8 deg across, 17.5 deg up: the control hulls (x from 1.8) lie outside the side
    // planes, 0.42 from the nearest (x = 0.42 depth, at the far corner x = 1.8, depth 3.2), within
    // the displacement scale 1.0.
    let off = offscreen(orbit(0.0, 0.0, 2.2));
    let pair = cubes(&[DVec3::new(-2.8, 0.0, 0.0), DVec3::new(2.8, 0.0, 0.0)]);
    let surface = scheme_surface(&ctx, &pair, 4, Scheme::GregoryStencil);
    let plain = RenderDesc {
        tess: uniform(4.0),
        ..RenderDesc::default()
    };
    let displaced = RenderDesc {
        displacement: Displacement::Procedural { scale: 1.0 },
        ..plain
    };
    let (_, none_plain) = draw(&ctx, &surface, &plain, &off, true);
    let (_, all_plain) = draw(&ctx, &surface, &plain, &off, false);
    let (_, kept) = draw(&ctx, &surface, &displaced, &off, true);
    eprintln!(
        "TES invocations: {} of {} undisplaced, {} displaced by 1.0",
        none_plain.tes_invocations, all_plain.tes_invocations, kept.tes_invocations
    );
    assert_eq!(none_plain.tes_invocations, 0, "both cubes are out of view");
    assert!(all_plain.tes_invocations > 0);
    assert!(kept.tes_invocations > none_plain.tes_invocations);
    assert_validation_clean(&ctx);
}

/// A close-up of part of the bishop, every scheme: the same image bitwise with and without
/// culling, and fewer evaluation-stage invocations with it.
#[test]
fn close_up_image_is_unchanged_and_cheaper_for_every_scheme() {
    let Some(ctx) = context() else { return };
    let m = mesh("catmark_bishop");
    let off = offscreen(orbit(30.0, 10.0, CLOSE_UP_DISTANCE));
    let render = RenderDesc {
        tess: uniform(4.0),
        ..RenderDesc::default()
    };
    for scheme in Scheme::ALL {
        let surface = scheme_surface(&ctx, &m, 4, scheme);
        let (full_image, full) = draw(&ctx, &surface, &render, &off, false);
        let (culled_image, culled) = draw(&ctx, &surface, &render, &off, true);
        eprintln!(
            "{scheme:?}: TES invocations {} without culling, {} with ({:.0} %)",
            full.tes_invocations,
            culled.tes_invocations,
            100.0 * culled.tes_invocations as f64 / full.tes_invocations as f64
        );
        assert!(
            full_image == culled_image,
            "{scheme:?}: culling changed the image"
        );
        assert!(
            culled.tes_invocations < full.tes_invocations,
            "{scheme:?}: nothing culled"
        );
        assert!(culled.tes_invocations > 0, "{scheme:?}: everything culled");
    }
    assert_validation_clean(&ctx);
}

const CLOSE_UP_DISTANCE: f64 = 1.0;
