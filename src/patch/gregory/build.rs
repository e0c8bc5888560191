//! Gregory patches from a mesh's topology (paper §3, one patch per face; §4.6 boundaries and
//! infinitely sharp creases), and which faces the construction covers.

use super::eval::{CornerRef, GregoryQuad, GregoryTriangle, PointRecipe};
use super::point::{combine, GregoryPoint, Weights};
use super::tangents::GregoryTangents;
use super::vertex::{
    has_construction, sectors, DartLimits, GregoryVertex, Rule, Sector, SharpEdges, VertexRing,
};
use crate::mesh::INFINITE_SHARPNESS;
use crate::patch::regular::RegularPatch;
use crate::topology::Topology;
use glam::DVec3;
use std::fmt;

/// One Gregory patch, the shape following the face.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GregoryPatch<P = DVec3> {
    /// A quad face.
    Quad(GregoryQuad<P>),
    /// A triangle.
    Triangle(GregoryTriangle<P>),
}

impl GregoryPatch {
    /// The patch's own normal at corner `k`: the Bézier net's corner derivatives, else the face
    /// points (the CPU side of `gregory_corner_normal` in `glsl/gregory/gregory.glsl`).
    pub fn corner_normal(&self, k: usize) -> DVec3 {
        match self {
            GregoryPatch::Quad(q) => super::eval::corner_normal(
                q.p[k],
                q.e_plus[k],
                q.e_minus[k],
                q.f_plus[k],
                q.f_minus[k],
            ),
            GregoryPatch::Triangle(t) => super::eval::corner_normal(
                t.p[k],
                t.e_plus[k],
                t.e_minus[k],
                t.f_plus[k],
                t.f_minus[k],
            ),
        }
    }
}

/// Why a face gets no Gregory patch (the renderer keeps its exact CPU path for it).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NotGregory {
    /// A hole, or a face without limit surface.
    NoSurface { face: u32 },
    /// Neither a triangle nor a quad.
    Polygon { face: u32, size: usize },
    /// A corner vertex touches a semi-sharp edge or has finite non-zero sharpness (not covered
    /// by the paper).
    SemiSharp { face: u32, vertex: u32 },
    /// A corner vertex has exactly one infinitely sharp edge (a dart; not covered by the paper,
    /// refused by the level-0 schemes only, [`check_face_level0`]).
    Dart { face: u32, vertex: u32 },
    /// An infinitely sharp vertex with fewer than two sharp edges (a cone point; adaptive end
    /// caps approximate it, [`Coverage::EndCap`]).
    Cusp { face: u32, vertex: u32 },
    /// A corner vertex is a dart whose limit masks (left eigenvectors of its subdivision
    /// matrix, `dart_limit`) missed their eigen-equation's tolerance; not seen at valences 3
    /// to 128 and 1000.
    DartLimit {
        face: u32,
        vertex: u32,
        valence: usize,
    },
    /// The face lies alone between two sharp edges of a crease vertex (crease sector of one
    /// face, e.g. a valence-2 boundary vertex with `EdgeOnly` interpolation). The crease rule
    /// gives the patch collinear edge tangents there (the exact tangent plane comes from a
    /// second-order term of the subdivision matrix's Jordan block), so the patch normal at that
    /// corner is undefined. (The paper's §4.6 sets `p = v` for any one-face vertex, which is the
    /// `EdgeAndCorner` surface, not the `EdgeOnly` one.) Adaptive end caps take it with face
    /// points in the exact tangent plane ([`Coverage::EndCap`]).
    OneFaceCreaseSector { face: u32, vertex: u32 },
    /// The face lies in a sector of more than two faces at a corner vertex: the exact surface
    /// there has no tangent plane spanned by the two sharp curves (its leading interior mode
    /// dominates), which the corner construction of §4.6 assumes (adaptive end caps
    /// approximate it, [`Coverage::EndCap`]).
    WideCornerSector { face: u32, vertex: u32 },
}

impl NotGregory {
    /// The face without Gregory patch.
    pub fn face(&self) -> u32 {
        match *self {
            NotGregory::NoSurface { face }
            | NotGregory::Polygon { face, .. }
            | NotGregory::SemiSharp { face, .. }
            | NotGregory::Dart { face, .. }
            | NotGregory::Cusp { face, .. }
            | NotGregory::DartLimit { face, .. }
            | NotGregory::OneFaceCreaseSector { face, .. }
            | NotGregory::WideCornerSector { face, .. } => face,
        }
    }
}

