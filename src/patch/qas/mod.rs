//! QAS, the quadratic approximation of Catmull-Clark surfaces (Boubekeur, Schlick 2007,
//! "Approximation of Subdivision Surfaces for Interactive Applications"): one Catmull-Clark
//! step with every new vertex projected to the limit (positions and normals from the limit masks
//! of [`crate::subdiv::limit`]), then per coarse face two quadratic Bézier patches fitted to
//! those limit points, one for positions and one for normals ([`bezier`]).
//!
//! - Quads: the step's 9 limit points (4 corners, 4 edge points, the face point) give the
//!   biquadratic patch interpolating all nine.
//! - Triangles: the paper's quadratic triangle on the 3 corner and 3 edge limit points; the face
//!   point is not used (six coefficients, all fixed by the corners and edges; a seventh point
//!   would make the patch cubic). `tests/scheme_qas.rs` reports how far the patch passes from it.
//! - Faces of n ≥ 5 sides: a fan of n quadratic triangles ([`QasKind::Fan`]), triangle `k`
//!   with corners `(F, V_k, V_{k+1})` (the face point's limit and the limit points of corners
//!   `k`, `k + 1`). Its outer edge `V_k V_{k+1}` is the coarse edge's quadratic through the
//!   level-1 edge point, built from the same rows by the same rule as the neighbour's, so it
//!   needs no neighbour change. Its spokes `F V_k` pass through the limit of the level-2 face
//!   point of sub-face `k` (the quad `(V_k, E_k, F, E_{k-1})` of the step; the limit at its
//!   `(½, ½)`, on the diagonal `F V_k`, [`crate::subdiv::limit::face_point_mask`]); both
//!   triangles of a spoke read the same three rows. The fan interpolates every limit point a
//!   per-sub-face construction would (corners, edge points, face point) plus one per sub-face.
//!
//! Why not the per-sub-face quads the issue names: a sub-face quad's outer edges are halves of
//! coarse edges, while the neighbour (a quad or triangle) draws the whole coarse edge as one
//! quadratic at the edge's level. Bitwise agreement would need the halves to be de Casteljau
//! halves of the neighbour's curve *and* the neighbour's edge tessellated as two halves whose
//! points coincide with the sub-faces' (transition patches on every face next to an n-gon, as
//! the adaptive scheme splits a coarse B-spline patch into a triangle fan per transition edge).
//! With equal spacing the halves' lattice `j / (L/2) · ½` is the whole edge's `j / L` only in
//! exact arithmetic (the adaptive scheme snaps both to one lattice), and with fractional
//! spacing an edge of level `L` is not two edges of level `L / 2` at all (the fractional
//! segments sit at the edge's middle): the neighbour would have to be split too, which changes
//! every neighbour's patch, level and capture layout. The fan reuses the triangle path, and its
//! outer edges are the neighbour's edges as they are.
//!
//! Each point is a sparse row over the control vertices (the one-step refinement matrix
//! composed with the level-1 limit mask, [`QasSurface`]), so animation re-applies the rows.
//! Positions have one row per level-1 vertex (and level-2 sub-face centre), so faces sharing a
//! corner or an edge get the same bits. Normals have one row pair (two tangents) per level-1
//! vertex and *sector* (faces around it not separated by a boundary or infinitely sharp edge):
//! both faces of a smooth edge read the same normal row, the two sides of a crease their own. At
//! a cusp (an infinitely sharp vertex with fewer than two sharp edges: one sector) the limit has
//! no normal, each face's mask gives its own; QAS takes the one of the sector's smallest face, so
//! the smooth edges there stay watertight in their normals too.
//!
//! Parameters of fan points ([`fan_to_sub_face`], [`sub_face_to_fan`]): a point of fan
//! triangle `k` at barycentric weights `(w0, w1, w2)` of `(F, V_k, V_{k+1})` is named in the
//! sub-face domains of the exact evaluator ([`crate::subdiv::eval`]): the median `F M` (`M`
//! the edge midpoint, `w1 = w2`) splits the triangle into `(F, V_k, M)`, mapped linearly onto
//! the half `v ≤ u` of sub-face `k` (`V_k → (0,0)`, `M → (1,0)`, `F → (1,1)`), and
//! `(F, M, V_{k+1})`, onto the half `u ≤ v` of sub-face `k + 1` (`V_{k+1} → (0,0)`,
//! `M → (0,1)`, `F → (1,1)`): `(u, v) = (w0 + 2 w2, w0)` in sub-face `k` when `w1 ≥ w2`, else
//! `(w0, w0 + 2 w1)` in sub-face `k + 1`. Spokes land on the sub-face diagonal `u = v`, the
//! centre on `(1, 1)`, the outer edge on the sub-faces' `v = 0` / `u = 0` edges.
//!
//! Accuracy drops where the normal turns fast and unevenly across a face (the quadratic through
//! three normals overshoots; e.g. the bishop's tight lathe bands: docs/measured.md's figures), and, as the
//! paper says, at high valences.

