//! The sparse end-cap rows of [`super::stencil_table::sparse_face_rows_direct`] computed once per
//! connectivity type (Loop et al. 2009 §4.3, as [`super::stencil_table::GregoryStencilTable`]
//! shares f32 types): faces whose local topology reads the same in the slots of their ring
//! (their corners' one-rings, corner by corner, each vertex once: the vertices of
//! [`super::stencil::canonical_ring`] in another order, then any vertex a one-sided neighbour's
//! far corner reads beyond them) run the very same construction steps
//! on the same slots, so their rows are one set of weights over slots, relabelled with each
//! face's ids ([`EndCapFaceRows::rows`]: the caller's, in one pass over the terms).
//!
//! Why the bits agree: a row weight of the direct construction is the sequence of
//! `a + w * b` updates the construction applies to that vertex's entry, in construction order;
//! the order follows the topology walk (rings, faces, edges in the topology's order), never the
//! vertex ids, and ids only decide where an entry sits in the sorted row. The `TypeKey`
//! records everything the construction reads (face sizes and vertex slots of every face around
//! every corner, each corner's edges with their other end, sharpness bits and face counts, and
//! whether each edge neighbour gets a patch; the corners' part as each corner's shape, made
//! once per vertex, and its ring's slots in the face's ring), so two faces with equal keys
//! produce equal rows slot by slot. A face whose rows leave its ring, or that gets no patch, is built directly.
//! The rows are two-stage ([`sparse_face_rows_direct`]): the vertex points of a smooth, dart or
//! crease corner (`vertex_count + 3 v + b`, [`super::GregoryVertex::vertex_points`]) take the
//! slots `ring_len + 3 slot(v) + b`; which rule a corner takes is part of its topology, hence of
//! the key. The vertex points' own (first-stage) rows are shared the same way, per ring type
//! ([`shared_vertex_point_rows`]).
//!
//! Types are shared further where they differ only in where their closed corners' rings start
//! (the topology starts a closed ring at its lowest-numbered face, which on refined levels is
//! arbitrary): the type key read with each closed corner's ring (valence at most
//! `MAX_TURNED_VALENCE`) started at the face keyed (the neighbour face for a one-sided
//! neighbour's far corner) groups types into classes, built directly once per class (on the car
//! at isolation 2, 210 / 170 types per call make 27 / 25 classes). A type's rows are its
//! class's first type's relabelled (`LocalRows::turned`, `Follows`): a smooth vertex reads
//! its ring start only through its derived cosine and sine sums (`InteriorBasis`: `e_j = p +
//! cos(2 pi j / n) q_c + sin(2 pi j / n) q_s`), so the weight pair on its `(q_c, q_s)` turns by
//! the angle between the two starts; a crease's two sector tangents swap where its sectors come
//! in the other order; darts, corners and cones relabel only. The rows the boundary curves and
//! edge normals read (each corner's `p`, `e_plus`, `e_minus`, the neighbours' edge points) are
//! written bitwise as the construction writes them, so two end caps at an edge read the same
//! bits; the face points' rows equal the construction's to rounding.

mod layouts;
mod vertex_points;

use rayon::prelude::*;

use super::build::{
    end_cap_patch_with, has_vertex_data, is_interior_vertex, topology_rule, vertex_covered,
    Coverage, NotGregory,
};
use super::corner_rings::{edge_word, vertex_word, CornerRings};
pub use super::face_rows::{FaceRows, RowsFrom, Terms};
use super::point::Weights;
#[cfg(doc)]
use super::stencil_table::sparse_face_rows_direct;
use super::stencil_table::{sparse_face_rows_direct_with, vertex_point_id, vertex_point_of};
use super::tangents::GregoryTangents;
use super::tangents_boundary::crease_factor_words;
use super::vertex::{DartLimits, Rule};
use super::word_hash::WordHashMap;
use crate::topology::Topology;
use layouts::{to_slots, EdgeAngles, Layouts, LocalRows, Turn};
use vertex_points::clear;
pub use vertex_points::shared_vertex_point_rows;

const NONE: u32 = u32::MAX;

/// The highest valence whose ring start an anchored key ([`Keyer::anchored_key`]) drops: the
/// direct construction shares a vertex's data between its faces in a batch, so around a
/// high-valence vertex a face costs less built directly than turned and laid out anew (on
/// `catmark_pole64` at isolation 2, anchoring the valence-64 pole cost +4.2 M instructions).
const MAX_TURNED_VALENCE: usize = 8;

/// The local topology of a face as its construction reads it, in the slots of its ring.
type TypeKey = Vec<u32>;

/// Per-call state: the slot of each vertex of the face being keyed, and which vertices get
/// per-vertex Gregory data (decided on the topology alone, with scalar points).
struct Keyer<'a> {
    topo: &'a Topology,
    tangents: GregoryTangents,
    slot: Vec<u32>,
    has_data: Vec<u8>,
    /// Per face: whether it gets a patch (0 or 1, 2 for not asked): a face is the edge
    /// neighbour of up to four faces keyed.
    has_patch: Vec<u8>,
    /// Per vertex: whether it is a smooth far corner in [`Self::push_one_sided_neighbour`]'s
    /// sense (0 or 1, 2 for not asked).
    smooth: Vec<u8>,
    /// The build's dart masks (whether one exists decides a dart's data; the construction
    /// reads the same solves).
    darts: &'a DartLimits,
    /// The corners' rings and shapes, each made once.
    corners: CornerRings<'a>,
    /// [`Self::key`]'s entries of the face's corners in [`Self::corners`].
    entries: Vec<usize>,
    /// Keying anchored ([`Self::anchored_key`]): the smooth vertices read so far.
    anchors: Option<Vec<Anchor>>,
}

