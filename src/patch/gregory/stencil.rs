//! The linear (stencil) form of the Gregory construction (§4.3): every control point of a
//! face's patch as a fixed weighted sum of the face's one-ring vertices, found by running the
//! one construction on unit weight vectors ([`gregory_patch_weights`]; it is linear in the
//! positions).
//!
//! The stencil family: a [`GregoryStencil`] is one face's control points over its one-ring
//! sorted by vertex id (f64, the reference form); [`super::stencil_table::GregoryStencilTable`]
//! groups the faces of a mesh by connectivity type in the layout the GPU stencil variant reads.
//! (Refined and limit points over all base vertices are [`crate::subdiv::StencilTable`].)
//!
//! Row order of a [`GregoryStencil`] with `N` corners (20 rows for quads, 15 for triangles):
//! row `5 i + k` is, for corner `i`, `k = 0` the corner point `p`, `1` the edge point `e+`
//! (towards corner `i + 1`), `2` the edge point `e-` (towards corner `i - 1`), `3` the face
//! point `f+`, `4` the face point `f-` ([`super::GregoryQuad`] field names,
//! [`GregoryPatch::points`] order).

use super::build::{check_face, gregory_patch_weights, GregoryPatch, NotGregory};
use super::point::Weights;
use crate::topology::Topology;
use glam::DVec3;
use std::fmt;

/// The largest one-ring a stencil patch may have (Vulkan's guaranteed
/// `maxTessellationPatchSize` and the paper's hull-shader limit).
pub const MAX_RING: usize = 32;

/// Control points per corner in the row layout (module docs).
pub const ROWS_PER_CORNER: usize = 5;

/// Why a face has no stencil.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoStencil {
    /// The face gets no Gregory patch at all.
    NotGregory(NotGregory),
    /// The face's one-ring has more than [`MAX_RING`] vertices.
    TooLarge {
        /// The face.
        face: u32,
        /// Its one-ring size.
        ring: usize,
    },
    /// The face's one-ring fits [`MAX_RING`] but exceeds a smaller patch size limit (the
    /// device's `maxTessellationPatchSize`).
    OverLimit {
        /// The face.
        face: u32,
        /// Its one-ring size.
        ring: usize,
        /// The limit.
        limit: usize,
    },
}

impl NoStencil {
    /// The face without stencil.
    pub fn face(&self) -> u32 {
        match *self {
            NoStencil::NotGregory(e) => e.face(),
            NoStencil::TooLarge { face, .. } | NoStencil::OverLimit { face, .. } => face,
        }
    }
}

impl fmt::Display for NoStencil {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (face, ring, limit) = match *self {
            NoStencil::NotGregory(e) => return e.fmt(f),
            NoStencil::TooLarge { face, ring } => (face, ring, MAX_RING),
            NoStencil::OverLimit { face, ring, limit } => (face, ring, limit),
        };
        write!(
            f,
            "face {face}: one-ring of {ring} vertices exceeds the {limit}-vertex patch limit"
        )
    }
}

impl std::error::Error for NoStencil {}

/// The stencil of one Gregory patch over its one-ring sorted by global vertex id.
#[derive(Debug, Clone, PartialEq)]
pub struct GregoryStencil {
    /// The face.
    pub face: u32,
    /// The face's one-ring vertices (all vertices of faces sharing a vertex with it), sorted by
    /// global id: the paper's "one global, consistent order" (§4.5).
    pub ring: Vec<u32>,
    /// `rows x ring.len()` weights, row-major; rows as in the module docs.
    pub weights: Vec<f64>,
}

impl GregoryStencil {
    /// Number of control points (20 for quads, 15 for triangles).
    pub fn rows(&self) -> usize {
        self.weights.len() / self.ring.len().max(1)
    }

    /// Weights of control point `r` over [`Self::ring`].
    pub fn row(&self, r: usize) -> &[f64] {
        let n = self.ring.len();
        &self.weights[r * n..(r + 1) * n]
    }

