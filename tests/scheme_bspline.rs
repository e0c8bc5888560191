//! Conformance of the `bspline-only` scheme (copy this file for a new scheme; the checks are in
//! `tests/common/conformance.rs`): regular faces as exact bicubic B-splines.

mod common;

use common::capture::{longest_triangle_edge, offscreen, scheme_surface, uniform};
use common::conformance::{
    animation_on, assert_matches_limit, draw, golden_patch_type, gpu_equals_cpu_on, watertight_on,
};
use common::crease_grid::torus;
use common::gpu::{assert_validation_clean, context};
use common::meshes::mesh;
use tessera::render::static_draw::StaticDraw;
use tessera::render::{RenderDesc, Scheme, TessMode, TessSettings};

const SCHEME: Scheme = Scheme::BsplineOnly;
/// The pass whose patches are exact.
const EXACT_PASS: &str = "bspline";

/// Exact: every point of every B-spline patch equals the Catmull-Clark limit at the same
/// (face, u, v) within 1e-6 of the bbox diagonal and 5e-5 rad (measured: <= 2.3e-7 of the
/// diagonal; normals <= 4.7e-7 rad on the embedded meshes, 1.6e-5 rad on the car, as far as
/// rounding its control points to f32 alone moves the exact normals there, 1.5e-5 rad: the
/// Bezier points and edge tangents are computed relative to a patch point, so the small faces'
/// derivatives keep their digits; 2.3e-4 rad in absolute coordinates).
#[test]
fn matches_the_exact_limit() {
    let Some(ctx) = context() else { return };
    for name in [
        "embedded:mixed",
        "embedded:open",
        "embedded:creased",
        "catmark_car",
    ] {
        let m = mesh(name);
        let (surface, records) = draw(&ctx, &m, SCHEME, uniform(6.0));
        assert_matches_limit(name, &m, &surface, &records, EXACT_PASS, 1e-6, 5e-5);
    }
}

/// GPU == CPU construction (`patch::RegularPatch`) at every captured parameter.
#[test]
fn gpu_equals_cpu_construction() {
    gpu_equals_cpu_on(SCHEME, &["embedded:open", "catmark_car"], 1e-6, 1e-3);
}

/// Bitwise watertight on every edge two patches share, whole and split (level 24 > 16).
#[test]
fn watertight() {
    watertight_on(
        SCHEME,
        &[
            ("embedded:open", 5.0),
            ("catmark_car", 5.0),
            ("catmark_car", 24.0),
        ],
    );
}

/// Moving the control vertices equals rebuilding from the moved mesh, bitwise.
#[test]
fn animation_equals_rebuild() {
    animation_on(SCHEME, "catmark_car");
}

/// Coloured by patch type (regular gold, CPU-path faces purple/green).
#[test]
fn golden() {
    golden_patch_type(SCHEME, "bspline_only_mixed_patch_type");
}

/// Screen-space levels keep every patch's own triangles when one draw of the index rule would
/// pass lavapipe's 2^16 domain points (`gpu::MAX_DOMAIN_POINTS_PER_DRAW`): the 8×8 torus's 64
/// B-spline patches are one draw of the index rule (64 16-point patches), at screen-space
/// levels of about 50 (0.5 pixels per segment, 256×256) some 160,000 domain points. Its
/// triangles (the triangle capture of `render::static_draw`) must have no edge longer than 0.1
/// of the diagonal; more than 131,072 triangles (mean level above 32) make sure one draw of 64
/// patches passes 2^16 points. Before `PatchDraws::max_level` (the pass drew by the index rule
/// alone) it fails.
#[test]
fn screen_space_levels_past_one_draw_s_domain_points_keep_their_triangles() {
    let Some(ctx) = context() else { return };
    let m = torus(&[]);
    let diag = m.bbox_diagonal();
    let surface = scheme_surface(&ctx, &m, 64, SCHEME);
    let render = RenderDesc {
        tess: TessSettings {
            mode: TessMode::Adaptive,
            pixels_per_edge: 0.5,
            ..uniform(64.0)
        },
        ..RenderDesc::default()
    };
    let fixed = StaticDraw::capture(&ctx, &surface, &render, &offscreen(256, 256)).unwrap();
    let longest = longest_triangle_edge(fixed.mesh());
    eprintln!(
        "torus 8x8, screen-space 0.5 px: {} triangles, longest edge {:.4} of the diagonal",
        fixed.captured(),
        longest / diag
    );
    assert!(fixed.captured() > 131_072, "{} triangles", fixed.captured());
    assert!(
        longest <= 0.1 * diag,
        "an edge of {:.3} of the diagonal",
        longest / diag
    );
    assert_validation_clean(&ctx);
}
