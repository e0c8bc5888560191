//! The end-cap corners as the shared rows' face keys read them ([`super::shared_rows`], Loop et
//! al. 2009 §4.3), made once per vertex rather than once per face around it: each vertex's
//! one-ring numbered by first appearance (the vertex, its edges' other ends, its faces'
//! vertices) and the id of its *shape*, everything the construction reads of the vertex's
//! ring over those slots. A face's key is then its corners' shape ids and places, plus the
//! face slot of every entry of every corner's ring but the first's (whose slots count up from
//! 0), which fixes how the rings overlap.

use super::tangents_boundary::crease_factor_words;
use super::word_hash::WordHashMap;
use crate::topology::Topology;

const NONE: u32 = u32::MAX;

/// The key's sharpness word of a promoted crease (`Topology::is_promoted_edge`: its face points
/// may differ from a real crease's, `VertexRing::one_sided_edge`): a NaN's bits, which no
/// sharpness has.
pub(super) const PROMOTED: u32 = u32::MAX - 1;

/// The key's vertex-sharpness word of a decayed corner (`Topology::is_decayed_corner`: its
/// tangents may differ from a smooth vertex's, `GregoryTangents::vertex_ring_factors`), another
/// NaN's bits; a decayed corner has no vertex sharpness.
const DECAYED_CORNER: u32 = u32::MAX - 2;

/// The key's word for vertex `v`'s own tags: [`DECAYED_CORNER`] or its sharpness bits.
pub(super) fn vertex_word(topo: &Topology, v: u32) -> u32 {
    match topo.is_decayed_corner(v) {
        true => DECAYED_CORNER,
        false => topo.vertex_sharpness(v).to_bits(),
    }
}

/// The key's word for edge `e`'s sharpness: [`PROMOTED`] or its sharpness bits.
pub(super) fn edge_word(topo: &Topology, e: u32) -> u32 {
    match topo.is_promoted_edge(e) {
        true => PROMOTED,
        false => topo.edge_sharpness(e).to_bits(),
    }
}

/// The one-rings and shape ids of the vertices asked, each made on first use.
pub(super) struct CornerRings<'a> {
    topo: &'a Topology,
    /// Per vertex: its entry in `shape` / `ring_at`, [`NONE`] before it is asked.
    entry: Vec<u32>,
    /// Per entry: the vertex's shape id.
    shape: Vec<u32>,
    /// `entries + 1` offsets into `ring`.
    ring_at: Vec<u32>,
    /// The rings of the vertices asked, one after another.
    ring: Vec<u32>,
    /// Per vertex of `topo`: its slot in the ring being numbered, [`NONE`] outside it.
    own: Vec<u32>,
    /// One buffer for every shape's words (a map entry copies it only for a new shape).
    words: Vec<u32>,
    shapes: WordHashMap<Vec<u32>, u32>,
}

impl<'a> CornerRings<'a> {
    /// Nothing asked yet.
    pub fn new(topo: &'a Topology) -> Self {
        CornerRings {
            topo,
            entry: vec![NONE; topo.vertex_count()],
            shape: Vec::new(),
            ring_at: vec![0],
            ring: Vec::new(),
            own: vec![NONE; topo.vertex_count()],
            words: Vec::new(),
            shapes: WordHashMap::default(),
        }
    }

    /// The entry of vertex `v`'s ring read from its face `start` on (its edges and faces
    /// turned alike, face `i` staying between edges `i` and `i + 1`): `v` first, then its
    /// edges' other ends, then its faces' vertices, each once. Two entries with the same
    /// [`Self::shape`] read the same in their rings' slots (sharpness, tags, crease factors,
    /// each edge's other end, sharpness and face count, each face's limit-surface flag, size
    /// and vertices). Made once per vertex from its first face; from another face anew on
    /// every call (the shared rows' anchored keys, a few per connectivity type).
    pub fn entry(&mut self, v: u32, start: usize) -> usize {
        if start != 0 {
            return self.push(v, start);
        }
        if self.entry[v as usize] == NONE {
            self.entry[v as usize] = self.push(v, 0) as u32;
        }
        self.entry[v as usize] as usize
    }

    /// The shape id of entry `i` ([`Self::entry`]).
    pub fn shape(&self, i: usize) -> u32 {
        self.shape[i]
    }

    /// The ring of entry `i` ([`Self::entry`]).
    pub fn ring(&self, i: usize) -> &[u32] {
        &self.ring[self.ring_at[i] as usize..self.ring_at[i + 1] as usize]
    }

    /// Numbers `v`'s ring from face `start` on and interns its shape: the new entry.
    fn push(&mut self, v: u32, start: usize) -> usize {
        let topo = self.topo;
        let (edges, faces) = (topo.vertex_edges(v), topo.vertex_faces(v));
        let turned = |items: &'a [u32]| {
            let (before, after) = items.split_at(start.min(items.len()));
            after.iter().chain(before).copied()
        };
        let first = self.ring.len();
        let (own, ring, words) = (&mut self.own[..], &mut self.ring, &mut self.words);
        let mut at = |u: u32| {
            if own[u as usize] == NONE {
                own[u as usize] = (ring.len() - first) as u32;
                ring.push(u);
            }
            own[u as usize]
        };
        at(v);
        words.clear();
        words.push(vertex_word(topo, v));
        words.extend(crease_factor_words(topo, v));
        words.push(edges.len() as u32);
        for e in turned(edges) {
            words.extend([
                at(topo.other_vertex(e, v)),
                edge_word(topo, e),
                topo.edge_faces(e).len() as u32,
            ]);
        }
        words.push(faces.len() as u32);
        for g in turned(faces) {
            let gv = topo.face_vertices(g);
            words.extend([u32::from(topo.has_limit_surface(g)), gv.len() as u32]);
            for &u in gv {
                words.push(at(u));
            }
        }
        for &u in &ring[first..] {
            own[u as usize] = NONE;
        }
        let next = self.shapes.len() as u32;
        let id = match self.shapes.get(words.as_slice()) {
            Some(&id) => id,
            None => {
                self.shapes.insert(words.clone(), next);
                next
            }
        };
        self.shape.push(id);
        self.ring_at.push(self.ring.len() as u32);
        self.shape.len() - 1
    }
}