    /// All control points from positions, in row order (f64).
    pub fn apply(&self, positions: &[DVec3]) -> Vec<DVec3> {
        (0..self.rows())
            .map(|r| {
                self.row(r)
                    .iter()
                    .zip(&self.ring)
                    .map(|(&w, &v)| w * positions[v as usize])
                    .sum()
            })
            .collect()
    }
}

/// The face's one-ring in canonical local order: corners in face order, then for each corner the
/// vertices of its faces, starting at the face and going around the ring, each face's vertices
/// starting at the corner; first appearance wins. Identical local connectivity gives identical
/// lists of local slots (§4.3).
pub fn canonical_ring(topo: &Topology, f: u32) -> Vec<u32> {
    let mut out: Vec<u32> = Vec::new();
    ring_walk(topo, f, |x| {
        if !out.contains(&x) {
            out.push(x);
        }
    });
    out
}

/// Every vertex of [`canonical_ring`]'s walk in order, repeats included (the ring is the
/// first appearances).
pub(super) fn ring_walk(topo: &Topology, f: u32, mut visit: impl FnMut(u32)) {
    for &v in topo.face_vertices(f) {
        visit(v);
    }
    for &v in topo.face_vertices(f) {
        let faces = topo.vertex_faces(v);
        let start = faces.iter().position(|&g| g == f).unwrap_or(0);
        // `faces` from `start` round to `start - 1`, each face's vertices from `v` round: the
        // two halves of a rotation rather than an index modulo the length per element.
        for &g in faces[start..].iter().chain(&faces[..start]) {
            let gv = topo.face_vertices(g);
            let k = gv.iter().position(|&x| x == v).unwrap_or(0);
            gv[k..].iter().chain(&gv[..k]).for_each(|&x| visit(x));
        }
    }
}

/// The canonical one-ring of face `f` if it gets a stencil with at most `limit` (capped at
/// [`MAX_RING`]) ring vertices, or why not.
pub(super) fn stencil_ring(topo: &Topology, f: u32, limit: usize) -> Result<Vec<u32>, NoStencil> {
    check_face(topo, f).map_err(NoStencil::NotGregory)?;
    let ring = canonical_ring(topo, f);
    if ring.len() > MAX_RING {
        return Err(NoStencil::TooLarge {
            face: f,
            ring: ring.len(),
        });
    }
    if ring.len() > limit {
        return Err(NoStencil::OverLimit {
            face: f,
            ring: ring.len(),
            limit,
        });
    }
    Ok(ring)
}

/// `rows x sorted_ring.len()` dense weights of `rows` over `sorted_ring` (ascending vertex ids).
/// Every weight of a Gregory row lies on the face's one-ring (rings of its corners only).
pub(super) fn dense_rows(rows: &[Weights], sorted_ring: &[u32]) -> Vec<f64> {
    let n = sorted_ring.len();
    let mut weights = vec![0.0; rows.len() * n];
    for (r, w) in rows.iter().enumerate() {
        for &(v, x) in &w.0 {
            if let Ok(k) = sorted_ring.binary_search(&v) {
                weights[r * n + k] = x;
            }
        }
    }
    weights
}

/// The stencil of face `f` over its sorted one-ring.
pub fn gregory_stencil(topo: &Topology, f: u32) -> Result<GregoryStencil, NoStencil> {
    let mut ring = stencil_ring(topo, f, MAX_RING)?;
    let patch: GregoryPatch<Weights> =
        gregory_patch_weights(topo, f).map_err(NoStencil::NotGregory)?;
    ring.sort_unstable();
    let points = patch.points();
    let rows: Vec<Weights> = (0..patch.corner_count())
        .flat_map(|i| points.map(|kind| kind[i].clone()))
        .collect();
    Ok(GregoryStencil {
        face: f,
        weights: dense_rows(&rows, &ring),
        ring,
    })
}
