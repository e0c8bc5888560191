//! Everything the GPU draw of a feature-adaptive surface reads, as CPU data over the global
//! refined vertex buffer (Köbler 2013 ch. 3-4): frame slots with their stencil rows, per-patch
//! records, the B-spline patches (whole, or as transition fans, §3.4), the Gregory end caps
//! (Loop et al. 2009) with their sparse stencil rows, and the coarse edges shared across levels.
//!
//! Watertightness (`glsl/common/watertight.glsl`) holds by slot: every GPU vertex id (corners,
//! canonical edge directions, edge tessellation chords) is a slot, so a limit point that is a
//! corner on several levels has one frame and one place in every canonical order.
//!
//! Patch edges: B-spline patches use [`crate::patch::edge_grid::PATCH_EDGES`] numbering (which
//! is face-edge numbering, edges 2 and 3 run against the face), end caps face order.

use std::ops::Range;

use glam::{DVec2, DVec3};

use super::census_index::{is_quad_end_cap, patch_index};
use super::coarse::CoarseEdges;
use super::error::DrawTablesError;
use super::exact_corners::ExactCorners;
use super::lattice_frames::LatticeFrames;
use super::promoted::{
    fillet_end_code, fillet_fine_code, fillet_fine_words, irregular_crease_vertex,
    positional_fillet_end, FilletEnd, FilletEnds,
};
use super::records::{
    words_bytes, BSplineDraw, CoarseEdge, EndCapDraw, PatchRecord, TransitionTriangle,
};
pub use super::rows::END_CAP_ROWS;
use super::rows::{patch_corners, CornerRows, SparseRows};
use super::sector_frames::SectorFrames;
use super::slot_rows::SlotCorners;
use super::slots::{Slots, NONE};
use super::surface::{check_end_cap, end_cap_error, EndCapError, EndCapFailure, EndCapTopologies};
use crate::patch::edge_grid::PATCH_EDGES;
use crate::patch::gregory::edge_flags::{edge_flags, Across, ManySectors};
use crate::patch::gregory::shared_rows::{
    end_cap_face_rows, shared_vertex_point_rows, FaceRows, Terms,
};
use crate::patch::gregory::stencil_table::VERTEX_POINTS;
use crate::patch::gregory::{DartLimits, GregoryTangents};
use crate::patch::single_crease::{gpu_cvs, Rotation, SingleCreasePatch};
use crate::patch::RegularPatch;
use crate::subdiv::adaptive::{AdaptiveRefinement, Domain, PatchCensus, PatchType};
use crate::subdiv::limit::SharedVertexMasks;
use crate::topology::is_sharp_edge;

/// The GPU draw data of an [`AdaptiveRefinement`] (topology only; positions are the global
/// refined buffer of [`AdaptiveRefinement::refine_positions`]).
#[derive(Debug, Clone)]
pub struct AdaptiveDrawTables {
    /// Frame slots of the patch corners.
    pub slots: Slots,
    /// Per frame (the slots, then the sector frames of `super::sector_frames`): the GPU
    /// writes `normalize(cross(du, dv))` (one sector, or a sector frame), else a zero normal so
    /// each patch keeps its own.
    pub shared_normal: Vec<bool>,
    /// Per census patch, face order: the sector frame of each corner (`u32::MAX`: none).
    pub sector_corners: Vec<[u32; 4]>,
    /// Rows `3 s .. 3 s + 2`: frame `s`'s limit position, du, dv (`cross(du, dv)` outward); then
    /// [`END_CAP_ROWS`] rows per end cap from [`Self::end_cap_first_row`]; then from
    /// [`Self::vertex_first_row`] the first stage: row `j` of it is vertex point `j`, a derived
    /// point of an end-cap corner ([`crate::patch::gregory::GregoryVertex::vertex_points`]: a
    /// smooth corner's limit position, cosine and sine sums, a dart's limit position and
    /// tangents, a crease's sector tangents), those the other rows read, in (level, vertex,
    /// point) order. The other rows read vertex point `j` as id `refined_points + j`: every
    /// patch at a vertex of valence `n` holds `O(1)` terms for it, not `O(n)`.
    pub rows: SparseRows,
    /// First end-cap row (`3 *` frames).
    pub end_cap_first_row: u32,
    /// First vertex-point row (after the end caps').
    pub vertex_first_row: u32,
    /// Refined points (every level's vertices): ids from here are vertex points.
    pub refined_points: u32,
    /// One record per census patch, census order.
    pub records: Vec<PatchRecord>,
    /// B-spline patches without finer neighbour.
    pub regular: Vec<BSplineDraw>,
    /// B-spline patches with a finer neighbour.
    pub transition: Vec<BSplineDraw>,
    /// The fans of the transition patches.
    pub triangles: Vec<TransitionTriangle>,
    /// Single-crease patches (Nießner, Loop, Greiner 2012) without finer neighbour, as
    /// [`BSplineDraw`]s in the GPU frame of `glsl/single_crease/`: control vertices rotated so the
    /// crease runs along `u = 1` ([`gpu_cvs`]), corners and edge-direction flags of the rotated
    /// patch, flags bits 8-9 the [`Rotation`]; their [`PatchRecord`]s are in the same frame.
    pub single_crease: Vec<BSplineDraw>,
    /// Single-crease patches with a finer neighbour.
    pub single_crease_transition: Vec<BSplineDraw>,
    /// The fans of the single-crease transition patches (`patch` indexes
    /// [`Self::single_crease_transition`]).
    pub single_crease_triangles: Vec<TransitionTriangle>,
    /// Per record (census order): the crease sharpness of a single-crease patch, else 0.
    pub sharpness: Vec<f32>,
    /// Gregory end caps.
    pub end_caps: Vec<EndCapDraw>,
    /// Edges of coarse patches with a finer neighbour.
    pub coarse_edges: Vec<CoarseEdge>,
    /// The end caps' lattice regions near irregular crease vertices, one word per end cap then
    /// their blocks (`super::lattice_frames::LatticeFrames::table_words`); their frames follow
    /// the exact-position frames.
    pub end_cap_lattice: Vec<u32>,
}