impl fmt::Display for NotGregory {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            NotGregory::NoSurface { face } => write!(f, "face {face}: hole or no limit surface"),
            NotGregory::Polygon { face, size } => write!(
                f,
                "face {face} has {size} vertices: Gregory patches exist for triangles and quads only"
            ),
            NotGregory::SemiSharp { face, vertex } => write!(
                f,
                "face {face}: vertex {vertex} has semi-sharp tags, not covered by the Gregory construction"
            ),
            NotGregory::Dart { face, vertex } => write!(
                f,
                "face {face}: vertex {vertex} is a dart (one sharp edge), not covered by the Gregory construction"
            ),
            NotGregory::Cusp { face, vertex } => write!(
                f,
                "face {face}: vertex {vertex} is a sharp vertex with fewer than two sharp edges"
            ),
            NotGregory::DartLimit {
                face,
                vertex,
                valence,
            } => write!(
                f,
                "face {face}: vertex {vertex} is a dart of valence {valence} whose limit masks \
                 (eigenvectors of its subdivision matrix) did not solve to tolerance"
            ),
            NotGregory::WideCornerSector { face, vertex } => write!(
                f,
                "face {face}: in a corner sector of more than two faces at vertex {vertex}, not covered by the Gregory construction"
            ),
            NotGregory::OneFaceCreaseSector { face, vertex } => write!(
                f,
                "face {face}: alone in a crease sector of vertex {vertex}, not covered by the Gregory construction"
            ),
        }
    }
}

impl std::error::Error for NotGregory {}

fn is_inf(s: f32) -> bool {
    s >= INFINITE_SHARPNESS
}

/// A semi-sharp (finite, nonzero) sharpness.
fn is_semi(s: f32) -> bool {
    s > 0.0 && !is_inf(s)
}

/// Per incident edge of `v`: infinitely sharp (boundary edges are, after the boundary rule).
fn sharp_edges(topo: &Topology, v: u32) -> Vec<bool> {
    topo.vertex_edges(v)
        .iter()
        .map(|&e| is_inf(topo.edge_sharpness(e)))
        .collect()
}

/// Which faces the construction takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Coverage {
    /// Faces whose corners the construction interpolates exactly (limit position and tangent
    /// plane): what the level-0 Gregory schemes draw ([`check_face`]).
    Exact,
    /// Adaptive end caps ([`check_face_for`]): also cone points, crease sectors of one
    /// face and corner sectors of more than two faces, where the end cap's corner is the
    /// exact limit point but its tangents are approximations ([`GregoryVertex::cone`],
    /// [`GregoryVertex::sectored`]) whose area shrinks by four per isolation level.
    EndCap,
}

/// Whether the construction covers vertex `v` as a corner of face `f` (`Ok`) or why not.
pub fn check_vertex(topo: &Topology, v: u32, f: u32) -> Result<(), NotGregory> {
    check_vertex_for(topo, v, f, Coverage::Exact)
}

/// [`check_vertex`] for the given coverage.
pub fn check_vertex_for(
    topo: &Topology,
    v: u32,
    f: u32,
    coverage: Coverage,
) -> Result<(), NotGregory> {
    if touches_semi_sharpness(topo, v) {
        return Err(NotGregory::SemiSharp { face: f, vertex: v });
    }
    if coverage == Coverage::EndCap {
        return Ok(());
    }
    let sharp = sharp_edges(topo, v);
    let count = sharp.iter().filter(|&&s| s).count();
    let corner = ring_corner_tag(topo, v, &sharp);
    if corner && count < 2 {
        return Err(NotGregory::Cusp { face: f, vertex: v });
    }
    if corner
        && sectors(&sharp, topo.vertex_faces(v).len())
            .iter()
            .any(|s| s.faces > 2 && in_sector(s, j_of(topo, v, f), sharp.len()))
    {
        return Err(NotGregory::WideCornerSector { face: f, vertex: v });
    }
    if one_face_crease_sector(topo, v, f) {
        return Err(NotGregory::OneFaceCreaseSector { face: f, vertex: v });
    }
    Ok(())
}

/// Whether vertex `v` or one of its edges has a semi-sharp (finite, nonzero) sharpness: the
/// first test of [`check_vertex_for`], the only one with [`Coverage::EndCap`], which reads the
/// vertex alone, not the face.
fn touches_semi_sharpness(topo: &Topology, v: u32) -> bool {
    is_semi(topo.vertex_sharpness(v))
        || topo
            .vertex_edges(v)
            .iter()
            .any(|&e| is_semi(topo.edge_sharpness(e)))
}

