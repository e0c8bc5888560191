//! The sparse end-cap rows of [`super::stencil_table::sparse_face_rows_direct`] computed once per
//! connectivity type (Loop et al. 2009 §4.3, as [`super::stencil_table::GregoryStencilTable`]
//! shares f32 types): faces whose local topology reads the same in the slots of their ring
//! (their corners' one-rings, corner by corner, each vertex once: the vertices of
//! [`super::stencil::canonical_ring`] in another order) run the very same construction steps
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

use rayon::prelude::*;

use super::build::{
    end_cap_patch_with, has_vertex_data, vertex_covered, vertex_ring_with, Coverage, NoPoint,
    NotGregory,
};
use super::corner_rings::{edge_word, vertex_word, CornerRings};
pub use super::face_rows::FaceRows;
use super::point::Weights;
#[cfg(doc)]
use super::stencil_table::sparse_face_rows_direct;
use super::stencil_table::{
    sparse_face_rows_direct_with, vertex_point_id, vertex_point_of, vertex_point_rows_with,
    VERTEX_POINTS,
};
use super::tangents::GregoryTangents;
use super::tangents_boundary::crease_factor_words;
use super::vertex::{is_interior_ring, DartLimits};
use super::word_hash::WordHashMap;
use crate::topology::Topology;

const NONE: u32 = u32::MAX;

/// The local topology of a face as its construction reads it, in the slots of its ring.
type TypeKey = Vec<u32>;

/// One type's rows over ring slots in the direct construction's values, stored column by
/// column, so that a face's rows come out ascending in its global ids by walking its slots in
/// id order once ([`from_slots`]) rather than sorting every row.
struct LocalRows {
    /// `rows + 1` term offsets: every face of the type has these.
    offsets: Vec<u32>,
    /// `slots + 1` offsets into `columns`.
    starts: Vec<u32>,
    /// Slot `s`'s terms `(row, weight)`, rows ascending: `columns[starts[s]..starts[s + 1]]`.
    columns: Vec<(u32, f64)>,
}

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
            let smooth = vertex_covered(topo, z, Coverage::EndCap)
                && is_interior_ring(&vertex_ring_with(topo, z, &|_| NoPoint));
            self.smooth[z as usize] = u8::from(smooth);
        }
        self.smooth[z as usize] == 1
    }

    /// The key of face `f` in `key` (cleared first: one buffer for every face keyed), its ring
    /// in `ring` with `slot` set (the vertices of its corners' rings, [`CornerRings::corner`],
    /// in corner order, each once); `None` where a vertex the construction reads lies outside
    /// the ring.
    ///
    /// Each corner is its shape id and the place of `f` among its faces, then every entry of
    /// every corner's ring is its slot in the face's ring: with the shapes this is what
    /// [`Self::push_vertex`] writes of each corner (its edges' other ends and its faces'
    /// vertices in the face's slots), so faces with equal keys read the same.
    fn key(&mut self, f: u32, key: &mut TypeKey) -> (Vec<u32>, Option<()>) {
        let topo = self.topo;
        let fv = topo.face_vertices(f);
        key.clear();
        key.push(fv.len() as u32);
        for &v in fv {
            let at = topo.vertex_faces(v).iter().position(|&g| g == f);
            key.extend([self.corners.corner(v).0, at.map_or(NONE, |j| j as u32)]);
        }
        let mut ring: Vec<u32> = Vec::with_capacity(RING_CAPACITY);
        for &v in fv {
            for &u in self.corners.corner(v).1 {
                let s = &mut self.slot[u as usize];
                if *s == NONE {
                    *s = ring.len() as u32;
                    ring.push(u);
                }
                key.push(*s);
            }
        }
        let edges = self.key_edges(f, key);
        (ring, edges)
    }

    /// The words of `f`'s key after its corners: per edge, the neighbour across it (its place
    /// at the edge's first corner, whether it gets a patch, its far corners where its face
    /// points there are one-sided), [`NONE`] where there is none.
    fn key_edges(&mut self, f: u32, key: &mut TypeKey) -> Option<()> {
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
                    self.push_one_sided_neighbour(key, f, g, e, [x, y])?;
                }
                None => key.push(NONE),
            }
        }
        Some(())
    }
}

impl Keyer<'_> {
    /// Vertex `v` as the construction reads it, for face `f`: its sharpness, its edges (other
    /// end's slot, sharpness or [`PROMOTED`], face count) and faces (sizes, vertex slots);
    /// `None` where one of those vertices lies outside the ring.
    fn push_vertex(&self, key: &mut TypeKey, f: u32, v: u32) -> Option<()> {
        let topo = self.topo;
        let slot = |x: u32| match self.slot[x as usize] {
            NONE => None,
            s => Some(s),
        };
        key.push(vertex_word(topo, v));
        key.extend(crease_factor_words(topo, v));
        let edges = topo.vertex_edges(v);
        key.push(edges.len() as u32);
        for &e in edges {
            key.push(slot(topo.other_vertex(e, v))?);
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
                key.push(slot(u)?);
            }
        }
        Some(())
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
                self.push_vertex(key, f, z)?;
            }
        }
        Some(())
    }
}

