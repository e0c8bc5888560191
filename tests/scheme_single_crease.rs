//! Conformance of the single-crease pass (Nießner, Loop, Greiner 2012) in the Gregory schemes:
//! regular quads with one semi-sharp crease line drawn as single-crease patches, exact against
//! the Catmull-Clark limit and their CPU construction (`SingleCreasePatch::eval`), bitwise
//! watertight with their neighbours (single-crease, B-spline, Gregory), sharpness changed at run
//! time, golden image, animation, validation clean (checks in `tests/common/conformance.rs`).

mod common;

use std::collections::BTreeSet;

use common::capture::{offscreen, patch_type_image, scheme_surface, sorted, uniform, Animation};
use common::conformance::{
    assert_animation_equals_rebuild, assert_gpu_equals_cpu, assert_matches_limit,
    assert_watertight, draw, Worst,
};
use common::crease_grid::{face, grid, grid_split, idx, line, torus, torus_idx, N};
use common::golden::check_golden;
use common::gpu::{assert_validation_clean, context};
use common::meshes::osd;
use glam::DVec3;
use tessera::gpu::Context;
use tessera::mesh::{ControlMesh, Crease};
use tessera::patch::single_crease::SingleCreasePatch;
use tessera::render::animate::twist;
use tessera::render::{RenderDesc, Scheme, SurfaceData};
use tessera::subdiv::eval::LimitEvaluator;
use tessera::topology::Topology;

const PASS: &str = "single-crease";
/// The sharpness values of the issue: fractional below 1, integer, fractional above 1, large.
const SHARPNESS: [f32; 7] = [0.3, 1.0, 1.7, 2.0, 2.5, 4.5, 9.9];
/// Position tolerance (fraction of the bbox diagonal) and normal tolerance (rad), f32 GPU.
const POS_TOL: f64 = 1e-6;
const NORMAL_TOL: f64 = 1e-5;

/// The faces the single-crease pass draws.
fn drawn(surface: &SurfaceData) -> BTreeSet<u32> {
    surface
        .part(PASS)
        .map_or_else(BTreeSet::new, |p| p.faces().iter().copied().collect())
}

/// Draws `m` with `scheme` at level 6 and checks the single-crease points against the exact limit
/// and the CPU construction; returns both worst errors.
fn exact(
    ctx: &Context,
    what: &str,
    m: &ControlMesh,
    scheme: Scheme,
) -> (SurfaceData, Worst, Worst) {
    exact_within(ctx, what, m, scheme, NORMAL_TOL, NORMAL_TOL)
}

/// [`exact`] with normal tolerances `limit_tol` (single-crease points against the limit) and
/// `cpu_tol` (every GPU point against its pass's CPU construction).
fn exact_within(
    ctx: &Context,
    what: &str,
    m: &ControlMesh,
    scheme: Scheme,
    limit_tol: f64,
    cpu_tol: f64,
) -> (SurfaceData, Worst, Worst) {
    let (surface, records) = draw(ctx, m, scheme, uniform(6.0));
    let limit = assert_matches_limit(what, m, &surface, &records, PASS, POS_TOL, limit_tol);
    let cpu = assert_gpu_equals_cpu(what, m, &surface, &records, POS_TOL, cpu_tol);
    (surface, limit, cpu)
}

fn worse(a: Worst, b: Worst) -> Worst {
    Worst {
        position: a.position.max(b.position),
        normal: a.normal.max(b.normal),
    }
}

