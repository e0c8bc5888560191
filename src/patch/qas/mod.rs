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
//! - Faces of five or more sides are refused ([`NotQas::Polygon`]) and stay on the exact CPU path.
//!
//! Each point is a sparse row over the control vertices (the one-step refinement matrix
//! composed with the level-1 limit mask, [`QasSurface`]), so animation re-applies the rows.
//! Positions have one row per level-1 vertex, so faces sharing a corner or an edge get the same
//! bits. Normals have one row pair (two tangents) per level-1 vertex and *sector* (faces around
//! it not separated by a boundary or infinitely sharp edge): both faces of a smooth edge read the
//! same normal row, the two sides of a crease their own. At a cusp (an infinitely sharp vertex
//! with fewer than two sharp edges: one sector) the limit has no normal, each face's mask gives
//! its own; QAS takes the one of the sector's smallest face, so the smooth edges there stay
//! watertight in their normals too.
//!
//! Accuracy drops where the normal turns fast and unevenly across a face (the quadratic through
//! three normals overshoots; e.g. the bishop's tight lathe bands: README figures), and, as the
//! paper says, at high valences.

pub mod bezier;

use std::collections::HashMap;
use std::fmt;

use glam::DVec3;
use rayon::prelude::*;

use crate::subdiv::limit::{vertex_mask, VertexMask};
use crate::subdiv::{Level, SparseMatrix};
use crate::topology::{is_sharp_edge, Topology};
use bezier::{eval_quad, eval_tri, quad_coefficients, tri_coefficients};
pub use bezier::{QUAD_CENTRE_SLOT, QUAD_CORNER_SLOTS, QUAD_EDGE_SLOTS};

/// Why QAS does not draw a face.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum NotQas {
    /// Neither a triangle nor a quad.
    Polygon {
        /// The face.
        face: u32,
        /// Its number of sides.
        sides: usize,
    },
    /// A limit mask of one of the face's level-1 vertices failed.
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
            NotQas::Polygon { face, .. } | NotQas::Mask { face, .. } => *face,
        }
    }
}

impl fmt::Display for NotQas {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            NotQas::Polygon { face, sides } => write!(
                f,
                "face {face}: {sides} sides (QAS draws triangles and quads; n-gons stay on the exact CPU path)"
            ),
            NotQas::Mask { face, why } => write!(f, "face {face}: {why}"),
        }
    }
}

/// The shape of a QAS patch.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum QasKind {
    /// Biquadratic, 9 points (slots `3 j + i`, [`QUAD_CORNER_SLOTS`], [`QUAD_EDGE_SLOTS`]).
    Quad,
    /// Quadratic triangle, 6 points: corners 0-2, then the midpoints of edges 0-2.
    Triangle,
}

