//! One feature-adaptive step made in place ([`refine_in_place`]): as OpenSubdiv's
//! `Vtr::Refinement` refines a sparse selection of its parent level (`vtr/refinement.cpp`,
//! `vtr/quadRefinement.cpp`), the kept child quads, their vertices, edges and one-rings are
//! written straight from the parent level's relations, with no sub-level extracted and no
//! bucketing: a face point's ring is its face's children, an edge point's the children beside
//! its edge, a vertex point's the children at its vertex's faces in its ring's order.
//!
//! The child level is the refinement of the sub-level the step's faces make
//! ([`Level::extract_increasing`] then [`Level::refine_kept`], kept as
//! `AdaptiveLevel::uniform_step` to check it against) up to numbering and ring starts: child
//! points are numbered by kind (face, edge, vertex points), each kind by first appearance among
//! the kept quads' corners, edges by first appearance among the quads' edges, and each ring
//! starts where its parent's does, not where `topology::build` would start it.

use super::kept::KeptEdges;
use super::level::Level;
use super::rules::{child_edge_sharpness, decrement};
use crate::topology::{self, Topology, NONE};
use crate::{Error, Result};

/// The parent components of a step's child points in the child numbering: face points, then
/// edge points, then vertex points (parent level ids); and the parent faces of its child quads.
#[derive(Debug, Clone, Default)]
pub(super) struct StepPoints {
    /// The parent faces of the face points.
    pub faces: Vec<u32>,
    /// The parent edges of the edge points.
    pub edges: Vec<u32>,
    /// The parent vertices of the vertex points.
    pub vertices: Vec<u32>,
    /// Per child quad (the child level's faces, in order): the parent face it is a child of;
    /// increasing. Filled when the step is made.
    pub quad_faces: Vec<u32>,
}

/// The child faces `keep` (flat corners of `level`, increasing) of the step refining `level`'s
/// faces `ring` (increasing) as a level of their own, and its child points' parents. Every kept
/// child's face must be in `ring` and every face at its corner vertex too (the adaptive step
/// keeps the children of refined faces and, of the faces around their vertices, the children at
/// those vertices): the rings and sharpness around a kept corner are then the level's. A vertex
/// or edge touching a face outside `ring` is incomplete in the child level (see [`Level`]),
/// as are child edges and vertices missing a child face of the whole refinement.
pub(super) fn refine_in_place(
    level: &Level,
    ring: &[u32],
    keep: &[u32],
) -> Result<(Level, StepPoints)> {
    let t = level.topology();
    if keep.is_empty() {
        return Err(Error::EmptyMesh("topology needs vertices and faces".into()));
    }
    let mut in_ring = vec![false; t.face_count()];
    for (i, &f) in ring.iter().enumerate() {
        if f as usize >= t.face_count() || (i > 0 && f <= ring[i - 1]) {
            return Err(Error::Invalid(format!(
                "adaptive step: ring face {i} is {f}: faces must increase and be below {}",
                t.face_count()
            )));
        }
        in_ring[f as usize] = true;
    }
    // Per vertex: a corner of a face not in `ring`.
    let mut outside = vec![false; t.vertex_count()];
    for (f, _) in in_ring.iter().enumerate().filter(|x| !x.1) {
        for &v in t.face_vertices(f as u32) {
            outside[v as usize] = true;
        }
    }
    let fc = FaceCorners::of(t);
    let quads = KeptQuads::new(t, fc, &in_ring, &outside, keep)?;
    let nk = keep.len();
    let nv = quads.points.faces.len() + quads.points.edges.len() + quads.points.vertices.len();
    let edges = child_edges(level, fc, &quads, keep);
    let face_offsets: Vec<u32> = (0..=nk as u32).map(|i| 4 * i).collect();
    let rings = child_rings(
        t,
        fc,
        &quads,
        &face_offsets,
        &edges.face_edges,
        edges.verts.len(),
    );
    let connectivity = topology::Connectivity {
        face_offsets,
        face_verts: quads.corners,
        face_edges: edges.face_edges,
        edge_verts: edges.verts,
        edge_faces: edges.faces,
        edge_face_local: edges.locals,
    };
    let holes = quads
        .parent_face
        .iter()
        .map(|&f| t.holes[f as usize])
        .collect();
    let mut sub = topology::with_given_rings(nv, connectivity, rings, 4, edges.sharpness, holes);
    if !t.no_limit.is_empty() {
        sub.no_limit = quads
            .parent_face
            .iter()
            .map(|&f| t.no_limit[f as usize])
            .collect();
    }
    sub.options = t.options;
    let mut points = quads.points;
    points.quad_faces = quads.parent_face;
    let incomplete = incomplete_points(level, &sub, &points, (ring, &in_ring), &outside);
    let first_vertex = points.faces.len() + points.edges.len();
    for (j, &pv) in points.vertices.iter().enumerate() {
        sub.vertex_sharpness[first_vertex + j] = decrement(t.vertex_sharpness[pv as usize]);
    }
    Ok((Level::with_flags(sub, edges.cut, incomplete), points))
}

