//! Gregory patches approximating Catmull-Clark surfaces (Loop, Schaefer, Ni, Castaño 2009).
//!
//! Every face that is not a regular B-spline patch becomes one Gregory patch: a quad face a
//! 20-point bicubic [`GregoryQuad`], a triangle a 15-point cubic-quartic [`GregoryTriangle`]
//! (paper §3.1, Fig. 4). Control points come in three kinds (§3.2-3.4):
//! - corner points `p[i]` on the Catmull-Clark limit surface,
//! - edge points `e_plus[i]` (on the edge from corner `i` to corner `i + 1`) and `e_minus[i]`
//!   (on the edge from corner `i` to corner `i - 1`), interpolating the limit tangent plane,
//! - face points `f_plus[i]` (next to the edge `i -> i + 1`) and `f_minus[i]` (next to the edge
//!   `i -> i - 1`), chosen for tangent-plane continuity across edges (eq. 6).
//!
//! Boundaries and infinitely sharp creases follow §4.6 ([`GregoryVertex::sectored`]). Faces
//! touching darts, semi-sharp tags, cone points or one-face crease sectors, polygons with more
//! than four sides and holes get no patch ([`NotGregory`]); the renderer keeps its exact CPU
//! path for them. Adaptive end caps ([`Coverage::EndCap`]) also take cone points, one-face crease
//! sectors and wide corner sectors, with the exact limit point and approximated tangents there.
//!
//! The construction is generic over [`GregoryPoint`]: run on positions it gives the patch, run on
//! unit weight vectors ([`Weights`]) it gives the stencil form of §4.3: one face's stencil in
//! [`stencil`], the faces of a mesh grouped by connectivity type for the GPU stencil variant in
//! [`stencil_table`]. [`table`] holds the flat per-vertex tables of the two-stage GPU variant
//! (§4.1-4.2).
//!
//! Corner `i` of a patch is corner `i` of its face; a quad patch uses the face's (u, v)
//! (corners at (0,0), (1,0), (1,1), (0,1)); a triangle patch uses barycentric
//! `(1 - u - v, u, v)` of corners 0, 1, 2.

pub mod accuracy;
mod build;
pub mod closest;
mod corner_rings;
mod corner_types;
pub mod edge_flags;
mod eval;
mod face_rows;
mod point;
pub mod shared_rows;
pub mod stencil;
pub mod stencil_table;
pub mod table;
pub mod tangent_fit;
pub mod tangents;
pub mod tangents_boundary;
pub mod tangents_tri;
pub mod tangents_tri_fit;
mod vertex;
pub mod vertex_fit;
/// The house's word hash, kept in `subdiv` (which cannot use `patch`) and re-exported here.
pub(crate) use crate::subdiv::word_hash;

pub use build::{
    check_face, check_face_for, check_face_level0, check_vertex, check_vertex_for, gregory_faces,
    gregory_patch, gregory_patch_at, gregory_patch_at_for, gregory_patch_at_with,
    gregory_patch_for, gregory_patch_weights, gregory_patch_weights_with, gregory_vertex,
    gregory_vertex_for, gregory_vertex_two_stage, gregory_vertex_with, gregory_vertices,
    gregory_vertices_with, is_supported_vertex, one_face_crease_sector, vertex_ring,
    vertex_ring_with, Coverage, GregoryPatch, NotGregory,
};
pub use eval::{CornerRef, GregoryQuad, GregoryTriangle, PatchPoint};
pub use point::{apply_terms, combine, GregoryPoint, Weights};
pub use tangents::GregoryTangents;
pub use vertex::{
    crease_tangent_weights, face_point, face_point_cos, is_interior_ring, sectors,
    subdominant_eigenvalue, DartLimits, GregoryVertex, InteriorBasis, Sector, VertexKind,
    VertexRing,
};
