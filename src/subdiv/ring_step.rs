//! The parent of a feature-adaptive step seen through its level, without extracting it
//! ([`RingStep`]): as OpenSubdiv's `Vtr::Refinement` refines a sparse selection of its parent
//! level in place, the step's faces, corners, vertices and rings are the level's, and only the
//! edges' numbering, orientation and flags follow the sub-level [`Level::extract_increasing`]
//! would make, so [`super::kept::refine_kept_in`] gives that sub-level's refinement bit for bit
//! (vertex numbering included).

use super::corners::{next_corner, prev_corner};
use super::kept::{StepEdge, StepParent};
use super::level::Level;
use crate::topology::NONE;
use crate::{Error, Result};

/// The sub-level of a level made of the faces `ring` (increasing), as far as the kept children
/// `keep` (flat corners of the level, increasing) read it. Every kept child's corner vertex must
/// have all its faces in `ring` (the adaptive step keeps the children of refined faces and, of
/// the faces around their vertices, the children at those vertices): its ring and the
/// sharpness around it are then the level's.
pub(super) struct RingStep<'a> {
    level: &'a Level,
    /// Per vertex of the level: a corner of a face not in `ring` (incomplete in the sub-level).
    outside: Vec<bool>,
    /// The kept children's edge points, each its edge as the sub-level has it and whether it
    /// is cut there ([`StepParent::is_cut_edge`]), in the sub-level's edge order.
    edges: Vec<(u32, StepEdge, bool)>,
    /// Per edge of the level: its index in `edges`, or NONE.
    point: Vec<u32>,
}

impl<'a> RingStep<'a> {
    /// The step of `level` refining the faces `ring` and keeping the children `keep`.
    pub fn new(level: &'a Level, ring: &[u32], keep: &[u32]) -> Result<RingStep<'a>> {
        let t = &level.topo;
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
        let mut outside = vec![false; t.vertex_count()];
        for (f, _) in in_ring.iter().enumerate().filter(|x| !x.1) {
            for &v in t.face_vertices(f as u32) {
                outside[v as usize] = true;
            }
        }
        // Per edge: NONE, then its index in `found`, then its index in `edges`.
        let mut point = vec![NONE; t.edge_count()];
        // Per edge point, in the order found: its sort key (smaller end, first corner) and its
        // edge as the sub-level has it.
        let mut keys = Vec::with_capacity(2 * keep.len());
        let mut found = Vec::with_capacity(2 * keep.len());
        let mut f = 0usize;
        for (i, &h) in keep.iter().enumerate() {
            if h as usize >= t.corner_count() || (i > 0 && h <= keep[i - 1]) {
                return Err(Error::Invalid(format!(
                    "adaptive step: child face {i} is corner {h}: corners must increase and be \
                     below {}",
                    t.corner_count()
                )));
            }
            while t.face_offsets[f + 1] <= h {
                f += 1;
            }
            let v = t.face_verts[h as usize];
            if !in_ring[f] || outside[v as usize] {
                return Err(Error::Invalid(format!(
                    "adaptive step: child face {i} (corner {h} of face {f}, vertex {v}): its \
                     face and every face at its vertex must be refined or in the ring"
                )));
            }
            let hp = prev_corner(t, f, h);
            for e in [t.face_edges[h as usize], t.face_edges[hp]] {
                if point[e as usize] == NONE {
                    point[e as usize] = found.len() as u32;
                    let edge = ring_edge(level, &in_ring, e);
                    let h0 = t.face_offsets[edge.faces[0] as usize] + u32::from(edge.locals[0]);
                    let [a, b] = t.edge_verts[e as usize];
                    keys.push(u64::from(a.min(b)) << 32 | u64::from(h0));
                    found.push(edge);
                }
            }
        }
        // The sub-level numbers edges by smaller end, then by first corner: both increase with
        // the level's (`Level::extract_increasing`). Each key is its edge's alone, and names
        // it: the edge leaving its first corner.
        let keys = sorted_keys(&keys, t.vertex_count());
        let edges: Vec<(u32, StepEdge, bool)> = keys
            .iter()
            .enumerate()
            .map(|(i, &key)| {
                let e = t.face_edges[key as u32 as usize];
                let j = std::mem::replace(&mut point[e as usize], i as u32);
                let edge = found[j as usize];
                let opened = edge.faces[1] == NONE && !t.is_boundary_edge(e);
                (e, edge, opened || level.is_cut_edge(e))
            })
            .collect();
        Ok(RingStep {
            level,
            outside,
            edges,
            point,
        })
    }
}

/// `keys` (smaller end vertex `<< 32 |` first corner, distinct, ends below `vertex_count`)
/// in increasing order: counted by end vertex, then each end's few keys (its edges to larger
/// vertices) ordered by insertion.
fn sorted_keys(keys: &[u64], vertex_count: usize) -> Vec<u64> {
    let mut start = vec![0u32; vertex_count + 1];
    for &key in keys {
        start[(key >> 32) as usize + 1] += 1;
    }
    for v in 0..vertex_count {
        start[v + 1] += start[v];
    }
    let mut sorted = vec![0u64; keys.len()];
    for &key in keys {
        let slot = &mut start[(key >> 32) as usize];
        // Insertion among the end's keys placed so far (those from `slot`'s bucket start on
        // lie before it in `sorted`, all with this end).
        let mut i = *slot as usize;
        *slot += 1;
        while i > 0 && sorted[i - 1] > key && sorted[i - 1] >> 32 == key >> 32 {
            sorted[i] = sorted[i - 1];
            i -= 1;
        }
        sorted[i] = key;
    }
    sorted
}

/// Edge `e` of `level` as the sub-level of the faces `in_ring` has it: its first face the one
/// whose corner on it comes first, oriented as there.
fn ring_edge(level: &Level, in_ring: &[bool], e: u32) -> StepEdge {
    let t = &level.topo;
    let mut sides = t
        .edge_faces(e)
        .iter()
        .zip(t.edge_face_locals(e))
        .filter(|(&g, _)| in_ring[g as usize])
        .map(|(&g, &k)| (t.face_offsets[g as usize] + u32::from(k), g, k));
    let first = sides
        .next()
        .expect("a kept child's edge lies on a ring face");
    let (first, second) = match sides.next() {
        Some(s) if s.0 < first.0 => (s, Some(first)),
        s => (first, s),
    };
    let (h, g, k) = first;
    let n = t.face_offsets[g as usize + 1] - t.face_offsets[g as usize];
    let hn = t.face_offsets[g as usize] + next_corner(u32::from(k), n);
    let (g1, k1) = second.map_or((NONE, 0), |s| (s.1, s.2));
    StepEdge {
        verts: [t.face_verts[h as usize], t.face_verts[hn as usize]],
        faces: [g, g1],
        locals: [k, k1],
    }
}

impl StepParent for RingStep<'_> {
    fn level(&self) -> &Level {
        self.level
    }