/// Exact: every captured point of a single-crease patch equals the exact limit
/// (`LimitEvaluator`) and `SingleCreasePatch::eval` at the same (face, u, v) within 1e-6 of the
/// bbox diagonal and 1e-5 rad, for every sharpness of the issue, on the open grid (rows 1-6 on
/// both sides of the line; rows 0 and 7 have boundary corners) and the torus (the whole loop).
/// Measured over both: <= 2.0e-7 of the diagonal, <= 3.7e-6 rad against the limit.
#[test]
fn exact_for_every_sharpness() {
    let Some(ctx) = context() else { return };
    let mut all = Worst::default();
    for s in SHARPNESS {
        let m = grid(&line(|_| s));
        let (surface, limit, cpu) =
            exact(&ctx, &format!("grid s = {s}"), &m, Scheme::GregoryStencil);
        let expect: BTreeSet<u32> = (1..N - 1).flat_map(|j| [face(3, j), face(4, j)]).collect();
        assert_eq!(drawn(&surface), expect, "grid s = {s}");
        all = worse(all, worse(limit, cpu));
        let m = torus(&line(|_| s));
        let (surface, limit, cpu) =
            exact(&ctx, &format!("torus s = {s}"), &m, Scheme::GregoryStencil);
        let expect: BTreeSet<u32> = (0..N).flat_map(|j| [face(3, j), face(4, j)]).collect();
        assert_eq!(drawn(&surface), expect, "torus s = {s}");
        all = worse(all, worse(limit, cpu));
    }
    eprintln!("single-crease, every sharpness: {all:?}");
    // The other scheme with the pass.
    exact(
        &ctx,
        "grid s = 2.5 (gregory-vs)",
        &grid(&line(|_| 2.5)),
        Scheme::GregoryVs,
    );
    assert_validation_clean(&ctx);
}

/// The OpenSubdiv shapes: `catmark_single_crease` (crease lines of sharpness 0.2 to 10 over a
/// grid), the car and `embedded:creased` are exact where the pass takes them, normals within
/// 1e-5 rad on the car too (measured: <= 8.6e-8 of the diagonal, <= 1.0e-6 rad on
/// catmark_single_crease; car 1.6e-7, 3.4e-6 rad, which is what rounding the car's control
/// points to f32 alone moves the exact normals there: 3.4e-6 rad); the creased cubes have only
/// valence-3 corners, so no face is a single-crease patch (they stay on the CPU path).
#[test]
fn osd_meshes() {
    let Some(ctx) = context() else { return };
    // The GPU == CPU check covers every pass: the car's Gregory normals are 1.1e-5 rad from
    // their f64 construction (tests/render_gregory_stencil.rs).
    for (name, cpu_tol) in [
        ("catmark_single_crease", NORMAL_TOL),
        ("catmark_car", 3e-5),
        ("embedded:creased", NORMAL_TOL),
    ] {
        let m = common::meshes::mesh(name);
        let (surface, limit, cpu) =
            exact_within(&ctx, name, &m, Scheme::GregoryStencil, NORMAL_TOL, cpu_tol);
        eprintln!(
            "{name}: {} single-crease faces, {} CPU-path faces; {limit:?} {cpu:?}",
            drawn(&surface).len(),
            surface.fallback_faces.len()
        );
        assert!(!drawn(&surface).is_empty());
    }
    for name in ["catmark_cube_creases0", "catmark_cube_creases1"] {
        let m = osd(name);
        let topo = Topology::new(&m).unwrap();
        assert!((0..m.face_count() as u32).all(|f| SingleCreasePatch::gather(&topo, f).is_none()));
        let (surface, _) = draw(&ctx, &m, Scheme::GregoryStencil, uniform(4.0));
        assert!(drawn(&surface).is_empty(), "{name}");
    }
    assert_validation_clean(&ctx);
}

