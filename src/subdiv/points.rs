//! The refinement matrix of one uniform Catmull-Clark step: each child vertex (face, edge,
//! vertex point) as a weighted sum of parent vertices, with the semi-sharp crease rules of
//! [`super::rules`].

use super::level::Level;
use super::rules::{child_edge_sharpness, decrement, fractional_weight, vertex_rule};
use super::rules::{VertexMask, VertexRule, REGULAR_EDGE_WEIGHTS, REGULAR_VERTEX_WEIGHTS};
use super::sparse::{merge_row, SparseMatrix};
use crate::topology::{Topology, NONE};
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
        if !regular_row(&self.topo, r, buf) {
            child_row(&self.topo, r, buf);
        }
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

/// Child vertex `r` pre-merged when its row has the regular smooth weights: the edge point of
/// a smooth edge between two quads (ends 3/8, the far corners 1/16) or the vertex point of a
/// smooth valence-4 interior vertex whose four faces are quads around it (9/16, edge
/// neighbours 3/32, diagonals 1/64); false (`buf` untouched) otherwise. Every weight and every
/// partial sum of [`child_row`]'s terms there is a multiple of 2^-6 below 2, exact in `f64`,
/// so [`merge_row`] of these few terms gives the bits of [`merge_row`] of `child_row`'s, in
/// whatever order either adds them (and the sort of 6 or 9 terms is short).
fn regular_row(t: &Topology, r: usize, buf: &mut Vec<(u32, f64)>) -> bool {
    let (nf, ne) = (t.face_count(), t.edge_count());
    if r < nf {
        return false;
    }
    if r < nf + ne {
        let e = (r - nf) as u32;
        let ([f0, f1], [l0, l1]) = (t.edge_faces[e as usize], t.edge_face_local[e as usize]);
        if f1 == NONE || !is_smooth_sharpness(t.edge_sharpness[e as usize]) {
            return false;
        }
        let (Some((q0, _)), Some((q1, _))) = (t.quad(f0), t.quad(f1)) else {
            return false;
        };
        let [a, b] = t.edge_verts[e as usize];
        let (l0, l1) = (usize::from(l0), usize::from(l1));
        let [end, far] = REGULAR_EDGE_WEIGHTS;
        buf.extend([
            (a, end),
            (b, end),
            (q0[(l0 + 2) % 4], far),
            (q0[(l0 + 3) % 4], far),
            (q1[(l1 + 2) % 4], far),
            (q1[(l1 + 3) % 4], far),
        ]);
        return true;
    }
    let v = (r - nf - ne) as u32;
    let (edges, faces) = (t.vertex_edges(v), t.vertex_faces(v));
    if edges.len() != 4
        || faces.len() != 4
        || !is_smooth_sharpness(t.vertex_sharpness[v as usize])
        || edges
            .iter()
            .any(|&e| !is_smooth_sharpness(t.edge_sharpness[e as usize]))
    {
        return false;
    }
    let ring: [u32; 4] = std::array::from_fn(|i| t.other_vertex(edges[i], v));
    let [centre, side, diagonal] = REGULAR_VERTEX_WEIGHTS;
    let start = buf.len();
    buf.push((v, centre));
    buf.extend(ring.map(|u| (u, side)));
    for (i, (&f, &k)) in faces.iter().zip(t.vertex_face_locals(v)).enumerate() {
        // Face `i` lies between edges `i` and `i + 1`: its corners beside `v` are their ends.
        let Some((q, _)) = t.quad(f) else {
            buf.truncate(start);
            return false;
        };
        let k = usize::from(k);
        let sides = [q[(k + 1) % 4], q[(k + 3) % 4]];
        let ends = [ring[i], ring[(i + 1) % 4]];
        if q[k] != v || !(sides == ends || sides == [ends[1], ends[0]]) {
            buf.truncate(start);
            return false;
        }
        buf.push((q[(k + 2) % 4], diagonal));
    }
    true
}

/// The ring edges with positive sharpness, as [`vertex_row`] hands them to
/// `VertexMask::add_rule`: on the stack up to 16 edges.
#[derive(Default)]
struct SharpEdges {
    small: [usize; 16],
    big: Vec<usize>,
}

impl SharpEdges {
    /// The indices `i` with `sharpness[i] > 0`, increasing.
    fn of(&mut self, sharpness: &[f32]) -> &[usize] {
        let sharp = (0..sharpness.len()).filter(|&i| sharpness[i] > 0.0);
        if sharpness.len() > self.small.len() {
            self.big.extend(sharp);
            return &self.big;
        }
        let mut n = 0;
        for i in sharp {
            self.small[n] = i;
            n += 1;
        }
        &self.small[..n]
    }
}

