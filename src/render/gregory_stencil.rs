//! The stencil variant of Gregory patches on the GPU (Loop et al. 2009, §4.3).

pub mod bench;
pub mod gpu;
pub mod session;

pub use bench::{bench_gregory, bench_paths, GregoryBenchRow, PathsBenchRow};
pub use gpu::{frame_set_layout, StencilPatches, StencilPlan};
pub use session::{GregoryFrameReport, GregorySession, GregoryVariant, SessionOptions};

pub use crate::patch::gregory::gregory_faces;
pub use crate::patch::gregory::stencil::MAX_RING;
pub use crate::patch::gregory::stencil_table::{
    GregoryStencilTable, Rejected, StencilPatch, StencilType, QUAD_POINTS, TRI_POINTS,
};
