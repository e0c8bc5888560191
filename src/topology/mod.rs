//! Mesh topology: edges, ordered one-rings, boundaries, per-face classification.
//!
//! [`Topology`] stores flat arrays (CSR style). One-ring convention, used everywhere in the
//! crate: around vertex `v`, `vertex_faces(v)[i]` lies between `vertex_edges(v)[i]` (the edge
//! leaving `v` along that face's winding) and `vertex_edges(v)[i + 1]` (cyclically for interior
//! vertices). The order is counter-clockwise seen from outside. A boundary vertex has one more
//! edge than faces and its ring starts at a boundary edge.
//!
//! The topology also carries the subdivision tags after the boundary rule has been applied:
//! boundary edges are infinitely sharp, and with
//! [`crate::mesh::BoundaryInterpolation::EdgeAndCorner`] a boundary vertex with a single face is
//! an infinitely sharp corner.

mod build;
mod connectivity;
mod fans;
pub(crate) mod par;
pub mod sectors;

pub(crate) use build::{build, with_given_rings, Connectivity, Rings};
pub(crate) use connectivity::NONE;
pub use connectivity::{FaceClass, Topology};
pub(crate) use fans::RingBuilder;
pub use sectors::{
    is_sharp_edge, sector_count, sector_counts, sector_faces, sector_slots, single_normal_vertex,
};

#[cfg(test)]
mod tests;