/// Whether sharpness `s` is smooth (`<= 0`; not NaN), as [`vertex_row`] and [`edge_row`] judge.
fn is_smooth_sharpness(s: f32) -> bool {
    s <= 0.0
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
    let (ends, faces) = edge_point_weights(t.edge_sharpness[e as usize], t.is_boundary_edge(e));
    buf.extend([(a, ends), (b, ends)]);
    if faces == 0.0 {
        return;
    }
    for &f in t.edge_faces(e) {
        let verts = t.face_vertices(f);
        let w = faces / verts.len() as f64;
        buf.extend(verts.iter().map(|&v| (v, w)));
    }
}

/// The weights of [`edge_row`] for an edge of sharpness `s` (`boundary`: one face): each end's,
/// and each face centroid's (`0` for the midpoint).
pub(crate) fn edge_point_weights(s: f32, boundary: bool) -> (f64, f64) {
    let s = s as f64;
    if boundary || s >= 1.0 {
        return (0.5, 0.0);
    }
    let sharp = s.max(0.0);
    let smooth = 1.0 - sharp;
    (0.5 * sharp + 0.25 * smooth, 0.25 * smooth)
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
    let mut mask = VertexMask::default();
    vertex_point_mask(
        &mut mask,
        t.vertex_sharpness[v as usize],
        ps,
        cs,
        faces.len(),
    );
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

/// The vertex-point mask of [`vertex_row`] into `mask`: a ring of `ps.len()` edges of
/// sharpness `ps` (`cs` their halves' at the vertex after the step) and `nf` faces, vertex
/// sharpness `pv`; the parent rule, blended with the child rule by the fractional weight when
/// they differ.
pub(crate) fn vertex_point_mask(mask: &mut VertexMask, pv: f32, ps: &[f32], cs: &[f32], nf: usize) {
    let cv = decrement(pv);
    let (mut pbuf, mut cbuf) = (SharpEdges::default(), SharpEdges::default());
    let psharp = pbuf.of(ps);
    let prule = vertex_rule(pv, psharp.len());
    mask.reset(ps.len(), nf);
    if matches!(prule, VertexRule::Smooth | VertexRule::Dart) {
        mask.add_rule(prule, psharp, 1.0);
    } else {
        let csharp = cbuf.of(cs);
        let crule = vertex_rule(cv, csharp.len());
        if crule == prule {
            mask.add_rule(prule, psharp, 1.0);
        } else {
            let w = fractional_weight(pv, cv, ps, cs);
            mask.add_rule(prule, psharp, w);
            mask.add_rule(crule, csharp, 1.0 - w);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::ControlMesh;

    /// The regular rows' short path gives every row of every level bit for bit as merging
    /// `child_row`'s terms does, and it is taken (meshes with creases, semi-sharp creases,
    /// boundaries, holes, non-quads, extraordinary vertices; two refinements each).
    #[test]
    fn regular_rows_are_merged_child_rows() {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/meshes/osd/");
        let mut regular = 0;
        for name in [
            "catmark_cube_creases1",
            "catmark_cubes_semisharp",
            "catmark_hole_test1",
            "catmark_nonquads",
            "catmark_pole8",
            "catmark_car",
        ] {
            let path = format!("{dir}{name}.obj");
            let mesh = ControlMesh::from_obj_file(&path, &Default::default()).unwrap();
            let mut level = Level::from_mesh(&mesh).unwrap();
            for _ in 0..3 {
                let t = level.topology();
                let rows = t.face_count() + t.edge_count() + t.vertex_count();
                let (mut fast, mut full) = (Vec::new(), Vec::new());
                for r in 0..rows {
                    level.refine_matrix_row(r, &mut fast);
                    full.clear();
                    child_row(t, r, &mut full);
                    merge_row(&mut full);
                    let bits = |row: &[(u32, f64)]| -> Vec<(u32, u64)> {
                        row.iter().map(|&(i, w)| (i, w.to_bits())).collect()
                    };
                    assert_eq!(bits(&fast), bits(&full), "{name} row {r}");
                    let mut probe = Vec::new();
                    regular += usize::from(regular_row(t, r, &mut probe));
                }
                level = level.refine_topology();
            }
        }
        assert!(regular > 1000, "regular rows taken {regular}");
    }
}
