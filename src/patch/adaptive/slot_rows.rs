//! Slot frames' rows (position, d/du, d/dv of each frame slot, [`super::slots`]), from the first
//! census patch with the slot as a corner, exact patches (B-spline, single-crease) before end
//! caps ([`CornerRows::visit`]; `Slots::new` finds each slot's first corner as it numbers the
//! slots), in two steps: [`SlotCorners::new`] takes each slot's corner and
//! computes the exact frames of promoted corners (a failed one unshares its slot's normal, which
//! the sector frames read), and [`SlotCorners::rows`] writes the rows once the frames after them
//! are known, into one buffer with room for those too: the slot rows, most of the frame rows,
//! are written once and not copied when the buffer grows for the frames after them (cachegrind
//! counts a large copy at about one instruction per two bytes).

use rayon::prelude::*;

use super::promoted::{exact_frame, promoted_vertex};
use super::rows::{CornerRows, SparseRows, TemplateTerms, EXACT_CORNER_TERMS};
use super::slots::NONE;
use super::surface::EndCapTopologies;
use crate::patch::gregory::Weights;
use crate::subdiv::adaptive::{AdaptivePatch, AdaptiveRefinement, PatchCensus, PatchType};
use crate::subdiv::limit::SharedVertexMasks;
use crate::topology::single_normal_vertex;

/// Each slot's corner and the exact frames of the promoted ones.
pub struct SlotCorners {
    /// Per slot: the corner whose rows it takes (its place in [`CornerRows::visit`] order).
    first: Vec<u32>,
    /// Per slot: its frame in `exact_frames` where its corner is an end cap's on a promoted crease
    /// where the exact limit has one normal (`super::promoted`), else [`NONE`].
    exact_of: Vec<u32>,
    /// Those slots' frames ([`exact_frame`]; empty tangent rows where the exact mask failed).
    exact_frames: Vec<[Weights; 3]>,
    /// At least the number of terms of the slot rows (each corner's
    /// [`CornerRows::terms_bound`], and the exact frames' terms).
    terms_bound: usize,
}

impl SlotCorners {
    /// The slots' corners `first` (per slot, its first corner in `corner_rows`' visit, as
    /// [`super::slots::Slots::new`] gives them), and per slot whether its normal is shared
    /// (one sector in the topology the frame's patch was built over; not where a promoted
    /// corner's exact mask failed, which keeps its end cap's corner, one per sector); `masks`
    /// the exact limit masks of promoted corners, shared with the sector frames.
    pub fn new(
        refinement: &AdaptiveRefinement,
        census: &PatchCensus,
        topologies: &EndCapTopologies,
        first: Vec<u32>,
        corner_rows: &CornerRows,
        masks: &SharedVertexMasks,
    ) -> (SlotCorners, Vec<bool>) {
        let (mut exact_slots, mut terms_bound) = (Vec::new(), 0);
        let mut shared: Vec<bool> = (first.iter().enumerate())
            .map(|(s, &i)| {
                let c = corner_rows.corner(i);
                terms_bound += corner_rows.terms_bound(c);
                let p = &census.patches[c.patch];
                let lev = &refinement.levels[p.level as usize];
                match p.kind {
                    PatchType::EndCap => {
                        let (t, caps) = (lev.topology(), topologies.get(p.level));
                        let exact =
                            promoted_vertex(t, caps, c.vertex) && single_normal_vertex(t, c.vertex);
                        if exact {
                            exact_slots.push(s);
                        }
                        exact || single_normal_vertex(caps, c.vertex)
                    }
                    _ => {
                        smooth_bspline_corner(p, c.k)
                            || single_normal_vertex(lev.topology(), c.vertex)
                    }
                }
            })
            .collect();
        let exact_frames: Vec<[Weights; 3]> = exact_slots
            .par_iter()
            .map(|&s| {
                let c = corner_rows.corner(first[s]);
                let p = &census.patches[c.patch];
                let lev = &refinement.levels[p.level as usize];
                exact_frame(lev, p.face, c.k, corner_rows.position_row(c), masks)
            })
            .collect();
        let mut exact_of = vec![NONE; first.len()];
        for (i, (&s, frame)) in exact_slots.iter().zip(&exact_frames).enumerate() {
            exact_of[s] = i as u32;
            terms_bound += frame.iter().map(|w| w.0.len()).sum::<usize>();
            if frame[1].0.is_empty() {
                shared[s] = false;
            }
        }
        let corners = SlotCorners {
            first,
            exact_of,
            exact_frames,
            terms_bound,
        };
        (corners, shared)
    }

    /// The slot rows in slot order (computed on the rayon pool in runs of slots, each written
    /// into flat rows of its own, with room for an exact patch's corner rows a slot, and
    /// appended; on one thread straight into the result), with room for `spare` (rows, terms)
    /// more.
    pub fn rows(&self, corner_rows: &CornerRows, spare: (usize, usize)) -> SparseRows {
        let chunk = if rayon::current_num_threads() == 1 {
            self.first.len().max(1)
        } else {
            256
        };
        let mut out = SparseRows::new();
        if chunk >= self.first.len() {
            out.reserve(3 * self.first.len() + spare.0, self.terms_bound + spare.1);
            self.push_run(0, &self.first, corner_rows, &mut out);
            return out;
        }
        let runs: Vec<SparseRows> = self
            .first
            .par_chunks(chunk)
            .enumerate()
            .map(|(i, run)| {
                let mut rows = SparseRows::new();
                rows.reserve(3 * run.len(), EXACT_CORNER_TERMS * run.len());
                self.push_run(i * chunk, run, corner_rows, &mut rows);
                rows
            })
            .collect();
        out.reserve(
            runs.iter().map(SparseRows::len).sum::<usize>() + spare.0,
            runs.iter().map(|r| r.ids.len()).sum::<usize>() + spare.1,
        );
        for run in &runs {
            out.append(run);
        }
        out
    }

