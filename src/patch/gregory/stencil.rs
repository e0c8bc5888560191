//! The linear (stencil) form of the Gregory construction for the GPU stencil variant (§4.3):
//! every control point of a patch as a weighted sum of the face's one-ring vertices.
//!
//! Rows are computed by running the one construction on unit weight vectors
//! ([`gregory_patch_weights`]). Row order of a patch with `N` corners (20 rows for quads, 15 for
//! triangles): row `5 i + k` is, for corner `i`, `k = 0` the corner point `p`, `1` the edge
//! point `e+` (towards corner `i + 1`), `2` the edge point `e-` (towards corner `i - 1`), `3`
//! the face point `f+`, `4` the face point `f-` ([`super::GregoryQuad`] field names).

use super::build::{gregory_patch_weights, GregoryPatch, NotGregory};
use super::point::Weights;
use crate::topology::Topology;
use glam::DVec3;
use std::collections::HashMap;
use std::fmt;

/// The largest one-ring a stencil patch may have (Vulkan's `maxTessellationPatchSize` floor
/// and the paper's hull-shader limit).
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
}

impl fmt::Display for NoStencil {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            NoStencil::NotGregory(e) => e.fmt(f),
            NoStencil::TooLarge { face, ring } => write!(
                f,
                "face {face}: one-ring of {ring} vertices exceeds the {MAX_RING}-vertex stencil patch"
            ),
        }
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
/// lists of local slots.
pub fn canonical_ring(topo: &Topology, f: u32) -> Vec<u32> {
    let mut out: Vec<u32> = Vec::new();
    let push = |x: u32, out: &mut Vec<u32>| {
        if !out.contains(&x) {
            out.push(x);
        }
    };
    for &v in topo.face_vertices(f) {
        push(v, &mut out);
    }
    for &v in topo.face_vertices(f) {
        let faces = topo.vertex_faces(v);
        let start = faces.iter().position(|&g| g == f).unwrap_or(0);
        for i in 0..faces.len() {
            let g = faces[(start + i) % faces.len()];
            let gv = topo.face_vertices(g);
            let k = gv.iter().position(|&x| x == v).unwrap_or(0);
            for t in 0..gv.len() {
                push(gv[(k + t) % gv.len()], &mut out);
            }
        }
    }
    out
}

/// Control-point weight vectors of a patch in row order.
fn patch_rows(p: GregoryPatch<Weights>) -> Vec<Weights> {
    let mut rows = Vec::new();
    let mut add = |p: Vec<Weights>,
                   ep: Vec<Weights>,
                   em: Vec<Weights>,
                   fp: Vec<Weights>,
                   fm: Vec<Weights>| {
        for i in 0..p.len() {
            rows.extend([
                p[i].clone(),
                ep[i].clone(),
                em[i].clone(),
                fp[i].clone(),
                fm[i].clone(),
            ]);
        }
    };
    match p {
        GregoryPatch::Quad(q) => add(
            q.p.to_vec(),
            q.e_plus.to_vec(),
            q.e_minus.to_vec(),
            q.f_plus.to_vec(),
            q.f_minus.to_vec(),
        ),
        GregoryPatch::Triangle(t) => add(
            t.p.to_vec(),
            t.e_plus.to_vec(),
            t.e_minus.to_vec(),
            t.f_plus.to_vec(),
            t.f_minus.to_vec(),
        ),
    }
    rows
}

/// The stencil of face `f` over its sorted one-ring.
pub fn gregory_stencil(topo: &Topology, f: u32) -> Result<GregoryStencil, NoStencil> {
    let patch = gregory_patch_weights(topo, f).map_err(NoStencil::NotGregory)?;
    let mut ring = canonical_ring(topo, f);
    if ring.len() > MAX_RING {
        return Err(NoStencil::TooLarge {
            face: f,
            ring: ring.len(),
        });
    }
    ring.sort_unstable();
    let rows = patch_rows(patch);
    let n = ring.len();
    let mut weights = vec![0.0; rows.len() * n];
    for (r, w) in rows.iter().enumerate() {
        for &(v, x) in &w.0 {
            // Every weight lies on the one-ring by construction (rings of the corners only).
            if let Ok(k) = ring.binary_search(&v) {
                weights[r * n + k] = x;
            }
        }
    }
    Ok(GregoryStencil {
        face: f,
        ring,
        weights,
    })
}

