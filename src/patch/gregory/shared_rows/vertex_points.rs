//! The end-cap corners' first-stage rows (their vertex points: limit point and two tangent
//! sums, [`super::super::GregoryVertex::vertex_points`]) shared per ring type, as the end caps'
//! rows are per face type ([`super`]'s module docs).

use rayon::prelude::*;

use crate::patch::gregory::corner_rings::vertex_word;
use crate::patch::gregory::face_rows::{FaceRows, Terms, TERM_PLACEHOLDER};
use crate::patch::gregory::point::Weights;
use crate::patch::gregory::stencil_table::vertex_point_rows_with;
use crate::patch::gregory::tangents::GregoryTangents;
use crate::patch::gregory::tangents_boundary::crease_factor_words;
use crate::patch::gregory::vertex::DartLimits;
use crate::patch::gregory::word_hash::WordHashMap;
use crate::topology::Topology;

const NONE: u32 = u32::MAX;

/// [`vertex_point_rows`](crate::patch::gregory::stencil_table::vertex_point_rows) of every
/// vertex of `vertices` (smooth, dart and crease vertices of `topo` as end-cap corners; empty
/// rows for others), vertex `i`'s rows `3 i..3 i + 3` of the flat rows returned, the
/// construction run once per ring type (Loop et al. 2009 §4.1, shared as the end-cap rows are,
/// [`super`]'s module docs): the
/// rows of a vertex read only its edges' other ends and sharpness, its faces' vertices and its
/// own sharpness, so vertices whose rings read the same in first-appearance slots
/// (`RingKeys`) have the same weights slot by slot, and every weight is the same sequence
/// of `a + w * b` updates whatever the ids. Bitwise the per-vertex rows, with the terms
/// `kept` keeps (dropped once per type, as [`super::end_cap_face_rows`] does: the draw tables
/// drop the zero terms, which the rows of most types hold, and closing up rows of every vertex
/// after copying them costs more); the keys, the types' rows and the relabelling run on the
/// rayon pool. Dart masks from `darts`.
pub fn shared_vertex_point_rows(
    topo: &Topology,
    vertices: &[u32],
    tangents: GregoryTangents,
    darts: &DartLimits,
    kept: Terms,
) -> FaceRows {
    let fresh = || vec![NONE; topo.vertex_count()];
    // The keys of runs of `RUN` vertices, each run's in flat arrays (no allocation per vertex).
    const RUN: usize = 256;
    let runs: Vec<RingKeys> = vertices
        .par_chunks(RUN)
        .map_init(fresh, |slot, run| {
            let mut keys = RingKeys::default();
            for &v in run {
                keys.push(topo, v, slot);
            }
            keys
        })
        .collect();
    let key_of = |i: usize| (&runs[i / RUN], i % RUN);
    let mut types: WordHashMap<&[u32], u32> = WordHashMap::default();
    // Per type: the index of a vertex of it; per vertex: its type.
    let mut representative: Vec<usize> = Vec::new();
    let type_of: Vec<u32> = (0..vertices.len())
        .map(|i| {
            let (keys, j) = key_of(i);
            let next = types.len() as u32;
            let t = *types.entry(keys.key(j)).or_insert(next);
            if t == next {
                representative.push(i);
            }
            t
        })
        .collect();
    let local: Vec<[Weights; 3]> = representative
        .par_iter()
        .map_init(fresh, |slot, &i| {
            let (keys, j) = key_of(i);
            let ring = keys.ring(j);
            for (s, &u) in ring.iter().enumerate() {
                slot[u as usize] = s as u32;
            }
            let mut rows =
                vertex_point_rows_with(topo, vertices[i], &|u| slot[u as usize], tangents, darts);
            clear(slot, ring);
            if kept == Terms::Nonzero {
                for w in &mut rows {
                    w.0.retain(|t| kept.keeps(t.1));
                }
            }
            rows
        })
        .collect();
    log::trace!(
        "vertex points: {} vertices, {} ring types",
        vertices.len(),
        representative.len()
    );
    // Relabelled into flat rows: one buffer of the exact size, each run's part of it filled on
    // the pool (no allocation per row or run, nothing copied after).
    let terms_of: Vec<usize> = local
        .iter()
        .map(|rows| rows.iter().map(|w| w.0.len()).sum())
        .collect();
    let mut out = FaceRows {
        offsets: Vec::with_capacity(3 * vertices.len() + 1),
        terms: Vec::new(),
    };
    out.offsets.push(0);
    let mut end = 0;
    for &t in &type_of {
        for w in &local[t as usize] {
            end += w.0.len() as u32;
            out.offsets.push(end);
        }
    }
    out.terms = vec![TERM_PLACEHOLDER; end as usize];
    let mut parts: Vec<&mut [(u32, f64)]> = Vec::with_capacity(runs.len());
    let mut rest = out.terms.as_mut_slice();
    for types in type_of.chunks(RUN) {
        let len = types.iter().map(|&t| terms_of[t as usize]).sum();
        let (part, after) = rest.split_at_mut(len);
        parts.push(part);
        rest = after;
    }
    parts
        .into_par_iter()
        .zip(&runs)
        .zip(type_of.par_chunks(RUN))
        .for_each(|((part, keys), types)| {
            let mut at = 0;
            for (j, &t) in types.iter().enumerate() {
                let ring = keys.ring(j);
                for w in &local[t as usize] {
                    let row = &mut part[at..at + w.0.len()];
                    for (term, &(s, x)) in row.iter_mut().zip(&w.0) {
                        *term = (ring[s as usize], x);
                    }
                    row.sort_unstable_by_key(|&(u, _)| u);
                    at += w.0.len();
                }
            }
        });
    out
}