/// A vertex of an anchored key ([`Keyer::anchored_key`]): its ring read from the face `start`
/// (of its faces) on, `valence` faces, and how its rows follow that start.
#[derive(Clone, Copy, Debug)]
struct Anchor {
    vertex: u32,
    start: u32,
    valence: u32,
    follows: Follows,
}

/// How the rows of an anchored vertex ([`Anchor`]) depend on where its ring starts, besides
/// which slot holds which vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Follows {
    /// Smooth: its cosine and sine sums turn with the start (derived points 1, 2,
    /// `InteriorBasis`).
    Turn,
    /// Crease: its two sector tangents (derived points 0, 1) come in the order of `sectors`,
    /// which read from this start is the topology ring's swapped (`true`) or not.
    Sectors(bool),
    /// Dart, corner or cone: not at all (a dart's masks turn with its sharp edge,
    /// `RingLimit::rotated`, so its limit point and tangents are the same sums; corners and
    /// cones have no derived point).
    Not,
}

/// The ring of the face being keyed: `rings[first..]`, slot `s` its `s`-th vertex.
struct FaceRing<'r> {
    rings: &'r mut Vec<u32>,
    first: usize,
}

impl FaceRing<'_> {
    /// Vertex `u`'s slot (`slot[u]`), the next one if `u` is not in the ring yet.
    fn slot(&mut self, slot: &mut [u32], u: u32) -> u32 {
        let s = &mut slot[u as usize];
        if *s == NONE {
            *s = (self.rings.len() - self.first) as u32;
            self.rings.push(u);
        }
        *s
    }
}

impl<'a> Keyer<'a> {
    /// Nothing asked yet, no slot set.
    fn new(topo: &'a Topology, tangents: GregoryTangents, darts: &'a DartLimits) -> Self {
        Keyer {
            topo,
            tangents,
            slot: vec![NONE; topo.vertex_count()],
            has_data: vec![2; topo.vertex_count()],
            has_patch: vec![2; topo.face_count()],
            smooth: vec![2; topo.vertex_count()],
            darts,
            corners: CornerRings::new(topo),
            entries: Vec::new(),
            anchors: None,
        }
    }

    /// Where the key reads vertex `v`'s ring from, as keyer of face `f` (one of `v`'s faces):
    /// its first face; in an anchored key, face `f` (recorded as an [`Anchor`]) if `v`'s faces
    /// close around it (else its ring's start is no choice: it starts at a boundary edge), at
    /// most [`MAX_TURNED_VALENCE`] of them, and the construction gives it data: smooth, or a
    /// dart, crease, corner or cone without frozen crease factors (those follow the order of
    /// its sectors, `Topology::crease_factors`).
    #[inline]
    fn start(&mut self, v: u32, f: u32) -> usize {
        // A plain key (pass 1, every face) reads every ring from its first face.
        if self.anchors.is_none() {
            return 0;
        }
        self.anchored_start(v, f)
    }

    /// [`Self::start`] in an anchored key.
    fn anchored_start(&mut self, v: u32, f: u32) -> usize {
        let topo = self.topo;
        let (faces, edges) = (topo.vertex_faces(v), topo.vertex_edges(v));
        let anchored = faces.len() <= MAX_TURNED_VALENCE
            && faces.len() == edges.len()
            && crease_factor_words(topo, v) == [0; 2];
        if !anchored || !self.has_data(v) {
            return 0;
        }
        let start = faces.iter().position(|&g| g == f).unwrap_or(0);
        let follows = match topology_rule(topo, v) {
            (Rule::Interior, _) => Follows::Turn,
            (Rule::Crease, sharp) => {
                // The crease's two sharp edges: the first and the next after it.
                let inf = |&e: &u32| topo.edge_sharpness(e) >= crate::mesh::INFINITE_SHARPNESS;
                let after = &edges[sharp.first + 1..];
                let second = sharp.first + 1 + after.iter().position(inf).unwrap_or(0);
                Follows::Sectors(sharp.first < start && start <= second)
            }
            _ => Follows::Not,
        };
        let anchor = Anchor {
            vertex: v,
            start: start as u32,
            valence: faces.len() as u32,
            follows,
        };
        if let Some(a) = self.anchors.as_mut() {
            a.push(anchor);
        }
        start
    }

    /// [`Self::key`] with every closed corner's ring that [`Self::start`] anchors, and every
    /// smooth far corner's ([`Self::push_one_sided_neighbour`]), read from the face keyed (the
    /// neighbour face for a far corner) rather than from the vertex's first face: faces whose
    /// keys differ only in where those rings start get the same anchored key; `anchors` the
    /// vertices so read (in key order, so faces of one anchored key list them alike).
    fn anchored_key(
        &mut self,
        f: u32,
        key: &mut TypeKey,
        rings: &mut Vec<u32>,
        anchors: &mut Vec<Anchor>,
    ) -> Option<()> {
        anchors.clear();
        self.anchors = Some(std::mem::take(anchors));
        let keyed = self.key(f, key, rings);
        *anchors = self.anchors.take().unwrap_or_default();
        keyed
    }

