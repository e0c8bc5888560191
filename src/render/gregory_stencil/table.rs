//! CPU side of the stencil variant (Loop et al. 2009, §4.3): every Gregory control point of a
//! face is a fixed linear combination of the face's one-ring vertices. The weights are found by
//! running the crate's construction ([`GregoryVertex::interior`], [`GregoryQuad::new`],
//! [`GregoryTriangle::new`]) on unit vectors (the construction is linear in the positions), the
//! ring is sorted by global vertex id (the paper's "one global, consistent order"), and patches
//! whose weight rows are identical share one connectivity type.

use std::collections::HashMap;

use glam::DVec3;

use crate::patch::gregory::{
    face_point, vertex_ring, CornerRef, GregoryQuad, GregoryTriangle, GregoryVertex,
};
use crate::patch::RegularPatch;
use crate::topology::Topology;

/// Control points of a quad Gregory patch.
pub const QUAD_POINTS: usize = 20;
/// Control points of a triangular Gregory patch.
pub const TRI_POINTS: usize = 15;
/// Extra rows after a quad's control points: per patch edge k the neighbour's other edge points
/// at both ends (`g_eout` of glsl/common/gregory.glsl), then the neighbour's face points next
/// to edge k at both ends (`g_nbr`).
pub const QUAD_EXTRA: usize = 16;
/// Extra rows after a triangle's control points (6 + 6).
pub const TRI_EXTRA: usize = 12;
/// Largest ring the GPU layout stores (Vulkan's guaranteed `maxTessellationPatchSize`).
pub const MAX_RING: usize = 32;

/// One face drawn by the stencil variant.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StencilPatch {
    /// Base-mesh face.
    pub face: u32,
    /// Corner vertex ids in face order (4th entry repeats corner 0 for triangles).
    pub corners: [u32; 4],
    /// Whether the face is a triangle (15 points) or a quad (20 points).
    pub triangle: bool,
    /// The face's one-ring (every vertex of every face touching a corner), ascending ids.
    pub ring: Vec<u32>,
    /// Index into [`StencilTable::types`].
    pub type_id: u32,
}

/// One connectivity type: the weight rows shared by every patch of the type.
#[derive(Debug, Clone, PartialEq)]
pub struct StencilType {
    /// Triangle (15 rows) or quad (20 rows).
    pub triangle: bool,
    /// Ring length (columns).
    pub ring_len: usize,
    /// `weights[row * ring_len + k]`: weight of ring vertex `k` in row `row`: the control points
    /// p0.., e_plus0.., e_minus0.., f_plus0.., f_minus0.. (20 or 15), then for each patch edge
    /// k (corner k -> k+1) the edge point of corner k's vertex on the ring edge beyond edge k
    /// and that of corner k+1's vertex beyond edge k (8 or 6 rows: the neighbour patch's own
    /// edge points there), then for each edge k the neighbour patch's face points next to edge
    /// k at corner k and at corner k+1 (8 or 6 rows, eq. 6 with the neighbour's face size): the
    /// shared TES builds symmetric edge normals from both patches' cross-edge derivatives.
    pub weights: Vec<f32>,
    /// Bit `k` of `masks[row]` set when the weight of ring vertex `k` in `row` is nonzero.
    pub masks: Vec<u32>,
}

/// A face the stencil variant does not draw, and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Rejected {
    /// Base-mesh face.
    pub face: u32,
    /// Reason, naming the face.
    pub reason: String,
}

/// Stencils of a set of faces, grouped by connectivity type.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StencilTable {
    /// Accepted faces.
    pub patches: Vec<StencilPatch>,
    /// Connectivity types.
    pub types: Vec<StencilType>,
    /// Faces left to another path (boundary/crease vertex, ring too large, not a tri/quad).
    pub rejected: Vec<Rejected>,
}

