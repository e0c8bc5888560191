//! The refinement matrix of one uniform Catmull-Clark step: each child vertex (face, edge,
//! vertex point) as a weighted sum of parent vertices, with the semi-sharp crease rules of
//! [`super::rules`].

use super::level::Level;
use super::rules::{child_edge_sharpness, decrement, fractional_weight, vertex_rule};
use super::rules::{VertexMask, VertexRule};
use super::sparse::{merge_row, SparseMatrix};
use crate::topology::Topology;
use glam::DVec3;

impl Level {
    /// The refinement matrix: rows are child vertices (face, edge, vertex points), columns are
    /// this level's vertices.
    pub fn refine_matrix(&self) -> SparseMatrix {
        let t = &self.topo;
        let (nf, ne, nv) = (t.face_count(), t.edge_count(), t.vertex_count());
        SparseMatrix::from_rows(nf + ne + nv, nv, |r, buf| child_row(t, r, buf))
    }

    /// Row `r` of [`Self::refine_matrix`] (child vertex `r`) into `buf` (cleared first), the
    /// same `(column, weight)` pairs in the same order, without the other rows.
    pub(crate) fn refine_matrix_row(&self, r: usize, buf: &mut Vec<(u32, f64)>) {
        buf.clear();
        child_row(&self.topo, r, buf);
        merge_row(buf);
    }

    /// The refinement matrix composed with `rhs` (whose rows are this level's vertices):
    /// the child vertices in terms of `rhs`'s columns, without storing the matrix.
    pub fn compose_refinement(&self, rhs: &SparseMatrix) -> SparseMatrix {
        let t = &self.topo;
        let (nf, ne, nv) = (t.face_count(), t.edge_count(), t.vertex_count());
        SparseMatrix::compose_rows(nf + ne + nv, rhs, |r, buf| child_row(t, r, buf))
    }

    /// The child vertex positions from this level's positions (one entry per vertex).
    pub fn refine_positions(&self, positions: &[DVec3]) -> Vec<DVec3> {
        self.refine_matrix().apply_vec(positions)
    }
}

/// Child vertex `r` (`[face | edge | vertex points]`) as parent terms, unmerged.
fn child_row(t: &Topology, r: usize, buf: &mut Vec<(u32, f64)>) {
    let (nf, ne) = (t.face_count(), t.edge_count());
    if r < nf {
        face_row(t, r as u32, buf);
    } else if r < nf + ne {
        edge_row(t, (r - nf) as u32, buf);
    } else {
        vertex_row(t, (r - nf - ne) as u32, buf);
    }
}

/// Face point: the centroid.
fn face_row(t: &Topology, f: u32, buf: &mut Vec<(u32, f64)>) {
    let verts = t.face_vertices(f);
    let w = 1.0 / verts.len() as f64;
    buf.extend(verts.iter().map(|&v| (v, w)));
}

/// Edge point: smooth `(v0 + v1 + c0 + c1) / 4` with face centroids `c`, midpoint when the edge
/// has sharpness `>= 1` or one face, `s * midpoint + (1 - s) * smooth` for `0 < s < 1`
/// (DeRose et al. 1998, section 3; Köbler 2013, section 3.2).
fn edge_row(t: &Topology, e: u32, buf: &mut Vec<(u32, f64)>) {
    let [a, b] = t.edge_verts[e as usize];
    let s = t.edge_sharpness[e as usize] as f64;
    if t.is_boundary_edge(e) || s >= 1.0 {
        buf.extend([(a, 0.5), (b, 0.5)]);
        return;
    }
    let sharp = s.max(0.0);
    let smooth = 1.0 - sharp;
    let ends = 0.5 * sharp + 0.25 * smooth;
    buf.extend([(a, ends), (b, ends)]);
    for &f in t.edge_faces(e) {
        let verts = t.face_vertices(f);
        let w = 0.25 * smooth / verts.len() as f64;
        buf.extend(verts.iter().map(|&v| (v, w)));
    }
}

/// Vertex point: the parent rule, blended with the child rule by the fractional weight when
/// they differ (DeRose et al. 1998, section 3; [`super::rules`]).
fn vertex_row(t: &Topology, v: u32, buf: &mut Vec<(u32, f64)>) {
    let edges = t.vertex_edges(v);
    let faces = t.vertex_faces(v);
    let ne = edges.len();
    let smooth = t.vertex_sharpness[v as usize] <= 0.0
        && edges.iter().all(|&e| t.edge_sharpness[e as usize] <= 0.0);
    if smooth && ne == faces.len() && ne >= 2 {
        // The smooth rule without building a mask (same weights as `VertexMask::add_rule`).
        let n = ne as f64;
        let inv = 1.0 / (n * n);
        buf.push((v, (n - 2.0) / n));
        for &e in edges {
            buf.push((t.other_vertex(e, v), inv));
        }
        for &f in faces {
            let verts = t.face_vertices(f);
            let w = inv / verts.len() as f64;
            buf.extend(verts.iter().map(|&u| (u, w)));
        }
        return;
    }
    let mut parent = [0f32; 16];
    let mut child = [0f32; 16];
    let mut big_p = Vec::new();
    let mut big_c = Vec::new();
    let (ps, cs): (&mut [f32], &mut [f32]) = if ne <= 16 {
        (&mut parent[..ne], &mut child[..ne])
    } else {
        big_p.resize(ne, 0.0);
        big_c.resize(ne, 0.0);
        (&mut big_p[..], &mut big_c[..])
    };
    for (i, &e) in edges.iter().enumerate() {
        ps[i] = t.edge_sharpness[e as usize];
        cs[i] = child_edge_sharpness(t, e, v);
    }
    let pv = t.vertex_sharpness[v as usize];
    let cv = decrement(pv);
    let psharp: Vec<usize> = (0..ne).filter(|&i| ps[i] > 0.0).collect();
    let prule = vertex_rule(pv, psharp.len());
    let mut mask = VertexMask::default();
    mask.reset(ne, faces.len());
    if matches!(prule, VertexRule::Smooth | VertexRule::Dart) {
        mask.add_rule(prule, &psharp, 1.0);
    } else {
        let csharp: Vec<usize> = (0..ne).filter(|&i| cs[i] > 0.0).collect();
        let crule = vertex_rule(cv, csharp.len());
        if crule == prule {
            mask.add_rule(prule, &psharp, 1.0);
        } else {
            let w = fractional_weight(pv, cv, ps, cs);
            mask.add_rule(prule, &psharp, w);
            mask.add_rule(crule, &csharp, 1.0 - w);
        }
    }
    buf.push((v, mask.vertex));
    for (i, &e) in edges.iter().enumerate() {
        if mask.edges[i] != 0.0 {
            buf.push((t.other_vertex(e, v), mask.edges[i]));
        }
    }
    for (i, &f) in faces.iter().enumerate() {
        if mask.faces[i] != 0.0 {
            let verts = t.face_vertices(f);
            let w = mask.faces[i] / verts.len() as f64;
            buf.extend(verts.iter().map(|&u| (u, w)));
        }
    }
}
