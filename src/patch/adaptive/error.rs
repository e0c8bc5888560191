//! Why the draw tables of an adaptive refinement cannot be built.

use thiserror::Error;

use super::surface::EndCapError;

/// Why the draw tables of a refinement cannot be built.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Error)]
pub enum DrawTablesError {
    /// An end cap without Gregory patch.
    #[error(transparent)]
    EndCap(#[from] EndCapError),
    /// Two patches sharing an edge are more than one level apart (Köbler 2013 §3.7 rules this
    /// out; the coarse-edge records assume it).
    #[error("patch of base face {base_face} (level {level} face {face}): the patch across its edge {edge} is more than one level away")]
    LevelGap {
        /// Base face of the patch.
        base_face: u32,
        /// Its level.
        level: u32,
        /// Its face in the level.
        face: u32,
        /// Its face edge.
        edge: u32,
    },
}

impl DrawTablesError {
    /// The base face the error names.
    pub fn base_face(&self) -> u32 {
        match self {
            DrawTablesError::EndCap(e) => e.base_face,
            DrawTablesError::LevelGap { base_face, .. } => *base_face,
        }
    }
}
