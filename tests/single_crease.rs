//! Single-crease patches (Nießner, Loop, Greiner 2012) against the exact limit: every face
//! `SingleCreasePatch::gather` accepts evaluates equal to `LimitEvaluator::eval`, and the
//! eligibility rule refuses what the curve case does not cover.

mod common;

use common::crease_grid::{face, grid, line, Edge, N};
use common::meshes::osd;
use glam::DVec3;
use tessera::mesh::INFINITE_SHARPNESS;
use tessera::patch::adaptive::{AdaptiveSurface, PatchShape};
use tessera::patch::basis::{bernstein, bernstein_deriv, eval_tensor};
use tessera::patch::single_crease::{CreaseSide, SingleCreasePatch};
use tessera::subdiv::adaptive::{
    AdaptiveOptions, AdaptiveRefinement, Domain, PatchCensus, PatchType,
};
use tessera::subdiv::eval::LimitEvaluator;
use tessera::subdiv::Level;
use tessera::topology::Topology;
use tessera::ControlMesh;

fn accepted(mesh: &ControlMesh) -> Vec<SingleCreasePatch> {
    let topo = Topology::new(mesh).unwrap();
    (0..mesh.face_count() as u32)
        .filter_map(|f| SingleCreasePatch::gather(&topo, f))
        .collect()
}

/// Worst position error (relative to the bbox diagonal) and normal angle (rad) of every accepted
/// patch against the exact limit on a 9×9 grid of `(u, v)`; also checks the Bézier sets.
fn worst(mesh: &ControlMesh, patches: &[SingleCreasePatch]) -> (f64, f64) {
    let eval = LimitEvaluator::new(mesh).unwrap();
    let pos = mesh.positions();
    let (lo, hi) = pos
        .iter()
        .fold((pos[0], pos[0]), |(a, b), &p| (a.min(p), b.max(p)));
    let diag = (hi - lo).length();
    let (mut dp, mut dn) = (0.0f64, 0.0f64);
    for p in patches {
        let sets = p.bezier_sets(pos);
        assert!((2..=3).contains(&sets.len()));
        let uv: Vec<(f64, f64)> = (0..81)
            .map(|k| ((k % 9) as f64 / 8.0, (k / 9) as f64 / 8.0))
            .collect();
        let exact = eval.eval_points(p.face as usize, 0, &uv).unwrap();
        for (&(u, v), e) in uv.iter().zip(&exact) {
            let s = p.eval(pos, u, v);
            dp = dp.max((s.position - e.position).length() / diag);
            dn = dn.max(
                s.normal
                    .cross(e.normal)
                    .length()
                    .atan2(s.normal.dot(e.normal)),
            );
            let b = bezier_eval(&sets, u, v);
            assert!(
                (b - s.position).length() < 1e-9 * diag,
                "Bézier set at {u}, {v}"
            );
        }
    }
    (dp, dn)
}

/// Evaluates the Bézier set covering `(u, v)` at its local parameters.
fn bezier_eval(sets: &[tessera::patch::single_crease::BezierSet], u: f64, v: f64) -> DVec3 {
    let x = if sets[0].across_u { u } else { v };
    let set = sets
        .iter()
        .find(|s| x <= s.range.1)
        .unwrap_or(&sets[sets.len() - 1]);
    let l = (x - set.range.0) / (set.range.1 - set.range.0);
    let (bu, bv) = if set.across_u { (l, v) } else { (u, l) };
    let (p, _, _) = eval_tensor(
        &set.points,
        &bernstein(bu),
        &bernstein_deriv(bu),
        &bernstein(bv),
        &bernstein_deriv(bv),
    );
    p
}

fn check(name: &str, mesh: &ControlMesh, patches: &[SingleCreasePatch]) {
    let (dp, dn) = worst(mesh, patches);
    println!(
        "{name}: {} patches, position {dp:.2e} diag, normal {dn:.2e} rad",
        patches.len()
    );
    assert!(dp <= 1e-9, "{name}: position {dp:e}");
    assert!(dn <= 1e-7, "{name}: normal {dn:e}");
}

