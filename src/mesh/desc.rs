//! What a [`ControlMesh`](super::ControlMesh) is built from: positions, faces, subdivision tags
//! and scheme options.

use glam::DVec3;

/// Sharpness at or above this value is infinitely sharp (the RenderMan / OpenSubdiv convention).
pub const INFINITE_SHARPNESS: f32 = 10.0;

/// How boundary edges and boundary corners are treated (`t interpolateboundary 1/0 m`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BoundaryInterpolation {
    /// `0`: boundary faces are not part of the limit surface (OpenSubdiv's `VTX_BOUNDARY_NONE`).
    None,
    /// `1`: boundary edges are infinitely sharp and valence-2 boundary vertices are corners.
    #[default]
    EdgeAndCorner,
    /// `2`: boundary edges are infinitely sharp, boundary corners follow the crease rule.
    EdgeOnly,
}

/// How semi-sharp crease sharpness decays under refinement (`t creasemethod 0/0/1 name`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CreaseMethod {
    /// Child sharpness is `s - 1` (DeRose, Kass, Truong 1998).
    #[default]
    Normal,
    /// Chaikin's rule: child sharpness averages with the neighbouring crease edges before `- 1`.
    Chaikin,
}

/// Subdivision options that a file or the API chooses for the whole mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SchemeOptions {
    /// Boundary interpolation rule.
    pub boundary: BoundaryInterpolation,
    /// Crease decay rule.
    pub crease_method: CreaseMethod,
}

/// A sharp edge given by its two end vertices (order does not matter).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crease {
    /// First end vertex (0-based).
    pub v0: u32,
    /// Second end vertex (0-based).
    pub v1: u32,
    /// Sharpness, `>= 0`; `>= INFINITE_SHARPNESS` is infinitely sharp.
    pub sharpness: f32,
}

/// A sharp (corner) vertex.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Corner {
    /// The vertex (0-based).
    pub vertex: u32,
    /// Sharpness, `>= 0`; `>= INFINITE_SHARPNESS` is infinitely sharp.
    pub sharpness: f32,
}

/// Everything needed to build a [`ControlMesh`](super::ControlMesh): the programmatic
/// constructor for engines.
///
/// Faces are given as `face_sizes` (one entry per face, each >= 3) and the concatenated
/// `face_vertices` (0-based), counter-clockwise seen from outside unless `left_handed` is set,
/// in which case every face is reversed on construction (corner 0 stays first). Crease and
/// corner vertices and hole faces are 0-based. [`ControlMesh::new`](super::ControlMesh::new)
/// validates everything and never panics; see [`validate`](super::validate) for the checks.
///
/// ```
/// use glam::DVec3;
/// use tessera::mesh::{ControlMeshDesc, Crease, INFINITE_SHARPNESS};
/// use tessera::ControlMesh;
///
/// // A square pyramid: one quad base (seen from below) and four triangles.
/// let mesh = ControlMesh::new(ControlMeshDesc {
///     positions: vec![
///         DVec3::new(-1.0, -1.0, 0.0),
///         DVec3::new(1.0, -1.0, 0.0),
///         DVec3::new(1.0, 1.0, 0.0),
///         DVec3::new(-1.0, 1.0, 0.0),
///         DVec3::new(0.0, 0.0, 1.0),
///     ],
///     face_sizes: vec![4, 3, 3, 3, 3],
///     face_vertices: vec![0, 3, 2, 1, 0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4],
///     creases: vec![Crease { v0: 0, v1: 4, sharpness: INFINITE_SHARPNESS }],
///     ..Default::default()
/// })?;
/// assert_eq!(mesh.face_count(), 5);
/// # Ok::<(), tessera::Error>(())
/// ```
#[derive(Debug, Clone, Default)]
pub struct ControlMeshDesc {
    /// Vertex positions.
    pub positions: Vec<DVec3>,
    /// Number of vertices of each face.
    pub face_sizes: Vec<u32>,
    /// Face vertex indices, concatenated in face order.
    pub face_vertices: Vec<u32>,
    /// Sharp edges.
    pub creases: Vec<Crease>,
    /// Sharp vertices.
    pub corners: Vec<Corner>,
    /// Faces that stay in the topology but are not part of the surface.
    pub holes: Vec<u32>,
    /// Scheme options.
    pub options: SchemeOptions,
    /// Faces are wound clockwise; reverse them to the counter-clockwise convention.
    pub left_handed: bool,
}