/// A line whose sharpness changes along it (1 on rows 0-3, 2.5 on rows 4-7): a face sees the
/// three line edges at its corners, so rows 1, 2, 5, 6 are single-crease patches and rows 3, 4
/// (whose corner edges have both values) are not. The decision is checked against the exact
/// refinement on both sides of the boundary: the accepted rows next to it are exact on the GPU,
/// and the refused rows are not single-crease surfaces of either sharpness (the construction
/// with 1 or with 2.5 misses the limit by far more than the tolerance).
#[test]
fn varying_sharpness_eligibility() {
    let Some(ctx) = context() else { return };
    let s = |j: usize| if j < 4 { 1.0 } else { 2.5 };
    let m = grid(&line(s));
    let (surface, limit, _) = exact(&ctx, "varying sharpness", &m, Scheme::GregoryStencil);
    let expect: BTreeSet<u32> = [1, 2, 5, 6]
        .into_iter()
        .flat_map(|j| [face(3, j), face(4, j)])
        .collect();
    assert_eq!(drawn(&surface), expect);
    eprintln!("varying sharpness, accepted rows: {limit:?}");
    let topo = Topology::new(&m).unwrap();
    let ev = LimitEvaluator::new(&m).unwrap();
    let diag = m.bbox_diagonal();
    for j in [3, 4] {
        for i in [3, 4] {
            let f = face(i, j);
            // The patch the face would be with one sharpness (taken from the same face on a
            // uniform line).
            let uniform = grid(&line(|_| 1.0));
            let base = SingleCreasePatch::gather(&Topology::new(&uniform).unwrap(), f).unwrap();
            assert!(SingleCreasePatch::gather(&topo, f).is_none());
            for guess in [1.0f32, 2.5] {
                let p = SingleCreasePatch {
                    sharpness: guess,
                    ..base
                };
                let worst = (0..=8)
                    .flat_map(|a| (0..=8).map(move |b| (a as f64 / 8.0, b as f64 / 8.0)))
                    .map(|(u, v)| {
                        let e = ev.eval(f as usize, 0, u, v).unwrap().position;
                        (p.eval(m.positions(), u, v).position - e).length() / diag
                    })
                    .fold(0.0, f64::max);
                eprintln!("face ({i}, {j}) as s = {guess}: {worst:.2e} of the diagonal");
                assert!(worst > 1e-4, "face ({i}, {j}) with s = {guess}: {worst:e}");
            }
        }
    }
    assert_validation_clean(&ctx);
}

/// The face in the split grid with corner `(i, j)` at its corner 0 (faces after the split shift).
fn quad_at(m: &ControlMesh, i: usize, j: usize) -> u32 {
    (0..m.face_count() as u32)
        .find(|&f| {
            m.face_size(f as usize) == 4
                && Topology::new(m).unwrap().face_vertices(f)[0] == idx(i, j)
        })
        .unwrap()
}

/// An extraordinary vertex next to eligible faces: face (1, 4) cut into two triangles gives
/// vertex (2, 4) valence 5, so faces (2, 3) and (2, 4) are Gregory patches sharing their
/// (3, 3)-(3, 4)-(3, 5) edges with the single-crease patches of column 3 (their edges away from
/// the crease). The single-crease patches stay exact; the shared edges are bitwise watertight.
#[test]
fn extraordinary_vertex_next_to_an_eligible_face() {
    let Some(ctx) = context() else { return };
    let m = grid_split(&line(|_| 1.7), Some((1, 4)));
    for scheme in [Scheme::GregoryStencil, Scheme::GregoryVs] {
        let (surface, _, _) = exact(&ctx, &format!("split grid ({scheme})"), &m, scheme);
        let sc = drawn(&surface);
        for j in [3, 4] {
            assert!(
                sc.contains(&quad_at(&m, 3, j)),
                "face (3, {j}) single-crease"
            );
            let g = quad_at(&m, 2, j);
            assert!(!sc.contains(&g) && surface.irregular_gpu_faces().contains(&g));
        }
        let (surface, records) = draw(&ctx, &m, scheme, uniform(5.0));
        assert_watertight(&format!("split grid ({scheme})"), &surface, &records);
    }
    assert_validation_clean(&ctx);
}

/// Bitwise watertight on every edge two GPU patches share (single-crease/single-crease across
/// and along the crease, single-crease/B-spline, single-crease/Gregory), whole and split into
/// sub-patches (level 24).
#[test]
fn watertight() {
    let Some(ctx) = context() else { return };
    let cases = [
        ("grid s = 2.5", grid(&line(|_| 2.5))),
        ("torus s = 0.3", torus(&line(|_| 0.3))),
        ("torus s = 9.9", torus(&line(|_| 9.9))),
        (
            "row crease s = 1.7",
            grid(
                &(0..N)
                    .map(|i| ((i, 4), (i + 1, 4), 1.7))
                    .collect::<Vec<_>>(),
            ),
        ),
        ("catmark_single_crease", osd("catmark_single_crease")),
        ("catmark_car", osd("catmark_car")),
        ("embedded:creased", common::meshes::mesh("embedded:creased")),
    ];
    for (name, m) in &cases {
        for level in [5.0, 24.0] {
            let (surface, records) = draw(&ctx, m, Scheme::GregoryStencil, uniform(level));
            assert!(!drawn(&surface).is_empty());
            let edges = assert_watertight(&format!("{name} level {level}"), &surface, &records);
            eprintln!("{name} level {level}: {edges} shared edges bitwise equal");
        }
    }
}

