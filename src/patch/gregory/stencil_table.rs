//! The Gregory stencils of a mesh grouped by connectivity type: the CPU tables of the GPU stencil
//! variant (Loop et al. 2009, §4.3). Every row is a fixed linear combination of the face's
//! one-ring vertices, computed by the one construction on unit weight vectors (as
//! [`super::stencil::GregoryStencil`]); the ring is kept in the canonical local order of
//! [`super::stencil::canonical_ring`], so faces with the same local connectivity share one
//! connectivity type (§4.3), and every weighted sum runs in ascending global vertex id (the
//! paper's "one global, consistent order", §4.5), so a point two patches share gets bitwise
//! equal values in both.

use std::borrow::Borrow;
use std::collections::HashMap;

use glam::DVec3;

use super::build::{
    check_face_shape, gregory_patch_for, gregory_patch_recipes, gregory_vertex_for,
    has_vertex_data, vertex_covered, vertex_ring_of_units, Coverage, GregoryPatch, NotGregory,
};
use super::corner_types::CornerTypes;
use super::eval::{edge_side_far_corners, edge_side_points, CornerRef, PointRecipe};
use super::face_rows::FaceRows;
use super::point::{merge_terms_into, ArenaWeights, GregoryPoint, Weights};
use super::stencil::{dense_rows, stencil_ring, NoStencil, MAX_RING, ROWS_PER_CORNER};
use super::tangents::GregoryTangents;
use super::vertex::{DartLimits, GregoryVertex};
use super::word_hash::WordHashMap;
use crate::topology::Topology;

/// Control points of a quad Gregory patch.
pub const QUAD_POINTS: usize = 20;
/// Control points of a triangular Gregory patch.
pub const TRI_POINTS: usize = 15;
/// Extra rows after a quad's control points: per patch edge k the neighbour's other edge points
/// at both ends (`g_eout` of glsl/common/gregory.glsl), then the neighbour's face points next
/// to edge k at both ends (`g_nbr`).
pub const QUAD_EXTRA: usize = 16;
/// Extra rows after a triangle's control points (6 + 6).
pub const TRI_EXTRA: usize = 12;

/// One face of a [`GregoryStencilTable`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StencilPatch {
    /// Base-mesh face.
    pub face: u32,
    /// Corner vertex ids in face order (4th entry repeats corner 0 for triangles).
    pub corners: [u32; 4],
    /// Whether the face is a triangle (15 points) or a quad (20 points).
    pub triangle: bool,
    /// The face's one-ring (every vertex of every face touching a corner) in the canonical local
    /// order of [`super::stencil::canonical_ring`]: the patch primitive's vertex list. Faces
    /// with the same local connectivity get the same weights slot by slot, so they share a
    /// connectivity type (§4.3).
    pub ring: Vec<u32>,
    /// Ring slots sorted by global vertex id: the order every weighted sum runs in, so a shared
    /// corner or edge point gets the same nonzero terms in the same order in both patches (§4.5).
    pub order: Vec<u8>,
    /// Index into [`GregoryStencilTable::types`].
    pub type_id: u32,
}

/// One connectivity type: the weight rows shared by every patch of the type.
#[derive(Debug, Clone, PartialEq)]
pub struct StencilType {
    /// Triangle (15 control points) or quad (20).
    pub triangle: bool,
    /// Ring length (columns).
    pub ring_len: usize,
    /// `weights[row * ring_len + k]`: weight of ring vertex `k` in row `row`: the control points
    /// p0.., e_plus0.., e_minus0.., f_plus0.., f_minus0.. (20 or 15), then for each patch edge
    /// k (corner k -> k+1) the edge point of corner k's vertex on the ring edge beyond edge k
    /// and that of corner k+1's vertex beyond edge k (8 or 6 rows: the neighbour patch's own
    /// edge points there), then for each edge k the neighbour patch's face points next to edge
    /// k at corner k and at corner k+1 (8 or 6 rows, eq. 6 with the neighbour's face size): the
    /// shared TES builds symmetric edge normals from both patches' cross-edge derivatives.
    pub weights: Vec<f32>,
    /// Bit `k` of `masks[row]` set when the weight of ring vertex `k` in `row` is nonzero.
    pub masks: Vec<u32>,
}

impl StencilType {
    /// Number of corners (3 or 4).
    pub fn corners(&self) -> usize {
        if self.triangle {
            3
        } else {
            4
        }
    }

    /// The row of control point `point` given in [`super::stencil::GregoryStencil`] order
    /// (`5 i + k`: corner `i`, kind `k`); the table stores the points kind by kind (`k n + i`).
    pub fn point_row(&self, point: usize) -> usize {
        let (i, k) = (point / ROWS_PER_CORNER, point % ROWS_PER_CORNER);
        k * self.corners() + i
    }
}

/// Gregory stencils of a set of faces, grouped by connectivity type: what a GPU stencil buffer
/// is made of.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GregoryStencilTable {
    /// Accepted faces, in input order.
    pub patches: Vec<StencilPatch>,
    /// Connectivity types.
    pub types: Vec<StencilType>,
    /// Faces without a stencil and why (no Gregory patch, ring too large), in input order.
    pub skipped: Vec<NoStencil>,
}