/// Id bit marking a derived vertex point in the uploaded row ids ([`AdaptiveDrawTables::row_id_bytes`]):
/// `DERIVED_ID | k` reads vertex point `k` (`glsl/adaptive/stencil_rows.glsl`).
pub const DERIVED_ID: u32 = 1 << 31;

/// The end caps' rows in two stages (Loop et al. 2009 §4.1 per vertex, §4.3 per patch).
struct EndCapRows {
    /// Rows of every end cap in census order (table layout, [`END_CAP_ROWS`] a cap) over
    /// global ids: refined vertices, then vertex points (`refined + 3 k + b`).
    caps: FaceRows,
    /// Per level with vertex points read: their first-stage rows, in (level, vertex, point)
    /// order vertex point `k`'s the `k`-th row of the runs.
    vertices: Vec<LevelVertexRows>,
}

/// One level's first-stage rows (`shared_vertex_point_rows` of the vertices whose points the
/// end caps read) over the level's vertices, kept as built until the draw tables take the runs
/// of rows read, each as one copy with the level's first global id added
/// ([`SparseRows::append_face_row_range`]): the rows are not copied into rows of their own first.
struct LevelVertexRows {
    /// The level's first global vertex id ([`crate::subdiv::adaptive::AdaptiveLevel::first_vertex`]).
    first: u32,
    /// Rows `VERTEX_POINTS * i + b`: point `b` of the `i`-th vertex.
    rows: FaceRows,
    /// The runs of consecutive rows read, ascending.
    runs: Vec<Range<usize>>,
}

impl LevelVertexRows {
    /// Number of rows read.
    fn len(&self) -> usize {
        self.runs.iter().map(ExactSizeIterator::len).sum()
    }

    /// At least the number of terms the rows read hold.
    fn terms_bound(&self) -> usize {
        let offsets = &self.rows.offsets;
        (self.runs.iter())
            .map(|r| (offsets[r.end] - offsets[r.start]) as usize)
            .sum()
    }
}

