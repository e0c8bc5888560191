//! GPU regular-patch pipeline on synthetic all-regular meshes: TES capture against an independent
//! CPU B-spline evaluation, bitwise watertightness of shared edges, winding, validation.

mod common;

use std::collections::HashMap;

use common::capture::{capture, image, offscreen, param_key, uniform, Animation};
use common::gpu::{assert_validation_clean, context};
use common::surfaces::{eval_patch, open_grid, torus};
use common::watertight::assert_regular_watertight;
use tessera::render::{
    CaptureRecord, OffscreenDesc, RenderDesc, Spacing, SurfaceData, TessMode, TessSettings,
};

/// Captures `s` at `tess` (96 x 96) and checks the pipeline statistics: one TCS invocation per
/// (sub-)patch, one record per TES invocation.
fn capture_checked(
    ctx: &tessera::gpu::Context,
    s: &SurfaceData,
    tess: TessSettings,
) -> Vec<CaptureRecord> {
    let render = RenderDesc {
        tess,
        ..RenderDesc::default()
    };
    let c = capture(ctx, s, &render, &offscreen(96, 96), true);
    let stats = c.stats.expect("statistics");
    let split = u64::from(tess.split());
    assert_eq!(
        stats.tcs_patches,
        s.regular_patches().len() as u64 * split * split
    );
    assert_eq!(
        stats.tes_invocations,
        c.records.len() as u64,
        "one record per TES invocation"
    );
    c.records
}

/// Every record matches the CPU limit within 1e-5 of the bbox diagonal (normals within 1e-3).
fn check_accuracy(s: &SurfaceData, recs: &[CaptureRecord]) {
    let (lo, hi) = s.bounding_box();
    let diag = (hi - lo).length();
    let by_face: HashMap<u32, usize> = s
        .regular_patches()
        .iter()
        .enumerate()
        .map(|(k, p)| (p.face, k))
        .collect();
    let mut worst = 0.0f64;
    for r in recs {
        let p = &s.regular_patches()[by_face[&r.face]];
        let (pos, n) = eval_patch(p, &s.positions, f64::from(r.u), f64::from(r.v));
        let g = glam::DVec3::from(r.position.map(f64::from));
        let gn = glam::DVec3::from(r.normal.map(f64::from));
        worst = worst.max((g - pos).length() / diag);
        assert!(
            (gn - n).length() < 1e-3,
            "normal of face {} at ({}, {}): {gn} vs {n}",
            r.face,
            r.u,
            r.v
        );
    }
    assert!(
        worst < 1e-5,
        "worst position error {worst} of the bbox diagonal"
    );
}

/// Both faces of every interior edge emit the same position bits; the number of shared edges.
fn check_watertight(s: &SurfaceData, recs: &[CaptureRecord]) -> usize {
    assert_regular_watertight("regular patches", s, recs)
}

#[test]
fn torus_uniform_matches_cpu_and_is_watertight() {
    let Some(ctx) = context() else { return };
    // 160 patches: more than one draw chunk (64 patches, gpu::patch_draw_chunks), the last partial.
    let s = torus(16, 10, 2.0, 0.7);
    let level = 5.0;
    let recs = capture_checked(&ctx, &s, uniform(level));
    // Equal spacing, level 5: a (5+1)^2 grid of domain points per quad patch.
    assert_eq!(recs.len(), s.regular_patches().len() * 36);
    check_accuracy(&s, &recs);
    // Torus: every edge is shared; 2 * faces edges.
    assert_eq!(check_watertight(&s, &recs), 2 * s.regular_patches().len());
    assert_validation_clean(&ctx);
}

