//! One-rings of a topology made from the rings of a related one by index arithmetic, instead of
//! bucketing corners and walking edges ([`build`](mod@super::build)'s `order_rings`): a sub-level's rings
//! from its level's, a refined level's from its parent's. Each vertex is given as the fans of
//! faces around it in the related topology's ring order, each face mapped to a new face or
//! dropped; the kept faces of each fan fall into runs, which are ordered as `order_rings` orders
//! them (open fans by their first corner, then a closed ring from its first corner), so the
//! rings are the ones [`build`](mod@super::build) would give.

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
    /// Runs of kept faces.
    runs: Vec<Run>,
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
        // Each offsets array sized on its own (a clone of a sized one would have room for
        // its one entry only, and grow vertex by vertex).
        let offsets = || {
            let mut o = Vec::with_capacity(vertices + 1);
            o.push(0);
            o
        };
        RingBuilder {
            face_offsets,
            face_edges,
            rings: Rings {
                vert_face_offsets: offsets(),
                vert_faces: Vec::with_capacity(corners),
                vert_face_local: Vec::with_capacity(corners),
                vert_edge_offsets: offsets(),
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
        let fo = self.face_offsets;
        for &(s, e, closed) in &self.fans {
            let fan = &self.entries[s..e];
            if !push_runs(&mut self.runs, s, fan, closed, |x| corner(fo, x)) {
                cycle = Some((s, e - s, self.first_corner(s, e)));
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

    /// Ends the current vertex, whose faces in a topology of quads (every new face a quad:
    /// corner `k` of face `f` is `4 f + k`) form the one fan `fan` (as [`Self::fan`] takes
    /// it): the ring [`Self::end_vertex`] gives, written straight from `fan` (no copy, no fan
    /// list), each face's corners and edges by quad arithmetic.
    pub(crate) fn quad_fan(&mut self, closed: bool, fan: &[(u32, u16)]) {
        let corner = |x| quad_corner(x) as u32;
        let fe = self.face_edges;
        let leaving = |x| fe[quad_corner(x)];
        let entering = |x| fe[quad_entering_corner(x)];
        if closed && fan.iter().all(|x| x.0 != NONE) {
            // One cycle, from its smallest corner.
            let first = (0..fan.len()).min_by_key(|&j| corner(fan[j])).unwrap_or(0);
            let n = fan.len();
            push_run(&mut self.rings, fan, first, n, false, leaving, entering);
        } else {
            // Open, or closed with a gap: runs, never the one cycle.
            self.runs.clear();
            push_runs(&mut self.runs, 0, fan, closed, corner);
            self.runs.sort_unstable_by_key(|r| r.0);
            for &(_, _, _, a, n) in &self.runs {
                push_run(&mut self.rings, fan, a, n, true, leaving, entering);
            }
        }
        self.next_vertex();
    }

    /// [`Self::quad_fan`] without `topology::build`'s order: a closed fan with every face kept
    /// starts at its first face, the runs of the others follow in fan order (a closed fan's
    /// from after its first left-out face). The same faces and edges, each run as
    /// counter-clockwise; for a level whose numbering is free (the adaptive step). Written in
    /// one pass over the fan: a run is its first face's leaving edge, then each face with its
    /// entering edge (the cycle's last face without it: that edge is the first one).
    pub(crate) fn quad_fan_as_given(&mut self, closed: bool, fan: &[(u32, u16)]) {
        let m = fan.len();
        let gap = fan.iter().position(|x| x.0 == NONE);
        let cycle = closed && gap.is_none();
        // A closed fan's runs from after its first left-out face (they may wrap around).
        let from = match gap {
            Some(g) if closed && g + 1 < m => g + 1,
            _ => 0,
        };
        let (r, fe) = (&mut self.rings, self.face_edges);
        let mut in_run = false;
        for i in 0..m {
            let j = if from + i < m { from + i } else { from + i - m };
            let x = fan[j];
            if x.0 == NONE {
                in_run = false;
                continue;
            }
            if !in_run {
                r.vert_edges.push(fe[quad_corner(x)]);
                in_run = true;
            }
            r.vert_faces.push(x.0);
            r.vert_face_local.push(x.1);
            if !cycle || i + 1 < m {
                r.vert_edges.push(fe[quad_entering_corner(x)]);
            }
        }
        self.next_vertex();
    }

    /// Ends the current vertex, whose faces in a topology of quads are the closed fan `fan` (as
    /// [`Self::fan`] takes it), when every face is kept: the ring as given, each face's leaving
    /// edge by quad arithmetic (what [`Self::quad_fan_as_given`] writes, without its runs).
    /// `false`, with nothing written, when a face is NONE. Inlined (one call a point of an
    /// adaptive step, most of them four faces: the call cost a sixth of the ring).
    #[inline(always)]
    pub(crate) fn try_quad_cycle(&mut self, fan: &[(u32, u16)]) -> bool {
        if fan.iter().any(|x| x.0 == NONE) {
            return false;
        }
        let (r, fe) = (&mut self.rings, self.face_edges);
        let leaving = |(f, k): (u32, u16)| fe[(4 * f + u32::from(k)) as usize];
        // Most fans have four faces (valence-4 vertices, quads' face points, interior edge
        // points): as arrays, each copy is unrolled and the vectors grow once each.
        // (Spelt out: `array::map` is not inlined here.)
        if let Ok(&[a, b, c, d]) = <&[(u32, u16); 4]>::try_from(fan) {
            r.vert_faces.extend_from_slice(&[a.0, b.0, c.0, d.0]);
            r.vert_face_local.extend_from_slice(&[a.1, b.1, c.1, d.1]);
            r.vert_edges
                .extend_from_slice(&[leaving(a), leaving(b), leaving(c), leaving(d)]);
        } else {
            r.vert_faces.extend(fan.iter().map(|x| x.0));
            r.vert_face_local.extend(fan.iter().map(|x| x.1));
            r.vert_edges.extend(fan.iter().map(|&x| leaving(x)));
        }
        self.next_vertex();
        true
    }

    /// The position in `entries[s..e]` of the face with the smallest corner.
    fn first_corner(&self, s: usize, e: usize) -> usize {
        (s..e)
            .min_by_key(|&j| self.corner(self.entries[j]))
            .map_or(0, |j| j - s)
    }

    /// The flat corner index of corner `k` of new face `f`.
    fn corner(&self, x: (u32, u16)) -> u32 {
        corner(self.face_offsets, x)
    }

    /// Closes the current vertex's ring.
    fn next_vertex(&mut self) {
        let r = &mut self.rings;
        r.vert_face_offsets.push(r.vert_faces.len() as u32);
        r.vert_edge_offsets.push(r.vert_edges.len() as u32);
        self.entries.clear();
        self.fans.clear();
    }

    /// Faces `a..a + n` (cyclically) of the fan `entries[s..s + m]`, as [`push_run`] writes
    /// them.
    fn push_faces(&mut self, s: usize, m: usize, a: usize, n: usize, open: bool) {
        let (fo, fe) = (self.face_offsets, self.face_edges);
        let leaving = |x| fe[corner(fo, x) as usize];
        let entering = |(f, k)| fe[entering_corner(fo, f, k)];
        let fan = &self.entries[s..s + m];
        push_run(&mut self.rings, fan, a, n, open, leaving, entering);
    }

    /// The rings of every vertex ended so far.
    pub(crate) fn finish(self) -> Rings {
        self.rings
    }
}

/// A run of kept faces of a fan: `(first face's corner, fan start, fan length, first face in
/// the fan, length)`; the first face counts cyclically from the fan's start.
type Run = (u32, usize, usize, usize, usize);

/// Pushes to `runs` the runs of kept faces (not `NONE`) of `fan` (starting at `s`; `closed` as
/// [`RingBuilder::fan`] takes it, a closed fan's runs cyclically from after its first left-out
/// face), `corner` the flat corner index of a face's corner. `false` for a closed fan with
/// every face kept: one cycle, no run.
fn push_runs(
    runs: &mut Vec<Run>,
    s: usize,
    fan: &[(u32, u16)],
    closed: bool,
    corner: impl Fn((u32, u16)) -> u32,
) -> bool {
    let m = fan.len();
    let kept = |j: usize| fan[j % m].0 != NONE;
    let from = if closed {
        match (0..m).find(|&j| !kept(j)) {
            Some(gap) => gap + 1,
            None => return false,
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
        runs.push((corner(fan[a % m]), s, m, a, j - a));
    }
    true
}

/// Appends to `rings` faces `a..a + n` (cyclically, `a + n < 2 m`) of the fan `fan` of `m`
/// faces, with the first face's `leaving` edge and each face's `entering` edge (the last
/// one's only for an `open` run). Inlined into its callers (one call a vertex), whose
/// `leaving` and `entering` then compile to plain loads.
#[inline(always)]
fn push_run(
    rings: &mut Rings,
    fan: &[(u32, u16)],
    a: usize,
    n: usize,
    open: bool,
    leaving: impl Fn((u32, u16)) -> u32,
    entering: impl Fn((u32, u16)) -> u32,
) {
    let m = fan.len();
    let a = if a >= m { a - m } else { a };
    // The run as the fan's end from `a` and, if it wraps, its start.
    let head = &fan[a..(a + n).min(m)];
    let wrapped = &fan[..(a + n).saturating_sub(m)];
    rings.vert_edges.push(leaving(head[0]));
    let mut left = n;
    for &(f, k) in head.iter().chain(wrapped) {
        left -= 1;
        rings.vert_faces.push(f);
        rings.vert_face_local.push(k);
        if open || left > 0 {
            rings.vert_edges.push(entering((f, k)));
        }
    }
}

/// The flat corner index of corner `k` of face `f` (faces `face_offsets`).
#[inline]
fn corner(face_offsets: &[u32], (f, k): (u32, u16)) -> u32 {
    face_offsets[f as usize] + u32::from(k)
}

/// The flat corner index of corner `k` of quad `f` (face `f` at corners `4 f..4 f + 4`): its
/// edge is the one leaving it.
#[inline]
fn quad_corner((f, k): (u32, u16)) -> usize {
    (4 * f + u32::from(k)) as usize
}

/// The flat corner index of the corner before corner `k` of quad `f` (face `f` at corners
/// `4 f..4 f + 4`): its edge is the one entering corner `k`.
#[inline]
fn quad_entering_corner((f, k): (u32, u16)) -> usize {
    (4 * f + u32::from((k + 3) & 3)) as usize
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The tests' quads: faces `0..QUADS`, corner `k` of face `f` at `4 f + k`.
    const QUADS: u32 = 12;

    /// The quads' leaving edges: a distinct id per corner, not in corner order.
    fn quad_face_edges() -> Vec<u32> {
        (0..4 * QUADS)
            .map(|c| (7 * c + 3) % (4 * QUADS) + 100)
            .collect()
    }

    /// Every fan of up to 6 of the quads, open and closed, every non-empty subset of its faces
    /// kept, faces and corners in an order that does not increase.
    fn quad_fans() -> Vec<(bool, Vec<(u32, u16)>)> {
        let mut fans = Vec::new();
        for m in 1..=6usize {
            let faces: Vec<(u32, u16)> = (0..m)
                .map(|j| {
                    (
                        ((5 * j + 3) % QUADS as usize) as u32,
                        ((3 * j + 1) % 4) as u16,
                    )
                })
                .collect();
            for closed in [false, true] {
                for kept in 1..1u32 << m {
                    let fan: Vec<(u32, u16)> = faces
                        .iter()
                        .enumerate()
                        .map(|(j, &x)| if (kept >> j) & 1 == 1 { x } else { (NONE, x.1) })
                        .collect();
                    fans.push((closed, fan));
                }
            }
        }
        fans
    }

    /// `quad_fan` writes the ring `fan` + `end_vertex` give (the general path as the oracle):
    /// every fan of [`quad_fans`] (runs that wrap around a closed fan's end, several runs,
    /// none), whose decreasing faces and corners mean the runs' and the cycle's smallest
    /// corners are searched for.
    #[test]
    fn quad_fan_equals_end_vertex() {
        let face_offsets: Vec<u32> = (0..=QUADS).map(|f| 4 * f).collect();
        let face_edges = quad_face_edges();
        let quad = quad_fans();
        let vertices = quad.len();
        let corners = 4 * QUADS as usize * vertices;
        let mut a = RingBuilder::new(&face_offsets, &face_edges, vertices, corners, corners);
        let mut b = RingBuilder::new(&face_offsets, &face_edges, vertices, corners, corners);
        for (closed, fan) in quad {
            a.quad_fan(closed, &fan);
            b.fan(closed, fan.iter().copied());
            b.end_vertex();
        }
        let (a, b) = (a.finish(), b.finish());
        assert_eq!(a.vert_face_offsets, b.vert_face_offsets);
        assert_eq!(a.vert_faces, b.vert_faces);
        assert_eq!(a.vert_face_local, b.vert_face_local);
        assert_eq!(a.vert_edge_offsets, b.vert_edge_offsets);
        assert_eq!(a.vert_edges, b.vert_edges);
    }

    /// `quad_fan_as_given` writes each run of kept faces in fan order (a closed fan's from
    /// after its first left-out face) as its first face's leaving edge, then each face with
    /// its entering edge; a closed fan with every face kept as one cycle from its first face,
    /// without its last face's entering edge. The runs spelt out by splitting the fan at its
    /// left-out faces, for every fan of [`quad_fans`].
    #[test]
    fn quad_fan_as_given_writes_runs_in_fan_order() {
        let face_offsets: Vec<u32> = (0..=QUADS).map(|f| 4 * f).collect();
        let face_edges = quad_face_edges();
        let leaving = |(f, k): (u32, u16)| face_edges[4 * f as usize + usize::from(k)];
        let entering = |(f, k): (u32, u16)| face_edges[4 * f as usize + usize::from(k + 3) % 4];
        let fans = quad_fans();
        let corners = 4 * QUADS as usize * fans.len();
        let mut rings = RingBuilder::new(&face_offsets, &face_edges, fans.len(), corners, corners);
        let (mut faces, mut locals, mut edges) = (Vec::new(), Vec::new(), Vec::new());
        let (mut face_offs, mut edge_offs) = (vec![0u32], vec![0u32]);
        for (closed, fan) in &fans {
            rings.quad_fan_as_given(*closed, fan);
            let m = fan.len();
            let gap = fan.iter().position(|x| x.0 == NONE);
            let start = if *closed { gap.map_or(0, |g| g + 1) } else { 0 };
            let order: Vec<(u32, u16)> = (start..start + m).map(|j| fan[j % m]).collect();
            for run in order.split(|x| x.0 == NONE).filter(|run| !run.is_empty()) {
                edges.push(leaving(run[0]));
                for &x in run {
                    faces.push(x.0);
                    locals.push(x.1);
                    edges.push(entering(x));
                }
            }
            if *closed && gap.is_none() {
                edges.pop();
            }
            face_offs.push(faces.len() as u32);
            edge_offs.push(edges.len() as u32);
        }
        let rings = rings.finish();
        assert_eq!(rings.vert_face_offsets, face_offs);
        assert_eq!(rings.vert_faces, faces);
        assert_eq!(rings.vert_face_local, locals);
        assert_eq!(rings.vert_edge_offsets, edge_offs);
        assert_eq!(rings.vert_edges, edges);
    }
}