    /// Whether face `f` has a corner whose faces close around it, more than
    /// [`MAX_TURNED_VALENCE`] of them: its anchored key still reads where `f` sits in that
    /// corner's ring, which differs between the faces of such a vertex, so its type is left a
    /// class of its own without keying it anew (on `catmark_pole64` at isolation 2 that keying
    /// cost 1.2 M instructions).
    fn has_unturned_corner(&self, f: u32) -> bool {
        let topo = self.topo;
        topo.face_vertices(f).iter().any(|&v| {
            let n = topo.vertex_faces(v).len();
            n > MAX_TURNED_VALENCE && n == topo.vertex_edges(v).len()
        })
    }

    /// Whether vertex `v` gets per-vertex data ([`super::gregory_vertex_for`] is `Some`): topology only,
    /// so the scalar construction answers for the weight one.
    fn has_data(&mut self, v: u32) -> bool {
        let h = &mut self.has_data[v as usize];
        if *h == 2 {
            *h = u8::from(has_vertex_data(self.topo, v, self.darts));
        }
        *h == 1
    }

    /// Whether face `g` gets a patch ([`super::build::gregory_patch_for`] is `Ok`).
    fn has_patch(&mut self, g: u32) -> bool {
        if self.has_patch[g as usize] == 2 {
            let patch = end_cap_patch_with(self.topo, g, |&v| self.has_data(v));
            self.has_patch[g as usize] = u8::from(patch);
        }
        self.has_patch[g as usize] == 1
    }

    /// Whether far corner `z` takes the interior construction (`gregory_vertex_two_stage`'s
    /// tests: covered, then the interior rule), asked once per vertex.
    fn is_smooth(&mut self, z: u32) -> bool {
        if self.smooth[z as usize] == 2 {
            let topo = self.topo;
            let smooth = vertex_covered(topo, z, Coverage::EndCap) && is_interior_vertex(topo, z);
            self.smooth[z as usize] = u8::from(smooth);
        }
        self.smooth[z as usize] == 1
    }

    /// The key of face `f` in `key` (cleared first: one buffer for every face keyed), its ring
    /// appended to `rings` with `slot` set (the vertices of its corners' rings,
    /// [`CornerRings::entry`], in corner order, each once; slots count from the ring's start),
    /// then the vertices [`Self::push_vertex`] reads beyond them, in walk order (a non-smooth
    /// far corner's ring: on the car at isolation 2, 24 faces, 20 of them sharing a type);
    /// `None` where a neighbour is missing from its corners' faces.
    ///
    /// Each corner is its shape id and the place of `f` among its faces, then every entry of
    /// every corner's ring is its slot in the face's ring (but the first corner's, whose slots
    /// count up from 0 as its shape numbers them): with the shapes this is what
    /// [`Self::push_vertex`] writes of each corner (its edges' other ends and its faces'
    /// vertices in the face's slots), so faces with equal keys read the same.
    fn key(&mut self, f: u32, key: &mut TypeKey, rings: &mut Vec<u32>) -> Option<()> {
        let topo = self.topo;
        let fv = topo.face_vertices(f);
        key.clear();
        key.push(fv.len() as u32);
        self.entries.clear();
        for &v in fv {
            let faces = topo.vertex_faces(v);
            let start = self.start(v, f);
            let at = faces.iter().position(|&g| g == f);
            let entry = self.corners.entry(v, start);
            self.entries.push(entry);
            let turned = |j: usize| ((j + faces.len() - start) % faces.len()) as u32;
            key.extend([self.corners.shape(entry), at.map_or(NONE, turned)]);
        }
        // The first corner's ring takes the face ring's first slots in order (its entries are
        // distinct): those slots follow from its shape, so the key leaves them out.
        let first = rings.len();
        let (slot, corners) = (&mut self.slot[..], &self.corners);
        let mut entries = self.entries.iter();
        if let Some(&entry) = entries.next() {
            let own = corners.ring(entry);
            for (s, &u) in own.iter().enumerate() {
                slot[u as usize] = s as u32;
            }
            rings.extend_from_slice(own);
        }
        let mut ring = FaceRing { rings, first };
        for &entry in entries {
            for &u in corners.ring(entry) {
                key.push(ring.slot(slot, u));
            }
        }
        self.key_edges(f, key, &mut ring)
    }

