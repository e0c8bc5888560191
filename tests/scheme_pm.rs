//! Conformance of `--scheme pm` (Pm-patches, Myles, Ni, Peters 2008; stencil variant) and
//! `--scheme pm-vs` (vertex-stage variant): every
//! captured TES point equals the CPU construction `patch::pm` at its captured parameters
//! (ordinary and polar facets in the face's domain, Pm sectors as `f:k` with the sector's
//! barycentric weights), the points of every patch kind are bitwise watertight (positions and,
//! the surface being G1, normals) at uniform, fractional and screen-space levels, animation
//! equals a rebuild, refused facets are named, and the patch-type golden.

mod common;

use std::collections::{BTreeSet, HashMap};

use common::capture::{image, patch_type_image, uniform, watertight_settings, Animation};
use common::capture::{offscreen, scheme_surface};
use common::conformance::draw;
use common::golden::check_golden;
use common::gpu::{assert_validation_clean, context};
use common::meshes::{capsule, mesh};
use common::watertight::assert_coincident_points_equal;
use glam::DVec3;
use tessera::mesh::{ControlMesh, ObjOptions};
use tessera::patch::pm::{NotPm, PmPatch};
use tessera::render::animate::twist;
use tessera::render::schemes::pm::{class_code, kind_name, reference_sample, PmTables};
use tessera::render::schemes::pm_vs::PmVsTables;
use tessera::render::{
    plan_for_scheme, CameraSpec, CaptureRecord, ColorBy, OffscreenDesc, RefusalReason, RenderDesc,
    Scheme, SchemeLimits, SurfaceData,
};

const SCHEME: Scheme = Scheme::Pm;
/// Both construction variants (the stencil rows and the vertex stage + TCS assembly).
const SCHEMES: [Scheme; 2] = [Scheme::Pm, Scheme::PmVs];

/// Closed tri/quad/pent meshes: all-quad (ordinary patches), triangles and quads, the mixed
/// mesh with its pentagon, and polar capsules.
fn meshes() -> Vec<(String, ControlMesh)> {
    let mut out: Vec<(String, ControlMesh)> = [
        "catmark_cube",
        "catmark_pyramid",
        "catmark_torus",
        "catmark_toroidal_tet",
        "embedded:mixed",
    ]
    .iter()
    .map(|n| (n.to_string(), mesh(n)))
    .collect();
    for n in [3, 6] {
        out.push((format!("capsule{n}"), capsule(n, 3)));
    }
    out
}

/// The Pm tables of either variant's part.
fn tables(surface: &SurfaceData) -> &PmTables {
    if let Some(p) = surface.part("pm-vs") {
        return &p
            .as_any()
            .downcast_ref::<PmVsTables>()
            .expect("pm-vs tables")
            .pm;
    }
    surface
        .part("pm")
        .expect("pm draws")
        .as_any()
        .downcast_ref::<PmTables>()
        .expect("pm tables")
}

/// A hexagon capped by a fan of triangles (the hexagon is refused, the triangles drawn).
fn hexagon_mesh() -> ControlMesh {
    ControlMesh::from_obj_str(
        "v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 0\nv 0 2 0\nv -1 1 0\nv 0.5 1 1\n\
         f 1 2 3 4 5 6\nf 2 1 7\nf 3 2 7\nf 4 3 7\nf 5 4 7\nf 6 5 7\nf 1 6 7\n",
        "hex",
        &ObjOptions::default(),
    )
    .unwrap()
}

