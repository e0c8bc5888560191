//! CPU side of the stencil variant (Loop et al. 2009, §4.3): every Gregory control point of a
//! face is a fixed linear combination of the face's one-ring vertices. The weights are found by
//! running the crate's one construction ([`gregory_patch_at`], interior, boundary and crease
//! vertices per §3 and §4.6) on unit vectors (it is linear in the positions), the
//! ring is kept in the canonical local order of [`canonical_ring`] (so faces with the same local connectivity share
//! one connectivity type, §4.3) and summed in ascending global vertex id (the paper's "one global,
//! consistent order", §4.5).

use std::collections::HashMap;

use glam::DVec3;

use crate::patch::gregory::stencil::canonical_ring;
use crate::patch::gregory::{check_face, gregory_patch_at, GregoryPatch};
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
    /// The face's one-ring (every vertex of every face touching a corner) in the canonical local
    /// order of [`canonical_ring`]: the patch primitive's vertex list. Faces with the same local
    /// connectivity get the same weights slot by slot, so they share a connectivity type (§4.3).
    pub ring: Vec<u32>,
    /// Ring slots sorted by global vertex id: the order every weighted sum runs in, so a shared
    /// corner or edge point gets the same nonzero terms in the same order in both patches (§4.5).
    pub order: Vec<u8>,
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

/// Control points of a patch in row order: p.., e_plus.., e_minus.., f_plus.., f_minus...
fn patch_rows(p: &GregoryPatch) -> Vec<DVec3> {
    let mut out = Vec::with_capacity(QUAD_POINTS);
    match p {
        GregoryPatch::Quad(q) => {
            for a in [q.p, q.e_plus, q.e_minus, q.f_plus, q.f_minus] {
                out.extend(a);
            }
        }
        GregoryPatch::Triangle(t) => {
            for a in [t.p, t.e_plus, t.e_minus, t.f_plus, t.f_minus] {
                out.extend(a);
            }
        }
    }
    out
}

/// The rows of face `f` from `positions` (see [`StencilType`]): its own control points, then per
/// edge k the neighbour patch's edge points and face points next to the edge, taken from the
/// neighbour's own construction ([`gregory_patch_at`], the same function its own stencil runs),
/// so they are bitwise its own values. Where the edge has no Gregory neighbour (boundary, a face
/// without Gregory patch) the patch's own points stand in.
fn control_points(topo: &Topology, positions: &[DVec3], f: u32) -> Vec<DVec3> {
    let own =
        patch_rows(&gregory_patch_at(topo, positions, f).expect("face checked by check_face"));
    let fv = topo.face_vertices(f);
    let n = fv.len();
    let mut eout = Vec::with_capacity(2 * n);
    let mut nbr = Vec::with_capacity(2 * n);
    for k in 0..n {
        let (x, y) = (fv[k], fv[(k + 1) % n]);
        let across = topo
            .find_edge(x, y)
            .and_then(|e| topo.edge_faces(e).iter().copied().find(|&g| g != f));
        let theirs = across.and_then(|g| {
            let d = topo.face_vertices(g);
            let m = d.len();
            // In g the edge runs y -> x: corner k2 = y, k2 + 1 = x.
            let k2 = (0..m).find(|&i| d[i] == y && d[(i + 1) % m] == x)?;
            let r = patch_rows(&gregory_patch_at(topo, positions, g).ok()?);
            let k2n = (k2 + 1) % m;
            // e_plus at x, e_minus at y, f_minus at x, f_plus at y.
            Some([r[m + k2n], r[2 * m + k2], r[4 * m + k2n], r[3 * m + k2]])
        });
        let [ex, ey, fx, fy] = theirs.unwrap_or([
            own[2 * n + k],
            own[n + (k + 1) % n],
            own[3 * n + k],
            own[4 * n + (k + 1) % n],
        ]);
        eout.extend([ex, ey]);
        nbr.extend([fx, fy]);
    }
    let mut out = own;
    out.extend(eout);
    out.extend(nbr);
    out
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
            if let Err(e) = check_face(topo, f) {
                table.rejected.push(reject(e.to_string()));
                continue;
            }
            let ring = canonical_ring(topo, f);
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
            let mut order: Vec<u8> = (0..ring.len() as u8).collect();
            order.sort_unstable_by_key(|&k| ring[k as usize]);
            table.patches.push(StencilPatch {
                face: f,
                corners,
                triangle,
                ring,
                order,
                type_id,
            });
        }
        table
    }

    /// The control points of patch `i` from the f32 stencil, summed as the TCS does (ascending
    /// global vertex id, zero weights skipped) but in f64.
    pub fn eval_points(&self, i: usize, positions: &[DVec3]) -> Vec<DVec3> {
        let p = &self.patches[i];
        let t = &self.types[p.type_id as usize];
        t.weights
            .chunks(t.ring_len)
            .map(|row| {
                p.order
                    .iter()
                    .map(|&k| (row[k as usize], p.ring[k as usize]))
                    .filter(|(w, _)| *w != 0.0)
                    .map(|(w, v)| f64::from(w) * positions[v as usize])
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
            let sorted: Vec<u32> = p.order.iter().map(|&k| p.ring[k as usize]).collect();
            assert!(sorted.windows(2).all(|w| w[0] < w[1]));
            assert_eq!(sorted.len(), p.ring.len());
            let t = &table.types[p.type_id as usize];
            for (row, m) in t.weights.chunks(t.ring_len).zip(&t.masks) {
                for (k, w) in row.iter().enumerate() {
                    assert_eq!(*w != 0.0, m & (1 << k) != 0);
                }
            }
        }
    }

    /// Nonzero weights of row `row` of patch `p` as (vertex id, f32 bits) in the summation order.
    fn row_by_id(t: &StencilTable, p: &StencilPatch, row: usize) -> Vec<(u32, u32)> {
        let ty = &t.types[p.type_id as usize];
        let w = &ty.weights[row * ty.ring_len..(row + 1) * ty.ring_len];
        p.order
            .iter()
            .map(|&k| (p.ring[k as usize], w[k as usize]))
            .filter(|(_, w)| *w != 0.0)
            .map(|(v, w)| (v, w.to_bits()))
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
    fn faces_with_the_same_connectivity_share_one_type() {
        // A cube: every face has four valence-3 corners in an all-quad ring, so one type.
        let positions = (0..8)
            .map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, (i >> 2) as f64 * 1.3))
            .collect();
        let face_vertices = vec![
            0, 2, 3, 1, 4, 5, 7, 6, 0, 1, 5, 4, 2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5,
        ];
        let mesh = ControlMesh::new(ControlMeshDesc {
            positions,
            face_sizes: vec![4; 6],
            face_vertices,
            ..Default::default()
        })
        .unwrap();
        let topo = Topology::new(&mesh).unwrap();
        let t = StencilTable::build(&topo, &gregory_faces(&topo), MAX_RING);
        assert_eq!(t.patches.len(), 6);
        assert_eq!(t.types.len(), 1);
        for (i, p) in t.patches.iter().enumerate() {
            let direct = control_points(&topo, mesh.positions(), p.face);
            for (a, b) in direct.iter().zip(&t.eval_points(i, mesh.positions())) {
                assert!((*a - *b).length() < 1e-6);
            }
        }
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