/// Whether face `f` lies alone in a sector of crease vertex `v` (two infinitely sharp edges,
/// crease rule), where the end cap's corner tangents are collinear
/// ([`GregoryVertex::sectored`]).
pub fn one_face_crease_sector(topo: &Topology, v: u32, f: u32) -> bool {
    let count = topo
        .vertex_edges(v)
        .iter()
        .filter(|&&e| is_inf(topo.edge_sharpness(e)))
        .count();
    if count != 2 || is_inf(topo.vertex_sharpness(v)) {
        return false;
    }
    let sharp = sharp_edges(topo, v);
    let j = j_of(topo, v, f);
    let nf = topo.vertex_faces(v).len();
    sectors(&sharp, nf)
        .iter()
        .any(|s| s.faces == 1 && s.start == j)
}

/// Index of face `f` in the ring of `v` (0 if absent).
fn j_of(topo: &Topology, v: u32, f: u32) -> usize {
    topo.vertex_faces(v)
        .iter()
        .position(|&g| g == f)
        .unwrap_or(0)
}

/// Whether ring face `j` lies in sector `s` of a ring with `ne` edges.
fn in_sector(s: &Sector, j: usize, ne: usize) -> bool {
    (j + ne - s.start) % ne < s.faces
}

/// Whether face `f` gets a Gregory patch (`Ok`) or why not.
pub fn check_face(topo: &Topology, f: u32) -> Result<(), NotGregory> {
    check_face_for(topo, f, Coverage::Exact)
}

/// [`check_face`] for the given coverage.
pub fn check_face_for(topo: &Topology, f: u32, coverage: Coverage) -> Result<(), NotGregory> {
    check_face_shape(topo, f)?;
    topo.face_vertices(f)
        .iter()
        .try_for_each(|&v| check_vertex_for(topo, v, f, coverage))
}

/// [`check_face_for`]'s tests of the face itself, before its corners': a limit surface, three
/// or four corners.
pub(super) fn check_face_shape(topo: &Topology, f: u32) -> Result<(), NotGregory> {
    if !topo.has_limit_surface(f) {
        return Err(NotGregory::NoSurface { face: f });
    }
    let fv = topo.face_vertices(f);
    if fv.len() != 3 && fv.len() != 4 {
        return Err(NotGregory::Polygon {
            face: f,
            size: fv.len(),
        });
    }
    Ok(())
}

/// Whether face `f` passes [`check_face_for`] with [`Coverage::EndCap`] and every corner has
/// data (`has_data(v)`: [`has_vertex_data`]), i.e. gets an end-cap patch: a corner with data
/// is covered, so passes the end-cap corner test, which reads the vertex alone
/// ([`vertex_covered`]); only the face's own tests remain.
pub(super) fn end_cap_patch_with(
    topo: &Topology,
    f: u32,
    has_data: impl FnMut(&u32) -> bool,
) -> bool {
    check_face_shape(topo, f).is_ok() && topo.face_vertices(f).iter().all(has_data)
}

/// [`check_face`] for the level-0 Gregory schemes (`gregory-stencil`, `gregory-vs`), which also
/// refuse faces with a dart corner: the dart construction ([`GregoryVertex::dart`], used by the
/// adaptive scheme's end caps) has no GLSL port in the two-stage variant, and the level-0
/// schemes keep such faces on their exact CPU path.
pub fn check_face_level0(topo: &Topology, f: u32) -> Result<(), NotGregory> {
    check_face(topo, f)?;
    match topo.face_vertices(f).iter().find(|&&v| {
        let sharp = sharp_edges(topo, v);
        sharp.iter().filter(|&&s| s).count() == 1 && !is_inf(topo.vertex_sharpness(v))
    }) {
        Some(&vertex) => Err(NotGregory::Dart { face: f, vertex }),
        None => Ok(()),
    }
}

/// Faces a Gregory scheme should draw: with a limit surface, not (boundary-)regular (those are
/// B-spline patches, [`RegularPatch`]), three or four corners. Whether the construction covers
/// them is [`check_face`].
pub fn gregory_faces(topo: &Topology) -> Vec<u32> {
    (0..topo.face_count() as u32)
        .filter(|&f| {
            topo.has_limit_surface(f)
                && matches!(topo.face_size(f), 3 | 4)
                && RegularPatch::gather(topo, f).is_none()
        })
        .collect()
}

/// The split one-ring of vertex `v` (paper Fig. 5) in the topology's ring order, from positions.
pub fn vertex_ring(topo: &Topology, positions: &[DVec3], v: u32) -> VertexRing<DVec3> {
    vertex_ring_with(topo, v, &|i: u32| positions[i as usize])
}

