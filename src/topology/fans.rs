//! One-rings of a topology made from the rings of a related one by index arithmetic, instead of
//! bucketing corners and walking edges ([`super::build`]'s `order_rings`): a sub-level's rings
//! from its level's, a refined level's from its parent's. Each vertex is given as the fans of
//! faces around it in the related topology's ring order, each face mapped to a new face or
//! dropped; the kept faces of each fan fall into runs, which are ordered as `order_rings` orders
//! them (open fans by their first corner, then a closed ring from its first corner), so the
//! rings are the ones [`super::build`] would give.

use super::build::Rings;
use super::{Topology, NONE};

/// The rings of a new topology, one vertex after the other. `face_offsets` and `face_edges` are
/// the new topology's.
pub(crate) struct RingBuilder<'a> {
    face_offsets: &'a [u32],
    face_edges: &'a [u32],
    rings: Rings,
    /// The current vertex's faces `(new face or NONE, corner)` in fan order.
    entries: Vec<(u32, u16)>,
    /// The current vertex's fans: `(first entry, end, closed)`.
    fans: Vec<(usize, usize, bool)>,
    /// Runs of kept faces: `(first corner, fan start, fan length, first face in the fan,
    /// length)`.
    runs: Vec<(u32, usize, usize, usize, usize)>,
}