#[test]
fn open_grid_fractional_and_adaptive_are_watertight() {
    let Some(ctx) = context() else { return };
    let s = open_grid(5, 4);
    // (nu - 1) interior vertical lines of nv edges + (nv - 1) horizontal lines of nu edges.
    let interior_edges = 4 * 4 + 3 * 5;
    for tess in [
        TessSettings {
            level: 4.3,
            spacing: Spacing::FractionalOdd,
            ..TessSettings::default()
        },
        TessSettings {
            level: 3.7,
            spacing: Spacing::FractionalEven,
            ..TessSettings::default()
        },
        // Split patches: 4x4 sub-patches of fractional level 7 / 4 each.
        TessSettings {
            level: 7.0,
            spacing: Spacing::FractionalOdd,
            max_patch_level: 2.0,
            ..TessSettings::default()
        },
        TessSettings {
            mode: TessMode::Adaptive,
            pixels_per_edge: 6.0,
            spacing: Spacing::FractionalOdd,
            ..TessSettings::default()
        },
        TessSettings {
            mode: TessMode::Adaptive,
            pixels_per_edge: 5.0,
            spacing: Spacing::Equal,
            ..TessSettings::default()
        },
    ] {
        let recs = capture_checked(&ctx, &s, tess);
        check_accuracy(&s, &recs);
        assert_eq!(check_watertight(&s, &recs), interior_edges, "{tess:?}");
    }
    assert_validation_clean(&ctx);
}

#[test]
fn front_faces_are_outside() {
    // On a closed surface the visible faces are front faces: culling back faces must not change
    // the picture when the TES winding and the front-face convention agree.
    let Some(ctx) = context() else { return };
    let s = torus(8, 6, 2.0, 0.7);
    let desc = offscreen(128, 96);
    let mut render = RenderDesc::default();
    render.tess.level = 4.0;
    let a = image(&ctx, &s, &render, &desc);
    render.cull_back_faces = true;
    let b = image(&ctx, &s, &render, &desc);
    let bg = a.get_pixel(0, 0).0;
    let covered = a.pixels().filter(|p| p.0 != bg).count();
    assert!(
        covered > 128 * 96 / 10,
        "torus covers only {covered} pixels"
    );
    let differing = a.pixels().zip(b.pixels()).filter(|(x, y)| x != y).count();
    assert!(
        differing * 200 < covered,
        "{differing} of {covered} pixels change with culling"
    );
    assert_validation_clean(&ctx);
}

#[test]
fn split_patches_cover_the_same_surface() {
    // Level 6 with sub-patch limit 3: every patch drawn as 2x2 sub-patches of level 3.
    let Some(ctx) = context() else { return };
    let s = torus(8, 6, 2.0, 0.7);
    let tess = TessSettings {
        level: 6.0,
        max_patch_level: 3.0,
        ..TessSettings::default()
    };
    assert_eq!(tess.split(), 2);
    let recs = capture_checked(&ctx, &s, tess);
    assert_eq!(recs.len(), s.regular_patches().len() * 4 * 16);
    // Same face (u, v) set as one patch at level 6: k/6 for k in 0..=6 (as f32).
    let mut uv: Vec<(u32, u32)> = recs
        .iter()
        .filter(|r| r.face == 0)
        .map(|r| ((r.u * 6.0).round() as u32, (r.v * 6.0).round() as u32))
        .collect();
    uv.sort_unstable();
    uv.dedup();
    assert_eq!(uv.len(), 49);
    check_accuracy(&s, &recs);
    assert_eq!(check_watertight(&s, &recs), 2 * s.regular_patches().len());
    assert_validation_clean(&ctx);
}