/// The kept child quads of a step: per parent corner its kept child, per child its parent face
/// and corners (the child numbering of [`StepPoints`]).
struct KeptQuads {
    /// Per parent corner: its kept child's index, or NONE.
    kept: Vec<u32>,
    /// Per kept child: its parent face.
    parent_face: Vec<u32>,
    /// Per kept child `i`, corners `4 i..4 i + 4`: the vertex point of its parent corner, the
    /// edge point of the corner's edge, the face point, the edge point of the previous edge.
    corners: Vec<u32>,
    /// The child points' parents.
    points: StepPoints,
}

impl KeptQuads {
    /// The kept children `keep` of `t` (as [`refine_in_place`] takes them), checked.
    fn new(
        t: &Topology,
        fc: FaceCorners,
        in_ring: &[bool],
        outside: &[bool],
        keep: &[u32],
    ) -> Result<KeptQuads> {
        let nk = keep.len();
        let mut kept = vec![NONE; t.corner_count()];
        let mut parent_face = Vec::with_capacity(nk);
        let mut points = StepPoints {
            faces: Vec::with_capacity(nk),
            edges: Vec::with_capacity(2 * nk),
            vertices: Vec::with_capacity(nk),
            quad_faces: Vec::new(),
        };
        let mut edge_point = vec![NONE; t.edge_count()];
        let mut vertex_point = vec![NONE; t.vertex_count()];
        // Each child's corners in one pass, each point by its index among its kind; the kinds'
        // offsets are added once their counts are known. Face points are numbered in increasing
        // face order (`keep` increases), so a child's is the number of faces seen, less one.
        let mut corners = Vec::with_capacity(4 * nk);
        let mut f = 0usize;
        for (i, &h) in keep.iter().enumerate() {
            if h as usize >= t.corner_count() || (i > 0 && h <= keep[i - 1]) {
                return Err(Error::Invalid(format!(
                    "adaptive step: child face {i} is corner {h}: corners must increase and be \
                     below {}",
                    t.corner_count()
                )));
            }
            if fc.quads_only {
                f = h as usize / 4;
            } else {
                while t.face_offsets[f + 1] <= h {
                    f += 1;
                }
            }
            let v = t.face_verts[h as usize];
            if !in_ring[f] || outside[v as usize] {
                return Err(Error::Invalid(format!(
                    "adaptive step: child face {i} (corner {h} of face {f}, vertex {v}): its \
                     face and every face at its vertex must be refined or in the ring"
                )));
            }
            kept[h as usize] = i as u32;
            parent_face.push(f as u32);
            if points.faces.last() != Some(&(f as u32)) {
                points.faces.push(f as u32);
            }
            let face_point = points.faces.len() as u32 - 1;
            let (off, end) = fc.range(f as u32);
            let hp = if h == off { end - 1 } else { h - 1 } as usize;
            let next_point = point_of(&mut edge_point, &mut points.edges, t.face_edges[h as usize]);
            let prev_point = point_of(&mut edge_point, &mut points.edges, t.face_edges[hp]);
            let vertex = point_of(&mut vertex_point, &mut points.vertices, v);
            corners.extend_from_slice(&[vertex, next_point, face_point, prev_point]);
        }
        let (nfp, nep) = (points.faces.len() as u32, points.edges.len() as u32);
        for quad in corners.chunks_exact_mut(4) {
            quad[0] += nfp + nep;
            quad[1] += nfp;
            quad[3] += nfp;
        }
        Ok(KeptQuads {
            kept,
            parent_face,
            corners,
            points,
        })
    }

    /// The kept child at corner `k` of parent face `g` (NONE if none).
    fn child(&self, fc: FaceCorners, g: u32, k: u32) -> u32 {
        self.kept[(fc.range(g).0 + k) as usize]
    }
}

