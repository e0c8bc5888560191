//! The crate's error type. Every failure a user can trigger (bad input, missing device features)
//! is reported through [`Error`]; nothing a user supplies may cause a panic.

use thiserror::Error;

/// Result alias used throughout the crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Every error tessera reports. Variants name the offending element (vertex, face, edge, line).
#[derive(Debug, Error, Clone, PartialEq)]
pub enum Error {
    /// The mesh has no vertices or no faces.
    #[error("empty mesh: {0}")]
    EmptyMesh(String),
    /// Generic invalid input that does not fit another variant.
    #[error("invalid input: {0}")]
    Invalid(String),
    /// Vulkan / device failure (see [`crate::gpu::GpuError`]).
    #[error(transparent)]
    Gpu(#[from] crate::gpu::GpuError),
}