/// Room [`Keyer::key`] makes for a face's ring up front: a quad's ring (16 vertices at
/// valence-4 corners, 24 at valence 6) without growing it.
const RING_CAPACITY: usize = 32;

/// `rows` over slots, or `None` when a weight lies outside the ring: vertex `v` at its slot,
/// derived point `b` of `v` ([`vertex_point_id`]) at `ring_len + 3 slot(v) + b`.
fn to_slots(topo: &Topology, rows: &FaceRows, slot: &[u32], ring_len: usize) -> Option<LocalRows> {
    let slot_of = |id: u32| match vertex_point_of(topo, id) {
        None => Some(slot[id as usize]).filter(|&s| s != NONE),
        Some((v, b)) => match slot[v as usize] {
            NONE => None,
            s => Some(ring_len as u32 + VERTEX_POINTS * s + b),
        },
    };
    let slots = (1 + VERTEX_POINTS as usize) * ring_len;
    let offsets = rows.offsets.clone();
    // Each term's slot, then a counting sort of the terms by slot (rows stay ascending).
    let mut at: Vec<u32> = Vec::with_capacity(rows.terms.len());
    let mut starts = vec![0u32; slots + 1];
    for &(v, _) in &rows.terms {
        let s = slot_of(v)?;
        at.push(s);
        starts[s as usize + 1] += 1;
    }
    for s in 0..slots {
        starts[s + 1] += starts[s];
    }
    let mut next = starts.clone();
    let mut columns = vec![(0, 0.0); at.len()];
    let terms = rows
        .rows()
        .enumerate()
        .flat_map(|(r, w)| w.iter().map(move |t| (r, t.1)));
    for (&s, (r, x)) in at.iter().zip(terms) {
        columns[next[s as usize] as usize] = (r as u32, x);
        next[s as usize] += 1;
    }
    Some(LocalRows {
        offsets,
        starts,
        columns,
    })
}

/// `rows` with slots replaced by ids: the vertex of slot `s` (`ring[s]`) by `vertex(ring[s])`,
/// its derived point `b` by `derived(ring[s], b)`; ascending ids when both maps are monotone
/// (in the vertex, then in `(vertex, point)`) and every derived id exceeds every vertex id, as
/// [`vertex_point_id`] numbers them: the slots walked in ascending order of their vertices
/// (sorted once), then their derived points in that order, each column's terms appended to
/// their rows.
fn from_slots(
    rows: &LocalRows,
    ring: &[u32],
    vertex: &(impl Fn(u32) -> u32 + ?Sized),
    derived: &(impl Fn(u32, u32) -> u32 + ?Sized),
) -> FaceRows {
    let l = ring.len();
    let mut order: Vec<u32> = (0..l as u32).collect();
    order.sort_unstable_by_key(|&s| ring[s as usize]);
    let terms = SCATTER.with(|scatter| {
        let (next, terms) = &mut *scatter.borrow_mut();
        next.clear();
        next.extend_from_slice(&rows.offsets);
        if terms.len() < rows.columns.len() {
            terms.resize(rows.columns.len(), (0, 0.0));
        }
        let mut put = |s: usize, id: u32| {
            let column = &rows.columns[rows.starts[s] as usize..rows.starts[s + 1] as usize];
            for &(r, x) in column {
                terms[next[r as usize] as usize] = (id, x);
                next[r as usize] += 1;
            }
        };
        for &s in &order {
            put(s as usize, vertex(ring[s as usize]));
        }
        for &s in &order {
            for b in 0..VERTEX_POINTS {
                let column = l + (VERTEX_POINTS * s + b) as usize;
                if rows.starts[column] < rows.starts[column + 1] {
                    put(column, derived(ring[s as usize], b));
                }
            }
        }
        terms[..rows.columns.len()].to_vec()
    });
    FaceRows {
        offsets: rows.offsets.clone(),
        terms,
    }
}

/// Row cursors and every term [`from_slots`] scatters into before copying them out at their
/// length: no zeroed allocation per face.
type Scatter = (Vec<u32>, Vec<(u32, f64)>);

thread_local! {
    /// [`from_slots`]'s buffers (they keep their capacity).
    static SCATTER: std::cell::RefCell<Scatter> = const {
        std::cell::RefCell::new((Vec::new(), Vec::new()))
    };
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
    let shared = end_cap_face_rows(topo, faces, tangents, darts);
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
    /// Its type's rows over slots, and the face's ring (the vertex of each slot).
    Shared { local: u32, ring: Vec<u32> },
}

