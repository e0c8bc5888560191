//! Edges between patches of neighbouring levels (Köbler 2013 §3.4, transition patches): every
//! edge of a B-spline patch with a one-level-finer neighbour becomes a [`CoarseEdge`] record
//! holding the coarse patch's 12 canonical grid points; the two finer patches along its halves
//! point to it, so both sides evaluate the one limit curve. Neighbouring patches differ by at
//! most one level (§3.7, regularity judged per vertex): [`DrawTablesError::LevelGap`] otherwise.

use super::error::DrawTablesError;
use super::records::CoarseEdge;
use super::slots::{Slots, NONE};
use crate::patch::edge_grid::edge_grid;
use crate::patch::single_crease::Rotation;
use crate::subdiv::adaptive::{
    AdaptiveLevel, AdaptivePatch, AdaptiveRefinement, ChildOf, PatchCensus,
};
use crate::topology::is_sharp_edge;

/// Per edge of `lev`, the next level's vertex that is its edge point ([`NONE`] if not kept).
fn edge_points(lev: &AdaptiveLevel, next: &AdaptiveLevel) -> Vec<u32> {
    let mut out = vec![NONE; lev.topology().edge_count()];
    for v in 0..next.level.vertex_count() as u32 {
        if let ChildOf::Edge(e) = lev.child_of(v) {
            out[e as usize] = v;
        }
    }
    out
}

/// Coarse-edge flags bits 3-4: the edge curve of a single-crease coarse patch (0 the B-spline
/// grid curve, also on the edge opposite the crease).
pub const CREASE_EDGE: u32 = 1 << 3;
/// Flags bits 3-4: an edge across the crease line of a single-crease coarse patch; bit 5
/// ([`CREASE_AT_LO`]): its crease end is `lo`.
pub const ACROSS_CREASE: u32 = 2 << 3;
/// Flags bit 5, see [`ACROSS_CREASE`].
pub const CREASE_AT_LO: u32 = 1 << 5;

/// The flags of face edge `k` of coarse patch `p` (record `record`) saying which single-crease
/// curve it is (`glsl/single_crease/single_crease.glsl`), bits 8-31 the record (whose sharpness
/// the curve reads); 0 for B-spline patches and the edge opposite the crease. `crease_is_lo`:
/// whether face corner `k` of the patch is the edge's `lo` end.
fn crease_flags(
    p: &AdaptivePatch,
    record: u32,
    k: usize,
    crease_is_lo: impl Fn(usize) -> bool,
) -> u32 {
    let Some(line) = p.crease else {
        return 0;
    };
    let kc = Rotation::of(line.side).face_corner(1);
    let kind = if k == kc {
        CREASE_EDGE
    } else if k == (kc + 2) % 4 {
        return 0;
    } else {
        // Edge k shares corner k (k = kc + 1) or k + 1 (k = kc - 1) with the crease edge.
        let corner = if k == (kc + 1) % 4 { k } else { (k + 1) % 4 };
        ACROSS_CREASE
            | if crease_is_lo(corner) {
                CREASE_AT_LO
            } else {
                0
            }
    };
    kind | record << 8
}

/// Flags bit 6: a whole edge shared at one level (an end cap next to a single-crease patch's
/// crease-aware edge), not a coarse edge with two halves; `mid_slot` is [`NONE`].
pub const WHOLE_EDGE: u32 = 1 << 6;

/// The record of face edge `k` of census patch `p` (record `record`, B-spline or single-crease)
/// with midpoint slot `mid_slot`: its 12 grid points in the canonical frame, end slots, flags.
fn edge_record(
    p: &AdaptivePatch,
    record: u32,
    k: usize,
    mid_slot: u32,
    sharp: bool,
    slots: &Slots,
) -> Option<CoarseEdge> {
    let b = p.bspline?;
    let slot = |g: u32| slots.of(g);
    let c = b.corners();
    // The finer face runs the edge c[k + 1] -> c[k].
    let grid = edge_grid(&b, c[(k + 1) % 4], c[k], slot)?;
    let (lo, hi) = (
        slot(c[k]).min(slot(c[(k + 1) % 4])),
        slot(c[k]).max(slot(c[(k + 1) % 4])),
    );
    Some(CoarseEdge {
        rows: grid.ids,
        lo_slot: lo,
        hi_slot: hi,
        mid_slot,
        flags: u32::from(sharp)
            | u32::from(grid.first_phantom) << 1
            | u32::from(grid.last_phantom) << 2
            | crease_flags(p, record, k, |corner| slot(c[corner]) == lo),
    })
}

