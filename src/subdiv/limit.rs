//! Catmull-Clark limit masks: limit position and tangents of any vertex of a [`Level`]
//! (smooth interior, dart, crease/boundary, corner, semi-sharp), limit positions and normals of
//! whole levels, and limit stencils.
//!
//! Method: a smooth interior vertex whose faces are all quads uses the closed-form masks of
//! Halstead, Kass, DeRose 1993 (appendix A). A vertex with non-quad faces or semi-sharp edges /
//! vertex sharpness is first refined locally (`Level::extract` of its faces + `Level::refine`)
//! until neither remains (at most `ceil(sharpness)` steps); so is a vertex whose one-ring holds
//! a vertex twice (next to a valence-2 vertex). Every other vertex (dart, crease, corner,
//! boundary) uses the left eigenvectors of its local subdivision matrix restricted to the
//! sector of the face of interest ([`masks::eigen_limit`], [`sector::sector_limit`]); for crease
//! vertices the position is the closed form `(1, 4, 1) / 6` along the crease and for corners
//! the vertex itself.
//!
//! The tangents are per face: their cross product is the limit of that face's own surface
//! normal at the vertex (along the face's diagonal). Faces of different sectors, and in corner
//! sectors of three faces each face, have different normals there ([`sector`] lists the cases).
//!
//! Darts (one infinitely sharp edge, smooth vertex rule): the position is the dominant left
//! eigenvector of the dart's own subdivision matrix, whose sharp edge takes the crease rule
//! (midpoints). That is where refinement converges (tests/limit_corners.rs tracks the vertex
//! through 8 and 40 local refinements). OpenSubdiv's Far and Bfr use the smooth interior mask at
//! a dart instead, which is off by 2.4e-3 to 1.3e-2 of the bounding-box diagonal on the shared
//! meshes' darts; the tangent plane comes from the same matrix (its two leading modes).

pub mod masks;
pub mod sector;

use std::cell::RefCell;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

use glam::DVec3;
use rayon::prelude::*;

use super::level::RingCorners;
use super::word_hash::WordHashMap;
use super::{Level, SparseMatrix, StencilTable};
use crate::mesh::{BoundaryInterpolation, CreaseMethod, INFINITE_SHARPNESS};
use crate::topology::{sector_slots, Topology};
use crate::{Error, Result};

/// Limit position and two tangent masks of one vertex, as weights over vertices of a level.
///
/// Tangents are taken in the sector of the chosen face and `tangent_u x tangent_v` is the
/// outward normal of a counter-clockwise face. At smooth interior vertices they are Halstead's
/// tangents along the face's edges (`tangent_u` toward the face's next corner, `tangent_v`
/// toward its previous one; for valence 4 exactly the B-spline partials). Elsewhere they are an
/// oriented basis of the face's tangent plane at the vertex: sectors between sharp edges as
/// [`sector`] tabulates (crease tangent and cross mode, both sharp edges' tangents, or the
/// leading modes); darts, corner tags without sharp edges (cusps, whose normal is
/// perpendicular to the cusp axis) and other cases the two leading eigenvectors of the local
/// subdivision matrix; a corner tag with one sharp edge and four quads, where the second place is
/// a tie, a per-face mix ([`sector::corner_tag4`]). Valence-2 vertices use the two positive 1/4
/// modes.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct VertexMask {
    /// Vertex indices of the level.
    pub indices: Vec<u32>,
    /// Limit position weights (sum 1).
    pub position: Vec<f64>,
    /// First tangent weights (sum 0).
    pub tangent_u: Vec<f64>,
    /// Second tangent weights (sum 0).
    pub tangent_v: Vec<f64>,
}

impl VertexMask {
    fn from_triples(mut t: Vec<(u32, [f64; 3])>) -> VertexMask {
        t.sort_unstable_by_key(|x| x.0);
        let mut m = VertexMask {
            indices: Vec::with_capacity(t.len()),
            position: Vec::with_capacity(t.len()),
            tangent_u: Vec::with_capacity(t.len()),
            tangent_v: Vec::with_capacity(t.len()),
        };
        for (i, w) in t {
            if m.indices.last() == Some(&i) {
                let k = m.indices.len() - 1;
                m.position[k] += w[0];
                m.tangent_u[k] += w[1];
                m.tangent_v[k] += w[2];
            } else {
                m.indices.push(i);
                m.position.push(w[0]);
                m.tangent_u.push(w[1]);
                m.tangent_v.push(w[2]);
            }
        }
        m
    }

    /// Applies the mask: `(position, tangent_u, tangent_v)`.
    pub fn apply(&self, positions: &[DVec3]) -> (DVec3, DVec3, DVec3) {
        let mut p = DVec3::ZERO;
        let mut tu = DVec3::ZERO;
        let mut tv = DVec3::ZERO;
        for (k, &i) in self.indices.iter().enumerate() {
            let x = positions[i as usize];
            p += self.position[k] * x;
            tu += self.tangent_u[k] * x;
            tv += self.tangent_v[k] * x;
        }
        (p, tu, tv)
    }
}

fn is_inf(s: f32) -> bool {
    s >= INFINITE_SHARPNESS
}

fn is_semi(s: f32) -> bool {
    s > 0.0 && s < INFINITE_SHARPNESS
}

/// Maximum number of local refinement steps (semi-sharpness < 10 decays in at most 10, plus one
/// step for non-quad faces).
const MAX_LOCAL_STEPS: u32 = 12;

/// The limit mask of vertex `v` of `level`, with tangents oriented by face `face` (one of the
/// faces of `v`). Errors if `face` is not incident to `v` or the local iteration fails.
pub fn vertex_mask(level: &Level, v: u32, face: u32) -> Result<VertexMask> {
    vertex_mask_rec(level, v, face, 0, LocalStep::Kept)
}

