//! Per-level look-ups of an adaptive refinement's census that the draw tables, the exact
//! corners, the lattice frames and the CPU surface share: which census patch each face is, the
//! quad-end-cap neighbour test, each level's topology as its end caps see it.

use std::borrow::Cow;

use super::slots::NONE;
use crate::subdiv::adaptive::{AdaptiveLevel, AdaptiveRefinement, PatchCensus, PatchType};
use crate::topology::Topology;

/// Per level, face to its census patch ([`NONE`] when the face is not drawn at that level).
pub fn patch_index(refinement: &AdaptiveRefinement, census: &PatchCensus) -> Vec<Vec<u32>> {
    let mut at: Vec<Vec<u32>> = refinement
        .levels
        .iter()
        .map(|l| vec![NONE; l.level.face_count()])
        .collect();
    for (i, p) in census.patches.iter().enumerate() {
        at[p.level as usize][p.face as usize] = i as u32;
    }
    at
}

/// Whether face `g` of `lev` is a quad end cap drawn at that level (`at`: that level's
/// [`patch_index`]), the neighbour the fillets and corner offsets of
/// [`super::promoted`] need on every side.
pub fn is_quad_end_cap(lev: &AdaptiveLevel, census: &PatchCensus, at: &[u32], g: u32) -> bool {
    lev.own[g as usize]
        && lev.topology().face_size(g) == 4
        && at[g as usize] != NONE
        && census.patches[at[g as usize] as usize].kind == PatchType::EndCap
}

/// Per level, its topology as its end caps see it ([`AdaptiveRefinement::end_cap_topology`]),
/// built once for the levels with end caps (the isolation level); the level's own topology
/// elsewhere.
pub struct EndCapTopologies<'a> {
    refinement: &'a AdaptiveRefinement,
    levels: Vec<Option<Cow<'a, Topology>>>,
}

impl<'a> EndCapTopologies<'a> {
    /// The end-cap topologies of `refinement`'s levels holding end caps of `census`.
    pub fn new(refinement: &'a AdaptiveRefinement, census: &PatchCensus) -> Self {
        let mut levels: Vec<Option<Cow<'a, Topology>>> =
            (0..refinement.levels.len()).map(|_| None).collect();
        for p in census
            .patches
            .iter()
            .filter(|p| p.kind == PatchType::EndCap)
        {
            let l = p.level as usize;
            if levels[l].is_none() {
                levels[l] = Some(refinement.end_cap_topology(l));
            }
        }
        EndCapTopologies { refinement, levels }
    }

    /// Level `level`'s topology as its end caps see it.
    pub fn get(&self, level: u32) -> &Topology {
        match &self.levels[level as usize] {
            Some(t) => t,
            None => self.refinement.levels[level as usize].topology(),
        }
    }
}