/// Whether the interior construction (§3) applies to vertex `v`: interior, no sharpness on it
/// or its edges. [`check_vertex`] tells whether any construction (§3 or §4.6) applies.
pub fn is_supported_vertex(topo: &Topology, v: u32) -> bool {
    !topo.is_boundary_vertex(v)
        && topo.vertex_sharpness(v) == 0.0
        && topo
            .vertex_edges(v)
            .iter()
            .all(|&e| topo.edge_sharpness(e) == 0.0)
}

/// The split one-ring of vertex `v` (paper Fig. 5) in the topology's ring order, with `point(i)`
/// the "position" of control vertex `i` (a [`DVec3`] or a unit [`Weights`] vector).
pub fn vertex_ring_with<P: GregoryPoint>(
    topo: &Topology,
    v: u32,
    point: &impl Fn(u32) -> P,
) -> VertexRing<P> {
    ring_of_points(
        topo,
        v,
        point(v),
        |pv, o| {
            let mut x = pv.clone();
            x.add_scaled(1.0, &point(o));
            combine(&[(0.5, &x)])
        },
        // A face's corners as points, then their centroid in one combination (`combine`: the
        // same bits as adding them one by one onto zero).
        |fv| {
            let w = 1.0 / fv.len() as f64;
            let corners: Vec<P> = fv.iter().map(|&u| point(u)).collect();
            let terms: Vec<(f64, &P)> = corners.iter().map(|x| (w, x)).collect();
            combine(&terms)
        },
    )
}

/// [`vertex_ring_with`] over unit [`Weights`], vertex `u` standing for `unit(id(u))`, with the
/// same bits: an edge midpoint `0.5 * (unit(v) + 1.0 * unit(o))` holds `0.5 * 1.0` at both
/// ends, a face centroid `1 / n` at each corner ([`Weights::from_terms`]: a repeated id's
/// weights summed in corner order, as `combine` sums them), each point built in one
/// allocation instead of a unit per ring vertex and a merge per point.
pub(super) fn vertex_ring_of_units(
    topo: &Topology,
    v: u32,
    id: &impl Fn(u32) -> u32,
) -> VertexRing<Weights> {
    let iv = id(v);
    ring_of_points(
        topo,
        v,
        Weights::unit(iv),
        |_, o| {
            // `unit(iv) + 1.0 * unit(io)`, then `0.5 *` it.
            let io = id(o);
            Weights(match iv.cmp(&io) {
                std::cmp::Ordering::Less => vec![(iv, 0.5 * 1.0), (io, 0.5 * (1.0 * 1.0))],
                std::cmp::Ordering::Greater => vec![(io, 0.5 * (1.0 * 1.0)), (iv, 0.5 * 1.0)],
                std::cmp::Ordering::Equal => vec![(iv, 0.5 * (1.0 + 1.0 * 1.0))],
            })
        },
        |fv| {
            let w = 1.0 / fv.len() as f64;
            Weights::from_terms(fv.iter().map(|&u| (id(u), w * 1.0)))
        },
    )
}

/// The split one-ring of vertex `v` with point `pv`: each edge's midpoint `midpoint(pv, o)`
/// (`o` the edge's other end) and each face's centroid `centroid(face vertices)` in the
/// topology's ring order, and the topology's part (sharp edges, corner tag, face sizes, far
/// sectors, promoted edges).
fn ring_of_points<P>(
    topo: &Topology,
    v: u32,
    pv: P,
    midpoint: impl Fn(&P, u32) -> P,
    centroid: impl Fn(&[u32]) -> P,
) -> VertexRing<P> {
    let m = topo
        .vertex_edges(v)
        .iter()
        .map(|&e| midpoint(&pv, topo.other_vertex(e, v)))
        .collect();
    let c = topo
        .vertex_faces(v)
        .iter()
        .map(|&f| centroid(topo.face_vertices(f)))
        .collect();
    let sharp = sharp_edges(topo, v);
    let count = sharp.iter().filter(|&&s| s).count();
    let corner = ring_corner_tag(topo, v, &sharp);
    let far_sector = if count == 2 && !corner {
        far_crease_sectors(topo, v, &sharp)
    } else {
        Vec::new()
    };
    VertexRing {
        v: pv,
        m,
        c,
        sharp,
        corner,
        face_sizes: super::tangents_tri::ring_face_sizes(topo, v),
        far_sector,
        promoted: promoted_edges(topo, v),
        decayed_corner: topo.is_decayed_corner(v),
        crease_factors: topo.crease_factors(v),
    }
}