/// How a local refinement step around a vertex makes the child's ring.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum LocalStep {
    /// Only the children of the vertex's corners (`Level::refine_kept`, the child's ring
    /// extraction itself) and only the refinement matrix's rows the child's mask reads.
    Kept,
    /// The whole ring refined (`Level::refine`), then the child's ring extracted: the former
    /// path, kept as the test oracle of [`LocalStep::Kept`].
    #[cfg(test)]
    WholeRing,
}

fn vertex_mask_rec(
    level: &Level,
    v: u32,
    face: u32,
    depth: u32,
    step: LocalStep,
) -> Result<VertexMask> {
    let topo = level.topology();
    if v as usize >= topo.vertex_count() || face as usize >= topo.face_count() {
        return Err(Error::Invalid(format!(
            "limit mask: vertex {v} or face {face} out of range"
        )));
    }
    let faces = topo.vertex_faces(v);
    let Some(i) = faces.iter().position(|&g| g == face) else {
        return Err(Error::Invalid(format!(
            "limit mask: face {face} is not incident to vertex {v}"
        )));
    };
    let edges = topo.vertex_edges(v);
    if needs_refinement(topo, v) {
        if depth >= MAX_LOCAL_STEPS {
            return Err(Error::Invalid(format!(
                "limit mask: vertex {v} still semi-sharp after {depth} local refinements"
            )));
        }
        return refined_mask(level, v, i, depth, step);
    }
    let sharp = edges
        .iter()
        .filter(|&&e| is_inf(topo.edge_sharpness(e)))
        .count();
    if sharp == 0 && !is_inf(topo.vertex_sharpness(v)) && !topo.is_boundary_vertex(v) {
        return Ok(smooth_mask(level, v, i));
    }
    eigen_mask(level, v, i, sharp, depth, step)
}

/// Limit masks ([`vertex_mask`]) of vertices that need local refinement (semi-sharp or next to
/// a non-quad face), shared between vertices whose rings are alike: each vertex's ring is
/// extracted in a numbering that depends only on its shape (`Level::try_extract_ring`: the
/// face of interest first, each face starting at the vertex, vertices numbered by first
/// appearance), and the mask over that extraction, a function of it alone (its faces in local
/// ids, holes, and the sharpness of the vertex and of its edges: the rest of the extraction is
/// read by no row the mask reads), is computed once per distinct key and renumbered for every
/// vertex that has it. The same mask as [`vertex_mask`]
/// but for the order in which the local refinements sum their terms (equal to 1e-12 relative,
/// `tests/limit_corners.rs`), and the same bits whichever vertex comes first. Other vertices
/// are computed directly. Errors are not kept (they name the vertex).
///
/// Shared by reference between threads (the table behind a lock taken only to look a mask up
/// and to store one; a mask two threads miss at once is computed by both, the same bits). The
/// table hashes its keys with the crate's word hash (`subdiv::word_hash`), which has no per-run
/// seed, so a build's instruction count repeats from run to run. A look-up that finds its mask
/// allocates only the mask it returns: the ring, its key and the relabelling order are made in
/// buffers kept per thread (`RingScratch`).
///
/// Within the crate, callers that ask for one corner's mask more than once (the draw tables'
/// slot, sector, exact-position and lattice frames all read the limit at the same promoted
/// corners) name it by a key (`corner_mask`) and get the mask made the first time, without its
/// ring, key and relabelling again. That key is the caller's promise (one name per corner for
/// the table's life), so the method is not public.
#[derive(Debug, Default)]
pub struct SharedVertexMasks {
    /// Masks by [`ring_key`].
    masks: Mutex<WordHashMap<Vec<u32>, VertexMask>>,
    /// Masks by the callers' corner keys ([`Self::corner_mask`]); `None` where the mask failed.
    corners: Mutex<CornerMasks>,
    /// Masks reused (for tests and profiles).
    hits: AtomicUsize,
}

/// [`SharedVertexMasks::corner_mask`]'s masks by corner key, `None` where the mask failed.
type CornerMasks = WordHashMap<(u32, u32), Option<Arc<VertexMask>>>;

/// The buffers of one thread's look-ups in [`SharedVertexMasks`].
#[derive(Default)]
struct RingScratch {
    ring: RingCorners,
    key: Vec<u32>,
    order: Vec<(u32, u32)>,
}

thread_local! {
    static RING_SCRATCH: RefCell<RingScratch> = RefCell::default();
}

