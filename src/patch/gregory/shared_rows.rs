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

mod layouts;
mod vertex_points;

use rayon::prelude::*;

use super::build::{
    end_cap_patch_with, has_vertex_data, is_interior_vertex, vertex_covered, Coverage, NotGregory,
};
use super::corner_rings::{edge_word, vertex_word, CornerRings};
pub use super::face_rows::{FaceRows, Terms};
use super::point::Weights;
#[cfg(doc)]
use super::stencil_table::sparse_face_rows_direct;
use super::stencil_table::{sparse_face_rows_direct_with, vertex_point_id, vertex_point_of};
use super::tangents::GregoryTangents;
use super::tangents_boundary::crease_factor_words;
use super::vertex::DartLimits;
use super::word_hash::WordHashMap;
use crate::topology::Topology;
use layouts::{to_slots, Layouts, LocalRows};
use vertex_points::clear;
pub use vertex_points::shared_vertex_point_rows;

const NONE: u32 = u32::MAX;

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
        }
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
    /// [`CornerRings::corner`], in corner order, each once; slots count from the ring's start),
    /// then the vertices [`Self::push_vertex`] reads beyond them, in walk order (a non-smooth
    /// far corner's ring: on the car at isolation 2, 24 faces, 20 of them sharing a type);
    /// `None` where a neighbour is missing from its corners' faces.
    ///
    /// Each corner is its shape id and the place of `f` among its faces, then every entry of
    /// every corner's ring is its slot in the face's ring: with the shapes this is what
    /// [`Self::push_vertex`] writes of each corner (its edges' other ends and its faces'
    /// vertices in the face's slots), so faces with equal keys read the same.
    fn key(&mut self, f: u32, key: &mut TypeKey, rings: &mut Vec<u32>) -> Option<()> {
        let topo = self.topo;
        let fv = topo.face_vertices(f);
        key.clear();
        key.push(fv.len() as u32);
        for &v in fv {
            let at = topo.vertex_faces(v).iter().position(|&g| g == f);
            key.extend([self.corners.corner(v).0, at.map_or(NONE, |j| j as u32)]);
        }
        let mut ring = FaceRing {
            first: rings.len(),
            rings,
        };
        for &v in fv {
            for &u in self.corners.corner(v).1 {
                key.push(ring.slot(&mut self.slot, u));
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
                    let at = topo.vertex_faces(x).iter().position(|&h| h == g)?;
                    key.push(at as u32);
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
                key.push(faces.len() as u32);
                key.push(faces.iter().position(|&h| h == g)? as u32);
                key.extend(faces.iter().map(|&h| topo.face_size(h) as u32));
            } else {
                self.push_vertex(key, ring, f, z);
            }
        }
        Some(())
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
/// docs): bitwise the same rows ([`sparse_face_rows_flat`] as [`Weights`]).
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
        match &self.faces[i] {
            Ok(FaceRow::Direct(rows)) => {
                let id = |id| match vertex_point_of(topo, id) {
                    None => vertex(id),
                    Some((v, b)) => derived(v, b),
                };
                FaceRows::relabelled(&rows.offsets, &rows.terms, self.kept, id)
            }
            Ok(FaceRow::Shared { layout }) => {
                self.layouts.rows(*layout, self.ring(i), vertex, derived)
            }
            Err(_) => FaceRows::default(),
        }
    }

    /// [`Self::rows`] of every face with a patch, in order, on the rayon pool.
    pub fn all_rows(
        &self,
        topo: &Topology,
        vertex: &(impl Fn(u32) -> u32 + Sync),
        derived: &(impl Fn(u32, u32) -> u32 + Sync),
    ) -> Vec<FaceRows> {
        (0..self.len())
            .into_par_iter()
            .with_min_len(256)
            .map(|i| self.rows(topo, i, vertex, derived))
            .collect()
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
    // Pass 1: each face's connectivity type (`None`: built directly), the first face of each
    // type its representative.
    let mut types: WordHashMap<TypeKey, u32> = WordHashMap::default();
    let mut type_of: Vec<Option<u32>> = Vec::with_capacity(faces.len());
    let mut representative: Vec<usize> = Vec::new();
    // Each face's ring, numbered once (the relabelling reads it again), in one buffer.
    let mut rings: Vec<u32> = Vec::new();
    let mut ring_at: Vec<u32> = Vec::with_capacity(faces.len() + 1);
    ring_at.push(0);
    let ring_of = |ring_at: &[u32], i: usize| ring_at[i] as usize..ring_at[i + 1] as usize;
    let mut key = TypeKey::new();
    for (i, &f) in faces.iter().enumerate() {
        let keyed = keyer.key(f, &mut key, &mut rings);
        let t = keyed.map(|()| match types.get(key.as_slice()) {
            Some(&t) => t,
            None => {
                let t = types.len() as u32;
                types.insert(key.clone(), t);
                representative.push(i);
                t
            }
        });
        ring_at.push(rings.len() as u32);
        clear(&mut keyer.slot, &rings[ring_of(&ring_at, i)]);
        type_of.push(t);
    }
    // Pass 2: the representatives and the faces without type, directly, in one batch (one
    // vertex's data serves all its faces).
    let is_rep = |i: usize, t: Option<u32>| t.is_none_or(|t| representative[t as usize] == i);
    let batch = |pick: &dyn Fn(usize) -> bool| -> Vec<usize> {
        (0..faces.len()).filter(|&i| pick(i)).collect()
    };
    let first = batch(&|i| is_rep(i, type_of[i]));
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
    // Rows over slots per type: `None` where the representative has no patch or its rows leave
    // its ring (then every face of the type is built directly), or it is the type's only face.
    let mut members = vec![0u32; representative.len()];
    for t in type_of.iter().flatten() {
        members[*t as usize] += 1;
    }
    let local: Vec<Option<LocalRows>> = representative
        .iter()
        .zip(&members)
        .map(|(&i, &m)| {
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
    // Pass 3: faces of a type without local rows, directly in a second batch; the others
    // relabelled.
    let second =
        batch(&|i| rows[i].is_none() && type_of[i].is_some_and(|t| local[t as usize].is_none()));
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
    // The types' rows in one list, each type with rows at its place there.
    let mut with_rows: Vec<LocalRows> = Vec::new();
    let at: Vec<u32> = local
        .into_iter()
        .map(|l| match l {
            Some(l) => {
                with_rows.push(l);
                with_rows.len() as u32 - 1
            }
            None => NONE,
        })
        .collect();
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
        "end-cap rows: {} faces, {} connectivity types, {} + {} built directly",
        faces.len(),
        types.len(),
        first.len(),
        second.len()
    );
    out
}

#[cfg(test)]
mod tests;
