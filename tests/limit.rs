//! Independent checks of the limit masks and the exact limit evaluator: hand-evaluated
//! B-splines, the sharpness rules' linearity, symmetry, and convergence of uniform refinement.

mod common;

use common::meshes::{corpus_options, osd, osd_names, osd_path};
use common::reference::bspline_basis;
use glam::DVec3;
use tessera::mesh::{BoundaryInterpolation, ControlMeshDesc, Corner, Crease, SchemeOptions};
use tessera::subdiv::eval::LimitEvaluator;
use tessera::subdiv::limit::{limit_normals, limit_positions, limit_stencil_tables};
use tessera::subdiv::Level;
use tessera::{ControlMesh, Error};

// ---------- helpers -------------------------------------------------------------------------

/// The cubic B-spline curve of `p` at `t` (basis written independently of
/// `tessera::patch::basis`).
fn hand_curve(p: [DVec3; 4], t: f64) -> DVec3 {
    let b = bspline_basis(t);
    (0..4).map(|i| b[i] * p[i]).sum()
}

fn hand_patch(p: &[[DVec3; 4]; 4], u: f64, v: f64) -> DVec3 {
    let bu = bspline_basis(u);
    let bv = bspline_basis(v);
    let mut s = DVec3::ZERO;
    for (j, row) in p.iter().enumerate() {
        for (i, x) in row.iter().enumerate() {
            s += bu[i] * bv[j] * *x;
        }
    }
    s
}