/// The rows of face `f` in the table layout ([`StencilType::weights`]) from `patch(g)`, the
/// Gregory patch of face `g` in any point type: its own control points, then per edge k the
/// neighbour patch's edge points and face points next to the edge, taken from the neighbour's
/// own construction (the rows its own stencil has), so they are bitwise its own values. Where
/// the edge has no Gregory neighbour (boundary, a face without Gregory patch) the patch's own
/// points stand in.
fn table_rows<P: GregoryPoint, B: Borrow<GregoryPatch<P>>>(
    topo: &Topology,
    f: u32,
    patch: impl Fn(u32) -> Result<B, NotGregory>,
) -> Result<Vec<P>, NotGregory> {
    let own = patch(f)?;
    Ok(table_rows_with(topo, f, own.borrow(), |_, g, k2| {
        Some(side_points(patch(g).ok()?.borrow(), k2))
    }))
}

/// The points of patch `q` beside its edge from corner `k2` to `k2 + 1`: `[e_plus at k2 + 1,
/// e_minus at k2, f_minus at k2 + 1, f_plus at k2]` (a neighbour's rows in `table_rows`).
fn side_points<P: GregoryPoint>(q: &GregoryPatch<P>, k2: usize) -> [P; 4] {
    let [_, ep, em, fp, fm] = q.points();
    let k2n = (k2 + 1) % ep.len();
    [
        ep[k2n].clone(),
        em[k2].clone(),
        fm[k2n].clone(),
        fp[k2].clone(),
    ]
}

/// `table_rows` from face `f`'s own patch and `neighbour(k, g, k2)`, the `side_points` of the
/// patch of face `g` across edge k of `f` (which runs from corner `k2` to `k2 + 1` in `g`,
/// [`edge_neighbour`]), `None` where `g` has no patch.
fn table_rows_with<P: GregoryPoint>(
    topo: &Topology,
    f: u32,
    own: &GregoryPatch<P>,
    mut neighbour: impl FnMut(usize, u32, usize) -> Option<[P; 4]>,
) -> Vec<P> {
    let theirs = |k| edge_neighbour(topo, f, k).and_then(|(g, k2)| neighbour(k, g, k2));
    table_rows_into(own, theirs, |rows, _| {
        rows.iter().map(|&p| p.clone()).collect()
    })
}

/// The face `g` across edge k of face `f` (corner k -> k + 1) and the corner `k2` of `g` the
/// edge runs from in `g` (to `k2 + 1`), if any.
fn edge_neighbour(topo: &Topology, f: u32, k: usize) -> Option<(u32, usize)> {
    let fv = topo.face_vertices(f);
    let (x, y) = (fv[k], fv[(k + 1) % fv.len()]);
    let g = topo
        .find_edge(x, y)
        .and_then(|e| topo.edge_faces(e).iter().copied().find(|&g| g != f))?;
    let d = topo.face_vertices(g);
    let m = d.len();
    // In g the edge runs y -> x: corner k2 = y, k2 + 1 = x.
    let k2 = (0..m).find(|&i| d[i] == y && d[(i + 1) % m] == x)?;
    Some((g, k2))
}

/// [`table_rows_with`] from `theirs(k)`, the neighbour's `side_points` across edge k (`None`
/// where there is no neighbour patch), the rows handed to `emit` at once, in order, by
/// reference (no row cloned; the caller sizes its storage from them), with each row's first
/// place (`first[r] < r` where row `r` is row `first[r]` again: the patch's own edge and face
/// points standing in beside an edge without a neighbour patch), so a caller may form it once.
/// Any row type: points, or the end caps' [`PointRecipe`]s.
fn table_rows_into<P, R>(
    own: &GregoryPatch<P>,
    mut theirs: impl FnMut(usize) -> Option<[P; 4]>,
    emit: impl FnOnce(&[&P], &[u8]) -> R,
) -> R {
    let points = own.points();
    let n = points[1].len();
    let theirs: [Option<[P; 4]>; 4] = std::array::from_fn(|k| (k < n).then(|| theirs(k)).flatten());
    // On the stack: at most a quad's rows. The control points kind by kind (`p`, `e_plus`,
    // `e_minus`, `f_plus`, `f_minus`: rows `kind * n + corner`).
    let mut rows: [&P; QUAD_POINTS + QUAD_EXTRA] = [&points[0][0]; QUAD_POINTS + QUAD_EXTRA];
    let mut first: [u8; QUAD_POINTS + QUAD_EXTRA] = std::array::from_fn(|r| r as u8);
    for (kind, kind_points) in points.into_iter().enumerate() {
        for (row, point) in rows[kind * n..(kind + 1) * n].iter_mut().zip(kind_points) {
            *row = point;
        }
    }
    // Edge k's `[ex, ey]` (rows `5 n + 2 k`, `+ 1`) and `[fx, fy]` (rows `7 n + 2 k`, `+ 1`):
    // the neighbour's, else the patch's own `e_minus[k]`, `e_plus[k + 1]`, `f_plus[k]`,
    // `f_minus[k + 1]`.
    for (k, their) in theirs.iter().enumerate().take(n) {
        let at = [
            5 * n + 2 * k,
            5 * n + 2 * k + 1,
            7 * n + 2 * k,
            7 * n + 2 * k + 1,
        ];
        match their {
            Some(points) => {
                for (&r, point) in at.iter().zip(points) {
                    rows[r] = point;
                }
            }
            None => {
                let k1 = (k + 1) % n;
                let own = [2 * n + k, n + k1, 3 * n + k, 4 * n + k1];
                for (&r, &o) in at.iter().zip(&own) {
                    rows[r] = rows[o];
                    first[r] = o as u8;
                }
            }
        }
    }
    emit(&rows[..9 * n], &first[..9 * n])
}