pub mod bezier;

use std::collections::HashMap;
use std::fmt;

use glam::DVec3;
use rayon::prelude::*;

use crate::subdiv::limit::{face_point_mask, vertex_mask, VertexMask};
use crate::subdiv::{Level, SparseMatrix};
use crate::topology::{is_sharp_edge, Topology};
use bezier::{eval_quad, eval_tri, quad_coefficients, tri_coefficients};
pub use bezier::{QUAD_CENTRE_SLOT, QUAD_CORNER_SLOTS, QUAD_EDGE_SLOTS};

/// Why QAS does not draw a face.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum NotQas {
    /// A limit mask of one of the face's level-1 (or, for n-gons, level-2 sub-face centre)
    /// points failed.
    Mask {
        /// The face.
        face: u32,
        /// The mask's error.
        why: String,
    },
}

impl NotQas {
    /// The face refused.
    pub fn face(&self) -> u32 {
        match self {
            NotQas::Mask { face, .. } => *face,
        }
    }
}

impl fmt::Display for NotQas {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            NotQas::Mask { face, why } => write!(f, "face {face}: {why}"),
        }
    }
}

/// The corner id of a fan triangle's centre (corner 0) in [`QasPatch::corners`]: larger than
/// every vertex id, so a spoke's canonical direction (from the smaller id) runs from its vertex.
pub const FAN_CENTRE: u32 = u32::MAX;

/// The shape of a QAS patch.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum QasKind {
    /// Biquadratic, 9 points (slots `3 j + i`, [`QUAD_CORNER_SLOTS`], [`QUAD_EDGE_SLOTS`]).
    Quad,
    /// Quadratic triangle, 6 points: corners 0-2, then the midpoints of edges 0-2.
    Triangle,
    /// One triangle of an n-gon's fan (n ≥ 5), laid out as a triangle: corners `F, V_k,
    /// V_{k+1}`, then the midpoints of the spoke `F V_k` (sub-face `k`'s centre), the outer
    /// edge (its edge point) and the spoke `V_{k+1} F` (sub-face `k + 1`'s centre).
    Fan,
}

impl QasKind {
    /// Limit points (and Bézier coefficients) per patch.
    pub fn points(self) -> usize {
        match self {
            QasKind::Quad => 9,
            QasKind::Triangle | QasKind::Fan => 6,
        }
    }
}

/// One patch: a base face and the rows of its limit points.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct QasPatch {
    /// Base face.
    pub face: u32,
    /// Shape.
    pub kind: QasKind,
    /// Fans: `k`, the face corner at the patch's corner 1 (points near it are in sub-face `k`,
    /// points near corner 2 in sub-face `k + 1`); `None` for quads and triangles.
    pub fan: Option<u32>,
    /// Base vertex ids of the corners (a triangle repeats corner 0 last; a fan is
    /// `[FAN_CENTRE, V_k, V_{k+1}, FAN_CENTRE]`).
    pub corners: [u32; 4],
    /// Position row of each point slot (unused slots 0).
    pub points: [u32; 9],
    /// Normal row of each point slot.
    pub normals: [u32; 9],
}

impl QasPatch {
    /// The base vertices at the patch's corners with their point slots (a fan's centre is no
    /// base vertex and is left out).
    pub fn corner_vertices(&self) -> Vec<(u32, usize)> {
        match self.kind {
            QasKind::Quad => (0..4)
                .map(|k| (self.corners[k], QUAD_CORNER_SLOTS[k]))
                .collect(),
            QasKind::Triangle => (0..3).map(|k| (self.corners[k], k)).collect(),
            QasKind::Fan => (1..3).map(|k| (self.corners[k], k)).collect(),
        }
    }
}