#[test]
fn update_positions_moves_the_surface_and_msaa_renders() {
    let Some(ctx) = context() else { return };
    let s = torus(8, 6, 2.0, 0.7);
    let samples = if ctx.info().limits.supports_samples(4) {
        4
    } else {
        1
    };
    let render = RenderDesc {
        tess: uniform(3.0),
        ..RenderDesc::default()
    };
    let desc = OffscreenDesc {
        samples,
        ..offscreen(64, 48)
    };
    let mut animation = Animation::new(&ctx, &s, &render, &desc);
    let before = animation.frame();
    // Animate: translate every control vertex; the limit surface translates with it.
    let shift = glam::DVec3::new(0.5, -1.0, 2.0);
    let moved: Vec<_> = s.positions.iter().map(|p| *p + shift).collect();
    animation.move_to(&moved).unwrap();
    let after = animation.frame();
    assert_eq!(before.len(), after.len());
    let mut a: Vec<_> = before.iter().map(|r| (param_key(r), r.position)).collect();
    let mut b: Vec<_> = after.iter().map(|r| (param_key(r), r.position)).collect();
    a.sort_by_key(|x| x.0);
    b.sort_by_key(|x| x.0);
    for ((ka, pa), (kb, pb)) in a.iter().zip(&b) {
        assert_eq!(ka, kb);
        let d = glam::Vec3::from(*pb) - glam::Vec3::from(*pa) - shift.as_vec3();
        assert!(
            d.length() < 1e-5,
            "face {} moved by {d} more than the shift",
            ka.0
        );
    }
    let mut s2 = s.clone();
    s2.positions = moved;
    check_accuracy(&s2, &after);
    assert!(animation.move_to(&s.positions[1..]).is_err());
    let img = animation.image();
    assert_eq!(img.dimensions(), (64, 48));
    assert_validation_clean(&ctx);
}

/// An infinitely sharp crease between two rows of regular patches: both sides mirror their own
/// phantom points, yet the crease curve (the cubic B-spline of the crease polygon, shared data)
/// must come out bitwise identical from both sides.
#[test]
fn infinitely_sharp_crease_between_regular_patches_is_watertight() {
    use glam::DVec3;
    use tessera::mesh::{ControlMesh, ControlMeshDesc, Crease, INFINITE_SHARPNESS};
    let Some(ctx) = context() else { return };
    let n = 6u32;
    let id = |i: u32, j: u32| j * (n + 1) + i;
    let mut positions = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (f64::from(i) * 0.37, f64::from(j) * 0.41);
            positions.push(DVec3::new(
                x,
                y,
                // Rows of very different magnitude on the two sides of the crease, so that a
                // side's own mirrored phantom (2a - b) does not cancel exactly.
                0.2 * (1.3 * x).sin()
                    + 0.15 * (0.9 * y).cos()
                    + 0.03 * f64::from((i * 7 + j * 3) % 5)
                    + if i == 3 { 1e-3 * y } else { 0.0 }
                    + 3.1 * (f64::from(i) - 3.0).abs().powi(2) * if i > 3 { 17.3 } else { 0.011 },
            ));
        }
    }
    let mut face_vertices = Vec::new();
    for j in 0..n {
        for i in 0..n {
            face_vertices.extend([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let creases = (0..n)
        .map(|j| Crease {
            v0: id(3, j),
            v1: id(3, j + 1),
            sharpness: INFINITE_SHARPNESS,
        })
        .collect();
    let mesh = ControlMesh::new(ControlMeshDesc {
        positions,
        face_sizes: vec![4; (n * n) as usize],
        face_vertices,
        creases,
        ..Default::default()
    })
    .unwrap();
    let s = tessera::render::surface_from_mesh(&mesh, 4).unwrap();
    // The crease is bounded by regular patches on both sides (rows away from the grid boundary).
    let crease_faces = s
        .regular_patches()
        .iter()
        .filter(|p| {
            let c = p.corners();
            c.iter().filter(|&&v| v % (n + 1) == 3).count() == 2
        })
        .count();
    assert!(
        crease_faces >= 8,
        "{crease_faces} regular faces along the crease"
    );
    for level in [4.0, 5.0] {
        let recs = capture_checked(&ctx, &s, uniform(level));
        check_accuracy(&s, &recs);
        assert!(check_watertight(&s, &recs) > 0);
    }
    assert_validation_clean(&ctx);
}
