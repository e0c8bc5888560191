//! A buffer holding every level of a uniform refinement (`subdiv::tables::RefinementTables`
//! layout) measured against the crate's f64 refinement (`StencilTable::refined`), and a
//! vertex's limit position by local refinement.

use glam::DVec3;
use tessera::subdiv::adaptive::AdaptiveRefinement;
use tessera::subdiv::tables::RefinementTables;
use tessera::subdiv::{Level, StencilTable};
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

/// The limit position of vertex `v` by local refinement: `levels` steps of the crate's
/// refinement of `v`'s faces, tracking `v`, then Aitken extrapolation of the last three
/// positions (the error of `v`'s position decays like the subdominant eigenvalue).
pub fn refined_limit(level: &Level, positions: &[DVec3], v: u32, levels: u32) -> DVec3 {
    let (mut level, mut pos, mut v) = (level.clone(), positions.to_vec(), v);
    let mut track = Vec::new();
    for _ in 0..levels {
        let faces = level.topology().vertex_faces(v).to_vec();
        let (sub, map) = level.extract(&faces);
        let sub_pos: Vec<DVec3> = map.iter().map(|&i| pos[i as usize]).collect();
        let v_sub = map.iter().position(|&x| x == v).unwrap() as u32;
        let (child, r) = sub.refine();
        pos = r.apply_vec(&sub_pos);
        v = sub.child_vertex_point(v_sub);
        level = child;
        track.push(pos[v as usize]);
    }
    let [a, b, c] = [
        track[track.len() - 3],
        track[track.len() - 2],
        track[track.len() - 1],
    ];
    let (d1, d2) = (b - a, c - b);
    if d2.length() == 0.0 {
        return c;
    }
    let r = d2.length() / d1.length();
    c + d2 * (r / (1.0 - r))
}
