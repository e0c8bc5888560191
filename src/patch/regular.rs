//! Regular bicubic B-spline patches (Köbler 2013 §3.1) as a patch scheme. The patch itself,
//! its gather from the topology and its evaluation live in [`crate::subdiv::bspline`], because
//! exact limit evaluation ([`crate::subdiv::eval`]) needs them and `subdiv` never depends on
//! `patch`.

pub use crate::subdiv::bspline::{eval_bspline, RegularPatch};
