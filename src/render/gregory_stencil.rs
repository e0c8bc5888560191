//! The stencil variant of Gregory patches on the GPU (Loop et al. 2009, §4.3).

pub mod bench;
pub mod gpu;
pub mod session;
pub mod table;

pub use bench::{bench_gregory, bench_paths, GregoryBenchRow, PathsBenchRow};
pub use gpu::{frame_set_layout, StencilPatches, StencilPlan};
pub use session::{GregoryFrameReport, GregorySession, GregoryVariant, SessionOptions};

pub use table::{
    gregory_faces, Rejected, StencilPatch, StencilTable, StencilType, MAX_RING, QUAD_POINTS,
    TRI_POINTS,
};
