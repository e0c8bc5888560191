//! The subdivision tables of `subdiv::tables` (Köbler 2013, section 4.2), applied level by level
//! on the CPU, reproduce the crate's refinement (`StencilTable::refined`) on the shared meshes.

mod common;

use common::meshes::{corpus_options, mesh, osd_names, osd_path};
use glam::DVec3;
use tessera::subdiv::tables::RefinementTables;
use tessera::subdiv::{Level, StencilTable};
use tessera::ControlMesh;

const DEPTH: u32 = 3;

fn diagonal(points: &[DVec3]) -> f64 {
    let lo = points.iter().fold(DVec3::splat(f64::MAX), |a, &p| a.min(p));
    let hi = points.iter().fold(DVec3::splat(f64::MIN), |a, &p| a.max(p));
    (hi - lo).length().max(f64::MIN_POSITIVE)
}

/// Worst distance (relative to the bbox diagonal) between the table refinement and the
/// stencil refinement over every level `1..=DEPTH`.
fn worst_relative_error(m: &ControlMesh) -> f64 {
    let level = Level::from_mesh(m).unwrap();
    let tables = RefinementTables::uniform(&level, DEPTH).unwrap();
    let control = m.positions();
    let buffer = tables.refine_cpu(control);
    let diag = diagonal(control);
    let mut worst = 0.0f64;
    for l in 1..=DEPTH {
        let expect = StencilTable::refined(m, l).unwrap().apply_vec(control);
        let start = tables.level_offsets[l as usize] as usize;
        assert_eq!(expect.len(), tables.level_len(l as usize) as usize);
        for (a, b) in buffer[start..start + expect.len()].iter().zip(&expect) {
            worst = worst.max(a.distance(*b) / diag);
        }
    }
    worst
}

#[test]
fn tables_reproduce_the_refinement_on_the_shared_meshes() {
    let mut checked = 0;
    for name in osd_names() {
        let Ok(m) = ControlMesh::from_obj_file(osd_path(&name), &corpus_options(&name)) else {
            continue;
        };
        let worst = worst_relative_error(&m);
        assert!(worst <= 1e-12, "{name}: {worst:e} of the diagonal");
        checked += 1;
    }
    for name in ["embedded:mixed", "embedded:open", "embedded:creased"] {
        let worst = worst_relative_error(&mesh(name));
        assert!(worst <= 1e-12, "{name}: {worst:e} of the diagonal");
    }
    assert!(checked >= 60, "only {checked} shared meshes loaded");
}