/// [`VertexRing::promoted`] of vertex `v`: per incident edge, whether it is a promoted crease
/// ([`Topology::is_promoted_edge`]); empty where none is.
fn promoted_edges(topo: &Topology, v: u32) -> Vec<bool> {
    let promoted: Vec<bool> = topo
        .vertex_edges(v)
        .iter()
        .map(|&e| topo.is_promoted_edge(e))
        .collect();
    match promoted.contains(&true) {
        true => promoted,
        false => Vec::new(),
    }
}

/// `VertexRing::far_sector` of crease vertex `v` with sharp edges `sharp`: per incident edge,
/// when the edge is smooth and its far end `w` is a crease vertex (two infinitely sharp edges,
/// no corner tag), the faces of `w`'s crease sector the edge lies inside; else 0.
pub fn far_crease_sectors(topo: &Topology, v: u32, sharp: &[bool]) -> Vec<usize> {
    topo.vertex_edges(v)
        .iter()
        .zip(sharp)
        .map(|(&e, &sharp_e)| {
            if sharp_e {
                return 0;
            }
            let w = topo.other_vertex(e, v);
            let w_sharp = sharp_edges(topo, w);
            let count = w_sharp.iter().filter(|&&s| s).count();
            if count != 2 || is_inf(topo.vertex_sharpness(w)) {
                return 0;
            }
            let ne = w_sharp.len();
            let Some(j) = topo.vertex_edges(w).iter().position(|&x| x == e) else {
                return 0;
            };
            sectors(&w_sharp, topo.vertex_faces(w).len())
                .into_iter()
                .find(|s| (1..s.faces).contains(&((j + ne - s.start) % ne)))
                .map_or(0, |s| s.faces)
        })
        .collect()
}

/// Per-vertex Gregory data of vertex `v`, or `None` where no supported face could use it
/// (default edge tangents, [`GregoryTangents::default`]).
pub fn gregory_vertex<P: GregoryPoint>(
    topo: &Topology,
    v: u32,
    point: &impl Fn(u32) -> P,
) -> Option<GregoryVertex<P>> {
    gregory_vertex_with(topo, v, point, GregoryTangents::default())
}

/// [`gregory_vertex`] with the given edge-tangent lengths.
pub fn gregory_vertex_with<P: GregoryPoint>(
    topo: &Topology,
    v: u32,
    point: &impl Fn(u32) -> P,
    tangents: GregoryTangents,
) -> Option<GregoryVertex<P>> {
    gregory_vertex_for(
        topo,
        v,
        point,
        tangents,
        Coverage::Exact,
        &DartLimits::new(),
    )
}

/// [`gregory_vertex_with`] for the given coverage, dart masks from `darts`.
pub fn gregory_vertex_for<P: GregoryPoint>(
    topo: &Topology,
    v: u32,
    point: &impl Fn(u32) -> P,
    tangents: GregoryTangents,
    coverage: Coverage,
    darts: &DartLimits,
) -> Option<GregoryVertex<P>> {
    if !vertex_covered(topo, v, coverage) {
        return None;
    }
    GregoryVertex::new(&vertex_ring_with(topo, v, point), tangents, darts)
}

/// Whether some face of `v` passes [`check_vertex_for`]: the test before per-vertex data.
pub(super) fn vertex_covered(topo: &Topology, v: u32, coverage: Coverage) -> bool {
    let faces = topo.vertex_faces(v);
    match coverage {
        // The end-cap test reads the vertex alone: one answer for every face.
        Coverage::EndCap => !faces.is_empty() && !touches_semi_sharpness(topo, v),
        Coverage::Exact => faces
            .iter()
            .any(|&f| check_vertex_for(topo, v, f, coverage).is_ok()),
    }
}

/// [`gregory_vertex_for`] with the vertex's first stage ([`GregoryVertex::vertex_points`]: a
/// smooth vertex's sums, a dart's limit point and tangents, a crease's sector tangents) given by
/// `points(v)` ([`GregoryVertex::from_vertex_points`]; corners and cones as
/// [`gregory_vertex_for`]): in weight space with `points` the units of derived points, the
/// two-stage form whose patch rows hold `O(1)` terms per corner.
pub fn gregory_vertex_two_stage<P: GregoryPoint>(
    topo: &Topology,
    v: u32,
    point: &impl Fn(u32) -> P,
    tangents: GregoryTangents,
    coverage: Coverage,
    darts: &DartLimits,
    points: &impl Fn(u32) -> [P; 3],
) -> Option<GregoryVertex<P>> {
    two_stage_of_ring(
        topo,
        v,
        || vertex_ring_with(topo, v, point),
        tangents,
        coverage,
        darts,
        points,
    )
}

