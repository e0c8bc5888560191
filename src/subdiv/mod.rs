//! Catmull-Clark subdivision: rules, refinement, limit masks, regular B-spline patches, exact
//! evaluation, stencil tables.
//!
//! [`Level`] is the unit of refinement; [`Level::refine`] performs one uniform step and returns
//! the child level with its [`SparseMatrix`]; [`StencilTable`] composes those matrices.

pub mod adaptive;
pub mod bspline;
pub mod eval;
mod level;
pub mod limit;
mod points;
mod refine;
pub mod rules;
pub mod single_crease;
pub mod sparse;
mod stencil;
pub mod tables;

pub use level::Level;
pub use sparse::SparseMatrix;
pub use stencil::StencilTable;
