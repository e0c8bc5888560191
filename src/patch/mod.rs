//! Patch schemes: CPU construction and reference evaluation, one module per scheme.
//!
//! - [`acc`]: ACC geometry patches of smooth interior quads (Loop, Schaefer 2008 §3).
//! - [`adaptive`]: the patches of a feature-adaptive refinement (B-splines and Gregory end
//!   caps at the isolation level) as one CPU surface.
//! - [`basis`]: cubic B-spline and Bernstein bases, B-spline to Bézier conversion.
//! - [`edge_grid`]: the canonical 12-point grid of a B-spline patch edge (watertight edges).
//! - [`regular`]: bicubic B-spline patches of regular (and boundary-regular) quads (defined in
//!   [`crate::subdiv::bspline`], which exact evaluation builds on).
//! - [`single_crease`]: regular quads with one semi-sharp crease line, evaluated directly
//!   (Nießner, Loop, Greiner 2012).
//! - [`gregory`]: Gregory patches of the other triangles and quads, with their stencil forms.
//! - [`qas`]: quadratic patches fitted to one Catmull-Clark step's limit points (Boubekeur,
//!   Schlick 2007).
//! - [`acc`]: ACC bicubic geometry patches of smooth quads (Loop, Schaefer 2008), a baseline.
//! - [`pm`]: Pm-patches (Myles, Ni, Peters 2008): one G1 patch per tri/quad/pent facet.

pub mod acc;
pub mod adaptive;
pub mod basis;
pub mod edge_grid;
pub mod gregory;
pub mod pm;
pub mod qas;
pub mod regular;
pub mod single_crease;

pub use regular::RegularPatch;
