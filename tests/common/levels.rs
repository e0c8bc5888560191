//! A buffer holding every level of a uniform refinement (`subdiv::tables::RefinementTables`
//! layout) measured against the crate's f64 refinement (`StencilTable::refined`).

use glam::DVec3;
use tessera::subdiv::adaptive::AdaptiveRefinement;
use tessera::subdiv::tables::RefinementTables;
use tessera::subdiv::StencilTable;
use tessera::ControlMesh;

/// The worst distance, relative to the bbox diagonal of `control`, between the refined levels
/// `1..` of `buffer` (laid out as `tables` says) and the uniform refinement of `mesh` with its
/// vertices at `control`.
pub fn worst_level_error(
    mesh: &ControlMesh,
    control: &[DVec3],
    tables: &RefinementTables,
    buffer: &[DVec3],
) -> f64 {
    let diag = diagonal(control);
    let mut worst = 0.0f64;
    for l in 1..tables.level_offsets.len() {
        let expect = StencilTable::refined(mesh, l as u32)
            .unwrap()
            .apply_vec(control);
        let start = tables.level_offsets[l] as usize;
        assert_eq!(expect.len(), tables.level_len(l) as usize, "level {l} size");
        for (a, b) in buffer[start..start + expect.len()].iter().zip(&expect) {
            worst = worst.max(a.distance(*b) / diag);
        }
    }
    worst
}

/// The bbox diagonal of `points`.
pub fn diagonal(points: &[DVec3]) -> f64 {
    let lo = points.iter().fold(DVec3::MAX, |a, &p| a.min(p));
    let hi = points.iter().fold(DVec3::MIN, |a, &p| a.max(p));
    (hi - lo).length()
}

/// The worst distance, relative to the bbox diagonal of `control`, between `buffer` (every
/// vertex of every level, global numbering) and the f64 adaptive refinement of `control`.
pub fn worst_adaptive_error(
    refinement: &AdaptiveRefinement,
    control: &[DVec3],
    buffer: &[DVec3],
) -> f64 {
    let expect = refinement.refine_positions(control);
    assert_eq!(buffer.len(), expect.len(), "refined vertex count");
    let diag = diagonal(control);
    buffer
        .iter()
        .zip(&expect)
        .map(|(a, b)| a.distance(*b) / diag)
        .fold(0.0, f64::max)
}