    /// The words of `f`'s key after its corners: per edge, the neighbour across it (its place
    /// at the edge's first corner, whether it gets a patch, its far corners where its face
    /// points there are one-sided), [`NONE`] where there is none.
    fn key_edges(&mut self, f: u32, key: &mut TypeKey, ring: &mut FaceRing) -> Option<()> {
        let topo = self.topo;
        let fv = topo.face_vertices(f);
        // Edge `k` of the face joins corners `k` and `k + 1` (`Topology::face_edges`).
        let n = fv.len();
        for (k, &e) in topo.face_edges(f).iter().enumerate() {
            let (x, y) = (fv[k], fv[(k + 1) % n]);
            match topo.edge_faces(e).iter().copied().find(|&g| g != f) {
                Some(g) => {
                    let faces = topo.vertex_faces(x);
                    let at = faces.iter().position(|&h| h == g)?;
                    // Corner `x`'s ring as the key read it (`Self::key`).
                    let start = match &self.anchors {
                        Some(a) => a.iter().find(|a| a.vertex == x).map_or(0, |a| a.start),
                        None => 0,
                    };
                    key.push(((at + faces.len() - start as usize) % faces.len()) as u32);
                    key.push(u32::from(self.has_patch(g)));
                    self.push_one_sided_neighbour(key, ring, f, g, e, [x, y])?;
                }
                None => key.push(NONE),
            }
        }
        Some(())
    }
}

impl Keyer<'_> {
    /// Vertex `v` as the construction reads it, for face `f`: its sharpness, its edges (other
    /// end's slot, sharpness or [`PROMOTED`](super::corner_rings::PROMOTED), face count) and faces (sizes, vertex slots);
    /// those vertices not yet in the ring appended to it (their slots, hence the walk order,
    /// are in the key, so faces with equal keys number them alike).
    fn push_vertex(&mut self, key: &mut TypeKey, ring: &mut FaceRing, f: u32, v: u32) {
        let topo = self.topo;
        let mut slot = |x: u32| ring.slot(&mut self.slot, x);
        key.push(vertex_word(topo, v));
        key.extend(crease_factor_words(topo, v));
        let edges = topo.vertex_edges(v);
        key.push(edges.len() as u32);
        for &e in edges {
            key.push(slot(topo.other_vertex(e, v)));
            key.push(edge_word(topo, e));
            key.push(topo.edge_faces(e).len() as u32);
        }
        let faces = topo.vertex_faces(v);
        key.push(faces.len() as u32);
        for &g in faces {
            let gv = topo.face_vertices(g);
            key.push(u32::from(g == f) | u32::from(topo.has_limit_surface(g)) << 1);
            key.push(gv.len() as u32);
            for &u in gv {
                key.push(slot(u));
            }
        }
    }

    /// The far corners of neighbour `g` across the sharp edge `e` (`x`-`y`) of `f`, when `g`'s face
    /// points beside that edge may be one-sided (`GregoryVertex::one_sided`): there `g`'s face
    /// point next to the edge is its other one at `x` (or `y`), which reads the edge point and
    /// cosine of `g`'s corner beyond, not a corner of `f` (the rows of [`sparse_face_rows_direct`]
    /// hold `g`'s face points next to the edge). A smooth corner (the interior construction, judged
    /// by the construction's own tests: two-stage, its derived points and cosine) is its valence,
    /// its faces' sizes and `g`'s place in its ring; another one is read in full
    /// ([`Self::push_vertex`]). Promoted creases too, whose face points are one-sided in some
    /// sectors only (`VertexRing::one_sided_edge`): more key than needed, the same rows.
    fn push_one_sided_neighbour(
        &mut self,
        key: &mut TypeKey,
        ring: &mut FaceRing,
        f: u32,
        g: u32,
        e: u32,
        [x, y]: [u32; 2],
    ) -> Option<()> {
        let topo = self.topo;
        let sharp = topo.edge_sharpness(e) >= crate::mesh::INFINITE_SHARPNESS;
        if !sharp || !self.tangents.one_sided_face_points(true) {
            return Some(());
        }
        for &z in topo.face_vertices(g) {
            if z == x || z == y {
                continue;
            }
            let faces = topo.vertex_faces(z);
            let smooth = self.is_smooth(z);
            key.push(u32::from(smooth));
            if smooth {
                let n = faces.len();
                let at = faces.iter().position(|&h| h == g)?;
                let start = self.start(z, g);
                key.push(n as u32);
                key.push(((at + n - start) % n) as u32);
                let turned = (0..n).map(|i| faces[(start + i) % n]);
                key.extend(turned.map(|h| topo.face_size(h) as u32));
            } else {
                self.push_vertex(key, ring, f, z);
            }
        }
        Some(())
    }
}

/// The connectivity types of one call grouped into classes: types whose representatives'
/// anchored keys ([`Keyer::anchored_key`]) agree, so that their rows differ only in where their
/// anchored vertices' rings start ([`Follows`]), which a turn of the first type's rows gives
/// ([`LocalRows::turned`]).
struct TypeClasses {
    /// Per type: its class.
    class_of: Vec<u32>,
    /// Per class: its first type.
    first: Vec<u32>,
    /// Per type: the slot in its ring of each slot of its anchored ring (`NONE` where that
    /// vertex is not in its ring), one type after another.
    slots: Vec<u32>,
    /// `types + 1` offsets into `slots`.
    slots_at: Vec<u32>,
    /// Per type: its anchors, each vertex as its slot in the type's ring.
    anchors: Vec<Anchor>,
    /// `types + 1` offsets into `anchors`.
    anchors_at: Vec<u32>,
}