/// Writes to `words` everything of the ring extraction of `ring` ([`RingCorners`],
/// `Level::try_extract_ring`) that its masks depend on, read from the level without making the
/// extraction (the vertex and face of interest are its vertex 0 and face 0): vertex count, face
/// offsets and corners; per edge at vertex 0 (per face corner whose edge has vertex 0 as an end)
/// its sharpness bits and whether the extraction cuts it (0/1); vertex 0's sharpness bits and
/// whether it is incomplete (0/1); per face hole and no-limit flags (0/1); the boundary
/// interpolation and the crease method.
///
/// The other edges' and vertices' sharpness and flags are left out: a mask reads only the rows
/// of vertex 0's child, the edge points of its edges and the face points of its faces
/// (`refined_local_mask` and [`masks::eigen_limit`]'s ring), which read the faces and vertex
/// 0's edges and vertex alone (the crease rules and Chaikin's child sharpness of a half at vertex
/// 0 read its own edges); the child ring's other elements are smooth whatever they were, and the
/// incomplete and cut flags steer no weight (they only flag what the evaluation must not read).
/// So rings that differ there share a mask (`tests::reduced_ring_keys_share_masks` compares
/// every shared mask with a fresh one, bit for bit).
fn ring_key(level: &Level, ring: &RingCorners, words: &mut Vec<u32>) {
    let t = level.topology();
    words.clear();
    words.push(ring.map.len() as u32);
    words.extend_from_slice(&ring.offsets);
    words.extend_from_slice(&ring.local);
    for j in 0..ring.faces.len() {
        let corners = &ring.local[ring.offsets[j] as usize..ring.offsets[j + 1] as usize];
        for c in 0..corners.len() {
            if corners[c] != 0 && corners[(c + 1) % corners.len()] != 0 {
                continue;
            }
            let e = ring.edge(t, j, c);
            // Cut: boundary only in the extraction (its other face is not in the ring), or
            // cut already.
            let opened =
                !t.is_boundary_edge(e) && !t.edge_faces(e).iter().all(|g| ring.faces.contains(g));
            words.push(t.edge_sharpness(e).to_bits());
            words.push(u32::from(opened || level.is_cut_edge(e)));
        }
    }
    let centre = ring.map[0];
    words.push(t.vertex_sharpness(centre).to_bits());
    words.push(u32::from(!level.is_complete_vertex(centre)));
    for &f in &ring.faces {
        let no_limit = t.no_limit.get(f as usize).copied().unwrap_or(false);
        words.push(u32::from(t.holes[f as usize]) | u32::from(no_limit) << 1);
    }
    words.push(match t.options.boundary {
        BoundaryInterpolation::None => 0,
        BoundaryInterpolation::EdgeAndCorner => 1,
        BoundaryInterpolation::EdgeOnly => 2,
    });
    words.push(u32::from(t.options.crease_method == CreaseMethod::Chaikin));
}

impl SharedVertexMasks {
    /// [`vertex_mask`] of vertex `v` of `level`, tangents oriented by `face`.
    pub fn vertex_mask(&self, level: &Level, v: u32, face: u32) -> Result<VertexMask> {
        let topo = level.topology();
        if v as usize >= topo.vertex_count() || !needs_refinement(topo, v) {
            return vertex_mask(level, v, face);
        }
        let Some(i) = topo.vertex_faces(v).iter().position(|&g| g == face) else {
            return vertex_mask(level, v, face);
        };
        // A hit is answered inside the thread's buffers; a miss leaves them with its ring and
        // key before refining, since the refinement may join on the rayon pool (large rings),
        // where this thread can run another look-up that needs the buffers.
        let looked_up = RING_SCRATCH.with(|scratch| {
            let s = &mut *scratch.borrow_mut();
            if !s.ring.fill(topo, v, i) {
                return Err(Error::Invalid(format!(
                    "limit mask: vertex {v} has no face {i}"
                )));
            }
            ring_key(level, &s.ring, &mut s.key);
            if let Some(m) = self.table().get(&s.key[..]) {
                self.hits.fetch_add(1, Ordering::Relaxed);
                return Ok(Ok(relabelled(m, &s.ring.map, &mut s.order)));
            }
            Ok(Err((s.ring.clone(), s.key.clone())))
        })?;
        let (ring, key) = match looked_up {
            Ok(hit) => return Ok(hit),
            Err(miss) => miss,
        };
        let (sub, map) = level.try_extract_ring(ring)?;
        let m = refined_local_mask(&sub, 0, 0, 0, LocalStep::Kept)?;
        let out = relabelled(&m, &map, &mut Vec::new());
        self.table().insert(key, m);
        Ok(out)
    }

    /// [`Self::vertex_mask`] of vertex `v` of `level` in face `face`, kept under `key`: the
    /// caller's name for `(level, v, face)`, one name per corner for the table's life (the
    /// adaptive draw tables use `v`'s global refined id and `face`). A corner asked again gets
    /// the same mask (the same bits) without a look-up by ring; one whose mask failed fails
    /// again (the first error names the cause).
    pub(crate) fn corner_mask(
        &self,
        key: (u32, u32),
        level: &Level,
        v: u32,
        face: u32,
    ) -> Result<Arc<VertexMask>> {
        let kept = self.corner_table().get(&key).cloned();
        let Some(mask) = kept else {
            let made = self.vertex_mask(level, v, face).map(Arc::new);
            self.corner_table().insert(key, made.as_ref().ok().cloned());
            return made;
        };
        mask.ok_or_else(|| {
            Error::Invalid(format!(
                "limit mask: vertex {v} in face {face} failed before"
            ))
        })
    }

    /// Masks reused so far (for tests and profiles).
    pub fn hits(&self) -> usize {
        self.hits.load(Ordering::Relaxed)
    }

    /// The table, locked (a panic elsewhere while it was held leaves whole entries only).
    fn table(&self) -> MutexGuard<'_, WordHashMap<Vec<u32>, VertexMask>> {
        self.masks.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// The corner table, locked (as [`Self::table`]).
    fn corner_table(&self) -> MutexGuard<'_, CornerMasks> {
        self.corners.lock().unwrap_or_else(PoisonError::into_inner)
    }
}

/// Mask `m` over an extraction's vertices as a mask over the extracted level's, through the
/// extraction's injective vertex map `map` (in any order), indices increasing. `order` is a
/// buffer.
fn relabelled(m: &VertexMask, map: &[u32], order: &mut Vec<(u32, u32)>) -> VertexMask {
    // (new index, term): the indices are distinct, so the order is that of the new indices.
    order.clear();
    order.extend((m.indices.iter().enumerate()).map(|(k, &i)| (map[i as usize], k as u32)));
    order.sort_unstable();
    let pick = |w: &[f64]| order.iter().map(|&(_, k)| w[k as usize]).collect();
    VertexMask {
        indices: order.iter().map(|&(i, _)| i).collect(),
        position: pick(&m.position),
        tangent_u: pick(&m.tangent_u),
        tangent_v: pick(&m.tangent_v),
    }
}