/// Faces a Gregory scheme should draw: with a limit surface, not (boundary-)regular, three or
/// four corners.
pub fn gregory_faces(topo: &Topology) -> Vec<u32> {
    (0..topo.face_count() as u32)
        .filter(|&f| {
            topo.has_limit_surface(f)
                && matches!(topo.face_size(f), 3 | 4)
                && RegularPatch::gather(topo, f).is_none()
        })
        .collect()
}

/// The one-ring of face `f`: every vertex of every face incident to one of its corners, sorted
/// by id, without repeats.
pub fn face_ring(topo: &Topology, f: u32) -> Vec<u32> {
    let mut ring: Vec<u32> = topo
        .face_vertices(f)
        .iter()
        .flat_map(|&c| topo.vertex_faces(c).iter())
        .flat_map(|&g| topo.face_vertices(g).iter().copied())
        .collect();
    ring.sort_unstable();
    ring.dedup();
    ring
}

/// Why the interior construction cannot take corner `v` (or `None` when it can).
fn unsupported(topo: &Topology, v: u32) -> Option<&'static str> {
    if topo.is_boundary_vertex(v) {
        Some("is on a boundary")
    } else if topo.vertex_sharpness(v) != 0.0
        || topo
            .vertex_edges(v)
            .iter()
            .any(|&e| topo.edge_sharpness(e) != 0.0)
    {
        Some("has sharpness on it or an incident edge")
    } else {
        None
    }
}

/// The rows of face `f` from `positions` (20 + 8 or 15 + 6 points, see [`StencilType`]).
fn control_points(topo: &Topology, positions: &[DVec3], f: u32) -> Vec<DVec3> {
    let fv = topo.face_vertices(f);
    let verts: Vec<GregoryVertex> = fv
        .iter()
        .map(|&v| GregoryVertex::interior(&vertex_ring(topo, positions, v)))
        .collect();
    let refs: Vec<CornerRef<'_>> = fv
        .iter()
        .zip(&verts)
        .map(|(&v, vertex)| CornerRef {
            vertex,
            j: topo
                .vertex_faces(v)
                .iter()
                .position(|&g| g == f)
                .expect("a face is in the ring of each of its corners"),
        })
        .collect();
    let mut out = Vec::with_capacity(QUAD_POINTS + QUAD_EXTRA);
    let n = refs.len();
    let mut extra = Vec::with_capacity(4 * n);
    for k in 0..n {
        let (a, b) = (&refs[k], &refs[(k + 1) % n]);
        extra.push(a.vertex.e[(a.j + a.vertex.n - 1) % a.vertex.n]);
        extra.push(b.vertex.e[(b.j + 2) % b.vertex.n]);
    }
    for k in 0..n {
        let (x, y) = (fv[k], fv[(k + 1) % n]);
        let (a, b) = (&refs[k], &refs[(k + 1) % n]);
        extra.extend(neighbour_face_points(topo, f, (x, a.vertex), (y, b.vertex)));
    }
    if n == 3 {
        let t = GregoryTriangle::new(&[refs[0], refs[1], refs[2]]);
        for a in [t.p, t.e_plus, t.e_minus, t.f_plus, t.f_minus] {
            out.extend(a);
        }
    } else {
        let q = GregoryQuad::new(&[refs[0], refs[1], refs[2], refs[3]]);
        for a in [q.p, q.e_plus, q.e_minus, q.f_plus, q.f_minus] {
            out.extend(a);
        }
    }
    out.extend(extra);
    out
}