/// The sub-face point `(sub-face, u, v)` (module docs) of the point at barycentric weights
/// `(w0, w1, w2)` of fan triangle `k` of an `n`-gon, `(F, V_k, V_{k+1})`.
pub fn fan_to_sub_face(k: u32, n: u32, w: [f64; 3]) -> (u32, f64, f64) {
    if w[1] >= w[2] {
        (k, w[0] + 2.0 * w[2], w[0])
    } else {
        ((k + 1) % n, w[0], w[0] + 2.0 * w[1])
    }
}

/// The inverse of [`fan_to_sub_face`]: the fan triangle of an `n`-gon holding point `(u, v)`
/// of sub-face `sub` (`v ≤ u`: triangle `sub`, else triangle `sub - 1`) and the barycentric
/// weights `(w1, w2)` of its corners 1 and 2 there.
pub fn sub_face_to_fan(sub: u32, n: u32, u: f64, v: f64) -> (u32, f64, f64) {
    if v <= u {
        let w2 = 0.5 * (u - v);
        (sub, 1.0 - v - w2, w2)
    } else {
        let w1 = 0.5 * (v - u);
        ((sub + n - 1) % n, w1, 1.0 - u - w1)
    }
}

/// The limit points of every row of a [`QasSurface`] for one set of control positions.
#[derive(Debug, Clone, PartialEq)]
pub struct QasPoints {
    /// Limit positions, one per position row.
    pub positions: Vec<DVec3>,
    /// Unit limit normals, one per normal row.
    pub normals: Vec<DVec3>,
}

/// The Bézier coefficients of one patch (unused slots zero).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QasControl {
    /// Shape.
    pub kind: QasKind,
    /// Position patch.
    pub position: [DVec3; 9],
    /// Normal patch (unnormalised interpolant of the unit limit normals).
    pub normal: [DVec3; 9],
}

impl QasControl {
    /// Fits both patches to the limit points `p` and normals `n` of the patch's slots.
    pub fn fit(kind: QasKind, p: &[DVec3; 9], n: &[DVec3; 9]) -> QasControl {
        let fit = |x: &[DVec3; 9]| match kind {
            QasKind::Quad => quad_coefficients(x),
            QasKind::Triangle | QasKind::Fan => {
                let t = tri_coefficients(&[x[0], x[1], x[2], x[3], x[4], x[5]]);
                let mut out = [DVec3::ZERO; 9];
                out[..6].copy_from_slice(&t);
                out
            }
        };
        QasControl {
            kind,
            position: fit(p),
            normal: fit(n),
        }
    }

    fn eval3(&self, c: &[DVec3; 9], u: f64, v: f64) -> (DVec3, DVec3, DVec3) {
        match self.kind {
            QasKind::Quad => eval_quad(c, u, v),
            QasKind::Triangle | QasKind::Fan => {
                eval_tri(&[c[0], c[1], c[2], c[3], c[4], c[5]], u, v)
            }
        }
    }

    /// Position and unit shading normal (the normal patch, normalised) at `(u, v)`: the quad's
    /// domain, or a triangle's (or fan triangle's) barycentric weights of corners 1 and 2.
    pub fn eval(&self, u: f64, v: f64) -> (DVec3, DVec3) {
        let p = self.eval3(&self.position, u, v).0;
        let n = self.eval3(&self.normal, u, v).0;
        (p, n.normalize_or_zero())
    }

    /// The geometric unit normal of the position patch, `normalize(dP/du x dP/dv)`.
    pub fn geometric_normal(&self, u: f64, v: f64) -> DVec3 {
        let (_, pu, pv) = self.eval3(&self.position, u, v);
        pu.cross(pv).normalize_or_zero()
    }
}

/// The QAS patches of a set of faces and the sparse rows of their limit points over the control
/// vertices (fixed for the topology; [`QasSurface::points`] applies them).
#[derive(Debug, Clone)]
pub struct QasSurface {
    /// Patches, quads first, then triangles, then n-gon fans (draw order), each group by face
    /// (fans by face and `k`).
    pub patches: Vec<QasPatch>,
    position: SparseMatrix,
    tangent_u: SparseMatrix,
    tangent_v: SparseMatrix,
}

/// A limit point of the step, in the level-1 mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum Node {
    /// Level-1 vertex `.0`, with a level-1 face `.1` holding it (its sector, for normals).
    Vertex(u32, u32),
    /// The centre of level-1 face `.0` (the limit of its level-2 face point).
    Centre(u32),
}

/// The row of `key` in `map`, appended to `list` if new.
fn row_of(map: &mut HashMap<Node, u32>, list: &mut Vec<Node>, key: Node) -> u32 {
    *map.entry(key).or_insert_with(|| {
        list.push(key);
        list.len() as u32 - 1
    })
}