/// [`gregory_vertex_two_stage`] with the vertex's split ring made by `ring` (only where the
/// vertex is covered).
pub(super) fn two_stage_of_ring<P: GregoryPoint>(
    topo: &Topology,
    v: u32,
    ring: impl FnOnce() -> VertexRing<P>,
    tangents: GregoryTangents,
    coverage: Coverage,
    darts: &DartLimits,
    points: &impl Fn(u32) -> [P; 3],
) -> Option<GregoryVertex<P>> {
    if !vertex_covered(topo, v, coverage) {
        return None;
    }
    GregoryVertex::from_vertex_points(&ring(), tangents, darts, points(v))
}

/// Whether vertex `v`'s split ring takes the interior construction
/// ([`super::is_interior_ring`]), from the topology alone without making the ring: no
/// infinitely sharp edge, no corner tag (without sharp edges, only an infinitely sharp vertex
/// has one), as many faces as edges.
pub(super) fn is_interior_vertex(topo: &Topology, v: u32) -> bool {
    let edges = topo.vertex_edges(v);
    !is_inf(topo.vertex_sharpness(v))
        && topo.vertex_faces(v).len() == edges.len()
        && !edges.iter().any(|&e| is_inf(topo.edge_sharpness(e)))
}

/// A point that is no point: the ring of a vertex built over it carries the topology only.
#[cfg(test)]
#[derive(Clone, Copy)]
pub(super) struct NoPoint;

#[cfg(test)]
impl GregoryPoint for NoPoint {
    fn zero() -> Self {
        NoPoint
    }

    fn add_scaled(&mut self, _: f64, _: &Self) {}
}

/// Whether [`gregory_vertex_for`] (end-cap coverage; [`gregory_vertex_two_stage`] alike) is
/// `Some` at `v`, from the topology alone: the coverage test ([`vertex_covered`]: a face, no
/// semi-sharp vertex or edge), then `vertex::has_construction` of the ring's shape (its edges'
/// sharpness, corner tag and face count; a dart's masks from `darts`, which the construction
/// then reads), both read in one pass over the edges.
pub(super) fn has_vertex_data(topo: &Topology, v: u32, darts: &DartLimits) -> bool {
    let (edges, faces) = (topo.vertex_edges(v), topo.vertex_faces(v).len());
    let vertex = topo.vertex_sharpness(v);
    if faces == 0 || is_semi(vertex) {
        return false;
    }
    // Most vertices are smooth (no sharpness on them or their edges, their faces closing
    // around them): the interior rule, which always has data, without classifying the ring.
    let smooth = |&e: &u32| topo.edge_sharpness(e) == 0.0;
    if vertex == 0.0 && faces == edges.len() && edges.iter().all(smooth) {
        return true;
    }
    let mut semi = false;
    let shape = SharpEdges::of_flags(edges.iter().map(|&e| {
        let s = topo.edge_sharpness(e);
        semi |= is_semi(s);
        is_inf(s)
    }));
    if semi {
        return false;
    }
    has_construction(shape, corner_tag(vertex, shape.sharp), faces, darts)
}

/// The rule [`GregoryVertex::new`] takes at vertex `v`, from the topology alone (its edges'
/// sharpness, corner tag and face count, as [`has_vertex_data`] reads them), and the ring's
/// sharp edges.
#[inline]
pub(super) fn topology_rule(topo: &Topology, v: u32) -> (Rule, SharpEdges) {
    let edges = topo.vertex_edges(v);
    let shape = SharpEdges::of_flags(edges.iter().map(|&e| is_inf(topo.edge_sharpness(e))));
    let corner = corner_tag(topo.vertex_sharpness(v), shape.sharp);
    let rule = Rule::of_shape(shape, corner, topo.vertex_faces(v).len());
    (rule, shape)
}

/// The corner tag of vertex `v`'s ring ([`VertexRing::corner`]), given its edges' sharpness
/// `sharp` ([`sharp_edges`]).
fn ring_corner_tag(topo: &Topology, v: u32, sharp: &[bool]) -> bool {
    corner_tag(
        topo.vertex_sharpness(v),
        sharp.iter().filter(|&&s| s).count(),
    )
}

/// The corner tag of a ring whose vertex has sharpness `vertex` and `sharp` infinitely sharp
/// edges: an infinitely sharp vertex, or more than two sharp edges.
fn corner_tag(vertex: f32, sharp: usize) -> bool {
    is_inf(vertex) || sharp > 2
}

/// Per-vertex Gregory data for every vertex (`None` where the construction does not apply).
pub fn gregory_vertices(topo: &Topology, positions: &[DVec3]) -> Vec<Option<GregoryVertex<DVec3>>> {
    gregory_vertices_with(topo, positions, GregoryTangents::default())
}