/// A `w x h` quad grid (vertices `(w+1) x (h+1)`, vertex `(i, j)` has index `j*(w+1)+i`), with
/// heights from `z(i, j)`.
fn grid_desc(w: usize, h: usize, z: impl Fn(usize, usize) -> f64) -> ControlMeshDesc {
    let mut d = ControlMeshDesc::default();
    for j in 0..=h {
        for i in 0..=w {
            d.positions.push(DVec3::new(i as f64, j as f64, z(i, j)));
        }
    }
    let id = |i: usize, j: usize| (j * (w + 1) + i) as u32;
    for j in 0..h {
        for i in 0..w {
            d.face_sizes.push(4);
            d.face_vertices
                .extend([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    d
}

fn bumpy(i: usize, j: usize) -> f64 {
    let (x, y) = (i as f64, j as f64);
    (0.7 * x).sin() + 0.5 * (1.3 * y).cos() + 0.1 * x * y
}

/// Uniform refinement `levels` times: every level (base first) and the last level's positions.
fn refine(mesh: &ControlMesh, levels: u32) -> (Vec<Level>, Vec<DVec3>) {
    let mut chain = vec![Level::from_mesh(mesh).unwrap()];
    let mut pos = mesh.positions().to_vec();
    for _ in 0..levels {
        let (child, m) = chain.last().unwrap().refine();
        pos = m.apply_vec(&pos);
        chain.push(child);
    }
    (chain, pos)
}

/// The level-`levels` vertex at parameter `(i, j) / 2^l` of base face `f` (`l = levels` for a
/// quad; for a non-quad, sub-face `sub` and `l = levels - 1`), following the contract's child
/// numbering: child `k` of a quad covers the quarter at corner `k`, its corner 0 at the parent's
/// corner `k` and its `(1, 0)` at the midpoint of edge `k -> k+1`.
fn refined_vertex(chain: &[Level], f: u32, sub: u32, i: u64, j: u64) -> u32 {
    let (face, corner) = refined_corner(chain, f, sub, i, j);
    chain[chain.len() - 1].topology().face_vertices(face)[corner]
}

/// The last-level face and its corner at parameter `(i, j) / 2^l` (see [`refined_vertex`]).
fn refined_corner(chain: &[Level], f: u32, sub: u32, i: u64, j: u64) -> (u32, usize) {
    let levels = (chain.len() - 1) as u32;
    let mut depth = 0;
    let mut face = f;
    let mut rem = levels;
    if chain[0].topology().face_size(f) != 4 {
        face = chain[0].child_faces(f).start + sub;
        depth += 1;
        rem -= 1;
    }
    let (mut a, mut b) = (i, j);
    while rem > 0 {
        let full = 1u64 << rem;
        let half = full / 2;
        let (k, na, nb) = match (a <= half, b <= half) {
            (true, true) => (0, a, b),
            (false, true) => (1, b, full - a),
            (false, false) => (2, full - a, full - b),
            (true, false) => (3, full - b, a),
        };
        face = chain[depth].child_faces(face).start + k;
        depth += 1;
        rem -= 1;
        a = na;
        b = nb;
    }
    let corner = match (a, b) {
        (0, 0) => 0,
        (1, 0) => 1,
        (1, 1) => 2,
        (0, 1) => 3,
        _ => panic!("not a corner"),
    };
    (face, corner)
}

/// Unit normal of a refined quad from its diagonals, `(p2 - p0) x (p3 - p1)`: robust at any
/// corner angle (valence-2 corners are flat).
fn corner_normal(level: &Level, pos: &[DVec3], face: u32, _corner: usize) -> DVec3 {
    let fv = level.topology().face_vertices(face);
    let p = |k: usize| pos[fv[k] as usize];
    (p(2) - p(0)).cross(p(3) - p(1)).normalize()
}

fn close(a: DVec3, b: DVec3, tol: f64) -> bool {
    (a - b).length() <= tol
}

// ---------- regular B-spline regions --------------------------------------------------------

#[test]
fn regular_grid_reproduces_hand_bspline() {
    let (w, h) = (7, 6);
    let mesh = ControlMesh::new(grid_desc(w, h, bumpy)).unwrap();
    let ev = LimitEvaluator::new(&mesh).unwrap();
    let p = |i: usize, j: usize| mesh.positions()[j * (w + 1) + i];
    for fj in 1..h - 1 {
        for fi in 1..w - 1 {
            let f = fj * w + fi;
            let mut cvs = [[DVec3::ZERO; 4]; 4];
            for (r, row) in cvs.iter_mut().enumerate() {
                for (c, x) in row.iter_mut().enumerate() {
                    *x = p(fi + c - 1, fj + r - 1);
                }
            }
            for (u, v) in [(0.0, 0.0), (0.25, 0.5), (1.0, 0.3), (0.6, 1.0), (0.9, 0.1)] {
                let s = ev.eval(f, 0, u, v).unwrap();
                assert!(close(s.position, hand_patch(&cvs, u, v), 1e-12));
                // Partials against central differences of the hand patch.
                let e = 1e-6;
                let du = (hand_patch(&cvs, u + e, v) - hand_patch(&cvs, u - e, v)) / (2.0 * e);
                let dv = (hand_patch(&cvs, u, v + e) - hand_patch(&cvs, u, v - e)) / (2.0 * e);
                assert!(close(s.du, du, 1e-7) && close(s.dv, dv, 1e-7));
                assert!((s.normal.length() - 1.0).abs() < 1e-12);
                assert!(s.normal.dot(du.cross(dv)) > 0.0);
            }
        }
    }
}

#[test]
fn cylinder_regular_region_reproduces_hand_bspline() {
    // A closed ring of 8 x 6 quads around the z axis: every vertex away from the two boundary
    // rings is regular.
    let (n, h) = (8usize, 6usize);
    let mut d = ControlMeshDesc::default();
    for j in 0..=h {
        for i in 0..n {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            d.positions.push(DVec3::new(
                a.cos(),
                a.sin(),
                j as f64 * 0.4 + 0.05 * (i * i) as f64,
            ));
        }
    }
    let id = |i: usize, j: usize| (j * n + i % n) as u32;
    for j in 0..h {
        for i in 0..n {
            d.face_sizes.push(4);
            d.face_vertices
                .extend([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let mesh = ControlMesh::new(d).unwrap();
    let ev = LimitEvaluator::new(&mesh).unwrap();
    let p = |i: usize, j: usize| mesh.positions()[id(i, j) as usize];
    for fj in 1..h - 1 {
        for fi in 0..n {
            let mut cvs = [[DVec3::ZERO; 4]; 4];
            for (r, row) in cvs.iter_mut().enumerate() {
                for (c, x) in row.iter_mut().enumerate() {
                    *x = p(fi + n + c - 1, fj + r - 1);
                }
            }
            for (u, v) in [(0.0, 0.0), (0.5, 0.5), (0.2, 0.9)] {
                let s = ev.eval(fj * n + fi, 0, u, v).unwrap();
                assert!(close(s.position, hand_patch(&cvs, u, v), 1e-12));
                // Outward: away from the axis.
                let radial = DVec3::new(s.position.x, s.position.y, 0.0);
                assert!(s.normal.dot(radial) > 0.0);
            }
        }
    }
}

// ---------- boundaries and creases ----------------------------------------------------------

#[test]
fn boundary_curve_is_bspline_of_boundary_polygon() {
    let (w, h) = (7, 5);
    let mesh = ControlMesh::new(grid_desc(w, h, bumpy)).unwrap();
    let ev = LimitEvaluator::new(&mesh).unwrap();
    let p = |i: usize, j: usize| mesh.positions()[j * (w + 1) + i];
    // Bottom row faces (v = 0 on the boundary), away from the corners.
    for fi in 1..w - 1 {
        let poly = [p(fi - 1, 0), p(fi, 0), p(fi + 1, 0), p(fi + 2, 0)];
        for t in [0.0, 0.3, 0.5, 1.0] {
            let s = ev.eval(fi, 0, t, 0.0).unwrap();
            assert!(
                close(s.position, hand_curve(poly, t), 1e-12),
                "face {fi} t {t}"
            );
        }
    }
    // Left column faces (u = 0 on the boundary): the curve runs along v.
    for fj in 1..h - 1 {
        let poly = [p(0, fj - 1), p(0, fj), p(0, fj + 1), p(0, fj + 2)];
        for t in [0.0, 0.7, 1.0] {
            let s = ev.eval(fj * w, 0, 0.0, t).unwrap();
            assert!(close(s.position, hand_curve(poly, t), 1e-12));
        }
    }
}

#[test]
fn boundary_regular_faces_agree_with_deep_refinement() {
    let (w, h) = (5, 4);
    let mesh = ControlMesh::new(grid_desc(w, h, bumpy)).unwrap();
    let ev = LimitEvaluator::new(&mesh).unwrap();
    let levels = 6;
    let (chain, pos) = refine(&mesh, levels);
    let lim = limit_positions(chain.last().unwrap(), &pos).unwrap();
    let normals = limit_normals(chain.last().unwrap(), &pos).unwrap();
    let diag = mesh.bbox_diagonal();
    let n = 1u64 << levels;
    // Boundary faces, including the corner faces (corner rule). The evaluator takes the
    // phantom-point B-spline path here; the limit masks (crease / corner eigen-analysis) of the
    // level-6 vertices must give the same points and normals.
    for f in [0u32, 1, 2, (w - 1) as u32, (w * h - 1) as u32, w as u32] {
        for (i, j) in [(0, 0), (n, 0), (n / 2, 0), (n / 4, n / 2), (n, n), (3, 7)] {
            let vtx = refined_vertex(&chain, f, 0, i, j) as usize;
            let s = ev
                .eval(f as usize, 0, i as f64 / n as f64, j as f64 / n as f64)
                .unwrap();
            assert!(close(pos[vtx], s.position, 1e-3 * diag));
            assert!(
                close(lim[vtx], s.position, 1e-9 * diag),
                "face {f} ({i},{j}): {:?} vs {:?}",
                lim[vtx],
                s.position
            );
            assert!(
                normals[vtx].dot(s.normal) > 1.0 - 1e-12,
                "face {f} ({i},{j}): normal {:?} vs {:?}",
                normals[vtx],
                s.normal
            );
        }
    }
}

/// A 6 x 6 grid with a crease along the row of vertices j = 3 (all six edges), bumpy heights.
fn creased_grid(sharpness: Option<f32>) -> ControlMesh {
    let (w, h) = (6, 6);
    let mut d = grid_desc(w, h, bumpy);
    if let Some(s) = sharpness {
        for i in 0..w {
            let a = (3 * (w + 1) + i) as u32;
            d.creases.push(Crease {
                v0: a,
                v1: a + 1,
                sharpness: s,
            });
        }
    }
    ControlMesh::new(d).unwrap()
}

#[test]
fn infinite_crease_is_bspline_of_crease_polygon() {
    let mesh = creased_grid(Some(10.0));
    let ev = LimitEvaluator::new(&mesh).unwrap();
    let w = 6;
    let p = |i: usize, j: usize| mesh.positions()[j * (w + 1) + i];
    for fi in 1..w - 1 {
        let poly = [p(fi - 1, 3), p(fi, 3), p(fi + 1, 3), p(fi + 2, 3)];
        for t in [0.0, 0.25, 0.5, 0.8, 1.0] {
            let curve = hand_curve(poly, t);
            // Face below the crease (its v = 1 side) and above it (its v = 0 side).
            let below = ev.eval(2 * w + fi, 0, t, 1.0).unwrap();
            let above = ev.eval(3 * w + fi, 0, t, 0.0).unwrap();
            assert!(close(below.position, curve, 1e-12));
            assert!(close(above.position, curve, 1e-12));
        }
    }
}

#[test]
fn zero_sharpness_equals_smooth() {
    let smooth = LimitEvaluator::new(&creased_grid(None)).unwrap();
    let zero = LimitEvaluator::new(&creased_grid(Some(0.0))).unwrap();
    for f in 0..36 {
        for (u, v) in [(0.0, 0.0), (0.3, 0.6), (1.0, 1.0), (0.5, 0.0)] {
            let a = smooth.eval(f, 0, u, v).unwrap();
            let b = zero.eval(f, 0, u, v).unwrap();
            assert!(close(a.position, b.position, 1e-14));
            assert!(close(a.normal, b.normal, 1e-12));
        }
    }
}

/// With sharpness `s` in `(0, 1)` the first step blends the sharp and smooth rules with weight
/// `s` and later steps are smooth, so the limit is `s L(1) + (1 - s) L(0)`; for `s` in `(1, 2)`
/// the first step is sharp and the second blends: `(s - 1) L(2) + (2 - s) L(1)`.
#[test]
fn fractional_sharpness_interpolates_integer_neighbours() {
    let ev = |s: f32| LimitEvaluator::new(&creased_grid(Some(s))).unwrap();
    let (e0, e1, e2) = (ev(0.0), ev(1.0), ev(2.0));
    // Sharpness is f32: the blend weights are the f32 values.
    let (s1, s2) = (0.3f32, 1.6f32);
    let (w1, w2) = (s1 as f64, s2 as f64 - 1.0);
    let (e03, e16) = (ev(s1), ev(s2));
    let mut moved = 0.0f64;
    for f in [13usize, 14, 15, 19, 20, 21, 8, 27] {
        for (u, v) in [(0.0, 0.0), (0.3, 0.6), (1.0, 1.0), (0.5, 0.0), (0.7, 0.9)] {
            let l = |e: &LimitEvaluator| e.eval(f, 0, u, v).unwrap().position;
            let expect = w1 * l(&e1) + (1.0 - w1) * l(&e0);
            assert!(close(l(&e03), expect, 1e-11), "s=0.3 face {f} ({u},{v})");
            let expect = w2 * l(&e2) + (1.0 - w2) * l(&e1);
            assert!(close(l(&e16), expect, 1e-11), "s=1.6 face {f} ({u},{v})");
            moved = moved.max((l(&e1) - l(&e0)).length());
        }
    }
    // The creases do change the surface (the test is not vacuous).
    assert!(moved > 1e-3);
}

// ---------- symmetry ------------------------------------------------------------------------

fn symmetric_samples(mesh: &ControlMesh, mirror: impl Fn(DVec3) -> DVec3, n: usize) {
    let ev = LimitEvaluator::new(mesh).unwrap();
    let grids = ev.eval_all_grids(n).unwrap();
    let all: Vec<_> = grids.into_iter().flatten().flatten().collect();
    assert!(!all.is_empty());
    let diag = mesh.bbox_diagonal();
    for s in &all {
        let mp = mirror(s.sample.position);
        let mn = mirror(s.sample.normal);
        let best = all
            .iter()
            .min_by(|a, b| {
                let da = (a.sample.position - mp).length();
                let db = (b.sample.position - mp).length();
                da.total_cmp(&db)
            })
            .unwrap();
        assert!(close(best.sample.position, mp, 1e-9 * diag));
        assert!(
            close(best.sample.normal, mn, 1e-7),
            "{:?} vs {:?}",
            best.sample.normal,
            mn
        );
    }
}

#[test]
fn cube_limit_is_symmetric_and_outward() {
    let mesh = osd("catmark_cube");
    // The cube is centred at the origin: mirror in x, and in the plane x = y.
    symmetric_samples(&mesh, |p| DVec3::new(-p.x, p.y, p.z), 4);
    symmetric_samples(&mesh, |p| DVec3::new(p.y, p.x, p.z), 4);
    let ev = LimitEvaluator::new(&mesh).unwrap();
    for f in 0..6 {
        for g in ev.eval_grid(f, 4).unwrap() {
            assert!(
                g.sample.normal.dot(g.sample.position) > 0.0,
                "normal points inward"
            );
        }
        // At a corner vertex (valence 3) the normal is along the position by symmetry.
        let c = ev.eval(f, 0, 0.0, 0.0).unwrap();
        assert!(close(c.normal, c.position.normalize(), 1e-6)); // file coordinates round sqrt(2)
    }
}

#[test]
fn pyramid_with_triangles_is_symmetric() {
    // Square base (quad) and four triangles, apex above the centre; symmetric under x -> -x.
    let d = ControlMeshDesc {
        positions: vec![
            DVec3::new(-1.0, -1.0, 0.0),
            DVec3::new(1.0, -1.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(-1.0, 1.0, 0.0),
            DVec3::new(0.0, 0.0, 1.5),
        ],
        face_sizes: vec![4, 3, 3, 3, 3],
        face_vertices: vec![3, 2, 1, 0, 0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4],
        ..Default::default()
    };
    let mesh = ControlMesh::new(d).unwrap();
    symmetric_samples(&mesh, |p| DVec3::new(-p.x, p.y, p.z), 4);
    symmetric_samples(&mesh, |p| DVec3::new(p.y, p.x, p.z), 4);
}

// ---------- convergence of refinement to the limit ------------------------------------------

/// Level-`levels` vertices approach the evaluator (< 1e-3 of the diagonal) and the limit masks of the
/// level-6 vertices agree with it to 1e-6.
fn converges(mesh: &ControlMesh, faces: &[usize], levels: u32) {
    let ev = LimitEvaluator::new(mesh).unwrap();
    let (chain, pos) = refine(mesh, levels);
    let lim = limit_positions(chain.last().unwrap(), &pos).unwrap();
    let diag = mesh.bbox_diagonal();
    let (mut worst_ref, mut worst_lim, mut worst_normal) = (0.0f64, 0.0f64, 1.0f64);
    for &f in faces {
        if !ev.has_limit_surface(f) {
            continue;
        }
        let quad = mesh.face_size(f) == 4;
        let subs = if quad { 1 } else { mesh.face_size(f) };
        let l = if quad { levels } else { levels - 1 };
        let n = 1u64 << l;
        for sub in 0..subs {
            for (i, j) in [
                (0, 0),
                (n, 0),
                (n, n),
                (0, n),
                (1, 0),
                (1, 1),
                (n / 2, n / 4),
                (3, n - 5),
                (n / 2, n / 2),
            ] {
                let (face6, corner) = refined_corner(&chain, f as u32, sub as u32, i, j);
                let last = chain.last().unwrap();
                let vtx = last.topology().face_vertices(face6)[corner] as usize;
                let s = ev
                    .eval(f, sub, i as f64 / n as f64, j as f64 / n as f64)
                    .unwrap();
                let rn = corner_normal(last, &pos, face6, corner);
                // At a vertex the refined corner normal is only a rough estimate (it converges
                // slowly at extraordinary, corner-tagged and semi-sharp vertices): check the
                // orientation there and the direction elsewhere.
                let near = |x: u64| x.min(n - x) < 4;
                let at_vertex = near(i) && near(j);
                if at_vertex {
                    assert!(rn.dot(s.normal) > 0.0, "face {f} ({i},{j}): normal flipped");
                } else if rn.dot(s.normal) < 0.99 {
                    panic!(
                        "face {f} sub {sub} ({i},{j}): normal {:?} vs refined {rn:?}",
                        s.normal
                    );
                } else {
                    worst_normal = worst_normal.min(rn.dot(s.normal));
                }
                worst_ref = worst_ref.max((pos[vtx] - s.position).length() / diag);
                worst_lim = worst_lim.max((lim[vtx] - s.position).length() / diag);
            }
        }
    }
    eprintln!(
        "level-{levels} points off by {worst_ref:e}, limit masks by {worst_lim:e}, min normal cosine {worst_normal}"
    );
    // Orientation and direction of the normal against the refined mesh's corner normal.
    assert!(worst_normal > 0.99, "normal cosine {worst_normal}");
    assert!(worst_ref < 1e-3, "level-{levels} points off by {worst_ref}");
    assert!(
        worst_lim < 1e-6,
        "level-{levels} limit masks off by {worst_lim}"
    );
}

#[test]
fn cube_refinement_converges_to_limit() {
    converges(&osd("catmark_cube"), &[0, 1, 2, 3, 4, 5], 6);
}

#[test]
fn creases_and_corners_converge_to_limit() {
    // Sharpness 5 leaves a single smooth step before level 6: refine deeper there.
    for (name, levels) in [
        ("catmark_cube_creases1", 8),
        ("catmark_cube_corner3", 6),
        ("catmark_cube_creases2", 6),
    ] {
        let mesh = osd(name);
        let faces: Vec<usize> = (0..mesh.face_count()).collect();
        converges(&mesh, &faces, levels);
    }
}

#[test]
fn nonquads_and_boundaries_converge_to_limit() {
    for name in [
        "catmark_pyramid",
        "catmark_nonquads",
        "catmark_edgecorner",
        "catmark_edgeonly",
        "catmark_dart_edgecorner",
        "catmark_val2_interior",
        "catmark_gregory_test8",
    ] {
        let mesh = osd(name);
        let faces: Vec<usize> = (0..mesh.face_count()).step_by(3).collect();
        converges(&mesh, &faces, 6);
    }
}

#[test]
fn semi_sharp_and_corner_tags_converge() {
    let mut d = grid_desc(5, 5, bumpy);
    d.creases = vec![
        Crease {
            v0: 7,
            v1: 8,
            sharpness: 1.5,
        },
        Crease {
            v0: 8,
            v1: 9,
            sharpness: 2.3,
        },
        Crease {
            v0: 8,
            v1: 14,
            sharpness: 0.6,
        },
        Crease {
            v0: 20,
            v1: 21,
            sharpness: 10.0,
        },
    ];
    d.corners = vec![
        Corner {
            vertex: 15,
            sharpness: 1.2,
        },
        Corner {
            vertex: 3,
            sharpness: 10.0,
        },
    ];
    d.options = SchemeOptions {
        boundary: BoundaryInterpolation::EdgeOnly,
        ..Default::default()
    };
    let mesh = ControlMesh::new(d).unwrap();
    let faces: Vec<usize> = (0..mesh.face_count()).collect();
    converges(&mesh, &faces, 6);
}

// ---------- every real mesh -----------------------------------------------------------------

#[test]
fn every_osd_mesh_evaluates() {
    let mut evaluated = 0;
    let mut skipped = Vec::new();
    for name in osd_names() {
        let mesh = match ControlMesh::from_obj_file(osd_path(&name), &corpus_options(&name)) {
            Ok(m) => m,
            Err(e) => {
                // Only non-manifold files may be refused (`nonman_*` also holds faces that repeat a vertex).
                assert!(
                    name.contains("nonman")
                        || matches!(
                            e,
                            Error::NonManifoldEdge { .. } | Error::NonManifoldVertex { .. }
                        ),
                    "{name} failed to load: {e}"
                );
                skipped.push(name);
                continue;
            }
        };
        let ev = LimitEvaluator::new(&mesh).unwrap_or_else(|e| panic!("{name}: {e}"));
        let grids = ev
            .eval_all_grids(2)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        for (f, g) in grids.iter().enumerate() {
            let Some(g) = g else { continue };
            for s in g {
                let x = s.sample;
                assert!(
                    x.position.is_finite() && (x.normal.length() - 1.0).abs() < 1e-9,
                    "{name} face {f}: {x:?}"
                );
            }
        }
        evaluated += 1;
    }
    eprintln!("evaluated {evaluated}, skipped (non-manifold) {skipped:?}");
    assert!(evaluated >= 70, "only {evaluated} meshes evaluated");
}

// ---------- limit stencils ------------------------------------------------------------------

/// Limit stencils over the base vertices reproduce the evaluator on a deformed copy of the mesh
/// (topology fixed, positions changed: the per-frame path).
#[test]
fn limit_stencils_follow_deformed_positions() {
    let mesh = osd("catmark_cube_creases1");
    let base = Level::from_mesh(&mesh).unwrap();
    let depth = 2;
    let tables = limit_stencil_tables(&base, depth).unwrap();
    // Deform: a twist around z.
    let moved: Vec<DVec3> = mesh
        .positions()
        .iter()
        .map(|p| {
            let a = 0.3 * p.z;
            DVec3::new(
                p.x * a.cos() - p.y * a.sin(),
                p.x * a.sin() + p.y * a.cos(),
                p.z * 1.2,
            )
        })
        .collect();
    let mut deformed = mesh.clone();
    deformed.set_positions(&moved).unwrap();
    let ev = LimitEvaluator::new(&deformed).unwrap();
    // The same evaluator obtained by moving the control points of the original one.
    let mut moved_ev = LimitEvaluator::new(&mesh).unwrap();
    moved_ev.set_positions(&moved).unwrap();
    assert!(moved_ev.set_positions(&moved[1..]).is_err());
    let pos = tables.position.apply_vec(&moved);
    let tu = tables.tangent_u.apply_vec(&moved);
    let tv = tables.tangent_v.apply_vec(&moved);
    let (chain, _) = refine(&mesh, depth);
    let last = chain.last().unwrap();
    let n = 1u64 << depth;
    let diag = deformed.bbox_diagonal();
    let mut checked = 0;
    for f in 0..mesh.face_count() {
        for (i, j) in [(0, 0), (1, 2), (n, 1), (2, 2), (3, n)] {
            let vtx = refined_vertex(&chain, f as u32, 0, i, j) as usize;
            let s = ev
                .eval(f, 0, i as f64 / n as f64, j as f64 / n as f64)
                .unwrap();
            assert!(close(pos[vtx], s.position, 1e-9 * diag));
            let m = moved_ev
                .eval(f, 0, i as f64 / n as f64, j as f64 / n as f64)
                .unwrap();
            assert_eq!(m, s);
            // The stencil normal uses the vertex's first face; compare where that face's
            // sector is the evaluated face's (smooth vertices: everywhere).
            let first = last.topology().vertex_faces(vtx as u32)[0];
            let smooth = last
                .topology()
                .vertex_edges(vtx as u32)
                .iter()
                .all(|&e| last.topology().edge_sharpness(e) == 0.0);
            if smooth || refined_corner(&chain, f as u32, 0, i, j).0 == first {
                let normal = tu[vtx].cross(tv[vtx]).normalize();
                assert!(close(normal, s.normal, 1e-7), "face {f} ({i},{j})");
                checked += 1;
            }
        }
    }
    assert!(checked > 20);
}

// ---------- watertightness across faces -----------------------------------------------------

/// Parameter of the point at fraction `t` along edge `k -> k+1` of a face with `n` corners.
fn edge_param(n: usize, k: usize, t: f64) -> (usize, f64, f64) {
    if n == 4 {
        let (u, v) = match k {
            0 => (t, 0.0),
            1 => (1.0, t),
            2 => (1.0 - t, 1.0),
            _ => (0.0, 1.0 - t),
        };
        (0, u, v)
    } else if t <= 0.5 {
        (k, 2.0 * t, 0.0)
    } else {
        ((k + 1) % n, 0.0, 2.0 * (1.0 - t))
    }
}

/// The two faces of every interior edge give the same limit points along it (different code
/// paths meet there: B-spline patches, local refinement, non-quad sub-faces), and the same
/// normals unless the edge is infinitely sharp (semi-sharp creases are smooth in the limit).
#[test]
fn adjacent_faces_agree_along_shared_edges() {
    for name in [
        "catmark_car",
        "catmark_nonquads",
        "catmark_cube_creases1",
        "catmark_pole8",
        "catmark_dart_edgeonly",
        "catmark_tent_creases1",
        "catmark_hole_test2",
        "catmark_chaikin1",
    ] {
        let mesh = osd(name);
        let ev = LimitEvaluator::new(&mesh).unwrap();
        let level = Level::from_mesh(&mesh).unwrap();
        let topo = level.topology();
        let diag = mesh.bbox_diagonal();
        let mut checked = 0;
        for e in 0..topo.edge_count() as u32 {
            let faces = topo.edge_faces(e);
            if faces.len() != 2 || !faces.iter().all(|&f| ev.has_limit_surface(f as usize)) {
                continue;
            }
            let [a, b] = topo.edge_vertices(e);
            let sharp = topo.edge_sharpness(e) >= 10.0;
            for t in [0.25, 0.5, 0.8] {
                let mut samples = Vec::new();
                for &f in faces {
                    let fv = topo.face_vertices(f);
                    let n = fv.len();
                    let k = (0..n)
                        .find(|&k| {
                            let (p, q) = (fv[k], fv[(k + 1) % n]);
                            (p, q) == (a, b) || (p, q) == (b, a)
                        })
                        .unwrap();
                    // Fraction measured from `a`.
                    let tt = if fv[k] == a { t } else { 1.0 - t };
                    let (sub, u, v) = edge_param(n, k, tt);
                    samples.push(ev.eval(f as usize, sub, u, v).unwrap());
                }
                let d = (samples[0].position - samples[1].position).length();
                assert!(d < 1e-9 * diag, "{name} edge {e} t {t}: gap {d}");
                if !sharp {
                    let c = samples[0].normal.dot(samples[1].normal);
                    assert!(c > 1.0 - 1e-9, "{name} edge {e} t {t}: normal cosine {c}");
                }
                checked += 1;
            }
        }
        assert!(checked > 0, "{name}");
        // Smooth vertices: every incident face gives the same limit point and normal.
        for v in 0..topo.vertex_count() as u32 {
            let smooth = topo.vertex_sharpness(v) == 0.0
                && !topo.is_boundary_vertex(v)
                && topo
                    .vertex_edges(v)
                    .iter()
                    .all(|&e| topo.edge_sharpness(e) == 0.0);
            let faces = topo.vertex_faces(v);
            if !smooth || !faces.iter().all(|&f| ev.has_limit_surface(f as usize)) {
                continue;
            }
            let samples: Vec<_> = faces
                .iter()
                .map(|&f| {
                    let fv = topo.face_vertices(f);
                    let k = fv.iter().position(|&x| x == v).unwrap();
                    let (sub, u, w) = edge_param(fv.len(), k, 0.0);
                    ev.eval(f as usize, sub, u, w).unwrap()
                })
                .collect();
            for s in &samples[1..] {
                assert!((s.position - samples[0].position).length() < 1e-12 * diag);
                assert!(
                    s.normal.dot(samples[0].normal) > 1.0 - 1e-9,
                    "{name} vertex {v}"
                );
            }
        }
    }
}

// ---------- errors and the command line -----------------------------------------------------

#[test]
fn evaluator_refuses_bad_queries() {
    let holes = osd("catmark_hole_test1");
    let ev = LimitEvaluator::new(&holes).unwrap();
    assert!(!ev.has_limit_surface(1));
    let e = ev.eval(1, 0, 0.5, 0.5).unwrap_err().to_string();
    assert!(
        e.contains("face 1") && e.contains("no limit surface"),
        "{e}"
    );
    assert!(ev.eval(0, 0, 0.5, 0.5).is_ok());
    assert!(ev
        .eval(99, 0, 0.5, 0.5)
        .unwrap_err()
        .to_string()
        .contains("face 99"));
    assert!(
        ev.eval(0, 1, 0.5, 0.5).is_err(),
        "quads have only sub-face 0"
    );
    assert!(ev.eval(0, 0, 1.5, 0.5).is_err());
    assert!(ev.eval(0, 0, f64::NAN, 0.5).is_err());
    // Boundary interpolation "none": faces touching the boundary have no limit surface.
    let none = osd("catmark_edgenone");
    let ev = LimitEvaluator::new(&none).unwrap();
    let with: Vec<usize> = (0..none.face_count())
        .filter(|&f| ev.has_limit_surface(f))
        .collect();
    assert!(!with.is_empty() && with.len() < none.face_count());
    for f in 0..none.face_count() {
        assert_eq!(ev.eval(f, 0, 0.5, 0.5).is_ok(), with.contains(&f));
    }
}

#[test]
fn command_line_writes_one_line_per_sample() {
    let bin = env!("CARGO_BIN_EXE_tessera");
    let out = common::out_dir("limit").join("nonquads.txt");
    let status = std::process::Command::new(bin)
        .arg("limit")
        .arg(osd_path("catmark_nonquads"))
        .args(["--grid", "3", "--out"])
        .arg(&out)
        .status()
        .unwrap();
    assert!(status.success());
    let text = std::fs::read_to_string(&out).unwrap();
    let mesh = osd("catmark_nonquads");
    let ev = LimitEvaluator::new(&mesh).unwrap();
    // 16 samples per quad or per sub-face of a non-quad.
    let expected: usize = (0..mesh.face_count())
        .map(|f| {
            16 * if mesh.face_size(f) == 4 {
                1
            } else {
                mesh.face_size(f)
            }
        })
        .sum();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), expected);
    let mut k = 0;
    for f in 0..mesh.face_count() {
        let n = mesh.face_size(f);
        for sub in 0..if n == 4 { 1 } else { n } {
            for j in 0..=3 {
                for i in 0..=3 {
                    let cols: Vec<&str> = lines[k].split(' ').collect();
                    k += 1;
                    assert_eq!(cols.len(), 9);
                    let label = if n == 4 {
                        format!("{f}")
                    } else {
                        format!("{f}:{sub}")
                    };
                    assert_eq!(cols[0], label);
                    let num = |c: usize| cols[c].parse::<f32>().unwrap();
                    assert_eq!((num(1), num(2)), (i as f32 / 3.0, j as f32 / 3.0));
                    let s = ev.eval(f, sub, i as f64 / 3.0, j as f64 / 3.0).unwrap();
                    let p = s.position.as_vec3();
                    let nn = s.normal.as_vec3();
                    // Printed values read back as exactly the f32 values.
                    assert_eq!([num(3), num(4), num(5)], [p.x, p.y, p.z]);
                    assert_eq!([num(6), num(7), num(8)], [nn.x, nn.y, nn.z]);
                }
            }
        }
    }
    // Hole faces print nothing.
    let output = std::process::Command::new(bin)
        .arg("limit")
        .arg(osd_path("catmark_hole_test1"))
        .args(["--grid", "1"])
        .output()
        .unwrap();
    assert!(output.status.success());
    let text = String::from_utf8(output.stdout).unwrap();
    assert!(text.lines().all(|l| !l.starts_with("1 ")));
    assert_eq!(text.lines().count(), 5 * 4);
    // Bad input: a non-zero exit with the typed error.
    let output = std::process::Command::new(bin)
        .arg("limit")
        .arg(osd_path("catmark_fan"))
        .output()
        .unwrap();
    assert!(!output.status.success());
    assert!(String::from_utf8_lossy(&output.stderr).contains("non-manifold edge"));
    std::fs::remove_file(&out).ok();
}