/// Rows of every end cap in census order, with the first-stage rows of the vertex points they
/// read (`end_cap_face_rows`, written once with global ids: the vertex points numbered here
/// per level, ascending in (level, vertex, point), so rows stay ascending).
fn end_cap_rows(
    refinement: &AdaptiveRefinement,
    census: &PatchCensus,
    topologies: &EndCapTopologies,
    tangents: GregoryTangents,
) -> Result<EndCapRows, EndCapError> {
    let caps: Vec<_> = census
        .patches
        .iter()
        .filter(|p| p.kind == PatchType::EndCap)
        .collect();
    let tangents = tangents.for_end_caps();
    let mut local = Vec::new();
    // Dart masks solved once for every level and both stages.
    let darts = DartLimits::new();
    for group in caps.chunk_by(|a, b| a.level == b.level) {
        for p in group {
            check_end_cap(refinement, p)?;
        }
        let faces: Vec<u32> = group.iter().map(|p| p.face).collect();
        let topo = topologies.get(group[0].level);
        // Without zero terms (`SparseRows` drops them): dropped once per type, not per face.
        let rows = end_cap_face_rows(topo, &faces, tangents, &darts, Terms::Nonzero);
        for (i, p) in group.iter().enumerate() {
            rows.result(i)
                .map_err(|e| end_cap_error(refinement, p, EndCapFailure::Gregory(e)))?;
        }
        local.push((group[0].level, rows));
    }
    // Number the vertex points the rows read, level by level in (vertex, point) order: `at`
    // is indexed by a level's `VERTEX_POINTS * v + b` (`vertex_point_id` less the level's
    // vertex count).
    let mut index: Vec<Vec<u32>> = vec![Vec::new(); refinement.levels.len()];
    for (l, rows) in &local {
        let t = topologies.get(*l);
        let at = &mut index[*l as usize];
        for i in 0..rows.len() {
            rows.derived_read(t, i, |v, b| {
                if at.is_empty() {
                    at.resize(VERTEX_POINTS as usize * t.vertex_count(), NONE);
                }
                at[(VERTEX_POINTS * v + b) as usize] = 0;
            });
        }
    }
    // (level, vertex, points read as a bit mask) per vertex with a vertex point read.
    let mut read: Vec<(u32, u32, u8)> = Vec::new();
    let mut count = 0;
    for (l, at) in index.iter_mut().enumerate() {
        for (i, k) in at.iter_mut().enumerate() {
            if *k == 0 {
                *k = count;
                count += 1;
                let (v, b) = (i as u32 / VERTEX_POINTS, i as u32 % VERTEX_POINTS);
                match read.last_mut() {
                    Some(last) if (last.0, last.1) == (l as u32, v) => last.2 |= 1 << b,
                    _ => read.push((l as u32, v, 1 << b)),
                }
            }
        }
    }
    let first = refinement.vertex_count() as u32;
    // Room for every level's rows at once (each level's call reserves its own otherwise).
    let mut caps = FaceRows::new();
    caps.offsets
        .reserve(END_CAP_ROWS * local.iter().map(|(_, r)| r.len()).sum::<usize>());
    caps.terms
        .reserve(local.iter().map(|(_, r)| r.terms_bound()).sum());
    for (l, rows) in &local {
        let (lev, t, at) = (
            &refinement.levels[*l as usize],
            topologies.get(*l),
            &index[*l as usize],
        );
        // Global ids: monotone in the local ones, so rows stay ascending.
        let derived = |v, b| first + at[(VERTEX_POINTS * v + b) as usize];
        rows.all_rows_into(t, &|u| lev.global(u), &derived, END_CAP_ROWS, &mut caps);
    }
    let mut vertices = Vec::new();
    for group in read.chunk_by(|a, b| a.0 == b.0) {
        let l = group[0].0;
        let at: Vec<u32> = group.iter().map(|&(_, v, _)| v).collect();
        // Without zero terms, as the end caps' rows.
        let rows =
            shared_vertex_point_rows(topologies.get(l), &at, tangents, &darts, Terms::Nonzero);
        let mut runs: Vec<Range<usize>> = Vec::new();
        for (i, &(_, _, mask)) in group.iter().enumerate() {
            for b in (0..VERTEX_POINTS as usize).filter(|b| mask & (1 << b) != 0) {
                let r = VERTEX_POINTS as usize * i + b;
                match runs.last_mut() {
                    Some(run) if run.end == r => run.end += 1,
                    _ => runs.push(r..r + 1),
                }
            }
        }
        vertices.push(LevelVertexRows {
            first: refinement.levels[l as usize].first_vertex,
            rows,
            runs,
        });
    }
    Ok(EndCapRows { caps, vertices })
}

/// The [`BSplineDraw`] of census record `record` with control vertices `patch`: corner slots
/// and flags (boundary mask, bit `4 + e` when edge `e` runs from the larger slot).
fn bspline_draw(
    record: u32,
    base_face: u32,
    patch: RegularPatch,
    slot: impl Fn(u32) -> u32,
) -> BSplineDraw {
    let corners = patch.corners().map(slot);
    let mut flags = u32::from(patch.boundary_mask & 0xf);
    for (e, &(s, t)) in PATCH_EDGES.iter().enumerate() {
        flags |= u32::from(corners[s] > corners[t]) << (4 + e);
    }
    BSplineDraw {
        record,
        base_face,
        patch,
        flags,
        corners,
    }
}

/// How many of each draw a census makes ([`AdaptiveDrawTables::with_tangents`]'s lists, sized
/// up front rather than grown).
#[derive(Default)]
struct DrawSizes {
    regular: usize,
    transition: usize,
    triangles: usize,
    single_crease: usize,
    single_crease_transition: usize,
    single_crease_triangles: usize,
    end_caps: usize,
}