/// At least the number of records [`CoarseEdges`] makes of `census` (sized up front rather
/// than grown, a record being 64 bytes): one per transition edge of a B-spline patch, and the
/// [`WHOLE_EDGE`] ones of [`CoarseEdges::whole`], at most three per single-crease patch (its
/// crease edge and the two edges across its crease line, each with one face across).
fn records_bound(census: &PatchCensus) -> usize {
    (census.patches.iter())
        .map(|p| match (&p.crease, &p.bspline) {
            (Some(_), _) => 3 + (p.transition & 0xf).count_ones() as usize,
            (None, Some(_)) => (p.transition & 0xf).count_ones() as usize,
            (None, None) => 0,
        })
        .sum()
}

/// The coarse edges of a refinement and the finer patches' references to them.
#[derive(Debug, Clone, Default)]
pub struct CoarseEdges {
    /// The records.
    pub edges: Vec<CoarseEdge>,
    /// Per census patch: slot of the midpoint of each transition edge (B-spline edge order).
    pub mid_slots: Vec<[u32; 4]>,
    /// (level, face, edge) of the coarse patch of each record.
    owner: Vec<(u32, u32, u32)>,
    /// Per level, per edge of that level: its record ([`NONE`]: none; a level without
    /// records has no entries).
    by_edge: Vec<Vec<u32>>,
    /// Finer patch edges pointing at each record.
    refs: Vec<u8>,
}

impl CoarseEdges {
    /// One record per transition edge of every transition B-spline patch, in census order.
    pub fn new(refinement: &AdaptiveRefinement, census: &PatchCensus, slots: &Slots) -> Self {
        let mut out = CoarseEdges {
            mid_slots: vec![[NONE; 4]; census.patches.len()],
            by_edge: vec![Vec::new(); refinement.levels.len()],
            ..Default::default()
        };
        let records = records_bound(census);
        out.edges.reserve_exact(records);
        out.owner.reserve_exact(records);
        out.refs.reserve_exact(records);
        let mids: Vec<Vec<u32>> = refinement
            .levels
            .windows(2)
            .map(|w| edge_points(&w[0], &w[1]))
            .collect();
        let slot = |g: u32| slots.of(g);
        for (i, p) in census.patches.iter().enumerate() {
            if p.bspline.is_none() || p.transition == 0 {
                continue;
            }
            let lev = &refinement.levels[p.level as usize];
            let t = lev.topology();
            for k in (0..4).filter(|k| p.transition & (1 << k) != 0) {
                let e = t.face_edges(p.face)[k];
                let mid = mids[p.level as usize][e as usize];
                let next = &refinement.levels[p.level as usize + 1];
                let mid_slot = if mid == NONE {
                    NONE
                } else {
                    slot(next.global(mid))
                };
                out.mid_slots[i][k] = mid_slot;
                let sharp = is_sharp_edge(t, e);
                let Some(record) = edge_record(p, i as u32, k, mid_slot, sharp, slots) else {
                    continue;
                };
                let by_edge = &mut out.by_edge[p.level as usize];
                if by_edge.is_empty() {
                    by_edge.resize(t.edge_count(), NONE);
                }
                by_edge[e as usize] = out.edges.len() as u32;
                out.owner.push((p.level, p.face, k as u32));
                out.refs.push(0);
                out.edges.push(record);
            }
        }
        out
    }

    /// A [`WHOLE_EDGE`] record for face edge `k` of end cap `f` of `level` when the patch across
    /// it (same level; `at`: [`super::census_index::patch_index`]) is a single-crease patch and the edge is one of its
    /// crease-aware curves (its crease edge or an edge across its crease line), so the end cap
    /// evaluates that curve as the single-crease patch does; [`NONE`] otherwise (the grid curve
    /// of the end cap's B-spline-neighbour rule is then the same curve).
    pub fn whole(
        &mut self,
        refinement: &AdaptiveRefinement,
        census: &PatchCensus,
        at: &[Vec<u32>],
        slots: &Slots,
        (level, f, k): (u32, u32, usize),
    ) -> u32 {
        let lev = &refinement.levels[level as usize];
        let t = lev.topology();
        let Some(g) = t.adjacent_face(f, k).filter(|&g| lev.own[g as usize]) else {
            return NONE;
        };
        let j = at[level as usize][g as usize];
        let Some(q) = census
            .patches
            .get(j as usize)
            .filter(|q| q.crease.is_some())
        else {
            return NONE;
        };
        let e = t.face_edges(f)[k];
        let Some(kq) = t.face_edges(g).iter().position(|&x| x == e) else {
            return NONE;
        };
        let Some(mut record) = edge_record(q, j, kq, NONE, false, slots) else {
            return NONE;
        };
        if record.flags & (CREASE_EDGE | ACROSS_CREASE) == 0 {
            return NONE;
        }
        record.flags |= WHOLE_EDGE;
        self.owner.push((level, g, kq as u32));
        self.refs.push(2);
        self.edges.push(record);
        (self.edges.len() - 1) as u32
    }

