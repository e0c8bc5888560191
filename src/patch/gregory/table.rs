//! Flat per-vertex connectivity for the two-stage GPU variant (§4.1-4.2): the paper's Fig. 7
//! (one-ring indices per vertex) and Fig. 8 (per-patch ring offsets) as plain `u32` arrays,
//! ready for storage buffers. A vertex shader reads a vertex's block, computes `m_i`, `c_i` and
//! from them `p`, `e_j`, `r_j^±` and `cos` ([`super::GregoryVertex`]); the TCS picks, per
//! patch corner, the entries of the patch's face with [`GregoryVertexTable::patch_offsets`] and
//! builds the face points with eq. 6.
//!
//! # Layout
//! `vertices[4 v .. 4 v + 4] = [offset, ne, nf, kind]` for vertex `v`: `ne` incident edges,
//! `nf` incident faces (`ne = nf + 1` on a boundary), `kind` one of [`KIND_NONE`] (no Gregory
//! data: the rest is 0), [`KIND_SMOOTH`], [`KIND_CREASE`], [`KIND_CORNER`]
//! ([`super::VertexKind`]). `ring[offset ..]` then holds, in this order:
//! 1. `ne` words: `w_j`, the far vertex of incident edge `j` (ring order of
//!    [`crate::topology::Topology`]; `m_j = (v + w_j) / 2`);
//! 2. `nf` sector words, one per incident face `i`: `start | faces << 16`, the sector holding
//!    face `i` (starting at sharp edge `start`, `faces` faces; ending at sharp edge
//!    `(start + faces) % ne`). Smooth vertices: `0 | nf << 16`. An edge is sharp iff it starts
//!    or ends a sector of a crease or corner vertex;
//! 3. per incident face `i` in ring order: one word `size`, then the `size - 3` vertices of the
//!    face other than `v`, `w_i`, `w_{(i+1) % ne}`, in face order after `w_{(i+1) % ne}` (one
//!    diagonal for a quad, none for a triangle); `c_i` is the mean of all `size` vertices;
//! 4. smooth vertices only: two words, the `f32` bits of the edge-tangent factor `s` and of the
//!    transversal factor `ρ` ([`super::GregoryTangents::ring_factors`]; both 1.0 for the
//!    paper's construction); crease vertices only: `nf` words, per incident face the `f32` bits
//!    of the cross-boundary factor `s(k)` of its sector ([`super::GregoryTangents::sector_scale`],
//!    keyed on the sector's 2-ring, `super::tangents_boundary::sector_band`);
//! 5. crease and corner vertices: one word, 1 if the face points beside sharp edges are
//!    one-sided ([`super::GregoryVertex::one_sided`] not empty: `Optimal` on a ring of quads),
//!    else 0.
//!
//! `patch_offsets[4 k .. 4 k + 4]`: for patch `k` (face `faces[k]`), per corner the index of the
//! face in that corner vertex's ring (the paper's Fig. 8 "rotation offset"); `u32::MAX` in the
//! fourth slot of a triangle.

use super::build::{check_face_level0, far_crease_sectors};
use super::tangents::GregoryTangents;
use super::tangents_boundary::sector_band;
use super::tangents_tri::ring_face_sizes;
use super::vertex::{sectors, GregoryVertex, VertexKind};
use crate::mesh::INFINITE_SHARPNESS;
use crate::topology::Topology;

/// `kind` of a vertex without Gregory data.
pub const KIND_NONE: u32 = 0;
/// `kind` of a smooth interior vertex.
pub const KIND_SMOOTH: u32 = 1;
/// `kind` of a boundary or crease vertex (two sharp edges).
pub const KIND_CREASE: u32 = 2;
/// `kind` of a corner vertex.
pub const KIND_CORNER: u32 = 3;

/// The flat per-vertex and per-patch tables (see the module docs for the exact layout).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct GregoryVertexTable {
    /// Four words per vertex: `[offset, ne, nf, kind]`.
    pub vertices: Vec<u32>,
    /// Ring blocks.
    pub ring: Vec<u32>,
    /// The faces drawn as Gregory patches, in patch order.
    pub faces: Vec<u32>,
    /// Four words per patch: the face's index in each corner vertex's ring.
    pub patch_offsets: Vec<u32>,
}

impl GregoryVertexTable {
    /// Builds the tables for the given faces; faces that get no Gregory patch are left out
    /// (see [`check_face_level0`]). Default edge tangents.
    pub fn new(topo: &Topology, faces: impl IntoIterator<Item = u32>) -> GregoryVertexTable {
        Self::with_tangents(topo, faces, GregoryTangents::default())
    }