impl DrawSizes {
    /// The sizes of `census`'s draws: single-crease patches, then B-spline patches, whole or
    /// with a fan ([`fan`]: a triangle per edge, two on a transition edge; a rotated record
    /// keeps its number of transition edges), then end caps.
    fn of(census: &PatchCensus) -> DrawSizes {
        let mut n = DrawSizes::default();
        for p in &census.patches {
            let fan = 4 + (p.transition & 0xf).count_ones() as usize;
            let whole = p.transition == 0;
            match (&p.crease, &p.bspline) {
                (Some(_), _) if whole => n.single_crease += 1,
                (Some(_), _) => {
                    n.single_crease_transition += 1;
                    n.single_crease_triangles += fan;
                }
                (None, Some(_)) if whole => n.regular += 1,
                (None, Some(_)) => {
                    n.transition += 1;
                    n.triangles += fan;
                }
                (None, None) => n.end_caps += 1,
            }
        }
        n
    }
}

/// The fan of transition patch `patch` with transition mask `transition`: per edge one
/// triangle, two (its halves) on a transition edge.
fn fan(patch: u32, transition: u32) -> impl Iterator<Item = TransitionTriangle> {
    (0..4).flat_map(move |edge| {
        let halves: &[u32] = if transition & (1 << edge) != 0 {
            &[1, 2]
        } else {
            &[0]
        };
        halves
            .iter()
            .map(move |&half| TransitionTriangle { patch, edge, half })
    })
}

/// The domain of `d` (origin, u axis, v axis as f32) seen through `map`, the face's `(u, v)` of
/// the patch's own `(u', v')` (affine).
fn domain_words(d: &Domain, map: impl Fn(f64, f64) -> (f64, f64)) -> [[f32; 2]; 3] {
    let at = |u, v| {
        let (u, v) = map(u, v);
        d.origin + u * d.u + v * d.v
    };
    let o = at(0.0, 0.0);
    let f2 = |x: DVec2| [x.x as f32, x.y as f32];
    [f2(o), f2(at(1.0, 0.0) - o), f2(at(0.0, 1.0) - o)]
}

/// `record` (face frame) in the GPU frame of a single-crease patch rotated by `rot`: GPU edge
/// `e` is face edge `rot.face_corner(e)`, the domain maps the GPU `(u', v')`.
fn rotated_record(record: PatchRecord, d: &Domain, rot: Rotation) -> PatchRecord {
    let face_edge = |e: usize| rot.face_corner(e);
    PatchRecord {
        domain: domain_words(d, |u, v| rot.face_uv(u, v)),
        transition: (0..4)
            .filter(|&e| record.transition & (1 << face_edge(e)) != 0)
            .fold(0, |m, e| m | 1 << e),
        mid_slots: std::array::from_fn(|e| record.mid_slots[face_edge(e)]),
        coarse: std::array::from_fn(|e| record.coarse[face_edge(e)]),
        mid_frames: std::array::from_fn(|e| record.mid_frames[face_edge(e)]),
        ..record
    }
}

impl AdaptiveDrawTables {
    /// The draw tables of `refinement` (default Gregory tangents for the end caps).
    pub fn new(refinement: &AdaptiveRefinement) -> Result<AdaptiveDrawTables, DrawTablesError> {
        Self::with_tangents(refinement, GregoryTangents::default())
    }