impl TypeClasses {
    /// The classes of the types of `representative` (per type: its first face, an index into
    /// `faces`, whose ring is `rings[ring_at[i]..ring_at[i + 1]]`).
    fn new(
        keyer: &mut Keyer,
        faces: &[u32],
        representative: &[usize],
        rings: &[u32],
        ring_at: &[u32],
    ) -> TypeClasses {
        let mut classes: WordHashMap<TypeKey, u32> = WordHashMap::default();
        let mut out = TypeClasses {
            class_of: Vec::with_capacity(representative.len()),
            first: Vec::new(),
            slots: Vec::new(),
            slots_at: vec![0],
            anchors: Vec::new(),
            anchors_at: vec![0],
        };
        let (mut key, mut ring, mut anchors) = (TypeKey::new(), Vec::new(), Vec::new());
        for (t, &i) in representative.iter().enumerate() {
            ring.clear();
            anchors.clear();
            let keyed = match keyer.has_unturned_corner(faces[i]) {
                true => None,
                false => keyer.anchored_key(faces[i], &mut key, &mut ring, &mut anchors),
            };
            clear(&mut keyer.slot, &ring);
            let next = out.first.len() as u32;
            let class = match keyed {
                Some(()) => *classes.entry(key.clone()).or_insert(next),
                None => next,
            };
            if class == next {
                out.first.push(t as u32);
            }
            out.class_of.push(class);
            let own = &rings[ring_at[i] as usize..ring_at[i + 1] as usize];
            for (s, &x) in own.iter().enumerate() {
                keyer.slot[x as usize] = s as u32;
            }
            out.slots
                .extend(ring.iter().map(|&u| keyer.slot[u as usize]));
            out.anchors.extend(anchors.iter().map(|a| Anchor {
                vertex: keyer.slot[a.vertex as usize],
                ..*a
            }));
            clear(&mut keyer.slot, own);
            out.slots_at.push(out.slots.len() as u32);
            out.anchors_at.push(out.anchors.len() as u32);
        }
        out
    }

    /// Type `t`'s anchored slots and anchors.
    fn of(&self, t: u32) -> (&[u32], &[Anchor]) {
        let t = t as usize;
        (
            &self.slots[self.slots_at[t] as usize..self.slots_at[t + 1] as usize],
            &self.anchors[self.anchors_at[t] as usize..self.anchors_at[t + 1] as usize],
        )
    }

    /// What makes the rows of type `t`'s class's first type `t`'s ([`LocalRows::turned`]):
    /// the slot in `t`'s ring of each slot of the first's, and at its slot in the first's
    /// ring, the turn of each smooth vertex whose ring starts elsewhere (`InteriorBasis`: the
    /// sums of a ring started `d` faces on are the first's turned by `2 pi d / n`; none where
    /// `d = 0`) and the swap of each crease whose sectors come in the other order
    /// ([`Follows`]). `None` where the rings do not map one onto the other or a vertex would
    /// take two turns.
    fn turns(&self, t: u32) -> Option<(Vec<u32>, Vec<Turn>)> {
        let (slots, anchors) = self.of(t);
        let (first_slots, first_anchors) = self.of(self.first[self.class_of[t as usize] as usize]);
        if slots.len() != first_slots.len() || anchors.len() != first_anchors.len() {
            return None;
        }
        let mut to = vec![NONE; slots.len()];
        for (&a, &b) in first_slots.iter().zip(slots) {
            *to.get_mut(a as usize)? = b;
        }
        if to.contains(&NONE) {
            return None;
        }
        // Per anchored slot of the first's ring: what its rows take (a turn by `d` faces, or
        // whether its sector tangents swap), 0 for nothing.
        let mut takes: Vec<(u32, Follows, u32, u32)> = Vec::new();
        for (a, b) in first_anchors.iter().zip(anchors) {
            let n = b.valence;
            if to.get(a.vertex as usize) != Some(&b.vertex) {
                return None;
            }
            let take = match (a.follows, b.follows) {
                (Follows::Turn, Follows::Turn) => (b.start + n - a.start) % n,
                (Follows::Sectors(x), Follows::Sectors(y)) => u32::from(x != y),
                (Follows::Not, Follows::Not) => 0,
                _ => return None,
            };
            match takes.iter().find(|u| u.0 == a.vertex) {
                Some(u) if u.2 != take => return None,
                Some(_) => {}
                None => takes.push((a.vertex, a.follows, take, n)),
            }
        }
        let turns = (takes.into_iter())
            .filter(|u| u.2 != 0)
            .map(|(slot, follows, take, n)| match follows {
                Follows::Turn => {
                    let a = 2.0 * std::f64::consts::PI * take as f64 / n as f64;
                    let (sin, cos) = a.sin_cos();
                    Turn::Rotate {
                        slot,
                        cos,
                        sin,
                        steps: take,
                        valence: n,
                    }
                }
                _ => Turn::Swap { slot },
            })
            .collect();
        Some((to, turns))
    }
}

/// [`super::stencil_table::sparse_face_rows_direct`] on `faces` split into one batch per rayon
/// thread (one batch on one thread): a face's rows do not depend on its batch, only the sharing
/// of vertex data does. `has_data`: the keys' answers of which vertices have data (per vertex
/// 0 or 1, 2 for not asked).
fn direct_batches(
    topo: &Topology,
    faces: &[u32],
    tangents: GregoryTangents,
    darts: &DartLimits,
    has_data: &[u8],
) -> Vec<Result<FaceRows, NotGregory>> {
    let direct = |batch| sparse_face_rows_direct_with(topo, batch, tangents, darts, Some(has_data));
    let per = faces.len().div_ceil(rayon::current_num_threads()).max(64);
    if faces.len() <= per {
        return direct(faces);
    }
    let batches: Vec<_> = faces.par_chunks(per).map(direct).collect();
    batches.into_iter().flatten().collect()
}

