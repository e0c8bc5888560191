//! The subdivision tables of `subdiv::tables` (Köbler 2013, section 4.2), applied level by level
//! on the CPU, reproduce the crate's refinement (`StencilTable::refined`) on the shared meshes,
//! uniform and feature-adaptive (`RefinementTables::adaptive` against
//! `AdaptiveRefinement::refine_positions`).

mod common;

use common::levels::{worst_adaptive_error, worst_level_error};
use common::meshes::{corpus_options, mesh, osd_names, osd_path, try_osd};
use tessera::subdiv::adaptive::AdaptiveRefinement;
use tessera::subdiv::tables::RefinementTables;
use tessera::subdiv::Level;
use tessera::ControlMesh;

/// Worst relative error of the f64 table refinement to depth 3.
fn table_error(m: &ControlMesh) -> f64 {
    let tables = RefinementTables::uniform(&Level::from_mesh(m).unwrap(), 3).unwrap();
    let buffer = tables.refine_cpu(m.positions());
    worst_level_error(m, m.positions(), &tables, &buffer)
}

#[test]
fn tables_reproduce_the_refinement_on_the_shared_meshes() {
    let mut checked = 0;
    for name in osd_names() {
        let Ok(m) = ControlMesh::from_obj_file(osd_path(&name), &corpus_options(&name)) else {
            continue;
        };
        let worst = table_error(&m);
        assert!(worst <= 1e-12, "{name}: {worst:e} of the diagonal");
        checked += 1;
    }
    for name in ["embedded:mixed", "embedded:open", "embedded:creased"] {
        let worst = table_error(&mesh(name));
        assert!(worst <= 1e-12, "{name}: {worst:e} of the diagonal");
    }
    assert!(checked >= 60, "only {checked} shared meshes loaded");
}

/// Worst distance, relative to the bbox diagonal, between the adaptive tables applied on the
/// CPU and `AdaptiveRefinement::refine_positions`, over every vertex of every level.
fn adaptive_table_error(m: &ControlMesh, isolation: u32) -> f64 {
    let refinement = AdaptiveRefinement::new(&Level::from_mesh(m).unwrap(), isolation).unwrap();
    let tables = RefinementTables::adaptive(&refinement).unwrap();
    worst_adaptive_error(
        &refinement,
        m.positions(),
        &tables.refine_cpu(m.positions()),
    )
}

#[test]
fn adaptive_tables_reproduce_the_adaptive_refinement() {
    let mut checked = 0;
    for name in osd_names() {
        let Ok(m) = try_osd(&name) else { continue };
        let deep =
            ["catmark_car", "catmark_cube_creases1", "catmark_pole64"].contains(&name.as_str());
        let mut worst = Vec::new();
        for isolation in 0..=if deep { 4 } else { 3 } {
            let e = adaptive_table_error(&m, isolation);
            assert!(
                e <= 1e-12,
                "{name} isolation {isolation}: {e:e} of the diagonal"
            );
            worst.push(format!("{e:.1e}"));
        }
        eprintln!("{name}: worst per isolation {}", worst.join(" "));
        checked += 1;
    }
    assert!(checked >= 60, "only {checked} shared meshes loaded");
}
