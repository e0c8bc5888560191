//! Validation of a [`super::ControlMeshDesc`] before it becomes a [`super::ControlMesh`].
//!
//! Temporary minimal checks (index ranges, face sizes, hole indices) so that construction never
//! panics; the full set of typed checks is being written in this module.

use super::ControlMeshDesc;
use crate::{Error, Result};

/// Checks a description; the first problem found is returned.
pub fn validate(desc: &ControlMeshDesc) -> Result<()> {
    if desc.positions.is_empty() || desc.face_sizes.is_empty() {
        return Err(Error::EmptyMesh("no vertices or no faces".into()));
    }
    let total: u64 = desc.face_sizes.iter().map(|&n| n as u64).sum();
    if total != desc.face_vertices.len() as u64 {
        return Err(Error::Invalid("face sizes do not add up to the face-vertex count".into()));
    }
    let nv = desc.positions.len() as u32;
    if let Some(i) = desc.face_vertices.iter().position(|&v| v >= nv) {
        return Err(Error::Invalid(format!("face-vertex index {i} out of range")));
    }
    if desc.face_sizes.iter().any(|&n| n < 3) {
        return Err(Error::Invalid("face with fewer than 3 vertices".into()));
    }
    let nf = desc.face_sizes.len() as u32;
    if desc.holes.iter().any(|&h| h >= nf) {
        return Err(Error::Invalid("hole index out of range".into()));
    }
    Ok(())
}
