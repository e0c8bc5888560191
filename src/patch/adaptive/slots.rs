//! Frame slots: one dense index per limit point that is a patch corner, shared by the vertices
//! of every level that are that point (a vertex point is the same limit point as its parent
//! vertex, Köbler 2013 §3.5), so corners of patches of different levels read one frame.

use crate::subdiv::adaptive::{AdaptiveRefinement, ChildOf};

/// No slot / no entry.
pub const NONE: u32 = u32::MAX;

/// The slot of every global vertex that is a patch corner.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Slots {
    /// Per slot: the global id of its origin (the vertex of the coarsest level that is the
    /// point), increasing.
    pub origins: Vec<u32>,
    /// Per global vertex: its slot, [`NONE`] when no patch has that point as a corner.
    pub of_vertex: Vec<u32>,
}

/// Per global vertex: the global id of the coarsest vertex it is a vertex point of (itself
/// unless it is `ChildOf::Vertex`).
pub fn origins(refinement: &AdaptiveRefinement) -> Vec<u32> {
    let mut origin: Vec<u32> = Vec::with_capacity(refinement.vertex_count());
    for (l, lev) in refinement.levels.iter().enumerate() {
        let own = lev.global(0)..lev.global(lev.level.vertex_count() as u32);
        let Some(parent) = l.checked_sub(1).map(|p| &refinement.levels[p]) else {
            origin.extend(own);
            continue;
        };
        // Written in place over the level's room (no push per vertex), the parent level's
        // origins read from the part before it.
        let start = origin.len();
        origin.resize(start + own.len(), 0);
        let (done, level) = origin.split_at_mut(start);
        let parents = &done[parent.global(0) as usize..];
        debug_assert_eq!(parent.children_of().len(), level.len());
        for ((o, g), &child) in level.iter_mut().zip(own).zip(parent.children_of()) {
            *o = match child {
                ChildOf::Vertex(p) => parents[p as usize],
                _ => g,
            };
        }
    }
    origin
}

impl Slots {
    /// Slots of the points of `corners` (global vertex ids of patch corners), numbered by
    /// increasing origin id, and per slot the place in `corners` of its first corner there (the
    /// frame's corner: `CornerRows::visit` order gives the exact patches' first).
    pub fn new(
        refinement: &AdaptiveRefinement,
        corners: impl ExactSizeIterator<Item = u32>,
    ) -> (Slots, Vec<u32>) {
        let mut of_vertex = origins(refinement);
        // At most a slot per corner and per vertex: room for every slot up front.
        let most = corners.len().min(of_vertex.len());
        // Per origin: the first corner there (its place in `corners`; NONE is above every
        // place), then the origin's slot.
        let mut at_origin = vec![NONE; of_vertex.len()];
        for (i, g) in corners.enumerate() {
            let first = &mut at_origin[of_vertex[g as usize] as usize];
            *first = (*first).min(i as u32);
        }
        let (mut origins, mut first_corners) = (Vec::with_capacity(most), Vec::with_capacity(most));
        for (o, s) in at_origin.iter_mut().enumerate() {
            if *s != NONE {
                first_corners.push(*s);
                *s = origins.len() as u32;
                origins.push(o as u32);
            }
        }
        // Each vertex's origin replaced by the origin's slot, in place.
        for o in &mut of_vertex {
            *o = at_origin[*o as usize];
        }
        (Slots { origins, of_vertex }, first_corners)
    }

    /// Number of slots.
    pub fn len(&self) -> usize {
        self.origins.len()
    }

    /// Whether there is no slot.
    pub fn is_empty(&self) -> bool {
        self.origins.is_empty()
    }

    /// The slot of global vertex `g` ([`NONE`] if it is no patch corner's point).
    pub fn of(&self, g: u32) -> u32 {
        self.of_vertex[g as usize]
    }
}