/// [`gregory_vertices`] with the given edge-tangent lengths.
pub fn gregory_vertices_with(
    topo: &Topology,
    positions: &[DVec3],
    tangents: GregoryTangents,
) -> Vec<Option<GregoryVertex<DVec3>>> {
    let point = |i: u32| positions[i as usize];
    let darts = DartLimits::new();
    (0..topo.vertex_count() as u32)
        .map(|v| gregory_vertex_for(topo, v, &point, tangents, Coverage::Exact, &darts))
        .collect()
}

/// The Gregory patch of face `f`, from per-vertex data made by [`gregory_vertices`] (or any
/// point type). Errors name the face and the reason when the face gets no Gregory patch.
pub fn gregory_patch<P: GregoryPoint>(
    topo: &Topology,
    vertices: &[Option<GregoryVertex<P>>],
    f: u32,
) -> Result<GregoryPatch<P>, NotGregory> {
    gregory_patch_for(topo, vertices, f, Coverage::Exact)
}

/// [`gregory_patch`] for the given coverage (`vertices` built with the same).
pub fn gregory_patch_for<P: GregoryPoint>(
    topo: &Topology,
    vertices: &[Option<GregoryVertex<P>>],
    f: u32,
    coverage: Coverage,
) -> Result<GregoryPatch<P>, NotGregory> {
    gregory_patch_from(topo, f, coverage, |v| vertices[v as usize].as_ref())
}

/// [`gregory_patch_for`] with each corner's data from `vertex` (`None`: none).
pub(super) fn gregory_patch_from<'a, P: GregoryPoint + 'a>(
    topo: &Topology,
    f: u32,
    coverage: Coverage,
    vertex: impl Fn(u32) -> Option<&'a GregoryVertex<P>>,
) -> Result<GregoryPatch<P>, NotGregory> {
    check_face_for(topo, f, coverage)?;
    assemble_face(topo, f, |_, v| vertex(v))
}

/// [`gregory_patch_from`] with the points not formed: the corners' points by reference, the
/// face points as their terms.
pub(super) fn gregory_patch_recipes<'a, P: 'a>(
    topo: &Topology,
    f: u32,
    coverage: Coverage,
    vertex: impl Fn(u32) -> Option<&'a GregoryVertex<P>>,
) -> Result<GregoryPatch<PointRecipe<'a, P>>, NotGregory> {
    check_face_for(topo, f, coverage)?;
    assemble_face_recipes(topo, f, |_, v| vertex(v))
}

/// Why corner `v` of checked face `f` has no vertex data: a dart without limit masks
/// ([`NotGregory::DartLimit`]), else (not reached) [`NotGregory::Cusp`].
fn no_vertex_data(topo: &Topology, f: u32, v: u32) -> NotGregory {
    let sharp = sharp_edges(topo, v);
    let faces = topo.vertex_faces(v).len();
    let dart = sharp.iter().filter(|&&s| s).count() == 1
        && !is_inf(topo.vertex_sharpness(v))
        && faces == sharp.len();
    if dart {
        NotGregory::DartLimit {
            face: f,
            vertex: v,
            valence: faces,
        }
    } else {
        NotGregory::Cusp { face: f, vertex: v }
    }
}

/// Builds the patch of a checked face from its corners' data (`get(k, v)` for corner `k`).
fn assemble_face<'a, P: GregoryPoint + 'a>(
    topo: &Topology,
    f: u32,
    get: impl Fn(usize, u32) -> Option<&'a GregoryVertex<P>>,
) -> Result<GregoryPatch<P>, NotGregory> {
    Ok(match assemble_face_recipes(topo, f, get)? {
        GregoryPatch::Quad(q) => GregoryPatch::Quad(q.formed()),
        GregoryPatch::Triangle(t) => GregoryPatch::Triangle(t.formed()),
    })
}

/// [`assemble_face`] with the points not formed.
fn assemble_face_recipes<'a, P: 'a>(
    topo: &Topology,
    f: u32,
    get: impl Fn(usize, u32) -> Option<&'a GregoryVertex<P>>,
) -> Result<GregoryPatch<PointRecipe<'a, P>>, NotGregory> {
    let fv = topo.face_vertices(f);
    let mut refs = Vec::with_capacity(fv.len());
    for (k, &v) in fv.iter().enumerate() {
        // The face passed check_face, so its corners have data but for a dart whose masks did
        // not solve (`dart_limit`); stay total anyway.
        let vertex = get(k, v).ok_or_else(|| no_vertex_data(topo, f, v))?;
        let j = topo
            .vertex_faces(v)
            .iter()
            .position(|&g| g == f)
            .ok_or(NotGregory::NoSurface { face: f })?;
        refs.push(CornerRef { vertex, j });
    }
    Ok(match refs.len() {
        3 => GregoryPatch::Triangle(GregoryTriangle::recipes(&[refs[0], refs[1], refs[2]])),
        _ => GregoryPatch::Quad(GregoryQuad::recipes(&[refs[0], refs[1], refs[2], refs[3]])),
    })
}