impl<'a> RingBuilder<'a> {
    /// A builder for `vertices` vertices, `corners` corners and `edges` edges. Every corner
    /// lies in one ring and every edge in the rings of its two ends, so the rings hold exactly
    /// `corners` faces and `2 * edges` edges: allocated once, never grown.
    pub(crate) fn new(
        face_offsets: &'a [u32],
        face_edges: &'a [u32],
        vertices: usize,
        corners: usize,
        edges: usize,
    ) -> RingBuilder<'a> {
        let mut offsets = Vec::with_capacity(vertices + 1);
        offsets.push(0);
        RingBuilder {
            face_offsets,
            face_edges,
            rings: Rings {
                vert_face_offsets: offsets.clone(),
                vert_faces: Vec::with_capacity(corners),
                vert_face_local: Vec::with_capacity(corners),
                vert_edge_offsets: offsets,
                vert_edges: Vec::with_capacity(2 * edges),
            },
            entries: Vec::with_capacity(16),
            fans: Vec::with_capacity(4),
            runs: Vec::with_capacity(4),
        }
    }

    /// A fan of the current vertex: `faces` in ring order (counter-clockwise, the face after a
    /// face lies across its edge entering the vertex), `closed` when the last face's entering
    /// edge is the first face's leaving edge.
    pub(crate) fn fan(&mut self, closed: bool, faces: impl IntoIterator<Item = (u32, u16)>) {
        let start = self.entries.len();
        self.entries.extend(faces);
        self.fans.push((start, self.entries.len(), closed));
    }

    /// The fans of vertex `v` of `t`, each face `g` at corner `k` mapped to `new(g, k)`. A
    /// vertex lies in one closed fan (as many edges as faces) or in open fans (one edge more
    /// than faces each, listed one after the other); several open fans are split where
    /// consecutive faces do not share an edge.
    pub(crate) fn fans_of(
        &mut self,
        t: &Topology,
        v: u32,
        mut new: impl FnMut(u32, u16) -> (u32, u16),
    ) {
        let faces = t.vertex_faces(v);
        let locals = t.vertex_face_locals(v);
        let n = faces.len();
        let open = t.vertex_edges(v).len() - n;
        if open <= 1 {
            let fan = faces.iter().zip(locals).map(|(&g, &k)| new(g, k));
            self.fan(open == 0, fan);
            return;
        }
        let leaves = |j: usize| leaving(t, faces[j], locals[j]);
        let enters = |j: usize| entering(t, faces[j], locals[j]);
        let mut start = 0;
        for j in 0..n {
            if j + 1 == n || enters(j) != leaves(j + 1) {
                let fan = (start..=j).map(|i| new(faces[i], locals[i]));
                self.fan(false, fan);
                start = j + 1;
            }
        }
    }

    /// Ends the current vertex: its kept faces and their edges appended as its ring.
    pub(crate) fn end_vertex(&mut self) {
        if let [(s, e, closed)] = self.fans[..] {
            if self.entries[s..e].iter().all(|x| x.0 != NONE) {
                let first = if closed { self.first_corner(s, e) } else { 0 };
                self.push_faces(s, e - s, first, e - s, !closed);
                self.next_vertex();
                return;
            }
        }
        let mut cycle = None;
        self.runs.clear();
        for &(s, e, closed) in &self.fans {
            let m = e - s;
            let kept = |j: usize| self.entries[s + j % m].0 != NONE;
            let from = if closed {
                match (0..m).find(|&j| !kept(j)) {
                    Some(gap) => gap + 1,
                    None => {
                        cycle = Some((s, m, self.first_corner(s, e)));
                        continue;
                    }
                }
            } else {
                0
            };
            let to = if closed { from + m - 1 } else { m };
            let mut j = from;
            while j < to {
                if !kept(j) {
                    j += 1;
                    continue;
                }
                let a = j;
                while j < to && kept(j) {
                    j += 1;
                }
                self.runs
                    .push((self.corner(self.entries[s + a % m]), s, m, a, j - a));
            }
        }
        self.runs.sort_unstable_by_key(|r| r.0);
        for i in 0..self.runs.len() {
            let (_, s, m, a, n) = self.runs[i];
            self.push_faces(s, m, a, n, true);
        }
        if let Some((s, m, first)) = cycle {
            self.push_faces(s, m, first, m, false);
        }
        self.next_vertex();
    }

    /// The position in `entries[s..e]` of the face with the smallest corner.
    fn first_corner(&self, s: usize, e: usize) -> usize {
        (s..e)
            .min_by_key(|&j| self.corner(self.entries[j]))
            .map_or(0, |j| j - s)
    }

    /// The flat corner index of corner `k` of new face `f`.
    fn corner(&self, (f, k): (u32, u16)) -> u32 {
        self.face_offsets[f as usize] + u32::from(k)
    }

    /// Closes the current vertex's ring.
    fn next_vertex(&mut self) {
        let r = &mut self.rings;
        r.vert_face_offsets.push(r.vert_faces.len() as u32);
        r.vert_edge_offsets.push(r.vert_edges.len() as u32);
        self.entries.clear();
        self.fans.clear();
    }

    /// Faces `a..a + n` (cyclically) of the fan `entries[s..s + m]`, with the first face's
    /// leaving edge and each face's entering edge (the last one's only for an `open` run).
    fn push_faces(&mut self, s: usize, m: usize, a: usize, n: usize, open: bool) {
        let (fo, fe) = (self.face_offsets, self.face_edges);
        let r = &mut self.rings;
        let at = |j: usize| s + if j >= m { j - m } else { j };
        let (f0, k0) = self.entries[at(a)];
        r.vert_edges
            .push(fe[(fo[f0 as usize] + u32::from(k0)) as usize]);
        for j in a..a + n {
            let (f, k) = self.entries[at(j)];
            r.vert_faces.push(f);
            r.vert_face_local.push(k);
            if open || j + 1 < a + n {
                r.vert_edges.push(fe[entering_corner(fo, f, k)]);
            }
        }
    }

    /// The rings of every vertex ended so far.
    pub(crate) fn finish(self) -> Rings {
        self.rings
    }
}

/// The edge of face `f` leaving its corner `k`.
fn leaving(t: &Topology, f: u32, k: u16) -> u32 {
    t.face_edges(f)[usize::from(k)]
}

/// The edge of face `f` entering its corner `k`.
fn entering(t: &Topology, f: u32, k: u16) -> u32 {
    t.face_edges[entering_corner(&t.face_offsets, f, k)]
}

/// The flat corner index of the corner before corner `k` of face `f` (faces `face_offsets`):
/// its edge is the one entering corner `k`.
#[inline]
fn entering_corner(face_offsets: &[u32], f: u32, k: u16) -> usize {
    let c = if k == 0 {
        face_offsets[f as usize + 1]
    } else {
        face_offsets[f as usize] + u32::from(k)
    };
    c as usize - 1
}