/// [`sparse_face_rows_direct`] with the construction run once per connectivity type (module
/// docs): the same rows ([`sparse_face_rows_flat`] as [`Weights`]), bitwise but for the face
/// points of turned types (module docs).
pub fn sparse_face_rows(
    topo: &Topology,
    faces: &[u32],
    tangents: GregoryTangents,
    darts: &DartLimits,
) -> Vec<Result<Vec<Weights>, NotGregory>> {
    sparse_face_rows_flat(topo, faces, tangents, darts)
        .into_iter()
        .map(|r| r.map(|r| r.to_weights()))
        .collect()
}

/// The rows of [`sparse_face_rows`], each face's in one [`FaceRows`]
/// ([`EndCapFaceRows::rows`] with the level's ids).
pub fn sparse_face_rows_flat(
    topo: &Topology,
    faces: &[u32],
    tangents: GregoryTangents,
    darts: &DartLimits,
) -> Vec<Result<FaceRows, NotGregory>> {
    let shared = end_cap_face_rows(topo, faces, tangents, darts, Terms::All);
    let derived = |v, b| vertex_point_id(topo, v, b);
    (0..faces.len())
        .map(|i| {
            shared
                .result(i)
                .map(|()| shared.rows(topo, i, &|u| u, &derived))
        })
        .collect()
}

/// The end-cap rows of one face as [`end_cap_face_rows`] keeps them.
enum FaceRow {
    /// Built directly: over the level's vertices and [`vertex_point_id`]s.
    Direct(FaceRows),
    /// Its type's rows laid out in the order of its ring's ids ([`Layouts::layout`]) (its
    /// ring: [`EndCapFaceRows::ring`]).
    Shared { layout: u32 },
}

/// The end-cap rows of a set of faces with the construction run once per connectivity type
/// (module docs), each face's kept as built (directly, or its type's rows laid out over slots
/// and its ring) until [`Self::rows`] writes them with the caller's ids: one pass over the
/// terms where relabelling them to the level's ids and then to the caller's would take two.
pub struct EndCapFaceRows {
    layouts: Layouts,
    faces: Vec<Result<FaceRow, NotGregory>>,
    /// The faces' rings (the vertex of each slot), one after another.
    rings: Vec<u32>,
    /// `faces + 1` offsets into `rings`.
    ring_at: Vec<u32>,
    /// The terms [`Self::rows`] keeps (a directly built face keeps them all until then, so
    /// [`Self::derived_read`] sees every term).
    kept: Terms,
}

impl EndCapFaceRows {
    /// Number of faces.
    pub fn len(&self) -> usize {
        self.faces.len()
    }

    /// Whether there is no face.
    pub fn is_empty(&self) -> bool {
        self.faces.is_empty()
    }

    /// The ring of face `i` (the vertex of each slot).
    fn ring(&self, i: usize) -> &[u32] {
        &self.rings[self.ring_at[i] as usize..self.ring_at[i + 1] as usize]
    }

    /// Whether face `i` (of the faces asked, in order) gets a patch, or why not.
    pub fn result(&self, i: usize) -> Result<(), NotGregory> {
        self.faces[i].as_ref().map(|_| ()).map_err(|e| *e)
    }

    /// Calls `mark(v, b)` for each derived point `b` of vertex `v` ([`vertex_point_id`]) face
    /// `i`'s rows read (a point may come more than once); nothing for a face without patch.
    pub fn derived_read(&self, topo: &Topology, i: usize, mut mark: impl FnMut(u32, u32)) {
        match &self.faces[i] {
            Ok(FaceRow::Direct(rows)) => rows
                .terms
                .iter()
                .filter_map(|&(id, _)| vertex_point_of(topo, id))
                .for_each(|(v, b)| mark(v, b)),
            Ok(FaceRow::Shared { layout }) => {
                let ring = self.ring(i);
                self.layouts.derived_read(*layout, |s, b| mark(ring[s], b));
            }
            Err(_) => {}
        }
    }

    /// Face `i`'s rows (empty for a face without patch) with vertex `u` written as
    /// `vertex(u)` and derived point `b` of vertex `v` as `derived(v, b)`: both monotone, every
    /// derived id past every vertex id (as [`vertex_point_id`]), so rows stay ascending; the
    /// terms [`end_cap_face_rows`] was asked to keep.
    pub fn rows(
        &self,
        topo: &Topology,
        i: usize,
        vertex: &(impl Fn(u32) -> u32 + Sync),
        derived: &(impl Fn(u32, u32) -> u32 + Sync),
    ) -> FaceRows {
        if self.faces[i].is_err() {
            return FaceRows::default();
        }
        let mut out = FaceRows::new();
        self.rows_into(topo, i, vertex, derived, &mut out);
        out
    }