/// The end-cap rows of a set of faces with the construction run once per connectivity type
/// (module docs), each face's kept as built (directly, or its type's rows over slots and its
/// ring) until [`Self::rows`] writes them with the caller's ids: one pass over the terms where
/// relabelling them to the level's ids and then to the caller's would take two.
pub struct EndCapFaceRows {
    local: Vec<LocalRows>,
    faces: Vec<Result<FaceRow, NotGregory>>,
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
            Ok(FaceRow::Shared { local, ring }) => {
                let starts = &self.local[*local as usize].starts;
                let l = ring.len();
                for (s, &v) in ring.iter().enumerate() {
                    for b in 0..VERTEX_POINTS {
                        let column = l + VERTEX_POINTS as usize * s + b as usize;
                        if starts[column] < starts[column + 1] {
                            mark(v, b);
                        }
                    }
                }
            }
            Err(_) => {}
        }
    }

    /// Face `i`'s rows (empty for a face without patch) with vertex `u` written as
    /// `vertex(u)` and derived point `b` of vertex `v` as `derived(v, b)`: both monotone, every
    /// derived id past every vertex id (as [`vertex_point_id`]), so rows stay ascending.
    pub fn rows(
        &self,
        topo: &Topology,
        i: usize,
        vertex: &(dyn Fn(u32) -> u32 + Sync),
        derived: &(dyn Fn(u32, u32) -> u32 + Sync),
    ) -> FaceRows {
        match &self.faces[i] {
            Ok(FaceRow::Direct(rows)) => {
                let terms = rows.terms.iter().map(|&(id, x)| {
                    let id = match vertex_point_of(topo, id) {
                        None => vertex(id),
                        Some((v, b)) => derived(v, b),
                    };
                    (id, x)
                });
                FaceRows {
                    offsets: rows.offsets.clone(),
                    terms: terms.collect(),
                }
            }
            Ok(FaceRow::Shared { local, ring }) => {
                from_slots(&self.local[*local as usize], ring, vertex, derived)
            }
            Err(_) => FaceRows::default(),
        }
    }

    /// [`Self::rows`] of every face with a patch, in order, on the rayon pool.
    pub fn all_rows(
        &self,
        topo: &Topology,
        vertex: &(dyn Fn(u32) -> u32 + Sync),
        derived: &(dyn Fn(u32, u32) -> u32 + Sync),
    ) -> Vec<FaceRows> {
        (0..self.len())
            .into_par_iter()
            .with_min_len(256)
            .map(|i| self.rows(topo, i, vertex, derived))
            .collect()
    }
}