/// Per-vertex data in weight space of every corner of `faces` and of their edge neighbours
/// (what [`table_rows`] assembles their patches from), computed once per vertex: a
/// high-valence vertex is shared by many faces and its data costs `O(valence^3)` here.
fn corner_data(
    topo: &Topology,
    faces: impl Iterator<Item = u32>,
    tangents: GregoryTangents,
    coverage: Coverage,
    darts: &DartLimits,
) -> Vec<Option<GregoryVertex<Weights>>> {
    let mut data: Vec<Option<GregoryVertex<Weights>>> =
        (0..topo.vertex_count()).map(|_| None).collect();
    let mut done = vec![false; topo.vertex_count()];
    for f in faces {
        for &e in topo.face_edges(f) {
            for &g in topo.edge_faces(e) {
                for &v in topo.face_vertices(g) {
                    if !std::mem::replace(&mut done[v as usize], true) {
                        data[v as usize] =
                            gregory_vertex_for(topo, v, &Weights::unit, tangents, coverage, darts);
                    }
                }
            }
        }
    }
    data
}

/// What a vertex's entry in [`EndCapCorners`] holds.
#[derive(Clone, Copy, PartialEq, Eq)]
enum CornerState {
    /// Nothing known yet.
    Unknown,
    /// Whether the vertex has data is known from its topology (`has_vertex_data`); not built.
    Known(bool),
    /// The data is built, at this index of [`EndCapCorners::built`] (`None` where the vertex
    /// has none).
    Built(u32),
}

/// The two-stage per-vertex data of end-cap corners ([`super::gregory_vertex_two_stage`], derived
/// points [`vertex_point_id`]), each vertex's built on first use: a face's rows read the data
/// of its own corners, and of a neighbour's other corners only where the neighbour's face
/// points beside the shared edge are one-sided (`edge_side_points`); elsewhere the neighbour
/// needs only to have a patch, which its other corners' topology decides.
struct EndCapCorners<'a> {
    topo: &'a Topology,
    darts: &'a DartLimits,
    /// The data of the vertices built, in build order (a batch builds a few hundred of a
    /// level's vertices: no entry per vertex of the level to fill and drop), its weight
    /// vectors in `arena`.
    built: Vec<Option<GregoryVertex<ArenaWeights>>>,
    /// The terms of every weight vector of `built`.
    arena: Vec<(u32, f64)>,
    state: Vec<CornerState>,
    /// The two-stage data per ring type the vertices' data is relabelled from.
    types: CornerTypes<'a>,
}

impl<'a> EndCapCorners<'a> {
    /// Nothing built; whether a vertex has data known where `known` says (per vertex 0 or 1,
    /// 2 for not known: the end-cap keys' `has_vertex_data` answers), else asked on first use.
    fn new(
        topo: &'a Topology,
        tangents: GregoryTangents,
        darts: &'a DartLimits,
        known: Option<&[u8]>,
    ) -> Self {
        let state = match known {
            Some(known) => known
                .iter()
                .map(|&h| match h {
                    0 | 1 => CornerState::Known(h == 1),
                    _ => CornerState::Unknown,
                })
                .collect(),
            None => vec![CornerState::Unknown; topo.vertex_count()],
        };
        EndCapCorners {
            topo,
            types: CornerTypes::new(topo, tangents, darts),
            darts,
            built: Vec::new(),
            arena: Vec::new(),
            state,
        }
    }

    /// The data of vertex `v` if it is built and has some.
    fn vertex(&self, v: u32) -> Option<&GregoryVertex<ArenaWeights>> {
        match self.state[v as usize] {
            CornerState::Built(i) => self.built[i as usize].as_ref(),
            _ => None,
        }
    }

    /// Builds the data of `vertices` not built yet, once per ring type ([`CornerTypes`]).
    fn build(&mut self, vertices: &[u32]) {
        for &v in vertices {
            let state = &mut self.state[v as usize];
            if !matches!(state, CornerState::Built(_)) {
                *state = CornerState::Built(self.built.len() as u32);
                let covered = vertex_covered(self.topo, v, Coverage::EndCap);
                let data = covered.then(|| self.types.vertex(v, &mut self.arena));
                self.built.push(data.flatten());
            }
        }
    }

