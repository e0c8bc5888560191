//! Exact evaluation of the Catmull-Clark limit surface at any `(face, sub, u, v)`.

use glam::DVec3;

/// A point of the limit surface with its partial derivatives and unit normal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LimitSample {
    /// Limit position.
    pub position: DVec3,
    /// dP/du (at an extraordinary vertex: a tangent along the face's u edge, scaled arbitrarily).
    pub du: DVec3,
    /// dP/dv (at an extraordinary vertex: a tangent along the face's v edge, scaled arbitrarily).
    pub dv: DVec3,
    /// `normalize(du x dv)`: outward for counter-clockwise faces.
    pub normal: DVec3,
}

impl LimitSample {
    /// Builds a sample from position and partials; the normal is `normalize(du x dv)` (zero if
    /// the partials are parallel).
    pub fn new(position: DVec3, du: DVec3, dv: DVec3) -> LimitSample {
        LimitSample {
            position,
            du,
            dv,
            normal: du.cross(dv).normalize_or_zero(),
        }
    }
}
