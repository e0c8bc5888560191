//! GPU regular-patch pipeline on synthetic all-regular meshes: TES capture against an independent
//! CPU B-spline evaluation, bitwise watertightness of shared edges, winding, validation.

mod render_common;

use std::collections::HashMap;

use render_common::{assert_validation_clean, context, eval_patch, open_grid, torus};
use tessera::render::capture_capacity_for;
use tessera::render::{
    render_to_image, CaptureRecord, OffscreenDesc, OffscreenSession, RenderDesc, Spacing,
    SurfaceData, TessMode, TessSettings,
};

fn capture(ctx: &tessera::gpu::Context, s: &SurfaceData, tess: TessSettings) -> Vec<CaptureRecord> {
    let cap = if tess.mode == TessMode::Adaptive {
        capture_capacity_for(
            s.regular_patches().len(),
            &TessSettings {
                level: 64.0,
                spacing: Spacing::FractionalEven,
                max_patch_level: f32::INFINITY,
                ..tess
            },
        )
    } else {
        capture_capacity_for(s.regular_patches().len(), &tess)
    };
    let render = RenderDesc {
        tess,
        capture_capacity: Some(cap),
        ..RenderDesc::default()
    };
    let desc = OffscreenDesc {
        width: 96,
        height: 96,
        ..OffscreenDesc::default()
    };
    let out = render_to_image(ctx, s, &render, &desc, true).expect("render");
    let recs = out.capture.expect("capture");
    let stats = out.report.expect("report").patch_stats;
    let split = u64::from(tess.split());
    assert_eq!(
        stats.tcs_patches,
        s.regular_patches().len() as u64 * split * split
    );
    assert_eq!(
        stats.tes_invocations,
        recs.len() as u64,
        "one record per TES invocation"
    );
    recs
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

/// A mesh edge as (smaller vertex id, larger vertex id).
type EdgeKey = (u32, u32);

/// Groups edge points by mesh edge; both faces of every interior edge must emit the same set of
/// bit patterns. Returns the number of shared edges checked.
fn check_watertight(s: &SurfaceData, recs: &[CaptureRecord]) -> usize {
    let by_face: HashMap<u32, usize> = s
        .regular_patches()
        .iter()
        .enumerate()
        .map(|(k, p)| (p.face, k))
        .collect();
    // (edge key, face) -> sorted bit patterns
    let mut sets: HashMap<(EdgeKey, u32), Vec<[u32; 3]>> = HashMap::new();
    for r in recs {
        let c = s.regular_patches()[by_face[&r.face]].corners();
        let mut edges = Vec::new();
        if r.v == 0.0 {
            edges.push((c[0], c[1]));
        }
        if r.u == 1.0 {
            edges.push((c[1], c[2]));
        }
        if r.v == 1.0 {
            edges.push((c[3], c[2]));
        }
        if r.u == 0.0 {
            edges.push((c[0], c[3]));
        }
        for (a, b) in edges {
            let key = (a.min(b), a.max(b));
            sets.entry((key, r.face))
                .or_default()
                .push(r.position.map(f32::to_bits));
        }
    }
    let mut per_edge: HashMap<(u32, u32), Vec<Vec<[u32; 3]>>> = HashMap::new();
    for ((key, _face), mut pts) in sets {
        pts.sort_unstable();
        pts.dedup();
        per_edge.entry(key).or_default().push(pts);
    }
    let mut shared = 0;
    for (key, sides) in per_edge {
        if sides.len() == 2 {
            shared += 1;
            assert_eq!(
                sides[0].len(),
                sides[1].len(),
                "edge {key:?}: point counts differ"
            );
            assert!(
                sides[0] == sides[1],
                "edge {key:?}: positions not bitwise identical"
            );
        }
    }
    shared
}

#[test]
fn torus_uniform_matches_cpu_and_is_watertight() {
    let Some(ctx) = context() else { return };
    // 160 patches: more than one draw chunk (64 patches, gpu::patch_draw_chunks), the last partial.
    let s = torus(16, 10, 2.0, 0.7);
    let level = 5.0;
    let recs = capture(
        &ctx,
        &s,
        TessSettings {
            level,
            ..TessSettings::default()
        },
    );
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
        let recs = capture(&ctx, &s, tess);
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
    let desc = OffscreenDesc {
        width: 128,
        height: 96,
        ..OffscreenDesc::default()
    };
    let mut render = RenderDesc::default();
    render.tess.level = 4.0;
    let a = render_to_image(&ctx, &s, &render, &desc, false)
        .unwrap()
        .image;
    render.cull_back_faces = true;
    let b = render_to_image(&ctx, &s, &render, &desc, false)
        .unwrap()
        .image;
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
    let recs = capture(&ctx, &s, tess);
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
    let tess = TessSettings {
        level: 3.0,
        ..TessSettings::default()
    };
    let samples = if ctx.info().limits.supports_samples(4) {
        4
    } else {
        1
    };
    let render = RenderDesc {
        tess,
        capture_capacity: Some(capture_capacity_for(s.regular_patches().len(), &tess)),
        ..RenderDesc::default()
    };
    let desc = OffscreenDesc {
        width: 64,
        height: 48,
        samples,
        ..OffscreenDesc::default()
    };
    let mut session = OffscreenSession::new(&ctx, &s, &render, &desc, false).unwrap();
    session.frame().unwrap();
    let before = session.capture().unwrap();
    // Animate: translate every control vertex; the limit surface translates with it.
    let shift = glam::DVec3::new(0.5, -1.0, 2.0);
    let moved: Vec<_> = s.positions.iter().map(|p| *p + shift).collect();
    session
        .renderer_mut()
        .update_positions(&moved, None)
        .unwrap();
    session.frame().unwrap();
    let after = session.capture().unwrap();
    assert_eq!(before.len(), after.len());
    let key = |r: &CaptureRecord| (r.face, r.u.to_bits(), r.v.to_bits());
    let mut a: Vec<_> = before.iter().map(|r| (key(r), r.position)).collect();
    let mut b: Vec<_> = after.iter().map(|r| (key(r), r.position)).collect();
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
    assert!(session
        .renderer_mut()
        .update_positions(&s.positions[1..], None)
        .is_err());
    let img = session.image().unwrap();
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
        let recs = capture(
            &ctx,
            &s,
            TessSettings {
                level,
                ..TessSettings::default()
            },
        );
        check_accuracy(&s, &recs);
        assert!(check_watertight(&s, &recs) > 0);
    }
    assert_validation_clean(&ctx);
}