impl QasSurface {
    /// The patches of `faces` of `topo` (faces with a limit surface) and the refused faces.
    pub fn build(topo: &Topology, faces: &[u32]) -> (QasSurface, Vec<NotQas>) {
        let base = Level::from_topology(topo.clone());
        let (level, refine) = base.refine();
        let t1 = level.topology();
        let mut refused = Vec::new();
        let mut slots: Vec<(u32, QasKind, Option<u32>, [Node; 9])> = Vec::new();
        for &f in faces {
            match topo.face_size(f) {
                3 => slots.push((f, QasKind::Triangle, None, face_slots(&base, f, false))),
                4 => slots.push((f, QasKind::Quad, None, face_slots(&base, f, true))),
                n => slots.extend(
                    (0..n as u32).map(|k| (f, QasKind::Fan, Some(k), fan_slots(&base, f, k))),
                ),
            }
        }
        // Quads, then triangles, then fans (one draw per shape; triangles and fans share one).
        let order = |k: QasKind| match k {
            QasKind::Quad => 0,
            QasKind::Triangle => 1,
            QasKind::Fan => 2,
        };
        slots.sort_by_key(|s| (order(s.1), s.0, s.2));

        // One position row per limit point, one normal row per (vertex, sector) or centre.
        let mut position_rows: HashMap<Node, u32> = HashMap::new();
        let mut normal_rows: HashMap<Node, u32> = HashMap::new();
        let mut position_list = Vec::new();
        let mut normal_list = Vec::new();
        let mut patches = Vec::with_capacity(slots.len());
        for (face, kind, fan, s) in &slots {
            let mut points = [0u32; 9];
            let mut normals = [0u32; 9];
            for k in 0..kind.points() {
                let (position_key, normal_key) = match s[k] {
                    Node::Vertex(w, g) => (
                        Node::Vertex(w, t1.vertex_faces(w)[0]),
                        Node::Vertex(w, sector_face(t1, w, g)),
                    ),
                    centre => (centre, centre),
                };
                points[k] = row_of(&mut position_rows, &mut position_list, position_key);
                normals[k] = row_of(&mut normal_rows, &mut normal_list, normal_key);
            }
            let fv = topo.face_vertices(*face);
            let corners = match fan {
                Some(k) => {
                    let k = *k as usize;
                    [FAN_CENTRE, fv[k], fv[(k + 1) % fv.len()], FAN_CENTRE]
                }
                None => [fv[0], fv[1], fv[2], fv[if fv.len() == 4 { 3 } else { 0 }]],
            };
            patches.push(QasPatch {
                face: *face,
                kind: *kind,
                fan: *fan,
                corners,
                points,
                normals,
            });
        }
        let masks = |keys: &[Node]| -> Vec<std::result::Result<VertexMask, String>> {
            keys.par_iter()
                .map(|&key| {
                    match key {
                        Node::Vertex(w, g) => vertex_mask(&level, w, g),
                        Node::Centre(g) => face_point_mask(&level, g),
                    }
                    .map_err(|e| e.to_string())
                })
                .collect()
        };
        let vmasks = masks(&position_list);
        let smasks = masks(&normal_list);
        // A face whose masks failed is refused (none is expected for faces with a limit
        // surface: the masks cover every vertex rule of the crate).
        let failed = |p: &QasPatch| {
            (0..p.kind.points()).find_map(|k| {
                let v = &vmasks[p.points[k] as usize];
                let s = &smasks[p.normals[k] as usize];
                v.as_ref().err().or(s.as_ref().err()).cloned()
            })
        };
        // (An n-gon is refused whole: the first of its fans that failed names the reason.)
        let mut failed_faces = std::collections::HashSet::new();
        for p in &patches {
            if let Some(why) = failed(p) {
                if failed_faces.insert(p.face) {
                    refused.push(NotQas::Mask { face: p.face, why });
                }
            }
        }
        patches.retain(|p| !failed_faces.contains(&p.face));
        let compose = |masks: &[std::result::Result<VertexMask, String>], which: usize| {
            SparseMatrix::compose_rows(masks.len(), &refine, |r, buf| {
                if let Ok(m) = &masks[r] {
                    let w = [&m.position, &m.tangent_u, &m.tangent_v][which];
                    buf.extend(m.indices.iter().copied().zip(w.iter().copied()));
                }
            })
        };
        let surface = QasSurface {
            patches,
            position: compose(&vmasks, 0),
            tangent_u: compose(&smasks, 1),
            tangent_v: compose(&smasks, 2),
        };
        (surface, refused)
    }