/// The rows of `faces` with the construction run once per connectivity type, kept per face
/// as built ([`EndCapFaceRows`]). The direct batches run on the rayon pool. Dart masks from
/// `darts` (one cache per build).
pub fn end_cap_face_rows(
    topo: &Topology,
    faces: &[u32],
    tangents: GregoryTangents,
    darts: &DartLimits,
) -> EndCapFaceRows {
    let mut keyer = Keyer::new(topo, tangents, darts);
    // Pass 1: each face's connectivity type (`None`: built directly), the first face of each
    // type its representative.
    let mut types: WordHashMap<TypeKey, u32> = WordHashMap::default();
    let mut type_of: Vec<Option<u32>> = Vec::with_capacity(faces.len());
    let mut representative: Vec<usize> = Vec::new();
    // Each face's ring, numbered once (the relabelling reads it again).
    let mut rings: Vec<Vec<u32>> = Vec::with_capacity(faces.len());
    let mut key = TypeKey::new();
    for (i, &f) in faces.iter().enumerate() {
        let (ring, keyed) = keyer.key(f, &mut key);
        let t = keyed.map(|()| match types.get(key.as_slice()) {
            Some(&t) => t,
            None => {
                let t = types.len() as u32;
                types.insert(key.clone(), t);
                representative.push(i);
                t
            }
        });
        clear(&mut keyer.slot, &ring);
        type_of.push(t);
        rings.push(ring);
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
            let ring = &rings[i];
            for (s, &x) in ring.iter().enumerate() {
                keyer.slot[x as usize] = s as u32;
            }
            let local = match &rows[i] {
                Some(Ok(r)) => to_slots(topo, r, &keyer.slot, ring.len()),
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
    let mut kept: Vec<LocalRows> = Vec::new();
    let at: Vec<u32> = local
        .into_iter()
        .map(|l| match l {
            Some(l) => {
                kept.push(l);
                kept.len() as u32 - 1
            }
            None => NONE,
        })
        .collect();
    let out = EndCapFaceRows {
        local: kept,
        faces: rows
            .into_iter()
            .zip(rings)
            .enumerate()
            .map(|(i, (r, ring))| match r {
                Some(r) => r.map(FaceRow::Direct),
                None => {
                    let t = type_of[i].expect("faces without type are built in the first batch");
                    let local = at[t as usize];
                    assert_ne!(
                        local, NONE,
                        "types without rows are built in the second batch"
                    );
                    Ok(FaceRow::Shared { local, ring })
                }
            })
            .collect(),
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

/// [`super::stencil_table::vertex_point_rows`] of every vertex of `vertices` (smooth, dart and
/// crease vertices of `topo` as end-cap corners; empty rows for others), vertex `i`'s rows
/// `3 i..3 i + 3` of the flat rows returned, the construction run
/// once per ring type (Loop et al. 2009 §4.1, shared as the end-cap rows are, module docs): the
/// rows of a vertex read only its edges' other ends and sharpness, its faces' vertices and its
/// own sharpness, so vertices whose rings read the same in first-appearance slots
/// (`RingKeys`) have the same weights slot by slot, and every weight is the same sequence
/// of `a + w * b` updates whatever the ids. Bitwise the per-vertex rows; the keys, the types'
/// rows and the relabelling run on the rayon pool. Dart masks from `darts`.
pub fn shared_vertex_point_rows(
    topo: &Topology,
    vertices: &[u32],
    tangents: GregoryTangents,
    darts: &DartLimits,
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
            let rows =
                vertex_point_rows_with(topo, vertices[i], &|u| slot[u as usize], tangents, darts);
            clear(slot, ring);
            rows
        })
        .collect();
    log::trace!(
        "vertex points: {} vertices, {} ring types",
        vertices.len(),
        representative.len()
    );
    // Relabelled into flat rows, run by run on the pool (no allocation per row).
    let parts: Vec<FaceRows> = runs
        .par_iter()
        .zip(type_of.par_chunks(RUN))
        .map(|(keys, types)| {
            let mut out = FaceRows::default();
            out.offsets.reserve(3 * types.len() + 1);
            out.offsets.push(0);
            for (j, &t) in types.iter().enumerate() {
                let ring = keys.ring(j);
                for w in &local[t as usize] {
                    let start = out.terms.len();
                    out.terms
                        .extend(w.0.iter().map(|&(s, x)| (ring[s as usize], x)));
                    out.terms[start..].sort_unstable_by_key(|&(u, _)| u);
                    out.offsets.push(out.terms.len() as u32);
                }
            }
            out
        })
        .collect();
    let mut out = FaceRows {
        offsets: Vec::with_capacity(3 * vertices.len() + 1),
        terms: Vec::with_capacity(parts.iter().map(|p| p.terms.len()).sum()),
    };
    out.offsets.push(0);
    for part in &parts {
        out.append(part);
    }
    out
}

/// What [`super::stencil_table::vertex_point_rows`] reads of the rings of a run of vertices, in
/// slots, flat: per vertex its key (edge count, face count, the vertex's sharpness bits, each
/// edge's other end and sharpness bits, each face's size and vertices) and its ring (the vertex
/// of each slot: the vertex at slot 0, its edges' other ends and its faces' vertices numbered by
/// first appearance in that order).
#[derive(Default)]
struct RingKeys {
    words: Vec<u32>,
    /// `vertices + 1` offsets into `words` (empty before the first vertex).
    word_at: Vec<u32>,
    ring: Vec<u32>,
    /// `vertices + 1` offsets into `ring` (empty before the first vertex).
    ring_at: Vec<u32>,
}

impl RingKeys {
    /// Appends the key and ring of `v`; `slot` is all [`NONE`] on entry and on return.
    fn push(&mut self, topo: &Topology, v: u32, slot: &mut [u32]) {
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
    fn key(&self, j: usize) -> &[u32] {
        &self.words[self.word_at[j] as usize..self.word_at[j + 1] as usize]
    }

    /// The ring of vertex `j` of the run.
    fn ring(&self, j: usize) -> &[u32] {
        &self.ring[self.ring_at[j] as usize..self.ring_at[j + 1] as usize]
    }
}

/// Resets the slots of `ring`.
fn clear(slot: &mut [u32], ring: &[u32]) {
    for &v in ring {
        slot[v as usize] = NONE;
    }
}

#[cfg(test)]
use super::corner_types::{end_cap_topologies, with_test_crease_factors, DECAYED_CORNER_DISKS};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{ControlMesh, ControlMeshDesc};
    use crate::patch::gregory::gregory_vertex_for;
    use crate::patch::gregory::stencil::{canonical_ring, ring_walk};
    use crate::subdiv::adaptive::EndCapSharpness;
    use glam::DVec3;
    use std::collections::HashMap;

    /// Meshes with holes, boundaries, darts, corners, infinitely sharp and semi-sharp creases,
    /// n-gons, triangles and valence-2 vertices.
    const TOPOLOGY_CORPUS: [&str; 10] = [
        "catmark_hole_test1",
        "catmark_hole_test4",
        "catmark_dart_edgecorner",
        "catmark_cube_corner4",
        "catmark_cube_creases2",
        "catmark_nonquads",
        "catmark_smoothtris1",
        "catmark_val2_interior",
        "catmark_xord_boundary",
        "catmark_cubes_semisharp",
    ];

    /// The topologies of every level of the isolation-2 adaptive refinement of corpus mesh
    /// `name`: both end-cap topologies (residual semi-sharpness smooth, or infinitely sharp from
    /// `CREASE_FROM`: darts where a semi-sharp line ends), after the level's own (semi-sharpness
    /// kept) if `own`.
    fn level_topologies(name: &str, own: bool) -> Vec<Topology> {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/meshes/osd/");
        let path = format!("{dir}{name}.obj");
        let mesh = ControlMesh::from_obj_file(&path, &Default::default()).unwrap();
        let level = crate::subdiv::Level::from_mesh(&mesh).unwrap();
        let adaptive = crate::subdiv::adaptive::AdaptiveRefinement::new(&level, 2).unwrap();
        let mut out = Vec::new();
        for l in &adaptive.levels {
            let t = l.topology();
            if own {
                out.push(t.clone());
            }
            out.push(t.without_semi_sharpness().into_owned());
            out.push(
                t.with_semi_sharpness_as_crease(EndCapSharpness::CREASE_FROM)
                    .into_owned(),
            );
        }
        out
    }

    /// The topological answer is the construction's, on every vertex of every level of the
    /// feature-adaptive refinement (sparse levels: rings cut open at their edge) of meshes with
    /// holes, boundaries, darts, corners, creases, n-gons, triangles and valence-2 vertices, in
    /// both end-cap topologies (fails if the interior or dart shortcut answers for a ring the
    /// construction rejects, or the coverage test is skipped).
    #[test]
    fn vertex_data_by_topology_is_the_constructions() {
        let mut seen = [0usize; 2];
        let darts = DartLimits::new();
        for name in TOPOLOGY_CORPUS {
            for topo in level_topologies(name, false) {
                for v in 0..topo.vertex_count() as u32 {
                    let point = |_: u32| 0.0f64;
                    let want = gregory_vertex_for(
                        &topo,
                        v,
                        &point,
                        GregoryTangents::default(),
                        Coverage::EndCap,
                        &DartLimits::new(),
                    )
                    .is_some();
                    let got = has_vertex_data(&topo, v, &darts);
                    assert_eq!(got, want, "{name}: vertex {v}");
                    seen[usize::from(want)] += 1;
                }
            }
        }
        assert!(seen[0] > 0 && seen[1] > 0, "{seen:?}");
        assert!(!darts.is_empty(), "no dart ring");
    }

    /// The end-cap shortcuts of the keys and corners are the checks they stand for, on every
    /// vertex and face of every level of the adaptive refinement of `TOPOLOGY_CORPUS` (with
    /// semi-sharp and infinitely sharp creases, holes, darts and n-gons), in the levels' own
    /// topologies (semi-sharpness kept) and both end-cap ones: `vertex_covered` with end-cap
    /// coverage is `check_vertex_for` passing at some face of the vertex, and
    /// `end_cap_patch_with` over `has_vertex_data` is `check_face_for` passing with data at
    /// every corner (fails if the one-face coverage test misreads a semi-sharp vertex or edge,
    /// or if the face test drops the face's own checks).
    #[test]
    fn end_cap_shortcuts_are_the_checks() {
        use crate::patch::gregory::build::{check_vertex_for, end_cap_patch_with};
        use crate::patch::gregory::check_face_for;
        let darts = DartLimits::new();
        // Per answer: uncovered vertices, covered ones, faces without and with a patch.
        let mut seen = [0usize; 4];
        for name in TOPOLOGY_CORPUS {
            for topo in level_topologies(name, true) {
                for v in 0..topo.vertex_count() as u32 {
                    let want = topo
                        .vertex_faces(v)
                        .iter()
                        .any(|&f| check_vertex_for(&topo, v, f, Coverage::EndCap).is_ok());
                    assert_eq!(
                        vertex_covered(&topo, v, Coverage::EndCap),
                        want,
                        "{name}: vertex {v}"
                    );
                    seen[usize::from(want)] += 1;
                }
                let data = |v: &u32| has_vertex_data(&topo, *v, &darts);
                for f in 0..topo.face_count() as u32 {
                    let want = check_face_for(&topo, f, Coverage::EndCap).is_ok()
                        && topo.face_vertices(f).iter().all(data);
                    assert_eq!(end_cap_patch_with(&topo, f, data), want, "{name}: face {f}");
                    seen[2 + usize::from(want)] += 1;
                }
            }
        }
        assert!(seen.iter().all(|&n| n > 0), "{seen:?}");
    }

    /// A grid of `n × n` quads, infinitely sharp along row `n / 2` from its left end to
    /// column `to`: vertices of one connectivity that differ only by the sharpness of their
    /// edges (smooth, crease, a dart where the crease ends inside, a corner where it meets
    /// the boundary).
    fn creased_grid(n: u32, to: u32) -> Topology {
        let w = n + 1;
        let positions = (0..w * w)
            .map(|i| DVec3::new((i % w) as f64, (i / w) as f64, ((i * 7 % 5) as f64) * 0.1))
            .collect();
        let face_vertices = (0..n * n)
            .flat_map(|f| {
                let (x, y) = (f % n, f / n);
                let v = y * w + x;
                [v, v + 1, v + 1 + w, v + w]
            })
            .collect();
        let creases = (0..to)
            .map(|x| crate::mesh::Crease {
                v0: n / 2 * w + x,
                v1: n / 2 * w + x + 1,
                sharpness: crate::mesh::INFINITE_SHARPNESS,
            })
            .collect();
        let mesh = ControlMesh::new(ControlMeshDesc {
            positions,
            face_sizes: vec![4; (n * n) as usize],
            face_vertices,
            creases,
            ..Default::default()
        })
        .unwrap();
        Topology::new(&mesh).unwrap()
    }

    /// The shared vertex points are bitwise the per-vertex construction on every vertex, on
    /// every level of the adaptive refinement of meshes with triangles, n-gons, high valence,
    /// boundaries, holes, infinitely sharp creases, corners and darts, in both end-cap
    /// topologies, on a creased grid and on a decayed corner (fails if the ring key leaves out
    /// what the construction reads, e.g. face sizes, the faces' vertices, the edges' sharpness,
    /// which tells the grid's crease vertices from its smooth ones, or the decayed-corner tag,
    /// which the end caps' tangents read; `Fitted` with frozen factors compared too), and rings
    /// are shared.
    #[test]
    fn shared_vertex_points_are_the_per_vertex_construction() {
        let (mut vertices, mut types) = (0, 0);
        // Vertices with vertex points, by number of sharp edges: smooth, dart, crease.
        let mut kinds = HashMap::new();
        let mut compare = |name: &str, topo: &Topology| {
            let all: Vec<u32> = (0..topo.vertex_count() as u32)
                .filter(|&v| !topo.vertex_faces(v).is_empty())
                .collect();
            for tangents in [
                GregoryTangents::Paper,
                GregoryTangents::Optimal,
                GregoryTangents::EndCaps,
                GregoryTangents::Fitted,
            ] {
                let shared = shared_vertex_point_rows(topo, &all, tangents, &DartLimits::new());
                assert_eq!(shared.len(), 3 * all.len());
                for (i, &v) in all.iter().enumerate() {
                    let want =
                        crate::patch::gregory::stencil_table::vertex_point_rows(topo, v, tangents);
                    let got: Vec<Weights> = (3 * i..3 * i + 3).map(|r| shared.weights(r)).collect();
                    let bits = |w: &[Weights]| {
                        w.iter()
                            .map(|w| w.0.iter().map(|&(u, x)| (u, x.to_bits())).collect())
                            .collect::<Vec<Vec<_>>>()
                    };
                    assert_eq!(bits(&got), bits(&want), "{name}: vertex {v}");
                    if !want[0].0.is_empty() || !want[1].0.is_empty() {
                        let ring = vertex_ring_with(topo, v, &|_| NoPoint);
                        let sharp = ring.sharp.iter().filter(|&&s| s).count();
                        *kinds.entry(sharp).or_insert(0) += 1;
                    }
                }
            }
            let mut slot = vec![NONE; topo.vertex_count()];
            let mut ring_keys = RingKeys::default();
            for &v in &all {
                ring_keys.push(topo, v, &mut slot);
            }
            let keys: std::collections::HashSet<&[u32]> =
                (0..all.len()).map(|j| ring_keys.key(j)).collect();
            vertices += all.len();
            types += keys.len();
        };
        compare("creased grid", &creased_grid(8, 5));
        // Frozen crease-sector factors (`GregoryTangents::Fitted`), a different pair at every
        // vertex. (The factor words cannot be shown missing here: no two crease rings of
        // three or more faces in a sector share a key on these levels; `corner_types`' oracle
        // shows them on the second stage.)
        for topo in end_cap_topologies("catmark_xord_boundary") {
            compare("xord_boundary, fitted", &with_test_crease_factors(topo));
        }
        for name in [
            DECAYED_CORNER_DISKS,
            "catmark_nonquads",
            "catmark_smoothtris1",
            "catmark_pole8",
            "catmark_car",
            "catmark_val2_interior",
            "catmark_cube_creases2",
            "catmark_dart_edgecorner",
            "catmark_hole_test1",
            "catmark_cube_corner4",
        ] {
            for topo in end_cap_topologies(name) {
                compare(name, &topo);
            }
        }
        assert!(
            types * 10 < vertices,
            "{types} ring types for {vertices} vertices"
        );
        // Smooth (no sharp edge), dart (one) and crease or boundary (two) rings were compared.
        assert!((0..3).all(|s| kinds.contains_key(&s)), "{kinds:?}");
    }

    /// The split rings over unit weights built without a unit per ring vertex are bitwise
    /// `vertex_ring_with` over `Weights::unit` (points and topology), with the identity and with
    /// a reversing id map (ids then descend along the ring, so the sorted points reorder), on
    /// every vertex of every level of meshes with triangles, n-gons, boundaries, holes, creases,
    /// darts and promoted semi-sharp creases, in both end-cap topologies (fails if a midpoint's
    /// or centroid's weight, order or a repeated id's sum differs).
    #[test]
    fn unit_rings_are_vertex_ring_with() {
        use crate::patch::gregory::build::vertex_ring_of_units;
        let bits = |w: &Weights| {
            w.0.iter()
                .map(|&(u, x)| (u, x.to_bits()))
                .collect::<Vec<_>>()
        };
        let mut compared = 0;
        let mut compare = |name: &str, topo: &Topology| {
            let n = topo.vertex_count() as u32;
            for v in 0..n {
                for reverse in [false, true] {
                    let id = |u: u32| if reverse { n - 1 - u } else { u };
                    let got = vertex_ring_of_units(topo, v, &id);
                    let want = vertex_ring_with(topo, v, &|u| Weights::unit(id(u)));
                    let points = |r: &crate::patch::gregory::VertexRing<Weights>| {
                        let mut p = vec![bits(&r.v)];
                        p.extend(r.m.iter().chain(&r.c).map(bits));
                        p
                    };
                    assert_eq!(points(&got), points(&want), "{name}: vertex {v}");
                    assert_eq!(
                        (&got.sharp, got.corner, &got.face_sizes),
                        (&want.sharp, want.corner, &want.face_sizes)
                    );
                    assert_eq!(
                        (&got.far_sector, &got.promoted),
                        (&want.far_sector, &want.promoted)
                    );
                    compared += 1;
                }
            }
        };
        // A 12-gon: centroids of more corners than `combine` merges in one pass.
        let gon = ControlMesh::new(ControlMeshDesc {
            positions: (0..12)
                .map(|k| {
                    let a = k as f64 * std::f64::consts::TAU / 12.0;
                    DVec3::new(a.cos(), a.sin(), 0.0)
                })
                .collect(),
            face_sizes: vec![12],
            face_vertices: (0..12).collect(),
            ..Default::default()
        })
        .unwrap();
        compare("12-gon", &Topology::new(&gon).unwrap());
        for name in [
            "catmark_nonquads",
            "catmark_smoothtris1",
            "catmark_hole_test1",
            "catmark_dart_edgecorner",
            "catmark_cube_creases2",
            "catmark_cubes_semisharp",
            "catmark_val2_interior",
        ] {
            for topo in end_cap_topologies(name) {
                compare(name, &topo);
            }
        }
        assert!(compared > 1000, "{compared} rings");
    }

    /// The ring walk visits what [`ring_walk`] documents, in order, and a face's key numbers
    /// its ring as [`Keyer::key`] documents (its corners' rings, each vertex of their rings
    /// once, in corner order), the same vertices as [`canonical_ring`], with `slot` set, on a
    /// pyramid whose faces start their vertex lists away from the walked corner, where every
    /// face has its own key (the apex's five triangles sit at five places in its ring); on a
    /// grid, the faces whose corners are interior share one key and the others do not (fails
    /// if a rotation starts at the wrong face or vertex, a ring vertex is missed or repeated,
    /// or the key reads ids rather than slots).
    #[test]
    fn face_keys_number_the_corners_rings() {
        // A pyramid over a pentagon: triangles, a pentagon, valences 3 and 5.
        let mut positions: Vec<DVec3> = (0..5)
            .map(|k| {
                let a = k as f64 * std::f64::consts::TAU / 5.0;
                DVec3::new(a.cos(), a.sin(), 0.0)
            })
            .collect();
        positions.push(DVec3::Z);
        let mut face_vertices = vec![4, 3, 2, 1, 0];
        for k in 0..5 {
            face_vertices.extend([k, (k + 1) % 5, 5]);
        }
        let mesh = ControlMesh::new(ControlMeshDesc {
            positions,
            face_sizes: vec![5, 3, 3, 3, 3, 3],
            face_vertices,
            ..Default::default()
        })
        .unwrap();
        let topo = Topology::new(&mesh).unwrap();
        let darts = DartLimits::new();
        let mut keyer = Keyer::new(&topo, GregoryTangents::default(), &darts);
        let mut keys = Vec::new();
        for f in 0..topo.face_count() as u32 {
            // The walk as documented: corners, then per corner its faces from `f` round,
            // each face's vertices from the corner round.
            let mut walk = topo.face_vertices(f).to_vec();
            for &v in topo.face_vertices(f) {
                let faces = topo.vertex_faces(v);
                let start = faces.iter().position(|&g| g == f).unwrap();
                for i in 0..faces.len() {
                    let gv = topo.face_vertices(faces[(start + i) % faces.len()]);
                    let k = gv.iter().position(|&x| x == v).unwrap();
                    walk.extend((0..gv.len()).map(|t| gv[(k + t) % gv.len()]));
                }
            }
            let mut visited = Vec::new();
            ring_walk(&topo, f, |x| visited.push(x));
            assert_eq!(visited, walk, "face {f}");
            let mut key = TypeKey::new();
            let (ring, keyed) = keyer.key(f, &mut key);
            assert!(keyed.is_some(), "face {f}");
            // Each corner, its edges' other ends, its faces' vertices in face order.
            let mut want: Vec<u32> = Vec::new();
            for &v in topo.face_vertices(f) {
                let ends = topo
                    .vertex_edges(v)
                    .iter()
                    .map(|&e| topo.other_vertex(e, v));
                let around = topo
                    .vertex_faces(v)
                    .iter()
                    .flat_map(|&g| topo.face_vertices(g));
                for u in std::iter::once(v).chain(ends).chain(around.copied()) {
                    if !want.contains(&u) {
                        want.push(u);
                    }
                }
            }
            assert_eq!(ring, want, "face {f}");
            let mut sorted = ring.clone();
            sorted.sort_unstable();
            let mut canonical = canonical_ring(&topo, f);
            canonical.sort_unstable();
            assert_eq!(sorted, canonical, "face {f}");
            for (s, &v) in ring.iter().enumerate() {
                assert_eq!(keyer.slot[v as usize], s as u32);
            }
            clear(&mut keyer.slot, &ring);
            keys.push(key);
        }
        let distinct: std::collections::HashSet<&TypeKey> = keys.iter().collect();
        assert_eq!(distinct.len(), keys.len());
        // A grid of 8 x 8 quads: faces with interior corners are those off the border.
        let grid = creased_grid(8, 0);
        let mut keyer = Keyer::new(&grid, GregoryTangents::default(), &darts);
        let (mut inner, mut outer) = (Vec::new(), Vec::new());
        for f in 0..64u32 {
            let mut key = TypeKey::new();
            let (ring, keyed) = keyer.key(f, &mut key);
            assert!(keyed.is_some(), "grid face {f}");
            clear(&mut keyer.slot, &ring);
            let (x, y) = (f % 8, f / 8);
            match (1..7).contains(&x) && (1..7).contains(&y) {
                true => inner.push((f, ring.len(), key)),
                false => outer.push(key),
            }
        }
        assert_eq!(inner.len(), 36);
        for (f, l, key) in &inner {
            assert_eq!(*l, 16, "grid face {f}");
            assert_eq!(*key, inner[0].2, "grid face {f}");
        }
        assert!(outer.iter().all(|k| *k != inner[0].2));
    }

    /// [`EndCapFaceRows::rows`] with other ids is the level's rows ([`sparse_face_rows_flat`])
    /// relabelled term by term, and [`EndCapFaceRows::derived_read`] marks exactly the
    /// derived points those rows read, on every face of every level of meshes with n-gons,
    /// holes, creases, darts and semi-sharp creases (faces without patch included: no rows,
    /// nothing read), shared and directly built faces both met (fails if a shared face's
    /// column of derived points is skipped or mislabelled, or a direct face's terms are
    /// relabelled as vertices).
    #[test]
    fn face_rows_take_the_callers_ids() {
        let darts = DartLimits::new();
        let (mut shared, mut direct) = (0, 0);
        for name in [
            "catmark_nonquads",
            "catmark_dart_edgecorner",
            "catmark_cubes_semisharp",
        ] {
            for topo in level_topologies(name, false) {
                let n = topo.vertex_count() as u32;
                let faces: Vec<u32> = (0..topo.face_count() as u32).collect();
                let tangents = GregoryTangents::default();
                let rows = end_cap_face_rows(&topo, &faces, tangents, &darts);
                let flat = sparse_face_rows_flat(&topo, &faces, tangents, &darts);
                // Monotone, derived ids past every vertex id, none the level's own.
                let vertex = |u: u32| 2 * u + 5;
                let derived = |v: u32, b: u32| 2 * n + 10 + 7 * v + b;
                for (i, want) in flat.iter().enumerate() {
                    match &rows.faces[i] {
                        Ok(FaceRow::Shared { .. }) => shared += 1,
                        Ok(FaceRow::Direct(_)) => direct += 1,
                        Err(_) => {}
                    }
                    let got = rows.rows(&topo, i, &vertex, &derived);
                    let mut read = std::collections::BTreeSet::new();
                    rows.derived_read(&topo, i, |v, b| {
                        read.insert((v, b));
                    });
                    let Ok(want) = want else {
                        assert!(got.is_empty() && read.is_empty(), "{name}: face {i}");
                        continue;
                    };
                    let relabel = |id: u32| match vertex_point_of(&topo, id) {
                        None => vertex(id),
                        Some((v, b)) => derived(v, b),
                    };
                    let terms: Vec<(u32, u64)> = want
                        .terms
                        .iter()
                        .map(|&(u, x)| (relabel(u), x.to_bits()))
                        .collect();
                    let bits: Vec<(u32, u64)> =
                        got.terms.iter().map(|&(u, x)| (u, x.to_bits())).collect();
                    assert_eq!(
                        (&got.offsets, bits),
                        (&want.offsets, terms),
                        "{name}: face {i}"
                    );
                    let want_read: std::collections::BTreeSet<(u32, u32)> = want
                        .terms
                        .iter()
                        .filter_map(|&(u, _)| vertex_point_of(&topo, u))
                        .collect();
                    assert_eq!(read, want_read, "{name}: face {i}");
                }
            }
        }
        assert!(shared > 0 && direct > 0, "{shared} shared, {direct} direct");
    }
}
