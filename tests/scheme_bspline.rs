//! Conformance of the `bspline-only` scheme (copy this file for a new scheme; the checks are in
//! `tests/common/conformance.rs`): regular faces as exact bicubic B-splines.

mod common;

use common::capture::{patch_type_image, uniform};
use common::conformance::{
    assert_animation_equals_rebuild, assert_gpu_equals_cpu, assert_matches_limit,
    assert_watertight, draw,
};
use common::golden::check_golden;
use common::gpu::{assert_validation_clean, context};
use common::meshes::{mesh, osd};
use tessera::render::animate::twist;
use tessera::render::Scheme;

const SCHEME: Scheme = Scheme::BsplineOnly;
/// The pass whose patches are exact.
const EXACT_PASS: &str = "bspline";

/// Exact: every point of every B-spline patch equals the Catmull-Clark limit at the same
/// (face, u, v) within 1e-6 of the bbox diagonal and 1e-3 rad (measured: <= 2.3e-7 of the
/// diagonal; normals <= 1.1e-6 rad on the embedded meshes, 2.3e-4 rad on the car, whose f32
/// derivatives of its small faces lose digits).
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
        assert_matches_limit(name, &m, &surface, &records, EXACT_PASS, 1e-6, 1e-3);
    }
}

/// GPU == CPU construction (`patch::RegularPatch`) at every captured parameter.
#[test]
fn gpu_equals_cpu_construction() {
    let Some(ctx) = context() else { return };
    for name in ["embedded:open", "catmark_car"] {
        let m = mesh(name);
        let (surface, records) = draw(&ctx, &m, SCHEME, uniform(5.0));
        assert_gpu_equals_cpu(name, &m, &surface, &records, 1e-6, 1e-3);
    }
}

/// Bitwise watertight on every edge two patches share, whole and split (level 24 > 16).
#[test]
fn watertight() {
    let Some(ctx) = context() else { return };
    for (name, level) in [
        ("embedded:open", 5.0),
        ("catmark_car", 5.0),
        ("catmark_car", 24.0),
    ] {
        let m = mesh(name);
        let (surface, records) = draw(&ctx, &m, SCHEME, uniform(level));
        assert_watertight(&format!("{name} level {level}"), &surface, &records);
    }
}

/// Moving the control vertices equals rebuilding from the moved mesh, bitwise.
#[test]
fn animation_equals_rebuild() {
    let Some(ctx) = context() else { return };
    let m = osd("catmark_car");
    let moved = twist(m.positions(), glam::DVec3::Z, 1.5, 0.3);
    assert_animation_equals_rebuild(&ctx, "catmark_car", &m, SCHEME, &moved);
}

/// Coloured by patch type (regular gold, CPU-path faces purple/green).
#[test]
fn golden() {
    let Some(ctx) = context() else { return };
    check_golden(
        "bspline_only_mixed_patch_type",
        &patch_type_image(&ctx, &mesh("embedded:mixed"), SCHEME),
    );
    assert_validation_clean(&ctx);
}
