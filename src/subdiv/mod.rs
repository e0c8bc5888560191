//! Catmull-Clark subdivision: rules, refinement, limit masks, regular B-spline patches, exact
//! evaluation, stencil tables.
//!
//! [`Level`] is the unit of refinement; [`Level::refine`] performs one uniform step and returns
//! the child level with its [`SparseMatrix`]; [`StencilTable`] composes those matrices.

pub mod adaptive;
pub mod bspline;
pub mod eval;
mod kept;
mod level;
pub mod limit;
mod points;
mod refine;
mod ring_step;
pub mod rules;
pub mod single_crease;
pub mod sparse;
mod stencil;
pub mod tables;

pub use level::Level;
pub use sparse::SparseMatrix;
pub use stencil::StencilTable;

/// Levels `0..=depth` (uniform refinement) of each corpus mesh `names`
/// (`../shared/meshes/osd/NAME.obj`), as `(name, level index, level)`: unit tests' inputs.
#[cfg(test)]
pub(crate) fn corpus_levels(names: &[&str], depth: u32) -> Vec<(String, u32, Level)> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/meshes/osd/");
    let mut out = Vec::new();
    for name in names {
        let path = format!("{dir}{name}.obj");
        let mesh = crate::ControlMesh::from_obj_file(&path, &Default::default()).unwrap();
        let mut level = Level::from_mesh(&mesh).unwrap();
        for d in 0..=depth {
            let next = (d < depth).then(|| level.refine_topology());
            out.push((name.to_string(), d, level));
            match next {
                Some(n) => level = n,
                None => break,
            }
        }
    }
    out
}