/// Whether [`vertex_mask`] refines around `v` first: semi-sharpness at `v` or on its edges, or
/// a non-quad face.
fn needs_refinement(topo: &Topology, v: u32) -> bool {
    is_semi(topo.vertex_sharpness(v))
        || topo
            .vertex_edges(v)
            .iter()
            .any(|&e| is_semi(topo.edge_sharpness(e)))
        || topo.vertex_faces(v).iter().any(|&g| topo.face_size(g) != 4)
}

/// Closed-form smooth interior mask on a quad ring (Halstead et al. 1993, appendix A).
fn smooth_mask(level: &Level, v: u32, i: usize) -> VertexMask {
    let topo = level.topology();
    let faces = topo.vertex_faces(v);
    let locals = topo.vertex_face_locals(v);
    let edges = topo.vertex_edges(v);
    let n = faces.len();
    let (wv, we, wf) = masks::smooth_position(n);
    let mut t = Vec::with_capacity(2 * n + 1);
    t.push((v, [wv, 0.0, 0.0]));
    // Halstead's tangents per valence (computed once); valence 2 below.
    let table = (n != 2).then(|| masks::SmoothTangent::of(n));
    for j in 0..n {
        let e = topo.other_vertex(edges[j], v);
        let fv = topo.face_vertices(faces[j]);
        let f = fv[(locals[j] as usize + 2) % 4];
        // Tangent weights `(e, f)` of ring index `j`: `u` along edge `i`, `v` along edge `i + 1`.
        let [(tue, tuf), (tve, tvf)] = match &table {
            Some(table) => [table.at(j, i), table.at(j, (i + 1) % n)],
            None => valence_two_tangents(i, j),
        };
        t.push((e, [we, tue, tve]));
        t.push((f, [wf, tuf, tvf]));
    }
    VertexMask::from_triples(t)
}

/// Tangent weights `[(e, f) of u, (e, f) of v]` of ring index `j` of a valence-2 vertex seen from
/// its face `i`. Halstead's tangents vanish there. The subdominant spectrum is 1/4 (twice, left
/// eigenvectors e_0 - e_1 and f_0 - f_1) and -1/4; the plane of the two positive modes,
/// oriented as the face (e_a at angle 0, the face's far corner at angle pi/2). The -1/4 mode is
/// as strong, so the faces' own normals alternate about this plane as they approach the vertex
/// and have no limit; the plane is their mean (tests/limit_corners.rs,
/// `valence_two_normals_alternate_about_the_quarter_modes_plane`).
fn valence_two_tangents(i: usize, j: usize) -> [(f64, f64); 2] {
    let w = if j == i { 0.5 } else { -0.5 };
    [(w, 0.0), (0.0, w)]
}

/// Row `r` of a sparse matrix as `(column, weight)` pairs.
fn row(m: &SparseMatrix, r: usize) -> impl Iterator<Item = (u32, f64)> + '_ {
    let (i, w) = m.row(r);
    i.iter().copied().zip(w.iter().copied())
}

/// Mask `cm` over the vertices of a refined extraction, mapped back to the extracted level's
/// vertices: through the refinement matrix `r`, then the extraction's vertex map `map`
/// (the identity for a mask over the extraction itself).
fn pull_back(cm: &VertexMask, r: &SparseMatrix, map: impl Fn(u32) -> u32) -> VertexMask {
    let mut t = Vec::new();
    for (k, &c) in cm.indices.iter().enumerate() {
        let w = [cm.position[k], cm.tangent_u[k], cm.tangent_v[k]];
        for (col, x) in row(r, c as usize) {
            t.push((map(col), [w[0] * x, w[1] * x, w[2] * x]));
        }
    }
    VertexMask::from_triples(t)
}

/// A mask over an extraction's vertices as a mask over the extracted level's, through the
/// extraction's vertex map `map`. `map` increases (`Level::try_extract` numbers vertices in
/// increasing old id), so this is bit for bit what pulling back through `map` directly gives:
/// `VertexMask::from_triples` sorts and sums the same terms in the same order.
fn mapped(mut m: VertexMask, map: &[u32]) -> VertexMask {
    for i in &mut m.indices {
        *i = map[*i as usize];
    }
    m
}

/// The faces of `v` extracted (sub face `j` is the `j`-th face of `v`) and `v`'s id there.
fn ring_extraction(level: &Level, v: u32) -> Result<(Level, Vec<u32>, u32)> {
    let faces = level.topology().vertex_faces(v);
    let (sub, map) = level.try_extract(faces)?;
    let v_sub = map
        .binary_search(&v)
        .map_err(|_| Error::Invalid(format!("limit mask: vertex {v} lost in extraction")))?
        as u32;
    Ok((sub, map, v_sub))
}

/// One local refinement step around `v`, then the mask of its child vertex, mapped back.
fn refined_mask(
    level: &Level,
    v: u32,
    i: usize,
    depth: u32,
    step: LocalStep,
) -> Result<VertexMask> {
    let (sub, map, v_sub) = ring_extraction(level, v)?;
    Ok(mapped(
        refined_local_mask(&sub, v_sub, i, depth, step)?,
        &map,
    ))
}

/// [`refined_mask`] of vertex `v_sub` of its ring's extraction `sub` (face `i` of `v_sub`, which
/// is sub face `i`), over `sub`'s vertices.
fn refined_local_mask(
    sub: &Level,
    v_sub: u32,
    i: usize,
    depth: u32,
    step: LocalStep,
) -> Result<VertexMask> {
    #[cfg(test)]
    if step == LocalStep::WholeRing {
        return whole_ring_refined_mask(sub, v_sub, i, depth, step);
    }
    match kept_corners(sub.topology(), v_sub) {
        Some(keep) => kept_refined_mask(sub, v_sub, i, depth, &keep),
        None => whole_ring_refined_mask(sub, v_sub, i, depth, step),
    }
}

