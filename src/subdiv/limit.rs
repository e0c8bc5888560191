//! Catmull-Clark limit masks: limit positions and tangents of the vertices of a [`Level`]
//! (smooth interior, crease/boundary, corner, dart), and limit stencils.

pub mod masks;