/// The index of parent component `x`'s child point among its kind (`points`, the parents of
/// that kind's points in order; `index`, per parent component, its point or NONE), numbered on
/// first sight.
#[inline(always)]
fn point_of(index: &mut [u32], points: &mut Vec<u32>, x: u32) -> u32 {
    let p = &mut index[x as usize];
    if *p == NONE {
        *p = points.len() as u32;
        points.push(x);
    }
    *p
}

/// The edges of a step's child level, numbered by first appearance among the kept quads' edges
/// (quad `i`'s edge `k` joins its corners `k` and `k + 1`: edges 0 and 3 halves of the parent
/// corner's edges, 1 and 2 spokes to the face point).
///
/// Each kept quad's edges (`keep` the quads' parent corners): a spoke is shared with the
/// neighbouring child of the same face, a half of a parent edge with the child at the same
/// end in the face across it; a half takes its parent edge's child sharpness
/// (`rules::child_edge_sharpness`) and is cut where its parent edge is or where the child
/// across is not kept though the parent edge has a second face.
fn child_edges(level: &Level, fc: FaceCorners, quads: &KeptQuads, keep: &[u32]) -> KeptEdges {
    let t = level.topology();
    let mut edges = KeptEdges::new(quads.parent_face.len());
    // A spoke, child `i`'s edge `local` (1: to the edge point of the corner's edge, 2: to the
    // previous edge's), shared with the child at the next corner (as its edge 2), or at the
    // previous one (its edge 1).
    let spoke = |edges: &mut KeptEdges, (i, local): (u32, u16), c: u32| {
        let other = (c != NONE).then_some((c, 3 - local));
        edges.push(&quads.corners, (i, local), other, 0.0, c == NONE);
    };
    for (i, (&h, &f)) in keep.iter().zip(&quads.parent_face).enumerate() {
        let i = i as u32;
        // Flat corners: `h`, the next and the previous of its face (the face's range read
        // once per child).
        let (off, end) = fc.range(f);
        let (next, prev) = (next_in(h, off, end), if h == off { end - 1 } else { h - 1 });
        let v = t.face_verts[h as usize];
        let unmade =
            |edges: &KeptEdges, local: usize| edges.face_edges[4 * i as usize + local] == NONE;
        if unmade(&edges, 0) {
            let e = t.face_edges[h as usize];
            push_half(level, fc, quads, &mut edges, (i, 0), (f, e, h - off, v));
        }
        if unmade(&edges, 1) {
            spoke(&mut edges, (i, 1), quads.kept[next as usize]);
        }
        if unmade(&edges, 2) {
            spoke(&mut edges, (i, 2), quads.kept[prev as usize]);
        }
        if unmade(&edges, 3) {
            let e = t.face_edges[prev as usize];
            push_half(level, fc, quads, &mut edges, (i, 3), (f, e, prev - off, v));
        }
    }
    edges
}

/// The half at `v` of parent edge `e` (the edge `kf` of face `f`) as kept child `i`'s edge
/// `local` (0: the corner's edge, 3: the previous one) of a step of `level` ([`child_edges`]):
/// shared with the child at `v` in the face across (where the edge is entering, or leaving,
/// `v`: at the next corner of `e`'s corner there, or at that corner), as its edge 3, or 0.
/// Inlined into its two calls (a call a parent edge half, most of a step's edges).
#[inline(always)]
fn push_half(
    level: &Level,
    fc: FaceCorners,
    quads: &KeptQuads,
    edges: &mut KeptEdges,
    (i, local): (u32, u16),
    (f, e, kf, v): (u32, u32, u32, u32),
) {
    let t = level.topology();
    let (g, kg) = across(t, e, f, kf);
    let c = if g == NONE {
        NONE
    } else {
        let (off, end) = fc.range(g);
        let corner = off + kg;
        let corner = if local == 0 {
            next_in(corner, off, end)
        } else {
            corner
        };
        quads.kept[corner as usize]
    };
    let cut = (c == NONE && g != NONE) || level.is_cut_edge(e);
    // A smooth parent edge has smooth halves (`rules::child_sharpness`): most edges, with no
    // call.
    let sharpness = if t.edge_sharpness[e as usize] == 0.0 {
        0.0
    } else {
        child_edge_sharpness(t, e, v)
    };
    let other = (c != NONE).then_some((c, 3 - local));
    edges.push(&quads.corners, (i, local), other, sharpness, cut);
}