    /// The draw tables of `refinement`, end caps with the given Gregory edge tangents.
    pub fn with_tangents(
        refinement: &AdaptiveRefinement,
        tangents: GregoryTangents,
    ) -> Result<AdaptiveDrawTables, DrawTablesError> {
        let census = refinement.census();
        let topologies = EndCapTopologies::new(refinement, census);
        let corners = patch_corners(refinement, census);
        let (slots, first_corners) = Slots::new(refinement, corners.iter().map(|c| c.global));
        let EndCapRows {
            caps,
            vertices: vertex_rows,
        } = end_cap_rows(refinement, census, &topologies, tangents)?;
        // End caps and vertex points: (rows, terms).
        let cap_rows = (
            caps.len() + vertex_rows.iter().map(LevelVertexRows::len).sum::<usize>(),
            caps.terms.len()
                + (vertex_rows.iter())
                    .map(LevelVertexRows::terms_bound)
                    .sum::<usize>(),
        );
        let corner_rows = CornerRows::new(refinement, census, &topologies, &caps, corners);
        // Exact limit masks of promoted corners, one table for slot, sector and exact-corner frames.
        let masks = SharedVertexMasks::default();
        let (slot_corners, mut shared_normal) = SlotCorners::new(
            refinement,
            census,
            &topologies,
            first_corners,
            &corner_rows,
            &masks,
        );
        let mut coarse = CoarseEdges::new(refinement, census, &slots);
        let mut sectors = SectorFrames::new(
            refinement,
            census,
            &topologies,
            &shared_normal,
            &slots,
            &coarse.mid_slots,
            &corner_rows,
            &masks,
        );
        let at = patch_index(refinement, census);
        let exact = ExactCorners::new(
            refinement,
            census,
            &topologies,
            &slots,
            &at,
            (slots.len() + sectors.rows.len()) as u32,
            &masks,
        );
        let lattice = LatticeFrames::new(
            refinement,
            census,
            &topologies,
            &at,
            (slots.len() + sectors.rows.len() + exact.rows.len()) as u32,
            &masks,
        );
        // Slot frames, then sector frames, exact-position and lattice frames, end caps, vertex
        // points, in one buffer made with room for all.
        let terms = sectors
            .rows
            .iter()
            .flatten()
            .map(|w| w.0.len())
            .sum::<usize>()
            + exact.rows.iter().map(|w| w.0.len()).sum::<usize>()
            + lattice.rows.term_count()
            + cap_rows.1;
        let mut rows = slot_corners.rows(
            &corner_rows,
            (
                3 * (sectors.rows.len() + exact.rows.len() + lattice.rows.len()) + cap_rows.0,
                terms,
            ),
        );
        drop(corner_rows);
        for r in sectors.rows.iter().flatten() {
            rows.push(r, 0);
        }
        shared_normal.reserve_exact(sectors.rows.len() + exact.rows.len() + lattice.rows.len());
        shared_normal.resize(slots.len() + sectors.rows.len(), true);
        // Exact-position frames: no tangents, no normal.
        for r in &exact.rows {
            rows.push(r, 0);
            rows.push_empty(2);
        }
        shared_normal.resize(shared_normal.len() + exact.rows.len(), false);
        // Lattice frames: no position, the exact tangents, a normal.
        for r in lattice.rows.iter() {
            rows.push_empty(1);
            for w in r {
                rows.push_long_row(w);
            }
        }
        shared_normal.resize(shared_normal.len() + lattice.rows.len(), true);
        let end_cap_first_row = rows.len() as u32;
        rows.append_face_rows(&caps);
        let vertex_first_row = rows.len() as u32;
        // Monotone ids (the level's first added): rows stay ascending.
        for level in &vertex_rows {
            for run in &level.runs {
                rows.append_face_row_range(&level.rows, run.clone(), level.first);
            }
        }
        let sizes = DrawSizes::of(census);
        let mut out = AdaptiveDrawTables {
            slots,
            shared_normal,
            sector_corners: std::mem::take(&mut sectors.corners),
            rows,
            end_cap_first_row,
            vertex_first_row,
            refined_points: refinement.vertex_count() as u32,
            records: Vec::with_capacity(census.patches.len()),
            regular: Vec::with_capacity(sizes.regular),
            transition: Vec::with_capacity(sizes.transition),
            triangles: Vec::with_capacity(sizes.triangles),
            single_crease: Vec::with_capacity(sizes.single_crease),
            single_crease_transition: Vec::with_capacity(sizes.single_crease_transition),
            single_crease_triangles: Vec::with_capacity(sizes.single_crease_triangles),
            sharpness: Vec::with_capacity(census.patches.len()),
            end_caps: Vec::with_capacity(sizes.end_caps),
            coarse_edges: Vec::new(),
            end_cap_lattice: Vec::new(),
        };
        let mut fillet_ends = FilletEnds::default();
        // Per level, its end-cap topology's vertices with two or more sectors.
        let mut many_sectors: Vec<ManySectors> = (refinement.levels.iter())
            .map(|_| ManySectors::default())
            .collect();
        for (i, p) in census.patches.iter().enumerate() {
            let lev = &refinement.levels[p.level as usize];
            let t = lev.topology();
            // The face's corners and edges, read once for every use below.
            let (fv, edges) = (t.face_vertices(p.face), t.face_edges(p.face));
            let n = fv.len();
            let mut fine = [NONE; 4];
            for (k, (c, &e)) in fine.iter_mut().zip(edges).enumerate() {
                *c = coarse.lookup(refinement, p.level, p.face, (k, e))?;
                if *c == NONE && p.kind == PatchType::EndCap {
                    *c = coarse.whole(refinement, census, &at, &out.slots, (p.level, p.face, k));
                }
            }
            let d = lev.domains[p.face as usize];
            let corner_frames = out.sector_corners[i];
            let record = PatchRecord {
                base_face: d.base_face,
                sub_face: d.sub_face.unwrap_or(NONE),
                level: p.level,
                kind: p.kind as u32,
                domain: domain_words(&d, |u, v| (u, v)),
                transition: u32::from(p.transition),
                mid_slots: coarse.mid_slots[i],
                coarse: fine,
                corner_frames,
                mid_frames: sectors.mids[i],
                fillet: 0,
                corner_exact: exact.frames[i],
                corner_fade: exact.codes[i],
                fillet_fine: [0; 3],
            };
            out.sharpness.push(p.crease.map_or(0.0, |l| l.sharpness));
            let slot = |v: u32| out.slots.of(v);
            // The first four corners' slots (B-spline and single-crease patches are quads).
            let mut face_slots = [NONE; 4];
            for (s, &v) in face_slots.iter_mut().zip(fv) {
                *s = slot(lev.global(v));
            }
            // Sector frames in the drawn patch's corner order (a rotated single-crease patch's
            // corners are the face's in another order): matched by slot.
            let drawn_frames = |draw: &BSplineDraw| {
                if corner_frames == [NONE; 4] {
                    // Most patches: no corner with a sector frame.
                    return corner_frames;
                }
                draw.corners.map(|c| {
                    face_slots
                        .iter()
                        .position(|&x| x == c)
                        .map_or(NONE, |j| corner_frames[j])
                })
            };
            if let Some(line) = p.crease {
                let rot = Rotation::of(line.side);
                out.records.push(rotated_record(record, &d, rot));
                let patch = RegularPatch {
                    face: p.face,
                    cvs: gpu_cvs(&SingleCreasePatch::from_line(p.face, line)),
                    boundary_mask: 0,
                };
                let mut draw = bspline_draw(i as u32, d.base_face, patch, slot);
                draw.flags |= (rot as u32) << 8;
                out.records[i].corner_frames = drawn_frames(&draw);
                let transition = out.records[i].transition;
                if transition == 0 {
                    out.single_crease.push(draw);
                } else {
                    let fan_of = out.single_crease_transition.len() as u32;
                    out.single_crease_triangles.extend(fan(fan_of, transition));
                    out.single_crease_transition.push(draw);
                }
                continue;
            }
            out.records.push(record);
            if let Some(b) = p.bspline {
                let draw = bspline_draw(i as u32, d.base_face, b, slot);
                out.records[i].corner_frames = drawn_frames(&draw);
                if p.transition == 0 {
                    out.regular.push(draw);
                    continue;
                }
                let fan_of = out.transition.len() as u32;
                out.triangles.extend(fan(fan_of, u32::from(p.transition)));
                out.transition.push(draw);
                continue;
            }
            let across = |_, g: Option<u32>| match g {
                Some(g) if !t.has_limit_surface(g) => Across::Nothing,
                Some(g) if !lev.own[g as usize] => Across::Patch,
                Some(g) => match at[p.level as usize][g as usize] {
                    NONE => Across::Nothing,
                    j => census.patches[j as usize]
                        .bspline
                        .map_or(Across::Patch, Across::BSpline),
                },
                None => Across::Nothing,
            };
            let caps = topologies.get(p.level);
            let many_sectors = &mut many_sectors[p.level as usize];
            let mut ef = edge_flags(caps, p.face, across, |v| lev.global(v), slot, many_sectors);
            // A promoted crease (`super::promoted`) between two end caps of this level: the
            // normal both share (bit 12 + k off: the neighbour's cross-edge derivative counts).
            // A quad end cap of this level (the neighbours both fillets need).
            let quad_cap = |g: u32| is_quad_end_cap(lev, census, &at[p.level as usize], g);
            let mut fine_codes = [0u32; 4];
            for (k, &e) in edges.iter().enumerate() {
                let across_cap = t.edge_faces(e).iter().any(|&g| g != p.face && quad_cap(g));
                if n == 4 && fine[k] == NONE && across_cap && caps.is_promoted_edge(e) {
                    ef.flags &= !(1 << (12 + k));
                    ef.flags |= 1 << (28 + k);
                    fine_codes[k] = fillet_fine_code(t.edge_sharpness(e));
                    // Its shared normal turns towards the limit's within the fillet of an
                    // irregular crease vertex at either end (`crease_turn_share`): bit 16 + the
                    // corner.
                    for c in [k, (k + 1) % 4] {
                        if irregular_crease_vertex(t, caps, fv[c]) {
                            out.records[i].transition |= 1 << (16 + c);
                        }
                    }
                } else if n == 4 && fine[k] == NONE && across_cap && !is_sharp_edge(caps, e) {
                    // An edge between two end caps from a vertex on a promoted crease: the
                    // fillet's sharpness at either end (4 bits each), both sides alike.
                    for (half, v) in [fv[k], fv[(k + 1) % 4]].into_iter().enumerate() {
                        let end = fillet_ends.at(p.level, t, caps, v, e);
                        if let Some(end) = end {
                            out.records[i].fillet |=
                                fillet_end_code(end.sharpness()) << (8 * k + 4 * half);
                        }
                        let corner = (k + half) % 4;
                        match end {
                            // The normal turns there (`fillet_rotation`): bit 8 + its corner.
                            Some(FilletEnd::Turn(_)) => {
                                out.records[i].transition |= 1 << (8 + corner);
                            }
                            // From the normal at the point (`turn_towards`): also bit 12 + it.
                            Some(FilletEnd::TurnMany(_)) => {
                                out.records[i].transition |=
                                    (1 << (8 + corner)) | (1 << (12 + corner));
                            }
                            _ => {}
                        }
                    }
                }
            }
            out.records[i].fillet_fine = fillet_fine_words(fine_codes);
            // The positional fillet reaches corner c whole (`positional_fillet_end`): bit 20 + c.
            if ef.flags >> 28 != 0 {
                for (c, &v) in fv.iter().enumerate() {
                    if positional_fillet_end(t, caps, v, quad_cap) {
                        out.records[i].transition |= 1 << (20 + c);
                    }
                }
            }
            // The face's slots, the first corner's past a triangle's last (isolation 0).
            let corners = std::array::from_fn(|c| face_slots[if c < n { c } else { 0 }]);
            let first_row = end_cap_first_row + (END_CAP_ROWS * out.end_caps.len()) as u32;
            out.end_caps.push(EndCapDraw {
                record: i as u32,
                base_face: d.base_face,
                flags: ef.flags,
                first_row,
                corners,
                grid: ef.grids,
            });
        }
        coarse.check_halves(refinement)?;
        out.coarse_edges = coarse.edges;
        out.end_cap_lattice = lattice.table_words(out.end_caps.iter().map(|c| c.record as usize));
        log::debug!(
            "adaptive draw tables: {} slots, {} rows, {} regular + {} transition ({} triangles) B-spline patches, {} + {} ({} triangles) single-crease patches, {} end caps, {} coarse edges, {} bytes",
            out.slots.len(),
            out.rows.len(),
            out.regular.len(),
            out.transition.len(),
            out.triangles.len(),
            out.single_crease.len(),
            out.single_crease_transition.len(),
            out.single_crease_triangles.len(),
            out.end_caps.len(),
            out.coarse_edges.len(),
            out.memory_bytes()
        );
        Ok(out)
    }

