//! tessera: Catmull-Clark subdivision surfaces rendered through real Vulkan tessellation stages.
//!
//! Layers, from the bottom up (the lower layers never depend on the upper ones):
//! - [`mesh`]: control meshes, OBJ input with OpenSubdiv-style tags, validation.
//! - [`topology`]: edges, ordered one-rings, boundaries and per-face classification.
//! - [`subdiv`]: Catmull-Clark rules with semi-sharp creases, refinement, limit masks,
//!   exact limit evaluation and stencil tables.
//! - [`patch`]: patch schemes (regular B-spline, ...) as CPU construction + reference evaluation.
//!
//! No Vulkan type appears in these layers.

pub mod assets;
pub mod error;
pub mod gpu;
pub mod mesh;
pub mod patch;
pub mod render;
pub mod subdiv;
pub mod topology;

pub use error::{Error, Result};
pub use mesh::ControlMesh;

/// The README's code blocks, compiled as doc tests (the "As a library" integration).
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
