//! The ACC geometry patches (§3): the masks, the refusals, the patch of a face (module docs of
//! [`super`]).

use std::fmt;

use glam::DVec3;

use crate::patch::basis::{bernstein, bernstein_deriv};
use crate::subdiv::bspline::eval_tensor;
use crate::topology::Topology;

/// Why ACC does not build a patch for a face.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum NotAcc {
    /// Not a quad (the paper's triangle extension is not built).
    Polygon {
        /// The face.
        face: u32,
        /// Its number of sides.
        sides: usize,
    },
    /// A corner is on a boundary or touches a sharp or semi-sharp edge, or is itself sharp.
    Feature {
        /// The face.
        face: u32,
        /// The corner vertex.
        vertex: u32,
    },
    /// A face around a corner is not a quad (the masks assume a quad ring).
    NonQuadRing {
        /// The face.
        face: u32,
        /// The corner vertex.
        vertex: u32,
    },
}

impl NotAcc {
    /// The face refused.
    pub fn face(&self) -> u32 {
        match self {
            NotAcc::Polygon { face, .. }
            | NotAcc::Feature { face, .. }
            | NotAcc::NonQuadRing { face, .. } => *face,
        }
    }
}

impl fmt::Display for NotAcc {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            NotAcc::Polygon { face, sides } => {
                write!(f, "face {face}: {sides} sides (ACC draws quads only)")
            }
            NotAcc::Feature { face, vertex } => write!(
                f,
                "face {face}: corner {vertex} is on a boundary, crease or sharp vertex (ACC covers smooth interior quads)"
            ),
            NotAcc::NonQuadRing { face, vertex } => write!(
                f,
                "face {face}: corner {vertex} has a non-quad face in its ring (ACC masks assume quads)"
            ),
        }
    }
}

/// One ACC geometry patch: a bicubic Bézier patch (`bezier[4 j + i]`, `i` along u; corners 0-3
/// of the face at `(0,0) (1,0) (1,1) (0,1)`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AccPatch {
    /// Base face.
    pub face: u32,
    /// Bézier points.
    pub bezier: [DVec3; 16],
}

impl AccPatch {
    /// Position, `d/du`, `d/dv` at `(u, v)`.
    pub fn eval(&self, u: f64, v: f64) -> (DVec3, DVec3, DVec3) {
        eval_tensor(
            &self.bezier,
            &bernstein(u),
            &bernstein_deriv(u),
            &bernstein(v),
            &bernstein_deriv(v),
        )
    }
}

/// Checks that face `f` is a quad whose corners are smooth interior vertices with quad rings.
pub fn check_face(topo: &Topology, f: u32) -> Result<(), NotAcc> {
    let fv = topo.face_vertices(f);
    if fv.len() != 4 {
        return Err(NotAcc::Polygon {
            face: f,
            sides: fv.len(),
        });
    }
    for &v in fv {
        let edges = topo.vertex_edges(v);
        let faces = topo.vertex_faces(v);
        if topo.is_boundary_vertex(v)
            || topo.vertex_sharpness(v) > 0.0
            || edges.len() != faces.len()
            || edges.iter().any(|&e| topo.edge_sharpness(e) > 0.0)
        {
            return Err(NotAcc::Feature { face: f, vertex: v });
        }
        if faces.iter().any(|&g| topo.face_size(g) != 4) {
            return Err(NotAcc::NonQuadRing { face: f, vertex: v });
        }
    }
    Ok(())
}

/// The interior point of corner `v` in quad `g`: `(n v + 2 (a + b) + c) / (n + 5)`.
pub(crate) fn interior(topo: &Topology, p: &[DVec3], v: u32, g: u32) -> DVec3 {
    let fv = topo.face_vertices(g);
    let k = fv.iter().position(|&x| x == v).expect("v is a corner of g");
    let n = topo.vertex_faces(v).len() as f64;
    let at = |d: usize| p[fv[(k + d) % 4] as usize];
    (p[v as usize] * n + (at(1) + at(3)) * 2.0 + at(2)) / (n + 5.0)
}

/// The edge point next to `v` on the edge `v - w` of face `f`: the average of `v`'s interior
/// points in `f` and in the face across that edge.
pub(crate) fn edge_point(topo: &Topology, p: &[DVec3], f: u32, v: u32, w: u32) -> DVec3 {
    let e = topo.find_edge(v, w).expect("an edge of f");
    let other = topo
        .edge_faces(e)
        .iter()
        .copied()
        .find(|&g| g != f)
        .expect("an interior edge has two faces");
    (interior(topo, p, v, f) + interior(topo, p, v, other)) * 0.5
}

/// The ACC geometry patch of face `f` for control positions `p` ([`check_face`] first).
pub fn acc_patch(topo: &Topology, p: &[DVec3], f: u32) -> Result<AccPatch, NotAcc> {
    check_face(topo, f)?;
    let fv = topo.face_vertices(f);
    let mut b = [DVec3::ZERO; 16];
    // Per corner k: its grid (i, j), the steps along u and v into the patch.
    let grid = [(0, 0, 1, 1), (3, 0, -1, 1), (3, 3, -1, -1), (0, 3, 1, -1)];
    for (k, &(i, j, du, dv)) in grid.iter().enumerate() {
        let v = fv[k];
        let at = |di: i32, dj: i32| (4 * (j + dj) + i + di) as usize;
        let ring = topo.vertex_faces(v);
        b[at(0, 0)] = ring
            .iter()
            .fold(DVec3::ZERO, |acc, &g| acc + interior(topo, p, v, g))
            / ring.len() as f64;
        b[at(du, dv)] = interior(topo, p, v, f);
        // Corners 0 and 2 reach their u neighbour forwards along the face, 1 and 3 backwards.
        let (next, prev) = (fv[(k + 1) % 4], fv[(k + 3) % 4]);
        let (u_end, v_end) = if k % 2 == 0 {
            (next, prev)
        } else {
            (prev, next)
        };
        b[at(du, 0)] = edge_point(topo, p, f, v, u_end);
        b[at(0, dv)] = edge_point(topo, p, f, v, v_end);
    }
    Ok(AccPatch { face: f, bezier: b })
}
