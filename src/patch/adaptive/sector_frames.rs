//! Sector frames: one limit normal per sector of a multi-sector point, shared by every patch of
//! that sector there.
//!
//! A frame slot ([`super::slots`]) has one normal only where its point has one sector; where
//! infinitely sharp edges split the point's faces (crease and corner vertices, points on a
//! crease edge) the slot's normal is zero and each patch would keep its own corner normal, so
//! two patches of one sector (across a smooth edge, or of two levels) drew normals a few ulp
//! apart (3e-7 rad on `catmark_inf_crease1`). Here each such (point, sector) with an exact patch
//! corner there (B-spline or single-crease: its corner rows are the sector's limit frame) or else
//! an end cap's corner (the Gregory corner's plane, the same for every face of the sector) gets
//! a frame of its own, appended after the slots; every patch corner and transition midpoint in
//! that sector reads its normal (positions still come from the slot). One-face crease sectors
//! keep the end cap's own corner normal (from its face points: its edge tangents are collinear).
//!
//! A sector is named across levels by its point's slot and a base face: the smallest base face
//! of the sector around the point when the point is a base vertex, else the patch's base face
//! (a point created by refinement lies inside a base edge or face, and only base edges are
//! infinitely sharp, so its sectors are the base faces beside it).

use super::promoted::{exact_frame, promoted_vertex};
use super::rows::CornerRows;
use super::slots::{Slots, NONE};
use super::surface::EndCapTopologies;
use crate::mesh::INFINITE_SHARPNESS;
use crate::patch::gregory::word_hash::WordHashMap;
use crate::patch::gregory::Weights;
use crate::subdiv::adaptive::{AdaptiveRefinement, PatchCensus, PatchType};
use crate::subdiv::limit::SharedVertexMasks;
use crate::topology::{sector_count, sector_counts, sector_faces, Topology};

/// The sector frames of a census and which patch corners and midpoints read them.
#[derive(Debug, Clone, Default)]
pub struct SectorFrames {
    /// Per sector frame: rows (position, d/du, d/dv) of its exact patch corner.
    pub rows: Vec<[Weights; 3]>,
    /// Per census patch, face order: the frame (slot numbering) of each corner's sector,
    /// [`NONE`] for none.
    pub corners: Vec<[u32; 4]>,
    /// Per census patch, face-edge order: the sector frame of the midpoint of each transition
    /// edge (`mid_slots`), [`NONE`] for none.
    pub mids: Vec<[u32; 4]>,
}

/// `(slot, base face)`: a sector of a multi-sector point.
type SectorKey = (u32, u32);