    /// Whether vertex `v` has data, without building it.
    fn has_data(&mut self, v: u32) -> bool {
        match self.state[v as usize] {
            CornerState::Built(i) => self.built[i as usize].is_some(),
            CornerState::Known(h) => h,
            CornerState::Unknown => {
                let h = has_vertex_data(self.topo, v, self.darts);
                self.state[v as usize] = CornerState::Known(h);
                h
            }
        }
    }

    /// Corner `v` of face `g` as the patch assembly takes it (`None` where `g`'s patch fails
    /// at it: no data, or `g` not in its ring); `v` built.
    fn corner(&self, v: u32, g: u32) -> Option<CornerRef<'_, ArenaWeights>> {
        let vertex = self.vertex(v)?;
        let j = self.topo.vertex_faces(v).iter().position(|&h| h == g)?;
        Some(CornerRef { vertex, j })
    }

    /// Builds what [`Self::side_points`] of face `g` at its corner `k2` reads; whether `g` has
    /// an end-cap patch: corners `k2` and `k2 + 1`, and `g`'s other corners where the face
    /// points there are one-sided ([`edge_side_far_corners`]).
    fn prepare_side(&mut self, g: u32, k2: usize) -> bool {
        let topo = self.topo;
        // `check_face_for`'s corner tests are implied by the corners' data (`end_cap_patch_with`).
        if check_face_shape(topo, g).is_err() {
            return false;
        }
        let gv = topo.face_vertices(g);
        let m = gv.len();
        let (y, x) = (gv[k2], gv[(k2 + 1) % m]);
        // `g` gets a patch only if every corner has data (`gregory_patch_for`).
        for &v in gv {
            if v != x && v != y && !(self.has_data(v) && topo.vertex_faces(v).contains(&g)) {
                return false;
            }
        }
        self.build(&[x, y]);
        let (Some(cx), Some(cy)) = (self.corner(x, g), self.corner(y, g)) else {
            return false;
        };
        let (needs_next, needs_prev) = edge_side_far_corners(&cx, &cy);
        if needs_next || needs_prev {
            self.build(gv);
        }
        true
    }

    /// `side_points` of the end-cap patch of face `g` at its corner `k2`, prepared
    /// ([`Self::prepare_side`] said `g` has a patch): from corners `k2` and `k2 + 1` alone
    /// unless the face points there are one-sided, else with `g`'s other corners too; the same
    /// terms as `g`'s whole patch either way, without assembling it.
    fn side_points(&self, g: u32, k2: usize) -> Option<[PointRecipe<'_, ArenaWeights>; 4]> {
        let gv = self.topo.face_vertices(g);
        let m = gv.len();
        let (y, x) = (gv[k2], gv[(k2 + 1) % m]);
        let (cx, cy) = (self.corner(x, g)?, self.corner(y, g)?);
        let (needs_next, needs_prev) = edge_side_far_corners(&cx, &cy);
        // Every corner of `g` has data where one is needed (as `gregory_patch_from` requires):
        // for a quad the corners after `x` and before `y` are its other two, for a triangle
        // its third.
        let far = |needed: bool, i: usize| {
            if needed {
                self.corner(gv[i % m], g).map(Some)
            } else {
                Some(None)
            }
        };
        let next = far(needs_next, k2 + 2)?;
        let prev = far(needs_prev, k2 + m - 1)?;
        edge_side_points(&cx, &cy, side_d(m), next.as_ref(), prev.as_ref())
    }
}

/// The `d` of eq. 6 for a face of `m` corners: 4 for triangles, 3 for quads (§3.4).
fn side_d(m: usize) -> f64 {
    if m == 3 {
        4.0
    } else {
        3.0
    }
}

/// The rows `rows` (weight vectors in `arena`) formed into one [`FaceRows`]: corners' points
/// copied, face points combined straight into its storage (no row of their own), each
/// combination once: a row that is an earlier one again (`first`, [`table_rows_into`]; a
/// corner's `f_minus` made its `f_plus` beside one sharp edge, `eval::assemble`) copied from
/// that row's terms.
fn face_rows_of(
    arena: &[(u32, f64)],
    rows: &[&PointRecipe<'_, ArenaWeights>],
    first: &[u8],
) -> FaceRows {
    let bound = |r: &PointRecipe<'_, ArenaWeights>| match r {
        PointRecipe::Given(w) => w.len(),
        PointRecipe::Combination(terms) => terms.iter().map(|(_, w)| w.len()).sum(),
    };
    let n = rows.len() / 9;
    let mut out = FaceRows {
        offsets: Vec::with_capacity(rows.len() + 1),
        terms: Vec::with_capacity(rows.iter().map(|r| bound(r)).sum()),
    };
    out.offsets.push(0);
    for (r, row) in rows.iter().enumerate() {
        let again = match row {
            _ if first[r] as usize != r => Some(first[r] as usize),
            // `f_minus` (rows `4 n..5 n`) equal to the same corner's `f_plus`.
            PointRecipe::Combination(_) if (4 * n..5 * n).contains(&r) => {
                same_combination(row, rows[r - n]).then_some(r - n)
            }
            _ => None,
        };
        match (again, row) {
            (Some(j), _) => {
                let (a, b) = (out.offsets[j] as usize, out.offsets[j + 1] as usize);
                out.terms.extend_from_within(a..b);
            }
            (None, PointRecipe::Given(w)) => out.terms.extend_from_slice(w.get(arena)),
            (None, PointRecipe::Combination(terms)) => {
                merge_terms_into(&terms.map(|(c, w)| (c, w.get(arena))), &mut out.terms)
            }
        }
        out.offsets.push(out.terms.len() as u32);
    }
    out
}