/// The corners of `v` in its faces' order: the child faces at `v`'s vertex point in its ring's
/// order (`Level::refine_topology`), when they increase as `Level::refine_kept` needs.
fn kept_corners(topo: &Topology, v: u32) -> Option<Vec<u32>> {
    let keep: Vec<u32> = (topo.vertex_faces(v).iter())
        .zip(topo.vertex_face_locals(v))
        .map(|(&g, &l)| topo.face_offsets[g as usize] + u32::from(l))
        .collect();
    keep.windows(2).all(|w| w[0] < w[1]).then_some(keep)
}

/// [`refined_local_mask`] through `sub.refine_kept(keep)`, which is
/// `sub.refine_topology().try_extract(keep)`: the ring extraction of `v_sub`'s child that the
/// whole-ring path makes, made directly. The child's mask over it is pulled back through the
/// rows of `sub`'s refinement matrix it reads, computed one by one. The same terms in the same
/// order as [`whole_ring_refined_mask`], so the same bits (`tests::kept_steps_are_whole_ring_steps`).
fn kept_refined_mask(
    sub: &Level,
    v_sub: u32,
    i: usize,
    depth: u32,
    keep: &[u32],
) -> Result<VertexMask> {
    let st = sub.topology();
    let lost = || {
        Error::Invalid(format!(
            "limit mask: ring vertex {v_sub} lost in refinement"
        ))
    };
    let (child, map) = sub.refine_kept(keep)?;
    let v_full = (st.face_count() + st.edge_count()) as u32 + v_sub;
    let v_child = map.binary_search(&v_full).map_err(|_| lost())? as u32;
    // Child face `k` is the child of `v_sub`'s `k`-th face at its corner.
    let k = (st.vertex_faces(v_sub).iter())
        .position(|&g| g == i as u32)
        .ok_or_else(lost)?;
    let ct = child.topology();
    if !ct
        .vertex_faces(v_child)
        .iter()
        .copied()
        .eq(0..keep.len() as u32)
    {
        // Not the whole-ring path's extraction (its faces in another order).
        return whole_ring_refined_mask(sub, v_sub, i, depth, LocalStep::Kept);
    }
    let cm = if needs_refinement(ct, v_child) {
        // `child` is already the ring extraction `refined_mask` would make of it.
        if depth + 1 >= MAX_LOCAL_STEPS {
            return Err(Error::Invalid(format!(
                "limit mask: ring vertex {v_sub} still semi-sharp after {} local refinements",
                depth + 1
            )));
        }
        refined_local_mask(&child, v_child, k, depth + 1, LocalStep::Kept)?
    } else {
        vertex_mask_rec(&child, v_child, k as u32, depth + 1, LocalStep::Kept)?
    };
    // Room up front for rows of up to 9 terms (a regular vertex point's; most are shorter),
    // and for one row of a vertex point up to valence 15 (`2 n + 1` terms on quads).
    let mut t = Vec::with_capacity(9 * cm.indices.len());
    let mut buf = Vec::with_capacity(32);
    for (j, &c) in cm.indices.iter().enumerate() {
        let w = [cm.position[j], cm.tangent_u[j], cm.tangent_v[j]];
        sub.refine_matrix_row(map[c as usize] as usize, &mut buf);
        t.extend(
            buf.iter()
                .map(|&(col, x)| (col, [w[0] * x, w[1] * x, w[2] * x])),
        );
    }
    Ok(VertexMask::from_triples(t))
}

/// [`refined_local_mask`] by refining the whole of `sub` and looking up `v_sub`'s child there.
fn whole_ring_refined_mask(
    sub: &Level,
    v_sub: u32,
    i: usize,
    depth: u32,
    step: LocalStep,
) -> Result<VertexMask> {
    // Extraction keeps the order of the given faces: faces[i] is sub face i.
    let face_sub = i as u32;
    let (child, r) = sub.refine();
    let st = sub.topology();
    let corner = st
        .face_vertices(face_sub)
        .iter()
        .position(|&x| x == v_sub)
        .ok_or_else(|| {
            Error::Invalid(format!(
                "limit mask: ring vertex {v_sub} is no corner of its sub face {face_sub}"
            ))
        })?;
    let v_child = (st.face_count() + st.edge_count()) as u32 + v_sub;
    let child_face = sub.child_faces(face_sub).start + corner as u32;
    let cm = vertex_mask_rec(&child, v_child, child_face, depth + 1, step)?;
    Ok(pull_back(&cm, &r, |c| c))
}

/// The limit mask, over `level`'s vertices, of the face point that refining `level` once puts
/// in face `f` (the limit at the centre of `f`'s domain, for a quad `(½, ½)`), tangents oriented
/// by the child face at `f`'s corner 0. `f` and the faces around its corners are refined
/// locally, which gives the face point's ring exactly (it lies inside `f`).
pub fn face_point_mask(level: &Level, f: u32) -> Result<VertexMask> {
    let topo = level.topology();
    if f as usize >= topo.face_count() {
        return Err(Error::Invalid(format!(
            "face-point mask: face {f} out of range"
        )));
    }
    let mut faces = vec![f];
    for &v in topo.face_vertices(f) {
        for &g in topo.vertex_faces(v) {
            if !faces.contains(&g) {
                faces.push(g);
            }
        }
    }
    // Extraction keeps the order of the given faces: `f` is sub face 0.
    let (sub, map) = level.try_extract(&faces)?;
    let (child, r) = sub.refine();
    let cm = vertex_mask(&child, sub.child_face_point(0), sub.child_faces(0).start)?;
    Ok(pull_back(&cm, &r, |c| map[c as usize]))
}