    /// At least the number of terms of [`Self::rows`] of every face.
    pub fn terms_bound(&self) -> usize {
        (self.faces.iter())
            .map(|f| match f {
                Ok(FaceRow::Direct(rows)) => rows.terms.len(),
                Ok(FaceRow::Shared { layout }) => self.layouts.term_count(*layout),
                Err(_) => 0,
            })
            .sum()
    }

    /// Appends [`Self::rows`] of face `i` to `out`.
    fn rows_into(
        &self,
        topo: &Topology,
        i: usize,
        vertex: &(impl Fn(u32) -> u32 + Sync),
        derived: &(impl Fn(u32, u32) -> u32 + Sync),
        out: &mut FaceRows,
    ) {
        match &self.faces[i] {
            Ok(FaceRow::Direct(rows)) => {
                let id = |id| match vertex_point_of(topo, id) {
                    None => vertex(id),
                    Some((v, b)) => derived(v, b),
                };
                out.relabelled_into(&rows.offsets, &rows.terms, self.kept, id);
            }
            Ok(FaceRow::Shared { layout }) => {
                (self.layouts).rows_into(*layout, self.ring(i), vertex, derived, out)
            }
            Err(_) => {}
        }
    }

    /// Appends [`Self::rows`] of every face, in order, to `out`, each face's padded with empty
    /// rows to `face_rows` rows (so face `i`'s rows start at `face_rows * i`): on the rayon
    /// pool in batches of whole faces, each batch's rows in one buffer (no buffer per face).
    /// The caller reserves room in `out` ([`Self::terms_bound`], for every level at once).
    pub fn all_rows_into(
        &self,
        topo: &Topology,
        vertex: &(impl Fn(u32) -> u32 + Sync),
        derived: &(impl Fn(u32, u32) -> u32 + Sync),
        face_rows: usize,
        out: &mut FaceRows,
    ) {
        let batch = |faces: std::ops::Range<usize>, out: &mut FaceRows| {
            for i in faces {
                let first = out.len();
                self.rows_into(topo, i, vertex, derived, out);
                out.push_empty(face_rows - (out.len() - first));
            }
        };
        let per = self.len().div_ceil(rayon::current_num_threads()).max(256);
        if self.len() <= per {
            return batch(0..self.len(), out);
        }
        let batches: Vec<FaceRows> = (0..self.len().div_ceil(per))
            .into_par_iter()
            .map(|b| {
                let mut rows = FaceRows::new();
                batch(b * per..self.len().min((b + 1) * per), &mut rows);
                rows
            })
            .collect();
        for rows in &batches {
            out.append(rows);
        }
    }
}

/// Pass 1 of [`end_cap_face_rows`]: each face's connectivity type (`None`: built directly),
/// the first face of each type its representative, and each face's ring, numbered once (the
/// relabelling reads it again), in one buffer.
struct FaceTypes {
    /// Number of types.
    types: usize,
    /// Per face: its type.
    type_of: Vec<Option<u32>>,
    /// Per type: its first face (an index into the faces keyed).
    representative: Vec<usize>,
    /// The faces' rings (the vertex of each slot), one after another.
    rings: Vec<u32>,
    /// `faces + 1` offsets into `rings`.
    ring_at: Vec<u32>,
}

impl FaceTypes {
    /// The types of `faces`.
    fn new(keyer: &mut Keyer, faces: &[u32]) -> FaceTypes {
        let mut types: WordHashMap<TypeKey, u32> = WordHashMap::default();
        let mut out = FaceTypes {
            types: 0,
            type_of: Vec::with_capacity(faces.len()),
            representative: Vec::new(),
            rings: Vec::new(),
            ring_at: Vec::with_capacity(faces.len() + 1),
        };
        out.ring_at.push(0);
        let mut key = TypeKey::new();
        for (i, &f) in faces.iter().enumerate() {
            let first = out.rings.len();
            let keyed = keyer.key(f, &mut key, &mut out.rings);
            let t = keyed.map(|()| match types.get(key.as_slice()) {
                Some(&t) => t,
                None => {
                    let t = types.len() as u32;
                    types.insert(key.clone(), t);
                    out.representative.push(i);
                    t
                }
            });
            out.ring_at.push(out.rings.len() as u32);
            clear(&mut keyer.slot, &out.rings[first..]);
            out.type_of.push(t);
        }
        out.types = types.len();
        out
    }
}