/// Whether `a` and `b` are combinations of the very same weight vectors with bitwise equal
/// coefficients (hence equal terms).
fn same_combination(a: &PointRecipe<'_, ArenaWeights>, b: &PointRecipe<'_, ArenaWeights>) -> bool {
    match (a, b) {
        (PointRecipe::Combination(x), PointRecipe::Combination(y)) => x
            .iter()
            .zip(y)
            .all(|((c, v), (d, w))| c.to_bits() == d.to_bits() && std::ptr::eq(*v, *w)),
        _ => false,
    }
}

/// The rows of each face of `faces` in the table layout ([`StencilType::weights`]: control
/// points, then the neighbours' edge and face points) as sparse weight vectors over `topo`'s
/// vertices, ascending ids, f64: the weights [`GregoryStencilTable::build`] rounds to f32, without
/// its ring-size limit (sparse rows have no fixed patch size). Built for adaptive end caps
/// ([`Coverage::EndCap`]) in two stages: a corner's limit point and edge points are
/// combinations of its derived points (smooth, dart and crease corners: ids from
/// [`vertex_point_id`], rows [`vertex_point_rows`]) and `O(1)` ring points, so each row holds
/// `O(1)` terms per corner and the rows of all faces around a vertex of valence `n` `O(n)`
/// together, not `O(n²)`. Face by face, the reference of
/// [`super::shared_rows::sparse_face_rows`], which shares the work between faces of one
/// connectivity type and gives the same bits. Dart masks from `darts`.
pub fn sparse_face_rows_direct(
    topo: &Topology,
    faces: &[u32],
    tangents: GregoryTangents,
    darts: &DartLimits,
) -> Vec<Result<Vec<Weights>, NotGregory>> {
    sparse_face_rows_direct_with(topo, faces, tangents, darts, None)
        .into_iter()
        .map(|r| r.map(|r| r.to_weights()))
        .collect()
}

/// [`sparse_face_rows_direct`], each face's rows in one [`FaceRows`] (sized from the rows,
/// which are not copied before), with whether each vertex has data known where `known` says (per vertex 0
/// or 1, 2 for not known: the end-cap keys' answers of `has_vertex_data`, asked again here
/// otherwise).
pub(super) fn sparse_face_rows_direct_with(
    topo: &Topology,
    faces: &[u32],
    tangents: GregoryTangents,
    darts: &DartLimits,
    known: Option<&[u8]>,
) -> Vec<Result<FaceRows, NotGregory>> {
    let mut corners = EndCapCorners::new(topo, tangents, darts, known);
    faces
        .iter()
        .map(|&f| {
            corners.build(topo.face_vertices(f));
            // Every corner data the rows read built first, then read all at once: per edge the
            // neighbour face and its corner the edge starts at, where it has a patch.
            let mut sides = [None; 4];
            for (k, side) in sides.iter_mut().enumerate().take(topo.face_size(f)) {
                *side = edge_neighbour(topo, f, k).filter(|&(g, k2)| corners.prepare_side(g, k2));
            }
            let corners = &corners;
            let own = gregory_patch_recipes(topo, f, Coverage::EndCap, |v| corners.vertex(v))?;
            let theirs = |k: usize| sides[k].and_then(|(g, k2)| corners.side_points(g, k2));
            Ok(table_rows_into(&own, theirs, |rows, first| {
                face_rows_of(&corners.arena, rows, first)
            }))
        })
        .collect()
}

pub use super::corner_types::{vertex_point_id, vertex_point_of, VERTEX_POINTS};

/// The first-stage rows of vertex `v` over `topo`'s vertices: its
/// [`GregoryVertex::vertex_points`] in weight space (empty rows where it has none: corners,
/// cones, a crease's unused points).
pub fn vertex_point_rows(topo: &Topology, v: u32, tangents: GregoryTangents) -> [Weights; 3] {
    vertex_point_rows_with(topo, v, &|u| u, tangents, &DartLimits::new())
}

