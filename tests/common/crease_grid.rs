//! The 8×8 quad grids with semi-sharp crease lines of the single-crease tests (open, over a
//! bumpy height field; or closed into a torus, where every crease line is a loop).

use glam::DVec3;
use tessera::mesh::{ControlMeshDesc, Crease};
use tessera::ControlMesh;

/// Quads per side.
pub const N: usize = 8;

/// A grid edge `((i0, j0), (i1, j1))` with its sharpness.
pub type Edge = ((usize, usize), (usize, usize), f32);

/// Vertex `(i, j)` of the open grid.
pub fn idx(i: usize, j: usize) -> u32 {
    (j * (N + 1) + i) as u32
}

/// Face `(i, j)` (both grids; on a split grid only before the split face).
pub fn face(i: usize, j: usize) -> u32 {
    (j * N + i) as u32
}

fn creases(list: &[Edge], vid: impl Fn(usize, usize) -> u32) -> Vec<Crease> {
    list.iter()
        .map(|&((a, b), (c, d), sharpness)| Crease {
            v0: vid(a, b),
            v1: vid(c, d),
            sharpness,
        })
        .collect()
}

/// An 8×8 grid of quads over a bumpy height field; `creases` lists `((i0, j0), (i1, j1), s)`.
pub fn grid(list: &[Edge]) -> ControlMesh {
    grid_split(list, None)
}

/// [`grid`] with face `split` cut into two triangles along its diagonal from `(i + 1, j)` to
/// `(i, j + 1)` (those two vertices get valence 5; the triangles come last).
pub fn grid_split(list: &[Edge], split: Option<(usize, usize)>) -> ControlMesh {
    let mut positions = Vec::new();
    for j in 0..=N {
        for i in 0..=N {
            let (x, y) = (i as f64, j as f64);
            let z = 0.7 * (0.9 * x).sin() * (0.6 * y).cos() + 0.05 * x * y;
            positions.push(DVec3::new(
                x + 0.1 * (1.3 * y).sin(),
                y + 0.1 * (0.7 * x).cos(),
                z,
            ));
        }
    }
    let mut face_vertices = Vec::new();
    let mut face_sizes = Vec::new();
    for j in 0..N {
        for i in 0..N {
            if split != Some((i, j)) {
                face_vertices.extend([idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)]);
                face_sizes.push(4);
            }
        }
    }
    if let Some((i, j)) = split {
        face_vertices.extend([idx(i, j), idx(i + 1, j), idx(i, j + 1)]);
        face_vertices.extend([idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)]);
        face_sizes.extend([3, 3]);
    }
    ControlMesh::new(ControlMeshDesc {
        positions,
        face_sizes,
        face_vertices,
        creases: creases(list, idx),
        ..Default::default()
    })
    .unwrap()
}

/// Vertex `(i, j)` of the torus (indices taken modulo `N`).
pub fn torus_idx(i: usize, j: usize) -> u32 {
    ((j % N) * N + i % N) as u32
}

/// An 8×8 torus of quads (every vertex valence 4, no boundary), slightly irregular;
/// `creases` as [`grid`], indices modulo `N`.
pub fn torus(list: &[Edge]) -> ControlMesh {
    let mut positions = Vec::new();
    for j in 0..N {
        for i in 0..N {
            let a = std::f64::consts::TAU * (i as f64 + 0.15 * (j as f64 * 0.9).sin()) / N as f64;
            let b = std::f64::consts::TAU * j as f64 / N as f64;
            let r = 1.0 + 0.12 * (2.0 * a + b).cos();
            positions.push(DVec3::new(
                (3.0 + r * b.cos()) * a.cos(),
                (3.0 + r * b.cos()) * a.sin(),
                r * b.sin(),
            ));
        }
    }
    let mut face_vertices = Vec::new();
    for j in 0..N {
        for i in 0..N {
            face_vertices.extend([
                torus_idx(i, j),
                torus_idx(i + 1, j),
                torus_idx(i + 1, j + 1),
                torus_idx(i, j + 1),
            ]);
        }
    }
    ControlMesh::new(ControlMeshDesc {
        positions,
        face_sizes: vec![4; N * N],
        face_vertices,
        creases: creases(list, torus_idx),
        ..Default::default()
    })
    .unwrap()
}

/// The line `i = 4` with sharpness `s(j)` on the edge from row `j` to `j + 1`.
pub fn line(s: impl Fn(usize) -> f32) -> Vec<Edge> {
    (0..N).map(|j| ((4, j), (4, j + 1), s(j))).collect()
}