/// What [`vertex_point_rows`](crate::patch::gregory::stencil_table::vertex_point_rows) reads
/// of the rings of a run of vertices, in slots, flat: per vertex its key (edge count, face count, the vertex's sharpness bits, each
/// edge's other end and sharpness bits, each face's size and vertices) and its ring (the vertex
/// of each slot: the vertex at slot 0, its edges' other ends and its faces' vertices numbered by
/// first appearance in that order).
#[derive(Default)]
pub(super) struct RingKeys {
    words: Vec<u32>,
    /// `vertices + 1` offsets into `words` (empty before the first vertex).
    word_at: Vec<u32>,
    ring: Vec<u32>,
    /// `vertices + 1` offsets into `ring` (empty before the first vertex).
    ring_at: Vec<u32>,
}

impl RingKeys {
    /// Appends the key and ring of `v`; `slot` is all [`NONE`] on entry and on return.
    pub(super) fn push(&mut self, topo: &Topology, v: u32, slot: &mut [u32]) {
        if self.word_at.is_empty() {
            self.word_at.push(0);
            self.ring_at.push(0);
        }
        let (edges, faces) = (topo.vertex_edges(v), topo.vertex_faces(v));
        let first = self.ring.len();
        let (words, ring) = (&mut self.words, &mut self.ring);
        words.extend([edges.len() as u32, faces.len() as u32, vertex_word(topo, v)]);
        words.extend(crease_factor_words(topo, v));
        let mut at = |u: u32, ring: &mut Vec<u32>| {
            if slot[u as usize] == NONE {
                slot[u as usize] = (ring.len() - first) as u32;
                ring.push(u);
            }
            slot[u as usize]
        };
        at(v, ring);
        for &e in edges {
            words.push(at(topo.other_vertex(e, v), ring));
            words.push(topo.edge_sharpness(e).to_bits());
        }
        for &f in faces {
            let fv = topo.face_vertices(f);
            words.push(fv.len() as u32);
            for &u in fv {
                words.push(at(u, ring));
            }
        }
        clear(slot, &ring[first..]);
        self.word_at.push(words.len() as u32);
        self.ring_at.push(ring.len() as u32);
    }

    /// The key of vertex `j` of the run.
    pub(super) fn key(&self, j: usize) -> &[u32] {
        &self.words[self.word_at[j] as usize..self.word_at[j + 1] as usize]
    }

    /// The ring of vertex `j` of the run.
    fn ring(&self, j: usize) -> &[u32] {
        &self.ring[self.ring_at[j] as usize..self.ring_at[j + 1] as usize]
    }
}

/// Resets the slots of `ring`.
pub(super) fn clear(slot: &mut [u32], ring: &[u32]) {
    for &v in ring {
        slot[v as usize] = NONE;
    }
}