#[test]
fn grid_with_one_crease_line_is_exact() {
    for s in [0.3f32, 1.0, 1.7, 2.0, 2.5, 4.5, 9.9] {
        let mesh = grid(&line(|_| s));
        let patches = accepted(&mesh);
        // Faces on both sides of the line, rows 1..=6 (the corners of rows 0 and 7 are on the
        // boundary): crease on their u = 1 / u = 0 edge.
        let mut expect: Vec<(u32, CreaseSide)> = (1..N - 1)
            .flat_map(|j| [(face(3, j), CreaseSide::U1), (face(4, j), CreaseSide::U0)])
            .collect();
        expect.sort();
        let mut got: Vec<(u32, CreaseSide)> = patches.iter().map(|p| (p.face, p.side)).collect();
        got.sort();
        assert_eq!(got, expect, "s = {s}");
        assert!(patches.iter().all(|p| p.sharpness == s));
        check(&format!("grid s = {s}"), &mesh, &patches);
    }
}

#[test]
fn crease_across_v_is_exact() {
    // The same line along a row: the crease lies on the faces' v edges.
    let cs: Vec<_> = (0..N).map(|i| ((i, 4), (i + 1, 4), 2.5f32)).collect();
    let mesh = grid(&cs);
    let patches = accepted(&mesh);
    assert_eq!(patches.len(), 12);
    assert!(patches
        .iter()
        .all(|p| matches!(p.side, CreaseSide::V0 | CreaseSide::V1)));
    check("grid, row crease", &mesh, &patches);
}

#[test]
fn varying_sharpness_along_the_line() {
    let s = |j: usize| if j < 4 { 1.0 } else { 2.5 };
    let mesh = grid(&line(s));
    let topo = Topology::new(&mesh).unwrap();
    for j in 1..N - 1 {
        // Face row j sees line edges j - 1, j, j + 1.
        let uniform = s(j - 1) == s(j) && s(j) == s(j + 1);
        for i in [3, 4] {
            let got = SingleCreasePatch::gather(&topo, face(i, j));
            assert_eq!(got.is_some(), uniform, "face ({i}, {j})");
        }
    }
    check("grid, varying sharpness", &mesh, &accepted(&mesh));
}

#[test]
fn refusals() {
    let refused = |cs: &[Edge], f: u32| {
        let mesh = grid(cs);
        SingleCreasePatch::gather(&Topology::new(&mesh).unwrap(), f).is_none()
    };
    let base = line(|_| 2.0);
    // Two crease lines through one face (columns 3 and 4).
    let mut two = base.clone();
    two.extend((0..N).map(|j| ((3, j), (3, j + 1), 2.0)));
    assert!(refused(&two, face(3, 3)));
    // L-shape: the line plus a row edge at a corner.
    let mut l = base.clone();
    l.push(((3, 3), (4, 3), 2.0));
    assert!(refused(&l, face(3, 3)));
    // A crease ending inside the net (only two of the three line edges sharp).
    let short: Vec<_> = base.iter().copied().filter(|e| e.0 .1 != 4).collect();
    assert!(refused(&short, face(3, 3)));
    // Infinitely sharp.
    assert!(refused(&line(|_| INFINITE_SHARPNESS), face(3, 3)));
    // No crease: a plain regular patch.
    assert!(refused(&[], face(3, 3)));
    // A boundary corner.
    assert!(refused(&base, face(3, 0)));
    // The crease on the outer ring only (column 4 seen from face column 2): not a feature of
    // the face.
    assert!(refused(&base, face(2, 3)));
    // Sanity: the face itself is accepted.
    assert!(!refused(&base, face(3, 3)));
}

#[test]
fn osd_meshes() {
    for name in ["catmark_single_crease", "catmark_cube_creases0"] {
        let mesh = osd(name);
        let patches = accepted(&mesh);
        check(name, &mesh, &patches);
    }
}

