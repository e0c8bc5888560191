//! Gregory patch construction (Loop, Schaefer, Ni, Castaño 2009): reproduction of the bicubic
//! B-spline at valence 4, continuity of position and tangent plane across shared edges, and
//! interpolation of the Catmull-Clark limit position at corners.

mod common;

use common::reference::{assert_meet_on_edge, bspline_basis};
use glam::DVec3;
use tessera::mesh::{ControlMesh, ControlMeshDesc};
use tessera::patch::gregory::{gregory_patch, gregory_vertices, GregoryPatch};
use tessera::topology::Topology;

/// A torus grid of `n x m` quads (every vertex valence 4) with deterministic bumps.
fn torus(n: usize, m: usize) -> (ControlMesh, impl Fn(usize, usize) -> u32) {
    let idx = move |i: usize, j: usize| ((j % m) * n + (i % n)) as u32;
    let mut positions = Vec::new();
    for j in 0..m {
        for i in 0..n {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            let b = std::f64::consts::TAU * j as f64 / m as f64;
            let bump = 0.15 * ((3 * i + 7 * j) % 5) as f64 / 5.0;
            let r = 1.0 + bump;
            positions.push(DVec3::new(
                (3.0 + r * b.cos()) * a.cos(),
                (3.0 + r * b.cos()) * a.sin(),
                r * b.sin(),
            ));
        }
    }
    let mut face_vertices = Vec::new();
    for j in 0..m {
        for i in 0..n {
            face_vertices.extend([idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)]);
        }
    }
    let desc = ControlMeshDesc {
        positions,
        face_sizes: vec![4; n * m],
        face_vertices,
        ..Default::default()
    };
    (ControlMesh::new(desc).unwrap(), idx)
}

#[test]
fn valence_four_reproduces_the_bicubic_bspline() {
    let (mesh, idx) = torus(8, 6);
    let topo = Topology::new(&mesh).unwrap();
    let verts = gregory_vertices(&topo, mesh.positions());
    let pos = mesh.positions();
    for (fi, fj) in [(0usize, 0usize), (3, 2), (7, 5)] {
        let f = (fj * 8 + fi) as u32;
        let GregoryPatch::Quad(q) = gregory_patch(&topo, &verts, f).unwrap() else {
            panic!("quad expected")
        };
        for s in 0..=6 {
            for t in 0..=6 {
                let (u, v) = (s as f64 / 6.0, t as f64 / 6.0);
                let (bu, bv) = (bspline_basis(u), bspline_basis(v));
                let mut expected = DVec3::ZERO;
                for a in 0..4 {
                    for b in 0..4 {
                        let p = pos[idx(fi + 8 + a - 1, fj + 6 + b - 1) as usize];
                        expected += bu[a] * bv[b] * p;
                    }
                }
                let got = q.eval(u, v).position;
                assert!(
                    (got - expected).length() < 1e-12,
                    "face {f} at ({u},{v}): {got} vs {expected}"
                );
            }
        }
        // The two face points of each corner coincide in the regular case.
        for i in 0..4 {
            assert!((q.f_plus[i] - q.f_minus[i]).length() < 1e-12);
        }
    }
}

/// Checks position and tangent-plane continuity along every edge shared by two patches.
fn check_continuity(mesh: &ControlMesh) -> usize {
    let topo = Topology::new(mesh).unwrap();
    let verts = gregory_vertices(&topo, mesh.positions());
    let patches: Vec<_> = (0..topo.face_count() as u32)
        .map(|f| gregory_patch(&topo, &verts, f).unwrap())
        .collect();
    let mut checked = 0;
    for e in 0..topo.edge_count() as u32 {
        let faces = topo.edge_faces(e);
        let locals = topo.edge_face_locals(e);
        assert_eq!(faces.len(), 2);
        for s in 1..8 {
            let t = s as f64 / 8.0;
            // Face 0 runs along the edge as its edge k0 at t; face 1 runs the other way.
            assert_meet_on_edge(
                e,
                (&patches[faces[0] as usize], locals[0] as usize),
                (&patches[faces[1] as usize], locals[1] as usize),
                t,
                true,
            );
            checked += 1;
        }
    }
    checked
}

fn cube(split_top: bool) -> ControlMesh {
    let mut positions: Vec<DVec3> = (0..8)
        .map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64))
        .collect();
    // Counter-clockwise seen from outside.
    let mut faces: Vec<Vec<u32>> = vec![
        vec![0, 2, 3, 1],
        vec![0, 1, 5, 4],
        vec![1, 3, 7, 5],
        vec![3, 2, 6, 7],
        vec![2, 0, 4, 6],
    ];
    if split_top {
        positions.push(DVec3::new(0.5, 0.5, 1.3));
        for (a, b) in [(4, 5), (5, 7), (7, 6), (6, 4)] {
            faces.push(vec![a, b, 8]);
        }
    } else {
        faces.push(vec![4, 5, 7, 6]);
    }
    let desc = ControlMeshDesc {
        positions,
        face_sizes: faces.iter().map(|f| f.len() as u32).collect(),
        face_vertices: faces.concat(),
        ..Default::default()
    };
    ControlMesh::new(desc).unwrap()
}

#[test]
fn quad_patches_join_with_tangent_plane_continuity() {
    assert!(check_continuity(&cube(false)) > 0);
}

#[test]
fn mixed_triangle_quad_patches_join_with_tangent_plane_continuity() {
    assert!(check_continuity(&cube(true)) > 0);
}

#[test]
fn corners_interpolate_the_catmull_clark_limit_of_quad_rings() {
    // Closed-form limit of a valence-n vertex of an all-quad ring (Halstead et al. 1993):
    // (n² v + 4 Σ e_i + Σ f_i) / (n (n + 5)), e_i edge neighbours, f_i diagonal vertices.
    let mesh = cube(false);
    let topo = Topology::new(&mesh).unwrap();
    let verts = gregory_vertices(&topo, mesh.positions());
    let pos = mesh.positions();
    for v in 0..8u32 {
        let n = topo.valence(v) as f64;
        let mut e_sum = DVec3::ZERO;
        let mut f_sum = DVec3::ZERO;
        for &f in topo.vertex_faces(v) {
            let fv = topo.face_vertices(f);
            let k = fv.iter().position(|&x| x == v).unwrap();
            e_sum += pos[fv[(k + 1) % 4] as usize];
            f_sum += pos[fv[(k + 2) % 4] as usize];
        }
        let expected = (n * n * pos[v as usize] + 4.0 * e_sum + f_sum) / (n * (n + 5.0));
        let got = verts[v as usize].as_ref().unwrap().p;
        assert!((got - expected).length() < 1e-14, "vertex {v}");
    }
}