/// The rows of `faces` with the construction run once per connectivity type, kept per face
/// as built ([`EndCapFaceRows`]), with the terms `kept` keeps (a type's dropped once for all
/// its faces). The direct batches run on the rayon pool. Dart masks from `darts` (one cache
/// per build).
pub fn end_cap_face_rows(
    topo: &Topology,
    faces: &[u32],
    tangents: GregoryTangents,
    darts: &DartLimits,
    kept: Terms,
) -> EndCapFaceRows {
    let mut keyer = Keyer::new(topo, tangents, darts);
    let FaceTypes {
        types,
        type_of,
        representative,
        mut rings,
        ring_at,
    } = FaceTypes::new(&mut keyer, faces);
    let ring_of = |ring_at: &[u32], i: usize| ring_at[i] as usize..ring_at[i + 1] as usize;
    // Pass 2: the types' classes (equal up to where closed corners' rings start), then the
    // first representative of each class and the faces without type, directly, in one batch
    // (one vertex's data serves all its faces).
    let classes = TypeClasses::new(&mut keyer, faces, &representative, &rings, &ring_at);
    let class_face =
        |t: u32| representative[classes.first[classes.class_of[t as usize] as usize] as usize];
    let batch = |pick: &dyn Fn(usize) -> bool| -> Vec<usize> {
        (0..faces.len()).filter(|&i| pick(i)).collect()
    };
    let first = batch(&|i| type_of[i].is_none_or(|t| class_face(t) == i));
    let mut rows: Vec<Option<Result<FaceRows, NotGregory>>> =
        (0..faces.len()).map(|_| None).collect();
    let first_faces: Vec<u32> = first.iter().map(|&i| faces[i]).collect();
    for (&i, r) in first.iter().zip(direct_batches(
        topo,
        &first_faces,
        tangents,
        darts,
        &keyer.has_data,
    )) {
        rows[i] = Some(r);
    }
    // Rows over slots per class (its first type's): `None` where that face has no patch or its
    // rows leave its ring (then every face of the class is built directly), or it is the
    // class's only face.
    let mut members = vec![0u32; classes.first.len()];
    for t in type_of.iter().flatten() {
        members[classes.class_of[*t as usize] as usize] += 1;
    }
    let class_rows: Vec<Option<LocalRows>> = (classes.first.iter().zip(&members))
        .map(|(&t, &m)| {
            let i = representative[t as usize];
            if m == 1 {
                return None;
            }
            let ring = &rings[ring_of(&ring_at, i)];
            for (s, &x) in ring.iter().enumerate() {
                keyer.slot[x as usize] = s as u32;
            }
            let local = match &rows[i] {
                Some(Ok(r)) => to_slots(topo, r, &keyer.slot, ring.len(), kept),
                _ => None,
            };
            clear(&mut keyer.slot, ring);
            local
        })
        .collect();
    // Each type's rows in one list: a class's first type's, a turned type's turned from them,
    // a type without turn its class's very rows; `to_class`: per other type of a class, the
    // slot in its ring of each slot of the class's (its faces' rings are put in the class's
    // order below, so that one layout serves the faces of every type without turn).
    let mut with_rows: Vec<LocalRows> = Vec::new();
    let class_at: Vec<u32> = (class_rows.into_iter())
        .map(|l| match l {
            Some(l) => {
                with_rows.push(l);
                with_rows.len() as u32 - 1
            }
            None => NONE,
        })
        .collect();
    let mut to_class: Vec<Option<Vec<u32>>> = vec![None; representative.len()];
    let angles = EdgeAngles::new(MAX_TURNED_VALENCE);
    let at: Vec<u32> = (0..representative.len())
        .map(|t| {
            let c = classes.class_of[t] as usize;
            let from = class_at[c];
            if from == NONE || classes.first[c] as usize == t {
                return from;
            }
            let Some((to, turns)) = classes.turns(t as u32) else {
                return NONE;
            };
            if to.len() != ring_of(&ring_at, representative[t]).len() {
                return NONE;
            }
            to_class[t] = Some(to);
            if turns.is_empty() {
                return from;
            }
            let turned = with_rows[from as usize].turned(&turns, kept, &angles);
            with_rows.push(turned);
            with_rows.len() as u32 - 1
        })
        .collect();
    // Pass 3: faces of a type without local rows, directly in a second batch; the others
    // relabelled.
    let second =
        batch(&|i| rows[i].is_none() && type_of[i].is_some_and(|t| at[t as usize] == NONE));
    let second_faces: Vec<u32> = second.iter().map(|&i| faces[i]).collect();
    for (&i, r) in second.iter().zip(direct_batches(
        topo,
        &second_faces,
        tangents,
        darts,
        &keyer.has_data,
    )) {
        rows[i] = Some(r);
    }
    // The shared faces' rings in their class's order.
    let mut class_order = Vec::new();
    for (i, t) in type_of.iter().enumerate() {
        let to = t.and_then(|t| to_class[t as usize].as_ref());
        if let (Some(to), None) = (to, &rows[i]) {
            let ring = &mut rings[ring_of(&ring_at, i)];
            class_order.clear();
            class_order.extend(to.iter().map(|&s| ring[s as usize]));
            ring.copy_from_slice(&class_order);
        }
    }
    let mut layouts = Layouts::new(with_rows);
    let out = EndCapFaceRows {
        faces: rows
            .into_iter()
            .enumerate()
            .map(|(i, r)| match r {
                Some(r) => r.map(FaceRow::Direct),
                None => {
                    let t = type_of[i].expect("faces without type are built in the first batch");
                    let local = at[t as usize];
                    assert_ne!(
                        local, NONE,
                        "types without rows are built in the second batch"
                    );
                    let layout = layouts.layout(local, &rings[ring_of(&ring_at, i)]);
                    Ok(FaceRow::Shared { layout })
                }
            })
            .collect(),
        layouts,
        rings,
        ring_at,
        kept,
    };
    log::trace!(
        "end-cap rows: {} faces, {} connectivity types in {} classes, {} + {} built directly",
        faces.len(),
        types,
        classes.first.len(),
        first.len(),
        second.len()
    );
    out
}

#[cfg(test)]
mod tests;