    /// The record face edge `k` of face `f` of `level` lies on (its neighbour across is drawn
    /// one level coarser), [`NONE`] when the neighbour is of the same level, finer, or not
    /// drawn (boundary, hole, no limit surface).
    ///
    /// The common case (the neighbour is of the same level, or there is none) is settled inline;
    /// only edges beside a face of another level go on to [`Self::lookup_coarser`]. `e` is the
    /// edge itself (`face_edges(f)[k]`, which the caller has at hand for every edge of the face).
    #[inline]
    pub fn lookup(
        &mut self,
        refinement: &AdaptiveRefinement,
        level: u32,
        f: u32,
        (k, e): (usize, u32),
    ) -> Result<u32, DrawTablesError> {
        let lev = &refinement.levels[level as usize];
        // The face across `e` from `f` (`Topology::adjacent_face`, given the edge).
        match *lev.topology().edge_faces(e) {
            [a, b] => {
                let h = if a == f { b } else { a };
                if lev.own[h as usize] {
                    Ok(NONE)
                } else {
                    self.lookup_coarser(refinement, level, f, k, h)
                }
            }
            _ => Ok(NONE),
        }
    }

    /// [`Self::lookup`] of face edge `k` of `f` whose neighbour `h` is not drawn at `level`.
    #[inline(never)]
    fn lookup_coarser(
        &mut self,
        refinement: &AdaptiveRefinement,
        level: u32,
        f: u32,
        k: usize,
        h: u32,
    ) -> Result<u32, DrawTablesError> {
        let lev = &refinement.levels[level as usize];
        let t = lev.topology();
        let gap = || DrawTablesError::LevelGap {
            base_face: lev.domains[f as usize].base_face,
            level,
            face: f,
            edge: k as u32,
        };
        let Some(parent) = level.checked_sub(1).map(|l| &refinement.levels[l as usize]) else {
            return Err(gap());
        };
        let (pf, _) = parent.child_face_parent(h);
        if !parent.topology().has_limit_surface(pf) {
            return Ok(NONE);
        }
        let fv = t.face_vertices(f);
        let ends = [fv[k], fv[(k + 1) % fv.len()]].map(|v| parent.child_of(v));
        let e = match ends {
            [ChildOf::Vertex(_), ChildOf::Edge(e)] | [ChildOf::Edge(e), ChildOf::Vertex(_)] => e,
            _ => return Err(gap()),
        };
        let r = self.by_edge[level as usize - 1]
            .get(e as usize)
            .copied()
            .filter(|&r| r != NONE)
            .ok_or_else(gap)?;
        self.refs[r as usize] += 1;
        Ok(r)
    }

    /// Checks that both halves of every record belong to drawn finer patches (the finer
    /// neighbour was not refined further).
    pub fn check_halves(&self, refinement: &AdaptiveRefinement) -> Result<(), DrawTablesError> {
        match self.refs.iter().position(|&n| n != 2) {
            None => Ok(()),
            Some(r) => {
                let (level, face, k) = self.owner[r];
                let lev = &refinement.levels[level as usize];
                Err(DrawTablesError::LevelGap {
                    base_face: lev.domains[face as usize].base_face,
                    level,
                    face,
                    edge: k,
                })
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::patch::adaptive::census_index::patch_index;
    use crate::patch::adaptive::rows::patch_corners;
    use crate::subdiv::adaptive::corpus_refinements;
    use crate::subdiv::adaptive::PatchType;

    /// `records_bound` bounds the records made as the draw tables make them (the transition
    /// edges', then a whole edge tried for every end-cap edge without a coarse record), over
    /// meshes with transition edges and single-crease patches.
    #[test]
    fn records_bound_bounds_the_records() {
        let cases = [
            ("catmark_car", 2),
            ("catmark_cube_creases1", 3),
            ("catmark_single_crease", 3),
            ("catmark_tent_creases1", 2),
        ];
        for (name, refinement) in corpus_refinements(&cases) {
            let census = refinement.census();
            let corners = patch_corners(&refinement, census);
            let (slots, _) = Slots::new(&refinement, corners.iter().map(|c| c.global));
            let at = patch_index(&refinement, census);
            let mut coarse = CoarseEdges::new(&refinement, census, &slots);
            assert!(!coarse.edges.is_empty(), "{name}");
            for p in census
                .patches
                .iter()
                .filter(|p| p.kind == PatchType::EndCap)
            {
                let t = refinement.levels[p.level as usize].topology();
                for (k, &e) in t.face_edges(p.face).iter().enumerate().take(4) {
                    if coarse.lookup(&refinement, p.level, p.face, (k, e)).unwrap() == NONE {
                        coarse.whole(&refinement, census, &at, &slots, (p.level, p.face, k));
                    }
                }
            }
            assert!(
                coarse.edges.len() <= records_bound(census),
                "{name}: {} records",
                coarse.edges.len()
            );
        }
    }
}