    /// Patch primitives drawn: whole B-spline, single-crease and end-cap patches, one per
    /// transition triangle.
    pub fn primitive_count(&self) -> usize {
        self.regular.len()
            + self.triangles.len()
            + self.single_crease.len()
            + self.single_crease_triangles.len()
            + self.end_caps.len()
    }

    /// Number of slots.
    pub fn slot_count(&self) -> usize {
        self.slots.len()
    }

    /// Number of frames the GPU computes: the slots, then the sector frames.
    pub fn frame_count(&self) -> usize {
        self.shared_normal.len()
    }

    /// The slot of global vertex `g`, `None` when no patch corner is that point.
    pub fn slot_of(&self, g: u32) -> Option<u32> {
        self.slots
            .of_vertex
            .get(g as usize)
            .copied()
            .filter(|&s| s != NONE)
    }

    /// `PatchRecord`s, 144 bytes each, census order.
    pub fn patch_record_bytes(&self) -> Vec<u8> {
        words_bytes(self.records.iter().map(PatchRecord::words))
    }

    /// Per slot one u32: bit 0 set when the normal is shared.
    pub fn slot_flag_bytes(&self) -> Vec<u8> {
        words_bytes(self.shared_normal.iter().map(|&s| [u32::from(s)]))
    }

    /// `PatchInfo`s of the non-transition B-spline patches, 32 bytes each.
    pub fn regular_info_bytes(&self) -> Vec<u8> {
        words_bytes(self.regular.iter().map(BSplineDraw::words))
    }

