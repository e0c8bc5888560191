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
//! Corner `i` of a patch is corner `i` of its face; a quad patch uses the face's (u, v)
//! (corners at (0,0), (1,0), (1,1), (0,1)).

mod build;
mod eval;
mod vertex;

pub use build::{gregory_patch, gregory_vertices, is_supported_vertex, vertex_ring, GregoryPatch};
pub use eval::{CornerRef, GregoryQuad, GregoryTriangle, PatchPoint};
pub use vertex::{face_point, subdominant_eigenvalue, GregoryVertex, VertexRing};