impl SectorFrames {
    /// Sector frames of `census` over `slots`, numbered from the number of slots (they follow
    /// the slots in the frame buffers); `mid_slots` per census patch as
    /// `CoarseEdges::mid_slots`, `corner_rows` the census's corners and their rows. End caps' sectors
    /// are those of their [`EndCapTopologies`] (residual semi-sharp creases split them too),
    /// except where the slot's normal is shared (`shared_normal`, one per slot: an exact patch,
    /// e.g. single-crease, gave the point its one normal, which the end cap reads there).
    /// `masks`: the exact limit masks of promoted corners, shared with the slot frames'.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        refinement: &AdaptiveRefinement,
        census: &PatchCensus,
        topologies: &EndCapTopologies,
        shared_normal: &[bool],
        slots: &Slots,
        mid_slots: &[[u32; 4]],
        corner_rows: &CornerRows,
        masks: &SharedVertexMasks,
    ) -> SectorFrames {
        let first = slots.len() as u32;
        let base = refinement.levels[0].topology();
        let base_vertices = base.vertex_count() as u32;
        // The sector key of slot `s` seen from base face `b`.
        let key = |s: u32, b: u32| -> SectorKey {
            let origin = slots.origins[s as usize];
            if origin < base_vertices {
                (
                    s,
                    sector_faces(base, origin, b).into_iter().min().unwrap_or(b),
                )
            } else {
                (s, b)
            }
        };
        let mut index: WordHashMap<SectorKey, u32> = WordHashMap::default();
        let mut out = SectorFrames::default();
        let mut counts = SectorCounts::new(refinement);
        // Corner keys per census patch (NONE slot: one sector, nothing to share).
        let mut corner_keys = Vec::with_capacity(census.patches.len());
        let mut promoted_corners = vec![[false; 4]; census.patches.len()];
        for p in &census.patches {
            let lev = &refinement.levels[p.level as usize];
            let b = lev.domains[p.face as usize].base_face;
            let mut keys = [None; 4];
            if p.kind == PatchType::EndCap {
                let caps = topologies.get(p.level);
                for (k, &v) in caps.face_vertices(p.face).iter().enumerate().take(4) {
                    let s = slots.of(lev.global(v));
                    // Most end-cap corners' slots have a shared normal: no key (nor whether
                    // they are promoted, read only where keyed); the few others walk their
                    // rings (no pass over the end caps' topology).
                    if shared_normal[s as usize] {
                        continue;
                    }
                    // On a promoted crease the sectors are the limit's (the level's own
                    // topology), each with its exact frame.
                    let promoted = promoted_vertex(lev.topology(), caps, v);
                    promoted_corners[corner_keys.len()][k] = promoted;
                    let t = if promoted { lev.topology() } else { caps };
                    if sector_count(t, v) >= 2 {
                        // The sector's smallest base face, seen at this level (every base face
                        // around a base vertex has one child around it: complete rings).
                        let own = sector_faces(t, v, p.face)
                            .into_iter()
                            .map(|g| lev.domains[g as usize].base_face)
                            .min()
                            .unwrap_or(b);
                        let origin = slots.origins[s as usize];
                        keys[k] = Some(if origin < base_vertices {
                            (s, own)
                        } else {
                            (s, b)
                        });
                    }
                }
            } else {
                let t = lev.topology();
                for (k, &v) in t.face_vertices(p.face).iter().enumerate().take(4) {
                    if counts.get(p.level, v) >= 2 {
                        keys[k] = Some(key(slots.of(lev.global(v)), b));
                    }
                }
            }
            corner_keys.push(keys);
        }
        // Frames from exact patches' corners, in census order; then, for sectors without one,
        // from end caps' corners (the Gregory corner's plane is the sector's: its edge points
        // lie in it), except in one-face crease sectors, whose corner normal the GPU takes
        // from the face points instead (`gregory_corner_normal`).
        corner_rows.visit(|c| {
            let Some(key) = corner_keys[c.patch][c.k] else {
                return;
            };
            let promoted = promoted_corners[c.patch][c.k];
            if index.contains_key(&key) || (!promoted && corner_rows.singular(c)) {
                return;
            }
            if promoted {
                let p = &census.patches[c.patch];
                let lev = &refinement.levels[p.level as usize];
                let frame = exact_frame(lev, p.face, c.k, corner_rows.position_row(c), masks);
                if frame[1].0.is_empty() {
                    return;
                }
                out.rows.push(frame);
            } else {
                out.rows.push(corner_rows.rows(c));
            }
            index.insert(key, first + (out.rows.len() - 1) as u32);
        });
        let frame = |key: Option<SectorKey>| key.and_then(|k| index.get(&k).copied());
        out.corners.reserve_exact(census.patches.len());
        out.mids.reserve_exact(census.patches.len());
        for ((p, keys), mids) in census.patches.iter().zip(&corner_keys).zip(mid_slots) {
            // Most patches have neither a keyed corner nor a transition midpoint.
            out.corners.push(if *keys == [None; 4] {
                [NONE; 4]
            } else {
                keys.map(|k| frame(k).unwrap_or(NONE))
            });
            if *mids == [NONE; 4] {
                out.mids.push([NONE; 4]);
                continue;
            }
            let lev = &refinement.levels[p.level as usize];
            let t = lev.topology();
            let b = lev.domains[p.face as usize].base_face;
            let edges = t.face_edges(p.face);
            out.mids.push(std::array::from_fn(|e| {
                let m = mids[e];
                // A midpoint has two sectors exactly when it lies on an interior sharp edge.
                let split = m != NONE
                    && e < edges.len()
                    && !t.is_boundary_edge(edges[e])
                    && t.edge_sharpness(edges[e]) >= INFINITE_SHARPNESS;
                if split {
                    frame(Some(key(m, b))).unwrap_or(NONE)
                } else {
                    NONE
                }
            }));
        }
        out
    }
}

/// [`sector_counts`] of each level's topology, each counted on first use in one pass over its
/// edges: the exact patches' corners ask for a vertex's count up to four times each, and the
/// pass is cheaper than a ring walk per vertex asked.
struct SectorCounts<'t> {
    /// Per level: its topology and its counts (empty: not counted yet).
    levels: Vec<(&'t Topology, Vec<u32>)>,
}

impl<'t> SectorCounts<'t> {
    fn new(refinement: &'t AdaptiveRefinement) -> Self {
        let levels = (refinement.levels.iter())
            .map(|lev| (lev.topology(), Vec::new()))
            .collect();
        SectorCounts { levels }
    }

    /// [`crate::topology::sector_count`] of vertex `v` of level `level`.
    fn get(&mut self, level: u32, v: u32) -> usize {
        let (topo, counts) = &mut self.levels[level as usize];
        if counts.is_empty() {
            *counts = sector_counts(topo);
        }
        counts[v as usize] as usize
    }
}