/// The face points of the face across edge `x -> y` of face `f` next to that edge, at `x` and at
/// `y`, computed with exactly the arguments the neighbour's own construction passes to
/// [`face_point`] (`assemble` in patch::gregory::eval), so the results are bitwise its own.
/// Where the neighbour is not a triangle or quad (no Gregory patch), `f`'s own face points.
fn neighbour_face_points(
    topo: &Topology,
    f: u32,
    (x, gx): (u32, &GregoryVertex),
    (y, gy): (u32, &GregoryVertex),
) -> [DVec3; 2] {
    let j_of = |v: u32, g: u32| topo.vertex_faces(v).iter().position(|&h| h == g);
    let g = topo
        .find_edge(x, y)
        .and_then(|e| topo.edge_faces(e).iter().copied().find(|&h| h != f));
    let (g, d) = match g.map(|g| (g, topo.face_size(g))) {
        Some((g, 4)) => (g, 3.0),
        Some((g, 3)) => (g, 4.0),
        _ => (f, if topo.face_size(f) == 3 { 4.0 } else { 3.0 }),
    };
    let (Some(jx), Some(jy)) = (j_of(x, g), j_of(y, g)) else {
        return [DVec3::ZERO; 2];
    };
    let (nx, ny) = (gx.n, gy.n);
    if g == f {
        // Own face points next to edge x -> y: f_plus at x, f_minus at y.
        let fx = face_point(d, nx, ny, gx.p, gx.e[jx], gy.e[(jy + 1) % ny], gx.r_plus[jx]);
        let fy = face_point(
            d,
            ny,
            nx,
            gy.p,
            gy.e[(jy + 1) % ny],
            gx.e[jx],
            gy.r_minus[jy],
        );
        return [fx, fy];
    }
    // In g the edge runs y -> x: f_minus at x (prev corner y), f_plus at y (next corner x).
    let fx = face_point(
        d,
        nx,
        ny,
        gx.p,
        gx.e[(jx + 1) % nx],
        gy.e[jy],
        gx.r_minus[jx],
    );
    let fy = face_point(d, ny, nx, gy.p, gy.e[jy], gx.e[(jx + 1) % nx], gy.r_plus[jy]);
    [fx, fy]
}

/// Weight rows of face `f` over `ring` (f64, `rows x ring.len()`), by linearity: ring vertices
/// `3b`, `3b+1`, `3b+2` are set to the unit vectors x, y, z (all other positions zero) and
/// component `c` of each control point is the weight of vertex `3b + c`. `scratch` holds one zero
/// position per mesh vertex and is left zeroed.
fn ring_weights(topo: &Topology, f: u32, ring: &[u32], scratch: &mut [DVec3]) -> Vec<f64> {
    let rows = if topo.face_size(f) == 3 {
        TRI_POINTS + TRI_EXTRA
    } else {
        QUAD_POINTS + QUAD_EXTRA
    };
    let l = ring.len();
    let mut w = vec![0.0; rows * l];
    for (b, chunk) in ring.chunks(3).enumerate() {
        for (c, &v) in chunk.iter().enumerate() {
            scratch[v as usize][c] = 1.0;
        }
        let pts = control_points(topo, scratch, f);
        for (row, p) in pts.iter().enumerate() {
            for c in 0..chunk.len() {
                w[row * l + 3 * b + c] = p[c];
            }
        }
        for &v in chunk {
            scratch[v as usize] = DVec3::ZERO;
        }
    }
    w
}