/// Mask from the eigenvectors of the local subdivision matrix restricted to the face's sector
/// (sectors between infinitely sharp edges do not interact: crease and corner rules only read
/// the sharp edges' ends).
fn eigen_mask(
    level: &Level,
    v: u32,
    i: usize,
    sharp: usize,
    depth: u32,
    step: LocalStep,
) -> Result<VertexMask> {
    let topo = level.topology();
    let faces = topo.vertex_faces(v).to_vec();
    let fail = || Error::Invalid(format!("limit mask: no convergence at vertex {v}"));
    let (sub, map) = level.extract(&faces);
    let v_sub = map.iter().position(|&x| x == v).ok_or_else(fail)? as u32;
    let (_child, r) = sub.refine();
    let st = sub.topology();
    let nf_sub = st.face_count() as u32;
    let ne_sub = st.edge_count() as u32;
    let sub_edges = st.vertex_edges(v_sub).to_vec();
    let sub_faces = st.vertex_faces(v_sub).to_vec();
    let sub_locals = st.vertex_face_locals(v_sub).to_vec();
    // Extraction keeps the order of the given faces: faces[i] is sub face i.
    let i_sub = sub_faces
        .iter()
        .position(|&g| g == i as u32)
        .ok_or_else(fail)?;
    let sec = sector_slots(st, v_sub, i_sub);
    // Sector ring (sub-level vertex ids) and, for each, the child vertex that replaces it.
    let mut ring: Vec<u32> = vec![v_sub];
    let mut child_of: Vec<(u32, u32)> = vec![(nf_sub + ne_sub + v_sub, v_sub)];
    let mut edge_slots: Vec<usize> = sec.clone();
    edge_slots.push(sec[sec.len() - 1] + 1);
    let mut simple = true;
    let mut add = |ring: &mut Vec<u32>, child_of: &mut Vec<(u32, u32)>, c: u32, x: u32| {
        match ring.iter().position(|&y| y == x) {
            None => {
                ring.push(x);
                child_of.push((c, x));
            }
            // The closing edge of a sector that wraps all the way round is listed twice.
            Some(k) => simple &= child_of[k].0 == c,
        }
    };
    for &k in &edge_slots {
        let e = sub_edges[k % sub_edges.len()];
        add(
            &mut ring,
            &mut child_of,
            nf_sub + e,
            st.other_vertex(e, v_sub),
        );
    }
    for &k in &sec {
        let g = sub_faces[k];
        let fv = st.face_vertices(g);
        add(
            &mut ring,
            &mut child_of,
            g,
            fv[(sub_locals[k] as usize + 2) % 4],
        );
    }
    if !simple {
        // A ring vertex in two roles (e.g. next to a valence-2 vertex): the ring matrix would mix
        // two children into one row. One refinement step makes every ring vertex distinct.
        if depth >= MAX_LOCAL_STEPS {
            return Err(fail());
        }
        return refined_mask(level, v, i, depth, step);
    }
    let m = ring.len();
    let pos_in_ring = |x: u32| ring.iter().position(|&y| y == x);
    let mut s = masks::Dense {
        m,
        a: vec![0.0; m * m],
    };
    for &(c, x) in &child_of {
        let ri = pos_in_ring(x).ok_or_else(fail)?;
        for (col, w) in row(&r, c as usize) {
            let ci = pos_in_ring(col).ok_or_else(fail)?;
            s.a[ri * m + ci] += w;
        }
    }
    let ne = sub_edges.len();
    let corner_rule = is_inf(topo.vertex_sharpness(v)) || sharp > 2;
    let opposite = {
        let fv = st.face_vertices(sub_faces[i_sub]);
        pos_in_ring(fv[(sub_locals[i_sub] as usize + 2) % 4]).ok_or_else(fail)?
    };
    let lim = if sharp >= 2 {
        // Sector bounded by sharp edges ([`sector::sector_limit`]).
        let lo = pos_in_ring(st.other_vertex(sub_edges[sec[0] % ne], v_sub)).ok_or_else(fail)?;
        let last = sec[sec.len() - 1];
        let hi =
            pos_in_ring(st.other_vertex(sub_edges[(last + 1) % ne], v_sub)).ok_or_else(fail)?;
        let ring = sector::SectorRing {
            m,
            lo,
            hi,
            a: pos_in_ring(st.other_vertex(sub_edges[i_sub], v_sub)).ok_or_else(fail)?,
            b: pos_in_ring(st.other_vertex(sub_edges[(i_sub + 1) % ne], v_sub)).ok_or_else(fail)?,
            faces: sec.len(),
            face: sec.iter().position(|&k| k == i_sub).ok_or_else(fail)?,
            corner: corner_rule,
        };
        let mut lim = sector::sector_limit(&s, &ring).ok_or_else(fail)?;
        if !sector::exact_orientation(&ring) {
            orient(&s, &mut lim, [ring.a, opposite, ring.b]);
        }
        lim
    } else if sharp == 1 && corner_rule && sec.len() == 4 && m == 9 {
        // A corner tag with one sharp edge and four quads: tied modes, a normal per face
        // ([`sector::corner_tag4`]; the ring starts at the sharp edge).
        let face = sec.iter().position(|&k| k == i_sub).ok_or_else(fail)?;
        sector::corner_tag4(&s, face).ok_or_else(fail)?
    } else {
        let a = pos_in_ring(st.other_vertex(sub_edges[i_sub], v_sub)).ok_or_else(fail)?;
        let b =
            pos_in_ring(st.other_vertex(sub_edges[(i_sub + 1) % ne], v_sub)).ok_or_else(fail)?;
        let mut x1 = vec![0.0; m];
        x1[a] = 1.0;
        x1[0] = -1.0;
        let mut x2 = vec![0.0; m];
        x2[b] = 1.0;
        x2[0] = -1.0;
        let mut lim = masks::eigen_limit(&s, 0, [x1, x2]).ok_or_else(fail)?;
        orient(&s, &mut lim, [a, opposite, b]);
        lim
    };
    let mut position = lim.position.clone();
    // Closed forms where they exist (exact; the tests check them against deep refinement).
    if corner_rule {
        position.iter_mut().for_each(|x| *x = 0.0);
        position[0] = 1.0;
    } else if sharp == 2 {
        let (wv, wend) = masks::crease_position();
        position.iter_mut().for_each(|x| *x = 0.0);
        position[0] = wv;
        for &e in &sub_edges {
            if is_inf(st.edge_sharpness(e)) {
                let x = pos_in_ring(st.other_vertex(e, v_sub)).ok_or_else(fail)?;
                position[x] += wend;
            }
        }
    }
    let t = ring
        .iter()
        .enumerate()
        .map(|(k, &x)| {
            (
                map[x as usize],
                [position[k], lim.tangents[0][k], lim.tangents[1][k]],
            )
        })
        .collect();
    Ok(VertexMask::from_triples(t))
}