    /// Position rows (one per level-1 limit point used).
    pub fn position_rows(&self) -> usize {
        self.position.rows()
    }

    /// Normal rows (one per level-1 limit point and sector used).
    pub fn normal_rows(&self) -> usize {
        self.tangent_u.rows()
    }

    /// Stored stencil weights (positions and both tangents).
    pub fn stencil_weights(&self) -> usize {
        self.position.nnz() + self.tangent_u.nnz() + self.tangent_v.nnz()
    }

    /// Every limit point and normal for control positions `positions`.
    pub fn points(&self, positions: &[DVec3]) -> QasPoints {
        let tu = self.tangent_u.apply_vec(positions);
        let tv = self.tangent_v.apply_vec(positions);
        QasPoints {
            positions: self.position.apply_vec(positions),
            normals: tu
                .iter()
                .zip(&tv)
                .map(|(a, b)| a.cross(*b).normalize_or_zero())
                .collect(),
        }
    }

    /// The fitted patches of patch `i` from precomputed `points`.
    pub fn control(&self, i: usize, points: &QasPoints) -> QasControl {
        let p = &self.patches[i];
        let mut pos = [DVec3::ZERO; 9];
        let mut nrm = [DVec3::ZERO; 9];
        for k in 0..p.kind.points() {
            pos[k] = points.positions[p.points[k] as usize];
            nrm[k] = points.normals[p.normals[k] as usize];
        }
        QasControl::fit(p.kind, &pos, &nrm)
    }

    /// The fitted patches of patch `i` computed from the control positions (only its rows).
    pub fn control_from(&self, i: usize, positions: &[DVec3]) -> QasControl {
        let p = &self.patches[i];
        let apply = |m: &SparseMatrix, r: u32| {
            let (idx, w) = m.row(r as usize);
            idx.iter()
                .zip(w)
                .fold(DVec3::ZERO, |acc, (&c, &x)| acc + positions[c as usize] * x)
        };
        let mut pos = [DVec3::ZERO; 9];
        let mut nrm = [DVec3::ZERO; 9];
        for k in 0..p.kind.points() {
            pos[k] = apply(&self.position, p.points[k]);
            let (a, b) = (
                apply(&self.tangent_u, p.normals[k]),
                apply(&self.tangent_v, p.normals[k]),
            );
            nrm[k] = a.cross(b).normalize_or_zero();
        }
        QasControl::fit(p.kind, &pos, &nrm)
    }

    /// The index of fan triangle `k` of n-gon `face`, if drawn.
    pub fn fan_patch(&self, face: u32, k: u32) -> Option<usize> {
        self.patches
            .iter()
            .position(|p| p.face == face && p.fan == Some(k))
    }

    /// Position and unit shading normal of n-gon `face` (`n` sides) at point `(u, v)` of its
    /// sub-face `sub` (the parameters the GPU captures, module docs), computed from the control
    /// positions; `None` if the face is not drawn as a fan.
    pub fn eval_sub_face(
        &self,
        positions: &[DVec3],
        face: u32,
        n: u32,
        sub: u32,
        u: f64,
        v: f64,
    ) -> Option<(DVec3, DVec3)> {
        let (k, w1, w2) = sub_face_to_fan(sub, n, u, v);
        let i = self.fan_patch(face, k)?;
        Some(self.control_from(i, positions).eval(w1, w2))
    }
}

/// The limit point of each slot of face `f` (quad or triangle): corners (vertex points, in the
/// child face of that corner), edge midpoints (edge points, in the child face of the edge's
/// first corner) and, for quads, the centre (face point).
fn face_slots(base: &Level, f: u32, quad: bool) -> [Node; 9] {
    let mut s = [Node::Centre(0); 9];
    for k in 0..base.topology().face_size(f) {
        let (corner, edge) = (corner_node(base, f, k), edge_node(base, f, k));
        if quad {
            s[QUAD_CORNER_SLOTS[k]] = corner;
            s[QUAD_EDGE_SLOTS[k]] = edge;
        } else {
            s[k] = corner;
            s[3 + k] = edge;
        }
    }
    if quad {
        s[QUAD_CENTRE_SLOT] = Node::Vertex(base.child_face_point(f), base.child_faces(f).start);
    }
    s
}