impl StencilTable {
    /// Builds the stencils of `faces`. Faces whose ring exceeds `max_ring` (at most
    /// [`MAX_RING`]; pass the device's `maxTessellationPatchSize`), that are not triangles or
    /// quads, or that touch a boundary or sharp vertex are listed in `rejected`.
    pub fn build(topo: &Topology, faces: &[u32], max_ring: usize) -> StencilTable {
        let max_ring = max_ring.min(MAX_RING);
        let mut table = StencilTable::default();
        let mut scratch = vec![DVec3::ZERO; topo.vertex_count()];
        let mut by_key: HashMap<(bool, Vec<u32>), u32> = HashMap::new();
        for &f in faces {
            let fv = topo.face_vertices(f);
            let reject = |reason: String| Rejected { face: f, reason };
            if !matches!(fv.len(), 3 | 4) {
                table.rejected.push(reject(format!(
                    "face {f} has {} corners: Gregory patches exist for triangles and quads only",
                    fv.len()
                )));
                continue;
            }
            if let Some((v, why)) = fv
                .iter()
                .find_map(|&v| unsupported(topo, v).map(|why| (v, why)))
            {
                table.rejected.push(reject(format!(
                    "face {f}: corner vertex {v} {why}, which the Gregory construction does not cover yet"
                )));
                continue;
            }
            let ring = face_ring(topo, f);
            if ring.len() > max_ring {
                table.rejected.push(reject(format!(
                    "face {f}: one-ring of {} vertices exceeds the {max_ring}-vertex patch limit",
                    ring.len()
                )));
                continue;
            }
            let w: Vec<f32> = ring_weights(topo, f, &ring, &mut scratch)
                .iter()
                .map(|&x| x as f32)
                .collect();
            let triangle = fv.len() == 3;
            let key = (triangle, w.iter().map(|x| x.to_bits()).collect::<Vec<_>>());
            let next = table.types.len() as u32;
            let type_id = *by_key.entry(key).or_insert(next);
            if type_id == next {
                let l = ring.len();
                let masks = w
                    .chunks(l)
                    .map(|row| {
                        row.iter()
                            .enumerate()
                            .filter(|(_, x)| **x != 0.0)
                            .fold(0u32, |m, (k, _)| m | (1 << k))
                    })
                    .collect();
                table.types.push(StencilType {
                    triangle,
                    ring_len: l,
                    weights: w,
                    masks,
                });
            }
            let mut corners = [fv[0]; 4];
            corners[..fv.len()].copy_from_slice(fv);
            table.patches.push(StencilPatch {
                face: f,
                corners,
                triangle,
                ring,
                type_id,
            });
        }
        table
    }