/// One connectivity type: the weights shared by every patch of that type, over the canonical
/// local ring order (§4.3).
#[derive(Debug, Clone, PartialEq)]
pub struct StencilType {
    /// Number of corners (3 or 4).
    pub corners: usize,
    /// Local ring size `ℓ <= 32`.
    pub ring_size: usize,
    /// `rows x ring_size` weights (f32, as the GPU reads them), row-major, canonical order.
    pub weights: Vec<f32>,
    /// Per row: bit `k` set when local ring slot `k` has a non-zero weight.
    pub masks: Vec<u32>,
}

/// One patch of a [`StencilTable`].
#[derive(Debug, Clone, PartialEq)]
pub struct StencilPatch {
    /// The face.
    pub face: u32,
    /// Index into [`StencilTable::types`].
    pub type_id: u32,
    /// Global vertex ids in canonical local order: the patch primitive's vertex list.
    pub ring: Vec<u32>,
    /// Local slots sorted by global vertex id: the order every weighted sum runs in, so shared
    /// corner and edge points get bitwise equal values in both patches (§4.5).
    pub order: Vec<u8>,
}

/// Gregory stencils of a mesh grouped by connectivity type: the unit a GPU stencil buffer is
/// made of.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StencilTable {
    /// Distinct connectivity types.
    pub types: Vec<StencilType>,
    /// Every face with a stencil, in face order.
    pub patches: Vec<StencilPatch>,
    /// Faces without a stencil and why (the renderer falls back for them).
    pub skipped: Vec<NoStencil>,
}

impl StencilTable {
    /// Builds the table for the given faces of `topo` (regular faces may be included: their
    /// Gregory patch reproduces the B-spline patch). Faces without a stencil go to `skipped`.
    pub fn new(topo: &Topology, faces: impl IntoIterator<Item = u32>) -> StencilTable {
        let mut table = StencilTable::default();
        let mut index: HashMap<(usize, Vec<u32>), u32> = HashMap::new();
        for f in faces {
            let patch = match gregory_patch_weights(topo, f) {
                Ok(p) => p,
                Err(e) => {
                    table.skipped.push(NoStencil::NotGregory(e));
                    continue;
                }
            };
            let ring = canonical_ring(topo, f);
            if ring.len() > MAX_RING {
                table.skipped.push(NoStencil::TooLarge {
                    face: f,
                    ring: ring.len(),
                });
                continue;
            }
            let rows = patch_rows(patch);
            let n = ring.len();
            let mut weights = vec![0f32; rows.len() * n];
            for (r, w) in rows.iter().enumerate() {
                for &(v, x) in &w.0 {
                    if let Some(k) = ring.iter().position(|&g| g == v) {
                        weights[r * n + k] = x as f32;
                    }
                }
            }
            let corners = rows.len() / ROWS_PER_CORNER;
            let key = (corners, weights.iter().map(|w| w.to_bits()).collect());
            let next = table.types.len() as u32;
            let type_id = *index.entry(key).or_insert_with(|| {
                let masks = (0..rows.len())
                    .map(|r| {
                        (0..n).fold(0u32, |m, k| {
                            if weights[r * n + k] != 0.0 {
                                m | (1 << k)
                            } else {
                                m
                            }
                        })
                    })
                    .collect();
                table.types.push(StencilType {
                    corners,
                    ring_size: n,
                    weights: weights.clone(),
                    masks,
                });
                next
            });
            let mut order: Vec<u8> = (0..n as u8).collect();
            order.sort_unstable_by_key(|&k| ring[k as usize]);
            table.patches.push(StencilPatch {
                face: f,
                type_id,
                ring,
                order,
            });
        }
        table
    }

    /// Control point `row` of `patch` computed as the GPU does: f32 products summed in the
    /// patch's global order, skipping masked-out slots, without fused multiply-add.
    pub fn eval_f32(&self, patch: &StencilPatch, row: usize, positions: &[[f32; 3]]) -> [f32; 3] {
        let t = &self.types[patch.type_id as usize];
        let n = t.ring_size;
        let mut acc = [0f32; 3];
        for &k in &patch.order {
            let k = k as usize;
            if t.masks[row] & (1 << k) == 0 {
                continue;
            }
            let w = t.weights[row * n + k];
            let x = positions[patch.ring[k] as usize];
            for c in 0..3 {
                acc[c] += w * x[c];
            }
        }
        acc
    }
}