    /// Index buffer of the non-transition B-spline patches: 16 control vertices each.
    pub fn regular_index_bytes(&self) -> Vec<u8> {
        words_bytes(self.regular.iter().map(|d| d.patch.cvs))
    }

    /// `PatchInfo`s of the transition patches, 32 bytes each.
    pub fn transition_info_bytes(&self) -> Vec<u8> {
        words_bytes(self.transition.iter().map(BSplineDraw::words))
    }

    /// Transition triangles, 16 bytes each.
    pub fn triangle_bytes(&self) -> Vec<u8> {
        words_bytes(self.triangles.iter().map(TransitionTriangle::words))
    }

    /// Index buffer of the transition triangles: their patch's 16 control vertices each.
    pub fn triangle_index_bytes(&self) -> Vec<u8> {
        words_bytes(
            self.triangles
                .iter()
                .map(|t| self.transition[t.patch as usize].patch.cvs),
        )
    }

    /// `PatchInfo`s of the single-crease patches, 32 bytes each: whole ones, then those with a
    /// finer neighbour.
    pub fn single_crease_info_bytes(&self) -> Vec<u8> {
        words_bytes(
            self.single_crease
                .iter()
                .chain(&self.single_crease_transition)
                .map(BSplineDraw::words),
        )
    }