    /// The control points of patch `i` from the f32 stencil, summed as the TCS does (ascending
    /// ring order, zero weights skipped) but in f64.
    pub fn eval_points(&self, i: usize, positions: &[DVec3]) -> Vec<DVec3> {
        let p = &self.patches[i];
        let t = &self.types[p.type_id as usize];
        t.weights
            .chunks(t.ring_len)
            .map(|row| {
                row.iter()
                    .zip(&p.ring)
                    .filter(|(w, _)| **w != 0.0)
                    .map(|(&w, &v)| f64::from(w) * positions[v as usize])
                    .sum()
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{ControlMesh, ControlMeshDesc};

    /// A closed mixed mesh: a triangular prism with one end capped by a fan of triangles (so
    /// valences 3, 4, 5 and tri/quad rings) and a slightly irregular shape.
    fn prism() -> ControlMesh {
        let positions = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.1, 0.0),
            DVec3::new(0.4, 0.9, 0.1),
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(1.1, 0.0, 1.2),
            DVec3::new(0.5, 1.0, 1.0),
            DVec3::new(0.5, 0.35, -0.4),
        ];
        let face_vertices = vec![
            3, 4, 5, // top
            0, 1, 4, 3, 1, 2, 5, 4, 2, 0, 3, 5, // sides
            1, 0, 6, 2, 1, 6, 0, 2, 6, // bottom fan
        ];
        ControlMesh::new(ControlMeshDesc {
            positions,
            face_sizes: vec![3, 4, 4, 4, 3, 3, 3],
            face_vertices,
            ..Default::default()
        })
        .unwrap()
    }

    #[test]
    fn stencil_reproduces_the_direct_construction() {
        let mesh = prism();
        let topo = Topology::new(&mesh).unwrap();
        let faces = gregory_faces(&topo);
        assert_eq!(faces.len(), 7);
        let table = StencilTable::build(&topo, &faces, MAX_RING);
        assert!(table.rejected.is_empty(), "{:?}", table.rejected);
        let pos = mesh.positions();
        for (i, p) in table.patches.iter().enumerate() {
            let direct = control_points(&topo, pos, p.face);
            let from_stencil = table.eval_points(i, pos);
            for (a, b) in direct.iter().zip(&from_stencil) {
                // f32 weights: relative rounding ~6e-8 of coordinates of size ~1.
                assert!((*a - *b).length() < 1e-6, "face {}: {a} vs {b}", p.face);
            }
            // Affine: the weights of every row sum to 1 (up to f32 rounding).
            let t = &table.types[p.type_id as usize];
            for row in t.weights.chunks(t.ring_len) {
                let s: f64 = row.iter().map(|&x| f64::from(x)).sum();
                assert!((s - 1.0).abs() < 1e-6, "face {}: row sum {s}", p.face);
            }
        }
    }

    #[test]
    fn ring_is_sorted_and_masks_match_weights() {
        let mesh = prism();
        let topo = Topology::new(&mesh).unwrap();
        let table = StencilTable::build(&topo, &gregory_faces(&topo), MAX_RING);
        for p in &table.patches {
            assert!(p.ring.windows(2).all(|w| w[0] < w[1]));
            let t = &table.types[p.type_id as usize];
            for (row, m) in t.weights.chunks(t.ring_len).zip(&t.masks) {
                for (k, w) in row.iter().enumerate() {
                    assert_eq!(*w != 0.0, m & (1 << k) != 0);
                }
            }
        }
    }

    /// Weights of row `row` of patch `p` by vertex id (f32 bits).
    fn row_by_id(t: &StencilTable, p: &StencilPatch, row: usize) -> Vec<(u32, u32)> {
        let ty = &t.types[p.type_id as usize];
        let w = &ty.weights[row * ty.ring_len..(row + 1) * ty.ring_len];
        p.ring
            .iter()
            .zip(w)
            .filter(|(_, w)| **w != 0.0)
            .map(|(v, w)| (*v, w.to_bits()))
            .collect()
    }

    #[test]
    fn shared_rows_are_bitwise_equal_on_both_sides_of_every_edge() {
        let mesh = prism();
        let topo = Topology::new(&mesh).unwrap();
        let t = StencilTable::build(&topo, &gregory_faces(&topo), MAX_RING);
        let by_face: HashMap<u32, &StencilPatch> = t.patches.iter().map(|p| (p.face, p)).collect();
        let mut checked = 0;
        for a in &t.patches {
            let c = topo.face_vertices(a.face);
            let n = c.len();
            for k in 0..n {
                let (x, y) = (c[k], c[(k + 1) % n]);
                let e = topo.find_edge(x, y).unwrap();
                let g = *topo.edge_faces(e).iter().find(|&&g| g != a.face).unwrap();
                let b = by_face[&g];
                let d = topo.face_vertices(g);
                let m = d.len();
                let k2 = (0..m).find(|&i| d[i] == y && d[(i + 1) % m] == x).unwrap();
                let k2n = (k2 + 1) % m;
                let pairs = [
                    (k, k2n),                        // p at x
                    ((k + 1) % n, k2),               // p at y
                    (n + k, 2 * m + k2n),            // e_plus[k] == e_minus[k2+1]
                    (2 * n + (k + 1) % n, m + k2),   // e_minus[k+1] == e_plus[k2]
                    (5 * n + 2 * k, m + k2n),        // other edge point at x == e_plus[k2+1]
                    (5 * n + 2 * k + 1, 2 * m + k2), // other edge point at y == e_minus[k2]
                    (7 * n + 2 * k, 4 * m + k2n),    // neighbour face point at x == f_minus[k2+1]
                    (7 * n + 2 * k + 1, 3 * m + k2), // neighbour face point at y == f_plus[k2]
                ];
                for (ra, rb) in pairs {
                    assert_eq!(
                        row_by_id(&t, a, ra),
                        row_by_id(&t, b, rb),
                        "faces {} / {g}: rows {ra} / {rb}",
                        a.face
                    );
                    checked += 1;
                }
            }
        }
        assert_eq!(checked, 8 * (3 + 3 * 4 + 3 * 3));
    }

    #[test]
    fn small_patch_limit_rejects_with_a_message() {
        let mesh = prism();
        let topo = Topology::new(&mesh).unwrap();
        let table = StencilTable::build(&topo, &gregory_faces(&topo), 4);
        assert!(table.patches.is_empty());
        assert_eq!(table.rejected.len(), 7);
        assert!(table.rejected[0]
            .reason
            .contains("exceeds the 4-vertex patch limit"));
    }
}