impl QasKind {
    /// Limit points (and Bézier coefficients) per patch.
    pub fn points(self) -> usize {
        match self {
            QasKind::Quad => 9,
            QasKind::Triangle => 6,
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
    /// Base vertex ids of the corners (a triangle repeats corner 0 last).
    pub corners: [u32; 4],
    /// Position row of each point slot (unused slots 0).
    pub points: [u32; 9],
    /// Normal row of each point slot.
    pub normals: [u32; 9],
}

impl QasPatch {
    /// The point slots of the corners, in corner order.
    pub fn corner_slots(&self) -> &'static [usize] {
        match self.kind {
            QasKind::Quad => &QUAD_CORNER_SLOTS,
            QasKind::Triangle => &[0, 1, 2],
        }
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
            QasKind::Triangle => {
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
            QasKind::Triangle => eval_tri(&[c[0], c[1], c[2], c[3], c[4], c[5]], u, v),
        }
    }

    /// Position and unit shading normal (the normal patch, normalised) at `(u, v)`: the quad's
    /// domain, or a triangle's barycentric weights of corners 1 and 2.
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
    /// Patches, quads first, then triangles (draw order), each group by face.
    pub patches: Vec<QasPatch>,
    position: SparseMatrix,
    tangent_u: SparseMatrix,
    tangent_v: SparseMatrix,
}

/// A level-1 limit point of a face: the level-1 vertex and a level-1 face of its sector.
type Slot = (u32, u32);

impl QasSurface {
    /// The patches of `faces` of `topo` (faces with a limit surface) and the refused faces.
    pub fn build(topo: &Topology, faces: &[u32]) -> (QasSurface, Vec<NotQas>) {
        let base = Level::from_topology(topo.clone());
        let (level, refine) = base.refine();
        let t1 = level.topology();
        let mut refused = Vec::new();
        let mut slots: Vec<(u32, QasKind, [Slot; 9])> = Vec::new();
        for &f in faces {
            let n = topo.face_size(f);
            let kind = match n {
                3 => QasKind::Triangle,
                4 => QasKind::Quad,
                _ => {
                    refused.push(NotQas::Polygon { face: f, sides: n });
                    continue;
                }
            };
            slots.push((f, kind, face_slots(&base, f, kind)));
        }
        // Quads first, then triangles (one draw per shape).
        slots.sort_by_key(|s| (s.1 == QasKind::Triangle, s.0));

        // One position row per level-1 vertex, one normal row per (vertex, sector).
        let mut vertex_rows: HashMap<u32, u32> = HashMap::new();
        let mut sector_rows: HashMap<Slot, u32> = HashMap::new();
        let mut vertex_list = Vec::new();
        let mut sector_list = Vec::new();
        let mut patches = Vec::with_capacity(slots.len());
        for (face, kind, s) in &slots {
            let mut points = [0u32; 9];
            let mut normals = [0u32; 9];
            for k in 0..kind.points() {
                let (w, g) = s[k];
                points[k] = *vertex_rows.entry(w).or_insert_with(|| {
                    vertex_list.push(w);
                    vertex_list.len() as u32 - 1
                });
                let key = (w, sector_face(t1, w, g));
                normals[k] = *sector_rows.entry(key).or_insert_with(|| {
                    sector_list.push(key);
                    sector_list.len() as u32 - 1
                });
            }
            let fv = topo.face_vertices(*face);
            let corners = [fv[0], fv[1], fv[2], fv[if fv.len() == 4 { 3 } else { 0 }]];
            patches.push(QasPatch {
                face: *face,
                kind: *kind,
                corners,
                points,
                normals,
            });
        }
        let masks = |keys: &[Slot]| -> Vec<std::result::Result<VertexMask, String>> {
            keys.par_iter()
                .map(|&(w, g)| vertex_mask(&level, w, g).map_err(|e| e.to_string()))
                .collect()
        };
        let vertex_keys: Vec<Slot> = vertex_list
            .iter()
            .map(|&w| (w, t1.vertex_faces(w)[0]))
            .collect();
        let vmasks = masks(&vertex_keys);
        let smasks = masks(&sector_list);
        // A face whose masks failed is refused (none is expected for faces with a limit
        // surface: the masks cover every vertex rule of the crate).
        let failed = |p: &QasPatch| {
            (0..p.kind.points()).find_map(|k| {
                let v = &vmasks[p.points[k] as usize];
                let s = &smasks[p.normals[k] as usize];
                v.as_ref().err().or(s.as_ref().err()).cloned()
            })
        };
        patches.retain(|p| match failed(p) {
            Some(why) => {
                refused.push(NotQas::Mask { face: p.face, why });
                false
            }
            None => true,
        });
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
}

/// The level-1 vertex and a level-1 face holding it for each point slot of face `f`: corners
/// (vertex points, in the child face of that corner), edge midpoints (edge points, in the child
/// face of the edge's first corner) and, for quads, the centre (face point).
fn face_slots(base: &Level, f: u32, kind: QasKind) -> [Slot; 9] {
    let topo = base.topology();
    let fv = topo.face_vertices(f);
    let fe = topo.face_edges(f);
    let child = base.child_faces(f).start;
    let corner = |k: usize| (base.child_vertex_point(fv[k]), child + k as u32);
    let edge = |k: usize| (base.child_edge_point(fe[k]), child + k as u32);
    let mut s = [(0, 0); 9];
    match kind {
        QasKind::Quad => {
            for k in 0..4 {
                s[QUAD_CORNER_SLOTS[k]] = corner(k);
                s[QUAD_EDGE_SLOTS[k]] = edge(k);
            }
            s[QUAD_CENTRE_SLOT] = (base.child_face_point(f), child);
        }
        QasKind::Triangle => {
            for k in 0..3 {
                s[k] = corner(k);
                s[3 + k] = edge(k);
            }
        }
    }
    s
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
