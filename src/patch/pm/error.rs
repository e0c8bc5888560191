//! Why a facet gets no patch of the Pm construction.

use std::fmt;

/// Why a facet gets no patch (the construction refuses it; a caller may draw it otherwise).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NotPm {
    /// The facet has more than five sides (or fewer than three).
    Polygon {
        /// The facet.
        face: u32,
        /// Its number of sides.
        size: usize,
    },
    /// The facet is a hole (tagged without surface).
    Hole {
        /// The facet.
        face: u32,
    },
    /// A corner lies on the mesh boundary (the paper covers closed meshes only).
    Boundary {
        /// The facet.
        face: u32,
        /// The boundary vertex.
        vertex: u32,
    },
    /// A corner has fewer than three edges, or its ring is not a closed fan of faces.
    Valence {
        /// The facet.
        face: u32,
        /// The vertex.
        vertex: u32,
        /// Its valence.
        valence: usize,
    },
}

impl NotPm {
    /// The refused facet.
    pub fn face(&self) -> u32 {
        match *self {
            NotPm::Polygon { face, .. }
            | NotPm::Hole { face }
            | NotPm::Boundary { face, .. }
            | NotPm::Valence { face, .. } => face,
        }
    }
}

impl fmt::Display for NotPm {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            NotPm::Polygon { face, size } => write!(
                f,
                "face {face}: {size} sides; Pm-patches take triangles, quads and pentagons"
            ),
            NotPm::Hole { face } => write!(f, "face {face}: a hole has no surface"),
            NotPm::Boundary { face, vertex } => write!(
                f,
                "face {face}: vertex {vertex} is on the boundary; Pm-patches need closed meshes"
            ),
            NotPm::Valence {
                face,
                vertex,
                valence,
            } => write!(
                f,
                "face {face}: vertex {vertex} of valence {valence} has no closed ring of at least three faces"
            ),
        }
    }
}

impl std::error::Error for NotPm {}
