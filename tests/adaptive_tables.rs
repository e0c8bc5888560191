//! The subdivision tables of `subdiv::tables` (Köbler 2013, section 4.2), applied level by level
//! on the CPU, reproduce the crate's refinement (`StencilTable::refined`) on the shared meshes.

mod common;

use common::levels::worst_level_error;
use common::meshes::{corpus_options, mesh, osd_names, osd_path};
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