    /// [`Self::new`] with the given edge-tangent lengths.
    pub fn with_tangents(
        topo: &Topology,
        faces: impl IntoIterator<Item = u32>,
        tangents: GregoryTangents,
    ) -> GregoryVertexTable {
        let mut t = GregoryVertexTable::default();
        for v in 0..topo.vertex_count() as u32 {
            let kind = vertex_kind(topo, v);
            if kind == KIND_NONE {
                t.vertices.extend([0, 0, 0, KIND_NONE]);
                continue;
            }
            let edges = topo.vertex_edges(v);
            let vfaces = topo.vertex_faces(v);
            let (ne, nf) = (edges.len(), vfaces.len());
            t.vertices
                .extend([t.ring.len() as u32, ne as u32, nf as u32, kind]);
            let w: Vec<u32> = edges.iter().map(|&e| topo.other_vertex(e, v)).collect();
            t.ring.extend(&w);
            let face_sizes = ring_face_sizes(topo, v);
            let quads = face_sizes.iter().all(|&k| k == 4);
            let mut sector_words = vec![(nf as u32) << 16; nf];
            let mut crease_words = Vec::new();
            if kind != KIND_SMOOTH {
                let sharp: Vec<bool> = edges
                    .iter()
                    .map(|&e| topo.edge_sharpness(e) >= INFINITE_SHARPNESS)
                    .collect();
                let far = if kind == KIND_CREASE {
                    far_crease_sectors(topo, v, &sharp)
                } else {
                    vec![0; ne]
                };
                let fitted = topo.crease_factors(v);
                let factor = |k: usize, band: usize, index: usize| {
                    (tangents.sector_scale(k, band, quads, fitted, index) as f32).to_bits()
                };
                crease_words = vec![factor(0, 0, 0); nf];
                for (index, s) in sectors(&sharp, nf).into_iter().enumerate() {
                    let band = sector_band(s.faces, (1..s.faces).map(|i| far[(s.start + i) % ne]));
                    for i in 0..s.faces {
                        sector_words[(s.start + i) % ne] = s.start as u32 | (s.faces as u32) << 16;
                        crease_words[(s.start + i) % ne] = factor(s.faces, band, index);
                    }
                }
            }
            t.ring.extend(&sector_words);
            for (i, &f) in vfaces.iter().enumerate() {
                let fv = topo.face_vertices(f);
                t.ring.push(fv.len() as u32);
                // Face i runs v, w_i, (extras), w_{i+1} in its own order.
                let k = fv.iter().position(|&x| x == w[i]).unwrap_or(0);
                for s in 1..=fv.len().saturating_sub(3) {
                    t.ring.push(fv[(k + s) % fv.len()]);
                }
            }
            if kind == KIND_SMOOTH {
                let factors = tangents.ring_factors(&face_sizes);
                t.ring.push((factors.tangent as f32).to_bits());
                t.ring.push((factors.transversal as f32).to_bits());
            }
            if kind == KIND_CREASE {
                t.ring.extend(&crease_words);
            }
            if kind == KIND_CREASE || kind == KIND_CORNER {
                t.ring
                    .push(u32::from(tangents.one_sided_face_points(quads)));
            }
        }
        for f in faces {
            if check_face_level0(topo, f).is_err() {
                continue;
            }
            t.faces.push(f);
            let mut offs = [u32::MAX; 4];
            for (k, &v) in topo.face_vertices(f).iter().enumerate() {
                let j = topo.vertex_faces(v).iter().position(|&g| g == f);
                offs[k] = j.map_or(u32::MAX, |j| j as u32);
            }
            t.patch_offsets.extend(offs);
        }
        t
    }
}

/// The table's `kind` word for vertex `v`: what [`super::gregory_vertex`] would build.
fn vertex_kind(topo: &Topology, v: u32) -> u32 {
    let point = |_: u32| 0.0f64;
    match super::build::gregory_vertex(topo, v, &point).map(|g: GregoryVertex<f64>| g.kind) {
        None => KIND_NONE,
        Some(VertexKind::Smooth) => KIND_SMOOTH,
        Some(VertexKind::Crease) => KIND_CREASE,
        Some(VertexKind::Corner) => KIND_CORNER,
        // No GLSL port: the level-0 schemes refuse faces at darts (`check_face_level0`) and
        // cone points (`check_face`).
        Some(VertexKind::Dart | VertexKind::Cone) => KIND_NONE,
    }
}
