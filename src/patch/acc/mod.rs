//! ACC geometry patches (Loop and Schaefer 2008, "Approximating Catmull-Clark Subdivision
//! Surfaces with Bicubic Patches", §3): per quad a bicubic Bézier patch whose 16 points are
//! masks over the one-rings of its corners.
//!
//! For corner `v` of valence `n` in a quad `(v, a, c, b)` (`a` the next corner, `c` the opposite
//! one, `b` the previous): the *interior point* `(n v + 2 (a + b) + c) / (n + 5)`. The patch takes
//! the interior points of its own face at its four inner points, at each corner the average of
//! the `n` interior points around the vertex, which is the Catmull-Clark limit position
//! `(n² v + 4 Σ edge neighbours + Σ diagonal neighbours) / (n (n + 5))`, and on each edge, next
//! to each end, the average of the two interior points of that end on either side of the edge
//! (weights `2n, 4, 2, 2, 1, 1` over `2n + 10`): both faces of an edge compute the same cubic
//! boundary curve, so the patches meet with C0. For valence 4 the masks are the B-spline to
//! Bézier change of basis, so a regular quad reproduces its B-spline patch exactly. At other
//! valences the edge points do not lie in the limit tangent plane (the averages keep every
//! Fourier mode of the ring, the tangent plane only the subdominant one): the geometry patches
//! are not G1 there, which the paper's separate tangent patches address for shading
//! ([`tangent`]: a continuous normal field over the C0 geometry). Faces that are not quads, or
//! whose corners touch a boundary, a crease or a non-quad face, are refused ([`NotAcc`]).

pub mod geometry;
pub mod tangent;

pub use geometry::{acc_patch, check_face, AccPatch, NotAcc};
pub use tangent::{AccEdgeFrame, AccTangentPatches};