/// The flat corner ranges of a parent level's faces: by quad arithmetic on a level of quads
/// only (every level after the first, [`Topology::quads_only`]), from the face offsets
/// otherwise.
#[derive(Clone, Copy)]
struct FaceCorners<'a> {
    offsets: &'a [u32],
    quads_only: bool,
}

impl<'a> FaceCorners<'a> {
    fn of(t: &'a Topology) -> FaceCorners<'a> {
        FaceCorners {
            offsets: &t.face_offsets,
            quads_only: t.quads_only(),
        }
    }

    /// The flat corners `off..end` of face `f`.
    #[inline(always)]
    fn range(self, f: u32) -> (u32, u32) {
        if self.quads_only {
            (4 * f, 4 * f + 4)
        } else {
            (self.offsets[f as usize], self.offsets[f as usize + 1])
        }
    }
}

/// The flat corner after `h` in the face of corners `off..end`, cyclically.
#[inline(always)]
fn next_in(h: u32, off: u32, end: u32) -> u32 {
    if h + 1 == end {
        off
    } else {
        h + 1
    }
}

/// The face across parent edge `e` from face `f`, whose edge `kf` it is, and `e`'s index in
/// that face; `(NONE, 0)` on a boundary.
fn across(t: &Topology, e: u32, f: u32, kf: u32) -> (u32, u32) {
    let [f0, f1] = t.edge_faces[e as usize];
    let [k0, k1] = t.edge_face_local[e as usize];
    if f0 == f && u32::from(k0) == kf {
        (f1, u32::from(k1))
    } else {
        (f0, u32::from(k0))
    }
}

/// The one-rings of a step's child level (`quads`, its quads' `face_offsets` and
/// `face_edges`, `edge_count` edges), in the child numbering, written from the parent `t`'s:
/// a face point's ring is its face's children (corner 2) in corner order, an edge point's the
/// children beside the edge (corners 1 and 3; `Level::refine_topology`'s order), a vertex
/// point's the children at its faces' corners (corner 0) in its ring's order, fan by fan. Each ring starts where its
/// parent's does ([`topology::RingBuilder::try_quad_cycle`] for a closed ring with every child
/// kept, [`topology::RingBuilder::quad_fan_as_given`] otherwise).
fn child_rings(
    t: &Topology,
    fc: FaceCorners,
    quads: &KeptQuads,
    face_offsets: &[u32],
    face_edges: &[u32],
    edge_count: usize,
) -> topology::Rings {
    let nk = quads.parent_face.len();
    let points = &quads.points;
    let nv = points.faces.len() + points.edges.len() + points.vertices.len();
    let mut rings = topology::RingBuilder::new(face_offsets, face_edges, nv, 4 * nk, edge_count);
    // Each point's fan in parent ring order, gathered once: written as one cycle when closed
    // with every child kept, as runs otherwise.
    let mut fan = Vec::with_capacity(16);
    for &f in &points.faces {
        let (a, b) = fc.range(f);
        fan.clear();
        fan.extend(quads.kept[a as usize..b as usize].iter().map(|&i| (i, 2)));
        closed_fan(&mut rings, &fan);
    }
    for &e in &points.edges {
        let [f0, f1] = t.edge_faces[e as usize];
        let [k0, k1] = t.edge_face_local[e as usize];
        let (k0, k1) = (u32::from(k0), u32::from(k1));
        let beside = |g: u32, k: u32| {
            let (off, end) = fc.range(g);
            let h = off + k;
            (
                quads.kept[h as usize],
                quads.kept[next_in(h, off, end) as usize],
            )
        };
        let (c00, c01) = beside(f0, k0);
        if f1 == NONE {
            rings.quad_fan_as_given(false, &[(c01, 3), (c00, 1)]);
        } else {
            let (c10, c11) = beside(f1, k1);
            closed_fan(&mut rings, &[(c00, 1), (c11, 3), (c10, 1), (c01, 3)]);
        }
    }
    for &v in &points.vertices {
        let child = |g: u32, k: u16| (quads.child(fc, g, u32::from(k)), 0);
        let (faces, locals) = (t.vertex_faces(v), t.vertex_face_locals(v));
        match t.vertex_edges(v).len() - faces.len() {
            0 => {
                fan.clear();
                fan.extend(faces.iter().zip(locals).map(|(&g, &k)| child(g, k)));
                closed_fan(&mut rings, &fan);
            }
            1 => {
                fan.clear();
                fan.extend(faces.iter().zip(locals).map(|(&g, &k)| child(g, k)));
                rings.quad_fan_as_given(false, &fan);
            }
            _ => {
                rings.fans_of(t, v, child);
                rings.end_vertex();
            }
        }
    }
    rings.finish()
}

/// The ring of a point whose children form the closed fan `fan` (in parent ring order): one
/// cycle when every child is kept, runs otherwise. Inlined into its three calls, with
/// [`topology::RingBuilder::try_quad_cycle`] (one call a point).
#[inline(always)]
fn closed_fan(rings: &mut topology::RingBuilder, fan: &[(u32, u16)]) {
    if !rings.try_quad_cycle(fan) {
        rings.quad_fan_as_given(true, fan);
    }
}

/// Per child vertex of `sub` (child points `points` of `level`'s faces `ring`, flagged per
/// face in `in_ring`; `outside` the vertices touching other faces): incomplete when a parent
/// vertex it depends on is incomplete in the step's faces (a corner of its face point's face,
/// of its edge point's faces, or of its vertex point's faces), when its edge point's edge is
/// cut there, or when `sub` misses some of its faces in the whole refinement.
fn incomplete_points(
    level: &Level,
    sub: &Topology,
    points: &StepPoints,
    (ring, in_ring): (&[u32], &[bool]),
    outside: &[bool],
) -> Vec<bool> {
    let t = level.topology();
    let bad = |v: u32| !level.is_complete_vertex(v) || outside[v as usize];
    // Per ring face: a corner is bad, judged in one pass. Only ring faces are asked for: a
    // face point's face holds a kept child, an edge point's faces are asked for once known to
    // be in the ring, and a vertex point's vertex is a kept child's corner, whose faces are
    // all in the ring (`KeptQuads::new`).
    let mut bad_face = vec![false; t.face_count()];
    for &f in ring {
        bad_face[f as usize] = t.face_vertices(f).iter().any(|&v| bad(v));
    }
    let face_bad = |f: u32| bad_face[f as usize];
    // The ring sizes of `sub`'s vertices `a..b` (their faces kept), in order.
    let sizes = |a: usize, b: usize| {
        sub.vert_face_offsets[a..=b]
            .windows(2)
            .map(|w| (w[1] - w[0]) as usize)
    };
    let (nfp, nep) = (points.faces.len(), points.edges.len());
    let mut incomplete = Vec::with_capacity(sub.vertex_count());
    for (&f, size) in points.faces.iter().zip(sizes(0, nfp)) {
        incomplete.push(face_bad(f) || size != t.face_size(f));
    }
    for (&e, size) in points.edges.iter().zip(sizes(nfp, nfp + nep)) {
        let faces = t.edge_faces[e as usize];
        let faces = if faces[1] == NONE {
            &faces[..1]
        } else {
            &faces[..]
        };
        let inc = level.is_cut_edge(e)
            || faces.iter().any(|&g| !in_ring[g as usize] || face_bad(g))
            || size != 2 * faces.len();
        incomplete.push(inc);
    }
    let end = sub.vertex_count();
    for (&pv, size) in points.vertices.iter().zip(sizes(nfp + nep, end)) {
        let faces = t.vertex_faces(pv);
        let inc = bad(pv) || faces.iter().any(|&g| face_bad(g)) || size != faces.len();
        incomplete.push(inc);
    }
    incomplete
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A kept child at a vertex with a face outside the ring is refused, naming the child; with
    /// the vertex's faces in the ring it is taken, with its corner's two edge points.
    #[test]
    fn child_at_a_vertex_with_faces_outside_the_ring_is_an_error() {
        let (_, _, level) = &crate::subdiv::corpus_levels(&["catmark_cube"], 0)[0];
        let t = level.topology();
        let h = t.face_offsets()[0];
        let err = refine_in_place(level, &[0], &[h])
            .err()
            .unwrap()
            .to_string();
        assert!(err.contains("child face 0 (corner 0 of face 0"), "{err}");
        let mut ring = t.vertex_faces(t.face_vertices(0)[0]).to_vec();
        ring.sort_unstable();
        let (_, points) = refine_in_place(level, &ring, &[h]).unwrap();
        assert_eq!(points.edges.len(), 2);
    }
}