/// Turns `lim`'s tangent pair to the orientation of the face whose corner `(v, e_a, f, e_b)`
/// has the ring entries `[a, f, b]`, judged at the face's diagonal: the pair
/// `(f - v, e_b - e_a)` ([`masks::face_orientation`]); left as it is if that cannot be decided.
fn orient(s: &masks::Dense, lim: &mut masks::EigenLimit, [a, f, b]: [usize; 3]) {
    let mut diagonal = vec![0.0; s.m];
    diagonal[f] += 1.0;
    diagonal[0] -= 1.0;
    let mut across = vec![0.0; s.m];
    across[b] += 1.0;
    across[a] -= 1.0;
    let t = [&lim.tangents[0][..], &lim.tangents[1][..]];
    if masks::face_orientation(s, 0, &diagonal, &across, t) == Some(-1.0) {
        lim.tangents[1].iter_mut().for_each(|x| *x = -*x);
    }
}

/// Limit positions of every vertex of `level` (vertices without faces keep their position).
pub fn limit_positions(level: &Level, positions: &[DVec3]) -> Result<Vec<DVec3>> {
    let topo = level.topology();
    (0..topo.vertex_count() as u32)
        .into_par_iter()
        .map(|v| match topo.vertex_faces(v).first() {
            None => Ok(positions[v as usize]),
            Some(&f) => Ok(vertex_mask(level, v, f)?.apply(positions).0),
        })
        .collect()
}

/// Limit unit normals of every vertex of `level`. At crease and corner vertices the normal is
/// the one of the sector of the vertex's first face. Vertices without faces get zero.
pub fn limit_normals(level: &Level, positions: &[DVec3]) -> Result<Vec<DVec3>> {
    let topo = level.topology();
    (0..topo.vertex_count() as u32)
        .into_par_iter()
        .map(|v| match topo.vertex_faces(v).first() {
            None => Ok(DVec3::ZERO),
            Some(&f) => {
                let (_, tu, tv) = vertex_mask(level, v, f)?.apply(positions);
                Ok(tu.cross(tv).normalize_or_zero())
            }
        })
        .collect()
}

/// Limit stencils of every vertex of a level: position and the two tangents, one row per
/// vertex (tangents oriented by the vertex's first face; vertices without faces: identity
/// position row, empty tangent rows).
#[derive(Debug, Clone, PartialEq)]
pub struct LimitStencils {
    /// Limit positions.
    pub position: SparseMatrix,
    /// First tangents (see [`VertexMask`]).
    pub tangent_u: SparseMatrix,
    /// Second tangents; `tangent_u x tangent_v` is the outward normal.
    pub tangent_v: SparseMatrix,
}

/// The limit masks of all vertices of `level` as matrices over `level`'s vertices.
pub fn limit_matrices(level: &Level) -> Result<LimitStencils> {
    let topo = level.topology();
    let n = topo.vertex_count();
    let masks: Vec<Option<VertexMask>> = (0..n as u32)
        .into_par_iter()
        .map(|v| match topo.vertex_faces(v).first() {
            None => Ok(None),
            Some(&f) => vertex_mask(level, v, f).map(Some),
        })
        .collect::<Result<_>>()?;
    let build = |k: usize| {
        SparseMatrix::from_rows(n, n, |r, buf| match &masks[r] {
            None if k == 0 => buf.push((r as u32, 1.0)),
            None => {}
            Some(m) => {
                let w = [&m.position, &m.tangent_u, &m.tangent_v][k];
                buf.extend(m.indices.iter().copied().zip(w.iter().copied()));
            }
        })
    };
    Ok(LimitStencils {
        position: build(0),
        tangent_u: build(1),
        tangent_v: build(2),
    })
}

/// Limit stencils of the vertices of uniform level `depth` below `base`, in terms of `base`'s
/// vertices (the per-frame GPU path: topology fixed, `apply` to new control positions).
pub fn limit_stencil_tables(base: &Level, depth: u32) -> Result<LimitStencilTables> {
    let refined = StencilTable::from_level(base, depth);
    let mut level = base.clone();
    for _ in 0..depth {
        level = level.refine_topology();
    }
    let m = limit_matrices(&level)?;
    let over_base = |a: &SparseMatrix| StencilTable::from_matrix(a.compose(refined.matrix()));
    Ok(LimitStencilTables {
        position: over_base(&m.position),
        tangent_u: over_base(&m.tangent_u),
        tangent_v: over_base(&m.tangent_v),
    })
}