    /// Index buffer of the whole single-crease patches: 16 rotated control vertices each.
    pub fn single_crease_index_bytes(&self) -> Vec<u8> {
        words_bytes(self.single_crease.iter().map(|d| d.patch.cvs))
    }

    /// Single-crease transition triangles, 16 bytes each (`patch` into the single-crease
    /// transition patches).
    pub fn single_crease_triangle_bytes(&self) -> Vec<u8> {
        words_bytes(
            self.single_crease_triangles
                .iter()
                .map(TransitionTriangle::words),
        )
    }

    /// Index buffer of the single-crease transition triangles: their patch's 16 rotated control
    /// vertices each.
    pub fn single_crease_triangle_index_bytes(&self) -> Vec<u8> {
        words_bytes(
            self.single_crease_triangles
                .iter()
                .map(|t| self.single_crease_transition[t.patch as usize].patch.cvs),
        )
    }

    /// Per record one f32: the crease sharpness of single-crease patches (0 for the others).
    pub fn sharpness_bytes(&self) -> Vec<u8> {
        words_bytes(self.sharpness.iter().map(|s| [s.to_bits()]))
    }

    /// `GregoryPatchInfo`s of the end caps, 32 bytes each.
    pub fn end_cap_info_bytes(&self) -> Vec<u8> {
        words_bytes(self.end_caps.iter().map(EndCapDraw::words))
    }

    /// Grid ids of the end caps, 48 each.
    pub fn end_cap_grid_bytes(&self) -> Vec<u8> {
        words_bytes(self.end_caps.iter().map(|c| c.grid))
    }

    /// The end caps' lattice table ([`Self::end_cap_lattice`]), u32 words.
    pub fn end_cap_lattice_bytes(&self) -> Vec<u8> {
        words_bytes(self.end_cap_lattice.iter().map(|&w| [w]))
    }

    /// Coarse edges, 64 bytes each.
    pub fn coarse_edge_bytes(&self) -> Vec<u8> {
        words_bytes(self.coarse_edges.iter().map(CoarseEdge::words))
    }

    /// Row offsets (`rows + 1` u32).
    pub fn row_offset_bytes(&self) -> Vec<u8> {
        words_bytes(self.rows.offsets.iter().map(|&o| [o]))
    }

    /// Row term ids (u32): refined points as they are, vertex point `k` as
    /// [`DERIVED_ID`]` | k`.
    pub fn row_id_bytes(&self) -> Vec<u8> {
        let n = self.refined_points;
        words_bytes(
            self.rows
                .ids
                .iter()
                .map(|&v| [if v < n { v } else { DERIVED_ID | (v - n) }]),
        )
    }

    /// Number of vertex points (first-stage rows, [`Self::vertex_first_row`] on).
    pub fn vertex_point_count(&self) -> usize {
        self.rows.len() - self.vertex_first_row as usize
    }

    /// The refined points followed by the vertex points (f64 weights): the positions every row
    /// of [`Self::rows`] applies to, from the refined ones
    /// ([`AdaptiveRefinement::refine_positions`]).
    pub fn with_vertex_points(&self, refined: &[DVec3]) -> Vec<DVec3> {
        let first = self.vertex_first_row as usize;
        let mut out = Vec::with_capacity(refined.len() + self.vertex_point_count());
        out.extend_from_slice(refined);
        out.extend((first..self.rows.len()).map(|r| self.rows.apply(r, refined)));
        out
    }

    /// Row term weights (f32).
    pub fn row_weight_bytes(&self) -> Vec<u8> {
        words_bytes(self.rows.weights_f32().map(|w| [w.to_bits()]))
    }

    /// Bytes of every GPU array together.
    pub fn memory_bytes(&self) -> usize {
        use super::records::{
            COARSE_EDGE_WORDS, PATCH_INFO_WORDS, PATCH_RECORD_WORDS, TRIANGLE_WORDS,
        };
        let words = self.records.len() * (PATCH_RECORD_WORDS + 1)
            + self.shared_normal.len()
            + (self.regular.len()
                + self.transition.len()
                + self.single_crease.len()
                + self.single_crease_transition.len()
                + self.end_caps.len())
                * PATCH_INFO_WORDS
            + (self.regular.len() + self.single_crease.len()) * 16
            + (self.triangles.len() + self.single_crease_triangles.len()) * (TRIANGLE_WORDS + 16)
            + self.end_caps.len() * 48
            + self.coarse_edges.len() * COARSE_EDGE_WORDS
            + self.end_cap_lattice.len()
            + self.rows.offsets.len()
            + 2 * self.rows.ids.len();
        4 * words
    }
}