/// The limit points of fan triangle `k` of n-gon `f` in the triangle's slots ([`QasKind::Fan`]).
fn fan_slots(base: &Level, f: u32, k: u32) -> [Node; 9] {
    let n = base.topology().face_size(f) as u32;
    let child = base.child_faces(f).start;
    let next = (k + 1) % n;
    let mut s = [Node::Centre(0); 9];
    s[0] = Node::Vertex(base.child_face_point(f), child);
    s[1] = corner_node(base, f, k as usize);
    s[2] = corner_node(base, f, next as usize);
    s[3] = Node::Centre(child + k);
    s[4] = edge_node(base, f, k as usize);
    s[5] = Node::Centre(child + next);
    s
}

/// Corner `k` of face `f`: its vertex point, in the child face (sub-face) at that corner.
fn corner_node(base: &Level, f: u32, k: usize) -> Node {
    let v = base.topology().face_vertices(f)[k];
    Node::Vertex(
        base.child_vertex_point(v),
        base.child_faces(f).start + k as u32,
    )
}

/// Edge `k -> k + 1` of face `f`: its edge point, in sub-face `k`.
fn edge_node(base: &Level, f: u32, k: usize) -> Node {
    let e = base.topology().face_edges(f)[k];
    Node::Vertex(
        base.child_edge_point(e),
        base.child_faces(f).start + k as u32,
    )
}

/// The smallest face of face `g`'s sector at vertex `w` (faces around `w` joined across edges
/// that are neither boundaries nor infinitely sharp): the canonical key of the sector's normal.
fn sector_face(topo: &Topology, w: u32, g: u32) -> u32 {
    let faces = topo.vertex_faces(w);
    let mut label: Vec<u32> = faces.to_vec();
    let joins: Vec<(usize, usize)> = topo
        .vertex_edges(w)
        .iter()
        .filter(|&&e| !is_sharp_edge(topo, e))
        .filter_map(|&e| match topo.edge_faces(e) {
            [a, b] => Some((
                faces.iter().position(|x| x == a)?,
                faces.iter().position(|x| x == b)?,
            )),
            _ => None,
        })
        .collect();
    // Propagate the smallest face id along the joins until nothing changes (rings are small).
    loop {
        let mut changed = false;
        for &(a, b) in &joins {
            let m = label[a].min(label[b]);
            if label[a] != m || label[b] != m {
                label[a] = m;
                label[b] = m;
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    faces.iter().position(|&x| x == g).map_or(g, |i| label[i])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sub-face map of fan points and its inverse: corners, the edge midpoint and the centre
    /// land where the module docs say, and every point off the spoke `F V_{k+1}` (which the
    /// inverse names from triangle `k + 1`) comes back to its own triangle and weights.
    #[test]
    fn fan_sub_face_map_round_trips() {
        let (k, n) = (4, 5);
        assert_eq!(fan_to_sub_face(k, n, [1.0, 0.0, 0.0]), (4, 1.0, 1.0));
        assert_eq!(fan_to_sub_face(k, n, [0.0, 1.0, 0.0]), (4, 0.0, 0.0));
        assert_eq!(fan_to_sub_face(k, n, [0.0, 0.0, 1.0]), (0, 0.0, 0.0));
        assert_eq!(fan_to_sub_face(k, n, [0.0, 0.5, 0.5]), (4, 1.0, 0.0));
        assert_eq!(fan_to_sub_face(k, n, [0.5, 0.5, 0.0]), (4, 0.5, 0.5));
        assert_eq!(fan_to_sub_face(k, n, [0.5, 0.0, 0.5]), (0, 0.5, 0.5));
        for j in 0..=8 {
            for i in 0..=8 - j {
                let (w1, w2) = (f64::from(i) / 8.0, f64::from(j) / 8.0);
                let (sub, u, v) = fan_to_sub_face(k, n, [1.0 - w1 - w2, w1, w2]);
                assert!((0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v));
                let (t, x1, x2) = sub_face_to_fan(sub, n, u, v);
                if w1 == 0.0 && w2 > 0.0 {
                    // On the spoke F V_{k+1}: triangle k + 1's spoke F V_{k+1} (its corner 1).
                    assert_eq!((t, x2), (0, 0.0));
                    assert!((x1 - w2).abs() < 1e-15);
                } else {
                    assert_eq!(t, k);
                    assert!((x1 - w1).abs() < 1e-15 && (x2 - w2).abs() < 1e-15);
                }
            }
        }
    }
}
