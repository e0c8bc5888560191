//! Machinery every patch scheme shares, written once: buffer uploads ([`upload`]), the shared
//! descriptor bindings and buffers of a surface ([`shared`]), the per-vertex limit frames every
//! patch corner reads ([`frames`]), the chunked × sub-patch draw loop ([`draw`]), TES capture
//! ([`capture`]) and the raster state and push constants of patch pipelines ([`pipeline`]).

pub mod capture;
pub mod draw;
pub mod frames;
pub mod pipeline;
pub mod shared;
pub mod upload;

pub use capture::{
    capture_capacity_for, triangle_bucket, Capture, CaptureRecord, CapturedPatch, CapturedTriangle,
    TriangleWindow, CAPTURE_HEADER_BYTES, CAPTURE_RECORD_BYTES, MAX_BUCKETS,
};
pub use draw::{bind_draw_state, largest_level, record_patch_draws, PatchDraws};
pub use frames::{NormalRule, VertexFrames};
pub use shared::SharedResources;