/// The crease line i = 4 (8 edges) of sharpness `s`, vertex ids by `vid`.
fn column_creases(vid: impl Fn(usize, usize) -> u32, s: f32) -> Vec<Crease> {
    (0..N)
        .map(|j| Crease {
            v0: vid(4, j),
            v1: vid(4, j + 1),
            sharpness: s,
        })
        .collect()
}

/// The crease loop of the torus (8 edges, every face along it a single-crease patch).
fn loop_creases(s: f32) -> Vec<Crease> {
    column_creases(torus_idx, s)
}

/// Sharpness is data: changing the torus's crease loop from 1 to 4.5 (and on to 0.3) at run time
/// captures bitwise what a surface planned from the mesh with the new sharpness captures; changes
/// the patches cannot follow are refused with the reason, changing nothing.
#[test]
fn set_sharpness_at_run_time() {
    let Some(ctx) = context() else { return };
    let m = torus(&line(|_| 1.0));
    let tess = uniform(5.0);
    let render = RenderDesc {
        tess,
        ..RenderDesc::default()
    };
    let surface = scheme_surface(&ctx, &m, 5, Scheme::GregoryStencil);
    let mut anim = Animation::new(&ctx, &surface, &render, &offscreen(64, 64));
    let before = sorted(anim.frame());
    for s in [4.5f32, 0.3] {
        anim.set_sharpness(&loop_creases(s)).unwrap();
        let changed = sorted(anim.frame());
        let (_, rebuilt) = draw(&ctx, &torus(&line(|_| s)), Scheme::GregoryStencil, tess);
        assert!(
            changed == sorted(rebuilt),
            "s = {s}: differs from a rebuilt surface"
        );
        assert!(changed != before);
    }
    let mut err = |creases: &[Crease]| anim.set_sharpness(creases).unwrap_err().to_string();
    // One edge of the loop alone: its faces would see two sharpness values.
    let e = err(&loop_creases(2.0)[..1]);
    assert!(e.contains("one sharpness"), "{e}");
    // Smooth or infinitely sharp: other patch types.
    for s in [0.0, 10.0, f32::NAN] {
        let e = err(&loop_creases(s));
        assert!(e.contains("outside 0 < s < 10"), "{e}");
    }
    // A smooth corner edge of a patch (a second crease).
    let e = err(&[Crease {
        v0: torus_idx(4, 2),
        v1: torus_idx(5, 2),
        sharpness: 1.0,
    }]);
    assert!(e.contains("smooth corner edge"), "{e}");
    // Not a mesh edge.
    let e = err(&[Crease {
        v0: torus_idx(0, 0),
        v1: torus_idx(4, 4),
        sharpness: 1.0,
    }]);
    assert!(e.contains("not a mesh edge"), "{e}");
    // Refused changes changed nothing: still the s = 0.3 surface.
    let (_, rebuilt) = draw(&ctx, &torus(&line(|_| 0.3)), Scheme::GregoryStencil, tess);
    assert!(sorted(anim.frame()) == sorted(rebuilt));
    // On the open grid the line's end faces are on the CPU path, which bakes the sharpness in.
    let g = grid(&line(|_| 1.0));
    let surface = scheme_surface(&ctx, &g, 5, Scheme::GregoryStencil);
    let mut anim = Animation::new(&ctx, &surface, &render, &offscreen(64, 64));
    let all = column_creases(idx, 2.0);
    let e = anim.set_sharpness(&all).unwrap_err().to_string();
    assert!(e.contains("not a single-crease patch"), "{e}");
    assert_validation_clean(&ctx);
}

/// Moving the control vertices equals rebuilding from the moved mesh, bitwise.
#[test]
fn animation_equals_rebuild() {
    let Some(ctx) = context() else { return };
    let m = torus(&line(|_| 2.5));
    let moved = twist(m.positions(), DVec3::Z, 1.5, 0.3);
    assert_animation_equals_rebuild(&ctx, "torus", &m, Scheme::GregoryStencil, &moved);
}