/// [`LimitStencils`] composed with the refinement: rows over the base vertices.
#[derive(Debug, Clone, PartialEq)]
pub struct LimitStencilTables {
    /// Limit positions of the level's vertices.
    pub position: StencilTable,
    /// First tangents.
    pub tangent_u: StencilTable,
    /// Second tangents.
    pub tangent_v: StencilTable,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A corner asked again by its key gets the mask made the first time (the same allocation,
    /// no look-up by ring), which is a fresh table's; a failed corner fails again.
    #[test]
    fn corner_masks_are_kept_by_key() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../shared/meshes/osd/catmark_cube_creases1.obj"
        );
        let mesh = crate::ControlMesh::from_obj_file(path, &Default::default()).unwrap();
        let level = Level::from_mesh(&mesh).unwrap();
        let topo = level.topology();
        let masks = SharedVertexMasks::default();
        let mut asked = 0;
        for v in (0..topo.vertex_count() as u32).filter(|&v| needs_refinement(topo, v)) {
            for &f in topo.vertex_faces(v) {
                let first = masks.corner_mask((v, f), &level, v, f).unwrap();
                let hits = masks.hits();
                let again = masks.corner_mask((v, f), &level, v, f).unwrap();
                assert!(Arc::ptr_eq(&first, &again), "vertex {v} face {f}");
                assert_eq!(masks.hits(), hits, "vertex {v} face {f}: looked up by ring");
                let fresh = SharedVertexMasks::default().vertex_mask(&level, v, f);
                assert_eq!(*first, fresh.unwrap(), "vertex {v} face {f}");
                asked += 1;
            }
        }
        assert!(asked > 8, "{asked} corners");
        let stranger = (0..topo.face_count() as u32)
            .find(|&g| !topo.vertex_faces(0).contains(&g))
            .unwrap();
        for _ in 0..2 {
            assert!(masks
                .corner_mask((0, stranger), &level, 0, stranger)
                .is_err());
        }
    }

    /// A mask's indices and weights' bits.
    fn bits(m: &VertexMask) -> (Vec<u32>, Vec<Vec<u64>>) {
        let w = [&m.position, &m.tangent_u, &m.tangent_v];
        let w = w.iter().map(|x| x.iter().map(|y| y.to_bits()).collect());
        (m.indices.clone(), w.collect())
    }

    /// The corpus meshes' levels that parse and are manifold (`Level::from_mesh` refuses the
    /// others), each with its first uniform level: `(name, depth, level)`.
    fn corpus_levels() -> Vec<(String, u32, Level)> {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/meshes/osd/");
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .filter_map(|e| {
                let name = e.unwrap().file_name().into_string().unwrap();
                name.strip_suffix(".obj").map(str::to_string)
            })
            .collect();
        names.sort();
        let mut levels = Vec::new();
        for name in names {
            let path = format!("{dir}{name}.obj");
            let Ok(mesh) = crate::ControlMesh::from_obj_file(&path, &Default::default()) else {
                continue;
            };
            let Ok(level) = Level::from_mesh(&mesh) else {
                continue;
            };
            let next = level.refine_topology();
            levels.push((name.clone(), 0, level));
            levels.push((name, 1, next));
        }
        levels
    }

    /// A mask shared by key (`ring_key` leaves out the sharpness and flags of the ring's other
    /// edges and vertices) is, bit for bit, the mask a fresh table makes from the vertex's own
    /// ring, for every vertex that refines locally and each of its faces, on every corpus mesh
    /// and its first uniform level; and some are shared.
    #[test]
    fn reduced_ring_keys_share_masks() {
        let (mut compared, mut hits) = (0, 0);
        for (name, d, level) in corpus_levels() {
            let topo = level.topology();
            let shared = SharedVertexMasks::default();
            for v in 0..topo.vertex_count() as u32 {
                if !needs_refinement(topo, v) {
                    continue;
                }
                for &f in topo.vertex_faces(v) {
                    let a = shared.vertex_mask(&level, v, f);
                    let b = SharedVertexMasks::default().vertex_mask(&level, v, f);
                    match (a, b) {
                        (Ok(a), Ok(b)) => {
                            assert_eq!(bits(&a), bits(&b), "{name} {d} vertex {v} face {f}")
                        }
                        (a, b) => {
                            assert_eq!(a.is_ok(), b.is_ok(), "{name} {d} vertex {v} face {f}")
                        }
                    }
                    compared += 1;
                }
            }
            hits += shared.hits();
        }
        assert!(
            compared > 1000 && hits > compared / 2,
            "{hits} of {compared} shared"
        );
    }

    /// Every mask that refines locally, of every vertex and face of every corpus mesh (and of
    /// its first uniform level), and the same masks over the vertices' ring extractions as
    /// `SharedVertexMasks` makes them: the kept-corner steps give the whole-ring steps' bits.
    #[test]
    fn kept_steps_are_whole_ring_steps() {
        let mut compared = 0;
        for (name, d, level) in corpus_levels() {
            let topo = level.topology();
            for v in 0..topo.vertex_count() as u32 {
                if !needs_refinement(topo, v) {
                    continue;
                }
                for (i, &f) in topo.vertex_faces(v).iter().enumerate() {
                    let kept = vertex_mask_rec(&level, v, f, 0, LocalStep::Kept);
                    let whole = vertex_mask_rec(&level, v, f, 0, LocalStep::WholeRing);
                    let mut ring = RingCorners::default();
                    assert!(ring.fill(topo, v, i));
                    let (sub, _) = level.try_extract_ring(ring).unwrap();
                    let kept_ring = refined_local_mask(&sub, 0, 0, 0, LocalStep::Kept);
                    let whole_ring = refined_local_mask(&sub, 0, 0, 0, LocalStep::WholeRing);
                    for (a, b) in [(kept, whole), (kept_ring, whole_ring)] {
                        match (a, b) {
                            (Ok(a), Ok(b)) => {
                                assert_eq!(
                                    bits(&a),
                                    bits(&b),
                                    "{name} level {d} vertex {v} face {f}"
                                )
                            }
                            (a, b) => assert_eq!(
                                a.is_ok(),
                                b.is_ok(),
                                "{name} level {d} vertex {v} face {f}: {a:?} / {b:?}"
                            ),
                        }
                        compared += 1;
                    }
                }
            }
        }
        assert!(compared > 1000, "{compared} masks compared");
    }
}