/// [`vertex_point_rows`] with vertex `u` standing for `unit(id(u))`, dart masks from `darts`.
pub fn vertex_point_rows_with(
    topo: &Topology,
    v: u32,
    id: &impl Fn(u32) -> u32,
    tangents: GregoryTangents,
    darts: &DartLimits,
) -> [Weights; 3] {
    let ring = vertex_ring_of_units(topo, v, id);
    GregoryVertex::vertex_points(&ring, tangents, darts).unwrap_or_default()
}

/// The Gregory patch in weight space of every face of `faces` and of their edge neighbours
/// (what [`table_rows`] reads), each built once: around an extraordinary vertex the faces are
/// one another's neighbours.
fn face_patches(
    topo: &Topology,
    faces: &[u32],
    tangents: GregoryTangents,
    coverage: Coverage,
    darts: &DartLimits,
) -> WordHashMap<u32, Result<GregoryPatch<Weights>, NotGregory>> {
    let vertices = corner_data(topo, faces.iter().copied(), tangents, coverage, darts);
    let mut patches = WordHashMap::default();
    for &f in faces {
        for g in std::iter::once(f).chain(
            topo.face_edges(f)
                .iter()
                .flat_map(|&e| topo.edge_faces(e).iter().copied()),
        ) {
            patches
                .entry(g)
                .or_insert_with(|| gregory_patch_for(topo, &vertices, g, coverage));
        }
    }
    patches
}

impl GregoryStencilTable {
    /// [`Self::build`] for every face of `faces` with the full [`MAX_RING`] ring limit (regular
    /// faces may be included: their Gregory patch reproduces the B-spline patch).
    pub fn new(topo: &Topology, faces: impl IntoIterator<Item = u32>) -> GregoryStencilTable {
        let faces: Vec<u32> = faces.into_iter().collect();
        Self::build(topo, &faces, MAX_RING)
    }

    /// Builds the stencils of `faces`. Faces whose ring exceeds `max_ring` (at most
    /// [`MAX_RING`]; pass the device's `maxTessellationPatchSize`) or that get no Gregory patch
    /// ([`super::check_face`]) are listed in `skipped`.
    pub fn build(topo: &Topology, faces: &[u32], max_ring: usize) -> GregoryStencilTable {
        Self::build_with(topo, faces, max_ring, GregoryTangents::default())
    }

    /// [`Self::build`] with the given edge-tangent lengths.
    pub fn build_with(
        topo: &Topology,
        faces: &[u32],
        max_ring: usize,
        tangents: GregoryTangents,
    ) -> GregoryStencilTable {
        let mut table = GregoryStencilTable::default();
        let mut accepted = Vec::with_capacity(faces.len());
        for &f in faces {
            match stencil_ring(topo, f, max_ring) {
                Ok(ring) => accepted.push((f, ring)),
                Err(e) => table.skipped.push(e),
            }
        }
        let faces: Vec<u32> = accepted.iter().map(|(f, _)| *f).collect();
        let darts = DartLimits::new();
        let patches = face_patches(topo, &faces, tangents, Coverage::Exact, &darts);
        let mut types = HashMap::new();
        for (f, ring) in accepted {
            match table_rows(topo, f, |g| patches[&g].as_ref().map_err(|e| *e)) {
                Ok(rows) => table.push(topo, f, ring, &rows, &mut types),
                Err(e) => table.skipped.push(NoStencil::NotGregory(e)),
            }
        }
        table
    }

    /// Adds face `f` with its canonical `ring` and its `rows` (weights over control vertices),
    /// sharing the type of an earlier face with bitwise equal f32 weights (`types`: weights key
    /// to type id).
    fn push(
        &mut self,
        topo: &Topology,
        f: u32,
        ring: Vec<u32>,
        rows: &[Weights],
        types: &mut HashMap<(bool, Vec<u32>), u32>,
    ) {
        let fv = topo.face_vertices(f);
        let triangle = fv.len() == 3;
        debug_assert_eq!(
            rows.len(),
            if triangle {
                TRI_POINTS + TRI_EXTRA
            } else {
                QUAD_POINTS + QUAD_EXTRA
            }
        );
        let l = ring.len();
        let mut order: Vec<u8> = (0..l as u8).collect();
        order.sort_unstable_by_key(|&k| ring[k as usize]);
        let sorted: Vec<u32> = order.iter().map(|&k| ring[k as usize]).collect();
        // Columns from ascending id back to the canonical slots; zero weights stored as +0.0 so
        // the type key does not depend on the sign of a cancelled weight.
        let mut w = vec![0f32; rows.len() * l];
        for (r, row) in dense_rows(rows, &sorted).chunks(l).enumerate() {
            for (&k, &x) in order.iter().zip(row) {
                if x != 0.0 {
                    w[r * l + k as usize] = x as f32;
                }
            }
        }
        let key = (triangle, w.iter().map(|x| x.to_bits()).collect::<Vec<_>>());
        let next = self.types.len() as u32;
        let type_id = *types.entry(key).or_insert(next);
        if type_id == next {
            let masks = w
                .chunks(l)
                .map(|row| {
                    row.iter()
                        .enumerate()
                        .filter(|(_, x)| **x != 0.0)
                        .fold(0u32, |m, (k, _)| m | (1 << k))
                })
                .collect();
            self.types.push(StencilType {
                triangle,
                ring_len: l,
                weights: w,
                masks,
            });
        }
        let mut corners = [fv[0]; 4];
        corners[..fv.len()].copy_from_slice(fv);
        self.patches.push(StencilPatch {
            face: f,
            corners,
            triangle,
            ring,
            order,
            type_id,
        });
    }