/// Coloured by patch type: the split grid with its crease line (regular gold, single-crease
/// teal, Gregory quads purple, triangles green).
#[test]
fn golden() {
    let Some(ctx) = context() else { return };
    let m = grid_split(&line(|_| 2.5), Some((1, 4)));
    check_golden(
        "single_crease_patch_type",
        &patch_type_image(&ctx, &m, Scheme::GregoryStencil),
    );
    assert_validation_clean(&ctx);
}

/// How many faces leave the CPU path with the pass: planned with and without it (the registry
/// line minus `single-crease`), on the car and the other shapes with semi-sharp creases.
#[test]
fn faces_leaving_the_cpu_path() {
    use tessera::render::schemes::{bspline::BSPLINE, gregory_stencil::GREGORY_STENCIL};
    use tessera::render::{plan_for_scheme, plan_passes, PlanOptions, SchemeLimits};
    let Some(ctx) = context() else { return };
    let limits = SchemeLimits::from_context(&ctx);
    for (name, expect) in [
        ("catmark_car", 188),
        ("catmark_single_crease", 32),
        ("embedded:creased", 6),
    ] {
        let m = common::meshes::mesh(name);
        let with = plan_for_scheme(&m, Scheme::GregoryStencil, &limits).unwrap();
        let without =
            plan_passes(&m, &[&BSPLINE, &GREGORY_STENCIL], &PlanOptions::new(limits)).unwrap();
        let taken = drawn(&with).len();
        eprintln!(
            "{name}: {taken} single-crease faces; CPU path {} -> {}",
            without.fallback_faces.len(),
            with.fallback_faces.len()
        );
        assert_eq!(taken, expect, "{name}");
        assert_eq!(
            without.fallback_faces.len() - with.fallback_faces.len(),
            taken
        );
    }
}

/// Sharpness is data in the adaptive scheme too, where the new refinement keeps the layout of
/// the old: the torus's crease loop (every face a single-crease patch, nothing refined) from 1
/// to 4.5 and 0.3, and the open grid's line (its ends refined around the crease-end vertices,
/// to a depth set by the integer part) from 2.2 to 2.7 (new kernel weights and stencil rows):
/// each captures bitwise what a surface planned from the mesh with the new sharpness captures.
/// A change that refines other faces (2.7 to 3.5) or touches a boundary edge is refused with
/// the reason, changing nothing.
#[test]
fn adaptive_set_sharpness_at_run_time() {
    let Some(ctx) = context() else { return };
    let tess = uniform(5.0);
    let render = RenderDesc {
        tess,
        ..RenderDesc::default()
    };
    let rebuilt = |m: &ControlMesh| sorted(draw(&ctx, m, Scheme::Adaptive, tess).1);
    let surface = scheme_surface(&ctx, &torus(&line(|_| 1.0)), 5, Scheme::Adaptive);
    let mut anim = Animation::new(&ctx, &surface, &render, &offscreen(64, 64));
    let before = sorted(anim.frame());
    for s in [4.5f32, 0.3] {
        anim.set_sharpness(&loop_creases(s)).unwrap();
        let changed = sorted(anim.frame());
        assert!(changed == rebuilt(&torus(&line(|_| s))), "torus s = {s}");
        assert!(changed != before);
    }
    let line_creases = |s: f32| column_creases(idx, s);
    let surface = scheme_surface(&ctx, &grid(&line(|_| 2.2)), 5, Scheme::Adaptive);
    let mut anim = Animation::new(&ctx, &surface, &render, &offscreen(64, 64));
    let before = sorted(anim.frame());
    anim.set_sharpness(&line_creases(2.7)).unwrap();
    let changed = sorted(anim.frame());
    assert!(changed == rebuilt(&grid(&line(|_| 2.7))), "grid 2.2 -> 2.7");
    assert!(changed != before);
    let e = anim
        .set_sharpness(&line_creases(3.5))
        .unwrap_err()
        .to_string();
    assert!(e.contains("changes the adaptive refinement"), "{e}");
    let e = anim
        .set_sharpness(&[Crease {
            v0: idx(0, 0),
            v1: idx(1, 0),
            sharpness: 1.0,
        }])
        .unwrap_err()
        .to_string();
    assert!(e.contains("boundary edge"), "{e}");
    assert!(
        sorted(anim.frame()) == changed,
        "a refused change changed the surface"
    );
    assert_validation_clean(&ctx);
}
