//! Exact limit positions at the promoted corners the positional fillet does not reach whole, for
//! the end caps' corner offsets ([`super::promoted::corner_offset_share`]).
//!
//! Where the positional fillet fades out (irregular crease vertices, crease ends, regular creases
//! beside a non-quad) the end caps keep the crease surface's corner, which is not the limit's.
//! Only where every face at the vertex is a quad end cap of its level
//! ([`super::promoted::corner_offset_vertex`]): a B-spline or single-crease patch there would
//! not add it.
//! Each such vertex gets one frame after the sector frames whose position row is the exact limit
//! position (its tangent rows empty: no normal); every quad end cap there reads it, so all add
//! the same `delta` (exact minus slot position) at the vertex, faded alike along shared edges.

use super::census_index::is_quad_end_cap;
use super::promoted::{corner_offset_code, corner_offset_vertex, exact_corner_position};
use super::slots::{Slots, NONE};
use super::surface::EndCapTopologies;
use crate::patch::gregory::word_hash::WordHashMap;
use crate::patch::gregory::Weights;
use crate::subdiv::adaptive::{AdaptiveRefinement, PatchCensus, PatchType};
use crate::subdiv::limit::SharedVertexMasks;

/// The exact-position frames of a census and which end-cap corners read them.
#[derive(Debug, Clone, Default)]
pub struct ExactCorners {
    /// Per frame: the row of its exact limit position.
    pub rows: Vec<Weights>,
    /// Per census patch, face corner order: the frame of the corner's exact position, [`NONE`]
    /// for none.
    pub frames: Vec<[u32; 4]>,
    /// Per census patch, bits `8k..8k + 8`: the fade width code of corner `k`'s offset
    /// ([`corner_offset_code`]; 0 where it has none).
    pub codes: Vec<u32>,
}

impl ExactCorners {
    /// The frames of the quad end caps' promoted corners the positional fillet does not reach
    /// whole, numbered from `first` in census order; `at` as
    /// [`super::census_index::patch_index`]; `masks` the build's exact limit masks.
    pub fn new(
        refinement: &AdaptiveRefinement,
        census: &PatchCensus,
        topologies: &EndCapTopologies,
        slots: &Slots,
        at: &[Vec<u32>],
        first: u32,
        masks: &SharedVertexMasks,
    ) -> ExactCorners {
        let mut out = ExactCorners {
            frames: Vec::with_capacity(census.patches.len()),
            codes: Vec::with_capacity(census.patches.len()),
            ..Default::default()
        };
        let mut by_slot: WordHashMap<u32, u32> = WordHashMap::default();
        // Per level, per vertex: its offset's width code where it is a corner-offset vertex,
        // else `None`; a property of the vertex, asked by each of its up to four quad end caps
        // (outer `None`: not asked yet; a level's table is made when first asked).
        let mut offset_codes: Vec<Vec<Option<Option<u32>>>> =
            vec![Vec::new(); refinement.levels.len()];
        for p in &census.patches {
            let mut frames = [NONE; 4];
            let mut codes = 0;
            let lev = &refinement.levels[p.level as usize];
            let t = lev.topology();
            if p.kind == PatchType::EndCap && t.face_size(p.face) == 4 {
                let caps = topologies.get(p.level);
                // A quad end cap of this level (the positional fillet's neighbours).
                let quad_cap = |g: u32| is_quad_end_cap(lev, census, &at[p.level as usize], g);
                let codes_here = &mut offset_codes[p.level as usize];
                if codes_here.is_empty() {
                    codes_here.resize(t.vertex_count(), None);
                }
                for (k, &v) in t.face_vertices(p.face).iter().enumerate() {
                    let code = *codes_here[v as usize].get_or_insert_with(|| {
                        corner_offset_vertex(t, caps, v, quad_cap)
                            .then(|| corner_offset_code(t, caps, v))
                    });
                    let Some(code) = code else {
                        continue;
                    };
                    let slot = slots.of(lev.global(v));
                    let frame = match by_slot.get(&slot) {
                        Some(&f) => f,
                        None => {
                            let Some(row) = exact_corner_position(lev, p.face, k, masks) else {
                                continue;
                            };
                            let f = first + out.rows.len() as u32;
                            out.rows.push(row);
                            by_slot.insert(slot, f);
                            f
                        }
                    };
                    frames[k] = frame;
                    codes |= code << (8 * k);
                }
            }
            out.frames.push(frames);
            out.codes.push(codes);
        }
        out
    }
}