/// The Gregory patch of face `f` built directly from positions (only the face's corners are
/// processed).
pub fn gregory_patch_at(
    topo: &Topology,
    positions: &[DVec3],
    f: u32,
) -> Result<GregoryPatch<DVec3>, NotGregory> {
    gregory_patch_at_with(topo, positions, f, GregoryTangents::default())
}

/// [`gregory_patch_at`] with the given edge-tangent lengths.
pub fn gregory_patch_at_with(
    topo: &Topology,
    positions: &[DVec3],
    f: u32,
    tangents: GregoryTangents,
) -> Result<GregoryPatch<DVec3>, NotGregory> {
    gregory_patch_at_for(
        topo,
        positions,
        f,
        tangents,
        Coverage::Exact,
        &DartLimits::new(),
    )
}

/// [`gregory_patch_at_with`] for the given coverage ([`Coverage::EndCap`]: an adaptive end cap),
/// dart masks from `darts`.
pub fn gregory_patch_at_for(
    topo: &Topology,
    positions: &[DVec3],
    f: u32,
    tangents: GregoryTangents,
    coverage: Coverage,
    darts: &DartLimits,
) -> Result<GregoryPatch<DVec3>, NotGregory> {
    let point = |i: u32| positions[i as usize];
    local_patch(topo, f, &point, tangents, coverage, darts)
}

/// The Gregory patch of face `f` with every control point as weights over control vertices.
pub fn gregory_patch_weights(topo: &Topology, f: u32) -> Result<GregoryPatch<Weights>, NotGregory> {
    gregory_patch_weights_with(topo, f, GregoryTangents::default())
}

/// [`gregory_patch_weights`] with the given edge-tangent lengths.
pub fn gregory_patch_weights_with(
    topo: &Topology,
    f: u32,
    tangents: GregoryTangents,
) -> Result<GregoryPatch<Weights>, NotGregory> {
    local_patch(
        topo,
        f,
        &Weights::unit,
        tangents,
        Coverage::Exact,
        &DartLimits::new(),
    )
}

fn local_patch<P: GregoryPoint>(
    topo: &Topology,
    f: u32,
    point: &impl Fn(u32) -> P,
    tangents: GregoryTangents,
    coverage: Coverage,
    darts: &DartLimits,
) -> Result<GregoryPatch<P>, NotGregory> {
    check_face_for(topo, f, coverage)?;
    let fv = topo.face_vertices(f);
    let mut data: Vec<Option<GregoryVertex<P>>> = Vec::with_capacity(fv.len());
    for &v in fv {
        data.push(GregoryVertex::new(
            &vertex_ring_with(topo, v, point),
            tangents,
            darts,
        ));
    }
    assemble_face(topo, f, |k, _| data[k].as_ref())
}

impl<P> GregoryPatch<P> {
    /// Number of corners: 4 for a quad, 3 for a triangle.
    pub fn corner_count(&self) -> usize {
        match self {
            GregoryPatch::Quad(_) => 4,
            GregoryPatch::Triangle(_) => 3,
        }
    }

    /// The five kinds of control points, each indexed by corner: `[p, e_plus, e_minus, f_plus,
    /// f_minus]` (the field names of [`GregoryQuad`]).
    pub fn points(&self) -> [&[P]; 5] {
        match self {
            GregoryPatch::Quad(q) => [&q.p, &q.e_plus, &q.e_minus, &q.f_plus, &q.f_minus],
            GregoryPatch::Triangle(t) => [&t.p, &t.e_plus, &t.e_minus, &t.f_plus, &t.f_minus],
        }
    }
}

impl GregoryPatch<DVec3> {
    /// Position and approximate derivatives (§4.4): quads at the face's `(u, v)`, triangles at
    /// barycentric `(1 - u - v, u, v)` of corners 0, 1, 2.
    pub fn eval(&self, u: f64, v: f64) -> super::PatchPoint {
        match self {
            GregoryPatch::Quad(q) => q.eval(u, v),
            GregoryPatch::Triangle(t) => t.eval(u, v),
        }
    }
}
