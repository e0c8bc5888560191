//! Conformance of the `gregory-vs` scheme: regular faces as exact B-splines, irregular
//! triangles and quads as Gregory patches (Loop, Schaefer, Ni, Castaño 2009) built by the
//! two-stage construction (vertex shader + TCS, §4.1-4.2). Checks in `tests/common/conformance.rs`.

mod common;

use common::capture::{patch_type_image, uniform};
use common::conformance::{
    assert_animation_equals_rebuild, assert_gpu_equals_cpu, assert_matches_limit,
    assert_watertight, draw,
};
use common::golden::check_golden;
use common::gpu::{assert_validation_clean, context};
use common::meshes::{mesh, osd};
use tessera::render::accuracy::measure_gpu;
use tessera::render::animate::twist;
use tessera::render::Scheme;

const SCHEME: Scheme = Scheme::GregoryVs;

/// Regular faces exact (1e-6 of the diagonal, 1e-3 rad; measured 4.9e-8, 6.5e-7 rad); Gregory
/// faces no less accurate than measured against the exact limit by closest point at the TES
/// points of level 8 (`tessera error embedded:mixed --scheme gregory-* --grid 8`: RMS 6.32e-4,
/// max 6.76e-3 of the diagonal, RMS normal 2.14e-2 rad, before and after the scheme
/// architecture; the CPU construction's grid gives the README's 5.67e-4).
#[test]
fn accuracy_against_the_exact_limit() {
    let Some(ctx) = context() else { return };
    let m = mesh("embedded:mixed");
    let (surface, records) = draw(&ctx, &m, SCHEME, uniform(6.0));
    assert_matches_limit("mixed", &m, &surface, &records, "bspline", 1e-6, 1e-3);
    let r = measure_gpu(&ctx, &m, SCHEME, 8).unwrap();
    assert_eq!(r.faces, 23, "Gregory faces of embedded:mixed");
    assert!(
        r.rms_distance <= 6.5e-4,
        "RMS distance {:e}",
        r.rms_distance
    );
    assert!(r.max_distance <= 7e-3, "max distance {:e}", r.max_distance);
    assert!(r.rms_normal <= 2.2e-2, "RMS normal {:e}", r.rms_normal);
    assert_validation_clean(&ctx);
}

/// GPU == CPU construction (`patch::gregory`, `patch::RegularPatch`) at every captured
/// parameter: 1e-6 of the diagonal, interior normals 1e-3 rad.
#[test]
fn gpu_equals_cpu_construction() {
    let Some(ctx) = context() else { return };
    for name in ["embedded:mixed", "embedded:open", "catmark_car"] {
        let m = mesh(name);
        let (surface, records) = draw(&ctx, &m, SCHEME, uniform(5.0));
        assert_gpu_equals_cpu(name, &m, &surface, &records, 1e-6, 1e-3);
    }
}

/// Bitwise watertight on every edge two GPU patches share (Gregory/Gregory, Gregory/B-spline,
/// B-spline/B-spline), whole and split into sub-patches (level 24).
#[test]
fn watertight() {
    let Some(ctx) = context() else { return };
    for (name, level) in [
        ("embedded:mixed", 5.0),
        ("embedded:open", 7.0),
        ("catmark_car", 5.0),
        ("embedded:mixed", 24.0),
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

/// Coloured by patch type (regular gold, Gregory quads purple, triangles green; the paper's
/// Fig. 1).
#[test]
fn golden() {
    let Some(ctx) = context() else { return };
    check_golden(
        "gregory_vs_mixed_patch_type",
        &patch_type_image(&ctx, &mesh("embedded:mixed"), SCHEME),
    );
    assert_validation_clean(&ctx);
}