/// Single-crease patches inside feature-adaptive refinement (`AdaptiveOptions::single_crease`):
/// every `PatchType::SingleCrease` patch of the `AdaptiveSurface`, evaluated with its full
/// sharpness over its level's refined points, equals the exact limit at the same base `(u, v)`
/// (9×9 samples of its own `(s, t)` mapped by its domain; 1e-9 of the bbox diagonal). The
/// surface is built from the census directly when an end cap touching a semi-sharp edge makes
/// `AdaptiveSurface::new` refuse (the car below isolation 6).
#[test]
fn adaptive_single_crease_patches_are_exact() {
    let cases = [
        ("catmark_single_crease", 1..=4),
        ("catmark_cube_creases0", 1..=4),
        ("catmark_cube_creases1", 1..=4),
        ("catmark_car", 1..=4),
        ("catmark_torus_creases0", 1..=2),
        ("catmark_tent_creases0", 2..=3),
    ];
    let mut via_surface = 0;
    for (name, levels) in cases {
        let mesh = osd(name);
        let eval = LimitEvaluator::new(&mesh).unwrap();
        let diag = mesh.bbox_diagonal();
        let mut total = 0;
        for isolation in levels {
            let options = AdaptiveOptions {
                single_crease: true,
                ..AdaptiveOptions::new(isolation)
            };
            let r = AdaptiveRefinement::with_options(&Level::from_mesh(&mesh).unwrap(), options)
                .unwrap();
            let surface = AdaptiveSurface::new(&r, mesh.positions());
            via_surface += surface.is_ok() as usize;
            // (domain, index in the surface, patch)
            let patches: Vec<(Domain, Option<usize>, SingleCreasePatch)> = match &surface {
                Ok(s) => s
                    .patches
                    .iter()
                    .enumerate()
                    .filter(|(_, p)| p.kind == PatchType::SingleCrease)
                    .map(|(i, p)| match p.shape {
                        PatchShape::SingleCrease(c) => (p.domain, Some(i), c),
                        _ => panic!("{name}: a single-crease patch of another shape"),
                    })
                    .collect(),
                Err(_) => PatchCensus::new(&r)
                    .patches
                    .iter()
                    .filter_map(|p| {
                        let c = p.crease?;
                        let d = r.levels[p.level as usize].domains[p.face as usize];
                        Some((d, None, SingleCreasePatch::from_line(p.face, c)))
                    })
                    .collect(),
            };
            total += patches.len();
            let positions = r.refine_positions(mesh.positions());
            let mut worst = 0.0f64;
            for (d, i, p) in &patches {
                let st: Vec<(f64, f64)> = (0..81)
                    .map(|k| ((k % 9) as f64 / 8.0, (k / 9) as f64 / 8.0))
                    .collect();
                let uv: Vec<(f64, f64)> = st
                    .iter()
                    .map(|&(a, b)| {
                        let x = d.origin + a * d.u + b * d.v;
                        (x.x, x.y)
                    })
                    .collect();
                let sub = d.sub_face.unwrap_or(0) as usize;
                let exact = eval.eval_points(d.base_face as usize, sub, &uv).unwrap();
                for (&(a, b), e) in st.iter().zip(&exact) {
                    let got = match (&surface, i) {
                        (Ok(s), Some(i)) => s.eval_patch(*i, a, b).position,
                        _ => p.eval(&positions, a, b).position,
                    };
                    worst = worst.max((got - e.position).length() / diag);
                }
            }
            println!(
                "{name} iso {isolation}: {} single-crease patches, worst {worst:.2e} diag",
                patches.len()
            );
            assert!(worst <= 1e-9, "{name} iso {isolation}: {worst:e}");
        }
        // catmark_cube_creases0's sharpness-2 creases end at valence-3 corners: at level 1
        // every face touches one, and at level 2 the creases are smooth.
        assert_eq!(
            total > 0,
            name != "catmark_cube_creases0",
            "{name}: {total}"
        );
    }
    // The torus (no end caps) and the tent at isolation 2 and 3 (no end caps) go through
    // `AdaptiveSurface::eval_patch`'s single-crease branch.
    assert!(via_surface >= 4, "{via_surface}");
}