    /// The nonzero terms `(weight, vertex)` of row `row` of `patch`, in summation order
    /// (ascending global vertex id), as the TCS runs them.
    fn terms<'a>(
        &'a self,
        patch: &'a StencilPatch,
        row: usize,
    ) -> impl Iterator<Item = (f32, u32)> + 'a {
        let t = &self.types[patch.type_id as usize];
        let w = &t.weights[row * t.ring_len..(row + 1) * t.ring_len];
        patch
            .order
            .iter()
            .map(move |&k| (w[k as usize], patch.ring[k as usize]))
            .filter(|(w, _)| *w != 0.0)
    }

    /// Every row of patch `i` from the f32 stencil, summed as the TCS does (ascending global
    /// vertex id, zero weights skipped) but in f64.
    pub fn eval_points(&self, i: usize, positions: &[DVec3]) -> Vec<DVec3> {
        let p = &self.patches[i];
        let t = &self.types[p.type_id as usize];
        (0..t.weights.len() / t.ring_len)
            .map(|row| {
                self.terms(p, row)
                    .map(|(w, v)| f64::from(w) * positions[v as usize])
                    .sum()
            })
            .collect()
    }

    /// Control point `point` of `patch` ([`StencilType::point_row`]) computed as the GPU does:
    /// f32 products summed in the patch's global order, skipping zero weights, without fused
    /// multiply-add.
    pub fn eval_f32(&self, patch: &StencilPatch, point: usize, positions: &[[f32; 3]]) -> [f32; 3] {
        let row = self.types[patch.type_id as usize].point_row(point);
        let mut acc = [0f32; 3];
        for (w, v) in self.terms(patch, row) {
            let x = positions[v as usize];
            for c in 0..3 {
                acc[c] += w * x[c];
            }
        }
        acc
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{ControlMesh, ControlMeshDesc};
    use crate::patch::gregory::{gregory_faces, gregory_patch_at};

    /// The rows of face `f` built directly from positions (what the stencil reproduces).
    fn control_points(topo: &Topology, positions: &[DVec3], f: u32) -> Vec<DVec3> {
        table_rows(topo, f, |g| gregory_patch_at(topo, positions, g)).unwrap()
    }

    /// A closed mixed mesh: a triangular prism with one end capped by a fan of triangles (so
    /// valences 3, 4, 5 and tri/quad rings) and a slightly irregular shape.
    fn prism() -> ControlMesh {
        let positions = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.1, 0.0),
            DVec3::new(0.4, 0.9, 0.1),
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(1.1, 0.0, 1.2),
            DVec3::new(0.5, 1.0, 1.0),
            DVec3::new(0.5, 0.35, -0.4),
        ];
        let face_vertices = vec![
            3, 4, 5, // top
            0, 1, 4, 3, 1, 2, 5, 4, 2, 0, 3, 5, // sides
            1, 0, 6, 2, 1, 6, 0, 2, 6, // bottom fan
        ];
        ControlMesh::new(ControlMeshDesc {
            positions,
            face_sizes: vec![3, 4, 4, 4, 3, 3, 3],
            face_vertices,
            ..Default::default()
        })
        .unwrap()
    }

    #[test]
    fn stencil_reproduces_the_direct_construction() {
        let mesh = prism();
        let topo = Topology::new(&mesh).unwrap();
        let faces = gregory_faces(&topo);
        assert_eq!(faces.len(), 7);
        let table = GregoryStencilTable::build(&topo, &faces, MAX_RING);
        assert!(table.skipped.is_empty(), "{:?}", table.skipped);
        let pos = mesh.positions();
        for (i, p) in table.patches.iter().enumerate() {
            let direct = control_points(&topo, pos, p.face);
            let from_stencil = table.eval_points(i, pos);
            for (a, b) in direct.iter().zip(&from_stencil) {
                // f32 weights: relative rounding ~6e-8 of coordinates of size ~1.
                assert!((*a - *b).length() < 1e-6, "face {}: {a} vs {b}", p.face);
            }
            // Affine: the weights of every row sum to 1 (up to f32 rounding).
            let t = &table.types[p.type_id as usize];
            for row in t.weights.chunks(t.ring_len) {
                let s: f64 = row.iter().map(|&x| f64::from(x)).sum();
                assert!((s - 1.0).abs() < 1e-6, "face {}: row sum {s}", p.face);
            }
        }
    }

    #[test]
    fn ring_is_sorted_and_masks_match_weights() {
        let mesh = prism();
        let topo = Topology::new(&mesh).unwrap();
        let table = GregoryStencilTable::build(&topo, &gregory_faces(&topo), MAX_RING);
        for p in &table.patches {
            let sorted: Vec<u32> = p.order.iter().map(|&k| p.ring[k as usize]).collect();
            assert!(sorted.windows(2).all(|w| w[0] < w[1]));
            assert_eq!(sorted.len(), p.ring.len());
            let t = &table.types[p.type_id as usize];
            for (row, m) in t.weights.chunks(t.ring_len).zip(&t.masks) {
                for (k, w) in row.iter().enumerate() {
                    assert_eq!(*w != 0.0, m & (1 << k) != 0);
                }
            }
        }
    }

    /// Nonzero weights of row `row` of patch `p` as (vertex id, f32 bits) in the summation order.
    fn row_by_id(t: &GregoryStencilTable, p: &StencilPatch, row: usize) -> Vec<(u32, u32)> {
        let ty = &t.types[p.type_id as usize];
        let w = &ty.weights[row * ty.ring_len..(row + 1) * ty.ring_len];
        p.order
            .iter()
            .map(|&k| (p.ring[k as usize], w[k as usize]))
            .filter(|(_, w)| *w != 0.0)
            .map(|(v, w)| (v, w.to_bits()))
            .collect()
    }

    #[test]
    fn shared_rows_are_bitwise_equal_on_both_sides_of_every_edge() {
        let mesh = prism();
        let topo = Topology::new(&mesh).unwrap();
        let t = GregoryStencilTable::build(&topo, &gregory_faces(&topo), MAX_RING);
        let by_face: HashMap<u32, &StencilPatch> = t.patches.iter().map(|p| (p.face, p)).collect();
        let mut checked = 0;
        for a in &t.patches {
            let c = topo.face_vertices(a.face);
            let n = c.len();
            for k in 0..n {
                let (x, y) = (c[k], c[(k + 1) % n]);
                let e = topo.find_edge(x, y).unwrap();
                let g = *topo.edge_faces(e).iter().find(|&&g| g != a.face).unwrap();
                let b = by_face[&g];
                let d = topo.face_vertices(g);
                let m = d.len();
                let k2 = (0..m).find(|&i| d[i] == y && d[(i + 1) % m] == x).unwrap();
                let k2n = (k2 + 1) % m;
                let pairs = [
                    (k, k2n),                        // p at x
                    ((k + 1) % n, k2),               // p at y
                    (n + k, 2 * m + k2n),            // e_plus[k] == e_minus[k2+1]
                    (2 * n + (k + 1) % n, m + k2),   // e_minus[k+1] == e_plus[k2]
                    (5 * n + 2 * k, m + k2n),        // other edge point at x == e_plus[k2+1]
                    (5 * n + 2 * k + 1, 2 * m + k2), // other edge point at y == e_minus[k2]
                    (7 * n + 2 * k, 4 * m + k2n),    // neighbour face point at x == f_minus[k2+1]
                    (7 * n + 2 * k + 1, 3 * m + k2), // neighbour face point at y == f_plus[k2]
                ];
                for (ra, rb) in pairs {
                    assert_eq!(
                        row_by_id(&t, a, ra),
                        row_by_id(&t, b, rb),
                        "faces {} / {g}: rows {ra} / {rb}",
                        a.face
                    );
                    checked += 1;
                }
            }
        }
        assert_eq!(checked, 8 * (3 + 3 * 4 + 3 * 3));
    }

    #[test]
    fn faces_with_the_same_connectivity_share_one_type() {
        // A cube: every face has four valence-3 corners in an all-quad ring, so one type.
        let positions = (0..8)
            .map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, (i >> 2) as f64 * 1.3))
            .collect();
        let face_vertices = vec![
            0, 2, 3, 1, 4, 5, 7, 6, 0, 1, 5, 4, 2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5,
        ];
        let mesh = ControlMesh::new(ControlMeshDesc {
            positions,
            face_sizes: vec![4; 6],
            face_vertices,
            ..Default::default()
        })
        .unwrap();
        let topo = Topology::new(&mesh).unwrap();
        let t = GregoryStencilTable::build(&topo, &gregory_faces(&topo), MAX_RING);
        assert_eq!(t.patches.len(), 6);
        assert_eq!(t.types.len(), 1);
        for (i, p) in t.patches.iter().enumerate() {
            let direct = control_points(&topo, mesh.positions(), p.face);
            for (a, b) in direct.iter().zip(&t.eval_points(i, mesh.positions())) {
                assert!((*a - *b).length() < 1e-6);
            }
        }
    }

    #[test]
    fn small_patch_limit_rejects_with_a_message() {
        let mesh = prism();
        let topo = Topology::new(&mesh).unwrap();
        let table = GregoryStencilTable::build(&topo, &gregory_faces(&topo), 4);
        assert!(table.patches.is_empty());
        assert_eq!(table.skipped.len(), 7);
        assert!(table.skipped[0]
            .to_string()
            .contains("exceeds the 4-vertex patch limit"));
    }
}