    /// The exact frame of slot `s`, if its corner takes one.
    fn exact_frame(&self, s: usize) -> Option<&[Weights; 3]> {
        let i = self.exact_of[s];
        (i != NONE).then(|| &self.exact_frames[i as usize])
    }

    /// Appends the rows of the slots from `first_slot` with corners `run` to `out`.
    fn push_run(
        &self,
        first_slot: usize,
        run: &[u32],
        corner_rows: &CornerRows,
        out: &mut SparseRows,
    ) {
        let mut terms = TemplateTerms::default();
        for (j, &c) in run.iter().enumerate() {
            match self.exact_frame(first_slot + j) {
                Some(frame) => {
                    for w in frame {
                        out.push(w, 0);
                    }
                }
                None => corner_rows.push_rows(corner_rows.corner(c), out, &mut terms),
            }
        }
    }
}

/// Whether corner `k` of `p` is a B-spline patch's corner with neither face edge beside it on a
/// phantom side (`RegularPatch::boundary_mask`: boundary or infinitely sharp): a regular corner
/// there is a smooth interior vertex of valence 4 (a regular crease or corner sector has a sharp
/// edge of each of its faces at the vertex, `bspline::corner_kind`), whose point has one sector
/// and one normal ([`single_normal_vertex`]), judged without walking its ring.
fn smooth_bspline_corner(p: &AdaptivePatch, k: usize) -> bool {
    let beside = 1 << k | 1 << ((k + 3) % 4);
    p.crease.is_none() && p.bspline.is_some_and(|b| b.boundary_mask & beside == 0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::patch::adaptive::rows::patch_corners;
    use crate::patch::adaptive::slots::{origins, Slots};
    use crate::subdiv::adaptive::corpus_refinements;

    /// Every census corner `smooth_bspline_corner` takes for one normal has one
    /// (`single_normal_vertex` of its level), and it takes some on every mesh; over meshes with
    /// boundaries, infinitely sharp creases and corners, darts and semi-sharp creases.
    #[test]
    fn smooth_bspline_corners_have_one_normal() {
        let cases = [
            ("catmark_car", 2),
            ("catmark_cube_creases1", 3),
            ("catmark_cube_corner4", 2),
            ("catmark_dart_edgecorner", 3),
            ("catmark_tent_creases1", 2),
            ("catmark_single_crease", 3),
            ("catmark_hole_test1", 2),
        ];
        for (name, refinement) in corpus_refinements(&cases) {
            let census = refinement.census();
            let mut taken = 0;
            for p in &census.patches {
                let t = refinement.levels[p.level as usize].topology();
                for (k, &v) in t.face_vertices(p.face).iter().enumerate().take(4) {
                    if smooth_bspline_corner(p, k) {
                        taken += 1;
                        assert!(
                            single_normal_vertex(t, v),
                            "{name}: vertex {v} of face {}",
                            p.face
                        );
                    }
                }
            }
            assert!(taken > 0, "{name}");
        }
    }

    /// Each vertex's origin is the vertex found by walking up its chain of vertex points one
    /// level at a time, itself where the chain stops at once; over meshes with and without end
    /// caps, and some vertices have an origin of another level.
    #[test]
    fn origins_end_vertex_point_chains() {
        let cases = [("catmark_car", 2), ("catmark_cube_creases1", 3)];
        for (name, refinement) in corpus_refinements(&cases) {
            let origin = origins(&refinement);
            assert_eq!(origin.len(), refinement.vertex_count(), "{name}");
            let mut moved = 0;
            for (l, lev) in refinement.levels.iter().enumerate() {
                for v in 0..lev.level.vertex_count() as u32 {
                    let (mut at, mut u) = (l, v);
                    while let Some(parent) = at.checked_sub(1).map(|p| &refinement.levels[p]) {
                        match parent.child_of(u) {
                            crate::subdiv::adaptive::ChildOf::Vertex(p) => (at, u) = (at - 1, p),
                            _ => break,
                        }
                    }
                    let want = refinement.levels[at].global(u);
                    moved += usize::from(want != lev.global(v));
                    assert_eq!(
                        origin[lev.global(v) as usize],
                        want,
                        "{name}: level {l}, {v}"
                    );
                }
            }
            assert!(moved > 0, "{name}");
        }
    }

    /// Every census corner has the slot of its origin, slots number the origins in increasing
    /// order, and each slot's first corner is the first corner at its point in the visit order
    /// (a scan over the corners); over meshes with end caps, creases, boundaries and holes.
    #[test]
    fn first_corners_are_the_first_at_each_point() {
        let cases = [
            ("catmark_car", 2),
            ("catmark_cube_creases1", 3),
            ("catmark_dart_edgecorner", 3),
            ("catmark_hole_test1", 2),
        ];
        for (name, refinement) in corpus_refinements(&cases) {
            let corners = patch_corners(&refinement, refinement.census());
            let (slots, first) = Slots::new(&refinement, corners.iter().map(|c| c.global));
            let origin = origins(&refinement);
            let mut want = vec![None; slots.len()];
            for (i, c) in corners.iter().enumerate() {
                let s = slots.of(c.global);
                assert_ne!(s, NONE, "{name}: corner {i}");
                assert_eq!(
                    slots.origins[s as usize], origin[c.global as usize],
                    "{name}"
                );
                want[s as usize].get_or_insert(i as u32);
            }
            let want: Vec<u32> = want.into_iter().map(|i| i.expect("a corner")).collect();
            assert_eq!(first, want, "{name}");
            assert!(slots.origins.windows(2).all(|o| o[0] < o[1]), "{name}");
        }
    }
}