/// GPU == CPU: every captured point within 1e-6 of the bbox diagonal of `patch::pm` at its
/// captured parameters, every normal (interior, edges, corners, centres, poles) within 1e-4 rad
/// (1e-3 on the bishop's small faces);
/// each point tagged with its facet's class. Every patch kind occurs.
#[test]
fn gpu_equals_cpu_construction() {
    let Some(ctx) = context() else { return };
    let mut kinds = BTreeSet::new();
    let mut cases = meshes();
    cases.push(("catmark_bishop".into(), mesh("catmark_bishop")));
    // Crease tags become crease scalars (eq. 14) on the GPU as on the CPU.
    cases.push((
        "catmark_torus_creases0".into(),
        mesh("catmark_torus_creases0"),
    ));
    for ((name, m), scheme) in cases
        .iter()
        .flat_map(|c| SCHEMES.iter().map(move |&s| (c, s)))
    {
        let name = format!("{name} {}", scheme.name());
        let (surface, records) = draw(&ctx, m, scheme, uniform(5.0));
        let t = tables(&surface);
        let patches: HashMap<u32, PmPatch> = t.patches(&surface.positions).into_iter().collect();
        let diag = m.bbox_diagonal();
        // The bishop's smallest faces are ~1e-3 of the diagonal: f32 normals there are good to
        // ~1e-4 rad (measured 1.1e-4 with its tags ignored; 6.8e-3 before the rows were summed
        // relative to a corner). Its 224 sharpness-6 tags are crease scalars a = 0.0104: the
        // patches beside them are nearly folded, their cross derivatives short, and f32 normals
        // there measure 3.0e-3 rad in both variants.
        let normal_tol = if name.starts_with("catmark_bishop") {
            5e-3
        } else {
            1e-4
        };
        let (mut worst_p, mut worst_n) = (0.0f64, 0.0f64);
        for r in &records {
            let patch = &patches[&r.face];
            let s = reference_sample(patch, r.sub_face, f64::from(r.u), f64::from(r.v));
            let p = DVec3::from(r.position.map(f64::from));
            let n = DVec3::from(r.normal.map(f64::from));
            let d = (p - s.position).length() / diag;
            let a = n.angle_between(s.normal);
            assert!(
                d <= 1e-6 && a <= normal_tol,
                "{name}: {r:?}: {d:.2e} of the diagonal, {a:.2e} rad from the CPU construction"
            );
            worst_p = worst_p.max(d);
            worst_n = worst_n.max(a);
            let class = t.class(r.face).expect("a drawn face");
            let kind = r.patch.expect("tagged").kind;
            assert_eq!(u32::from(kind), 16 + class_code(class), "{name}: {r:?}");
            kinds.insert(kind_name(kind).unwrap());
        }
        assert!(!records.is_empty(), "{name}: nothing captured");
        eprintln!(
            "{name}: {} points, {} patches: {worst_p:.2e} of the diagonal, {worst_n:.2e} rad",
            records.len(),
            t.gpu.patch_count()
        );
    }
    let all: BTreeSet<&str> = ["pm-ordinary", "pm-polar", "pm-3", "pm-4", "pm-5"].into();
    assert_eq!(kinds, all);
    assert_validation_clean(&ctx);
}

/// Bitwise watertight: every two captured points closer than 1e-6 of the diagonal (shared
/// corners, outer edges between any two patch kinds, inner spokes and centres of Pm-patches,
/// poles) have the same position bits and the same normal bits, at uniform 1, 5 and 8,
/// fractional odd 5 and even 6, screen-space and camera-distance levels (a sector's spokes take
/// the chord level of `spoke_tess_level`, which both sectors of a spoke compute alike).
#[test]
fn watertight() {
    let Some(ctx) = context() else { return };
    let mut settings = watertight_settings();
    settings.push(tessera::render::TessSettings {
        mode: tessera::render::TessMode::Distance,
        ..uniform(8.0)
    });
    let mut cases = meshes();
    cases.push(("hexagon fan".into(), hexagon_mesh()));
    cases.push((
        "catmark_cube_creases2".into(),
        mesh("catmark_cube_creases2"),
    ));
    for ((name, m), scheme) in cases
        .iter()
        .flat_map(|c| SCHEMES.iter().map(move |&s| (c, s)))
    {
        for tess in &settings {
            let (_, records) = draw(&ctx, m, scheme, *tess);
            let pairs = assert_coincident_points_equal(m, &records);
            eprintln!(
                "{name} {} {:?} {}: {pairs} coincident pairs",
                scheme.name(),
                tess.spacing,
                tess.level
            );
            assert!(pairs > 0, "{name} {tess:?}: no coincident points");
        }
    }
    assert_validation_clean(&ctx);
}

/// Sorted by face, sub-face and parameters (sectors of one face share parameters).
fn sorted(mut records: Vec<CaptureRecord>) -> Vec<CaptureRecord> {
    records.sort_by_key(|r| (r.face, r.sub_face, r.u.to_bits(), r.v.to_bits()));
    records
}

/// Moving the control vertices (only the control positions and vertex frames re-uploaded; the
/// stencil rows stay) captures bitwise what a surface built from the moved mesh captures.
#[test]
fn animation_equals_rebuild() {
    let Some(ctx) = context() else { return };
    for ((name, m), scheme) in [
        ("embedded:mixed".to_string(), mesh("embedded:mixed")),
        ("capsule5".to_string(), capsule(5, 3)),
    ]
    .iter()
    .flat_map(|c| SCHEMES.iter().map(move |&s| (c, s)))
    {
        let name = format!("{name} {}", scheme.name());
        let moved = twist(m.positions(), DVec3::Z, 1.5, 0.3);
        let render = RenderDesc {
            tess: uniform(5.0),
            ..RenderDesc::default()
        };
        let surface = scheme_surface(&ctx, m, 5, scheme);
        let mut anim = Animation::new(&ctx, &surface, &render, &offscreen(64, 64));
        let before = sorted(anim.frame());
        anim.move_to(&moved).unwrap();
        let animated = sorted(anim.frame());
        let mut moved_mesh = m.clone();
        moved_mesh.set_positions(&moved).unwrap();
        let (_, rebuilt) = draw(&ctx, &moved_mesh, scheme, uniform(5.0));
        assert!(!animated.is_empty(), "{name}: nothing captured");
        assert!(animated != before, "{name}: the twist moved nothing");
        assert!(
            animated == sorted(rebuilt),
            "{name}: the animated capture differs from a rebuilt surface"
        );
    }
    assert_validation_clean(&ctx);
}