    fn edge_point_count(&self) -> u32 {
        self.edges.len() as u32
    }

    fn edge_point(&self, e: u32) -> u32 {
        self.point[e as usize]
    }

    fn point_edge(&self, i: u32) -> u32 {
        self.edges[i as usize].0
    }

    fn edge(&self, e: u32) -> StepEdge {
        self.edges[self.point[e as usize] as usize].1
    }

    fn is_cut_edge(&self, e: u32) -> bool {
        self.edges[self.point[e as usize] as usize].2
    }

    fn is_complete_vertex(&self, v: u32) -> bool {
        self.level.is_complete_vertex(v) && !self.outside[v as usize]
    }

    fn has_flags(&self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A kept child at a vertex with a face outside the ring is refused, naming the child; with
    /// the vertex's faces in the ring it is taken.
    #[test]
    fn child_at_a_vertex_with_faces_outside_the_ring_is_an_error() {
        let (_, _, level) = &crate::subdiv::corpus_levels(&["catmark_cube"], 0)[0];
        let t = level.topology();
        let h = t.face_offsets()[0];
        let err = RingStep::new(level, &[0], &[h]).err().unwrap().to_string();
        assert!(err.contains("child face 0 (corner 0 of face 0"), "{err}");
        let mut ring = t.vertex_faces(t.face_vertices(0)[0]).to_vec();
        ring.sort_unstable();
        let step = RingStep::new(level, &ring, &[h]).unwrap();
        assert_eq!(step.edge_point_count(), 2);
    }

    /// `sorted_keys` orders as a comparison sort does: keys of many ends, several per end in
    /// decreasing corner order, ends 0 and the last one, gaps.
    #[test]
    fn sorted_keys_equal_a_comparison_sort() {
        let vertex_count = 40u64;
        let keys: Vec<u64> = (0..300u64)
            .map(|i| (((i * 17) % vertex_count) << 32) | ((1000 - 3 * i) % 997))
            .filter(|key| (key >> 32) % 7 != 3)
            .collect();
        let mut expected = keys.clone();
        expected.sort_unstable();
        expected.dedup();
        assert_eq!(expected.len(), keys.len(), "distinct keys");
        assert_eq!(sorted_keys(&keys, vertex_count as usize), expected);
        assert!(sorted_keys(&[], 3).is_empty());
    }
}