/// A hexagon and faces on a boundary are refused by name (they stay on the exact CPU path);
/// the hexagon's neighbours are drawn.
#[test]
fn refusals_name_the_facet() {
    let hex = hexagon_mesh();
    let surface = plan_for_scheme(&hex, SCHEME, &SchemeLimits::NO_DEVICE).unwrap();
    let r: Vec<_> = surface.refusals.iter().filter(|r| r.pass == "pm").collect();
    assert_eq!(r.len(), 1, "{r:?}");
    assert_eq!(
        r[0].reason,
        RefusalReason::NotPm(NotPm::Polygon { face: 0, size: 6 })
    );
    assert!(r[0].to_string().starts_with("face 0: 6 sides"), "{}", r[0]);
    assert_eq!(tables(&surface).gpu.faces.len(), 6);

    let open = mesh("embedded:open");
    let surface = plan_for_scheme(&open, SCHEME, &SchemeLimits::NO_DEVICE).unwrap();
    let boundary: Vec<_> = surface
        .refusals
        .iter()
        .filter(|r| matches!(r.reason, RefusalReason::NotPm(NotPm::Boundary { .. })))
        .collect();
    assert!(!boundary.is_empty(), "{:?}", surface.refusals);
    let first = boundary[0].to_string();
    assert!(first.contains("is on the boundary"), "{first}");
}

/// Coloured by patch type: ordinary gold, polar blue, Pm m = 3 green, 4 purple, 5 red:
/// embedded:mixed from the default camera (polar, ordinary, m = 3, 4) and from below (the
/// pentagon, m = 5).
#[test]
fn golden() {
    let Some(ctx) = context() else { return };
    let m = mesh("embedded:mixed");
    check_golden("pm_mixed_patch_type", &patch_type_image(&ctx, &m, SCHEME));
    // The vertex-stage variant draws the same surface: the same golden.
    check_golden(
        "pm_mixed_patch_type",
        &patch_type_image(&ctx, &m, Scheme::PmVs),
    );
    let render = RenderDesc {
        tess: uniform(8.0),
        color_by: ColorBy::PatchType,
        ..RenderDesc::default()
    };
    let below = OffscreenDesc {
        camera: CameraSpec::Orbit {
            azimuth_deg: 215.0,
            elevation_deg: -25.0,
            distance: 4.0,
        },
        ..offscreen(256, 256)
    };
    let surface = scheme_surface(&ctx, &m, 8, SCHEME);
    check_golden(
        "pm_mixed_below_patch_type",
        &image(&ctx, &surface, &render, &below),
    );
    assert_validation_clean(&ctx);
}

/// Crease scalars from the mesh's tags (paper Fig. 12, the axe blade): catmark_cube_creases0's
/// two sharpness-2 edges (a = (2/3) 2^-2 = 1/6) are a sharp blade on the otherwise rounded
/// cube, shaded, level 12.
#[test]
fn crease_golden() {
    let Some(ctx) = context() else { return };
    let m = mesh("catmark_cube_creases0");
    let render = RenderDesc {
        tess: uniform(12.0),
        ..RenderDesc::default()
    };
    let surface = scheme_surface(&ctx, &m, 12, SCHEME);
    assert!(surface.fallback_faces.is_empty());
    check_golden(
        "pm_cube_creases0_blade",
        &image(&ctx, &surface, &render, &offscreen(256, 256)),
    );
    assert_validation_clean(&ctx);
}

/// Animated (`--animate`): embedded:mixed twisted about z (`render::animate::twist`, amplitude
/// 1.5, phase 0.3) after a first frame, only the control positions re-uploaded, coloured by patch
/// type at level 8; both variants draw the same golden, and the frame differs from the unmoved
/// one.
#[test]
fn animated_golden() {
    let Some(ctx) = context() else { return };
    let m = mesh("embedded:mixed");
    let render = RenderDesc {
        tess: uniform(8.0),
        color_by: ColorBy::PatchType,
        ..RenderDesc::default()
    };
    let moved = twist(m.positions(), DVec3::Z, 1.5, 0.3);
    for scheme in SCHEMES {
        let surface = scheme_surface(&ctx, &m, 8, scheme);
        let mut anim = Animation::new(&ctx, &surface, &render, &offscreen(256, 256));
        anim.frame();
        let still = anim.image();
        anim.move_to(&moved).unwrap();
        anim.frame();
        let twisted = anim.image();
        assert!(
            twisted != still,
            "{}: the twist changed nothing",
            scheme.name()
        );
        check_golden("pm_mixed_animated_patch_type", &twisted);
    }
    assert_validation_clean(&ctx);
}
