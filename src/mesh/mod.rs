//! Control meshes: positions, polygonal faces of any size >= 3, and the subdivision tags
//! (creases, corners, holes, boundary interpolation, crease method) that OpenSubdiv-style
//! files carry.
//!
//! A [`ControlMesh`] is always valid once constructed: [`ControlMesh::new`] runs the checks in
//! [`validate`] and refuses bad input with a typed [`crate::Error`] naming the offending element.

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

/// Everything needed to build a [`ControlMesh`]: the programmatic constructor for engines.
///
/// Faces are given as `face_sizes` (one entry per face, each >= 3) and the concatenated
/// `face_vertices` (0-based), counter-clockwise seen from outside unless `left_handed` is set,
/// in which case every face is reversed on construction (corner 0 stays first). Crease and
/// corner vertices and hole faces are 0-based. [`ControlMesh::new`] validates everything and
/// never panics; see [`validate`] for the checks.
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

/// A validated polygonal control mesh with subdivision tags.
#[derive(Debug, Clone)]
pub struct ControlMesh {
    pub(crate) positions: Vec<DVec3>,
    /// `face_offsets[f]..face_offsets[f + 1]` indexes `face_vertices`; length `faces + 1`.
    pub(crate) face_offsets: Vec<u32>,
    pub(crate) face_vertices: Vec<u32>,
    pub(crate) creases: Vec<Crease>,
    pub(crate) corners: Vec<Corner>,
    pub(crate) holes: Vec<bool>,
    pub(crate) options: SchemeOptions,
    pub(crate) warnings: Vec<MeshWarning>,
}

impl ControlMesh {
    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of faces (holes included).
    pub fn face_count(&self) -> usize {
        self.face_offsets.len() - 1
    }

    /// Vertex positions.
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }

    /// The vertices of face `f`, counter-clockwise.
    pub fn face(&self, f: usize) -> &[u32] {
        let a = self.face_offsets[f] as usize;
        let b = self.face_offsets[f + 1] as usize;
        &self.face_vertices[a..b]
    }

    /// Number of vertices of face `f`.
    pub fn face_size(&self, f: usize) -> usize {
        (self.face_offsets[f + 1] - self.face_offsets[f]) as usize
    }

    /// Offsets into [`Self::face_vertices`], one per face plus one.
    pub fn face_offsets(&self) -> &[u32] {
        &self.face_offsets
    }

    /// All face vertex indices, concatenated.
    pub fn face_vertices(&self) -> &[u32] {
        &self.face_vertices
    }

    /// Sharp edges as given (validated: every one is an edge of the mesh).
    pub fn creases(&self) -> &[Crease] {
        &self.creases
    }

    /// Sharp vertices as given.
    pub fn corners(&self) -> &[Corner] {
        &self.corners
    }

    /// Whether face `f` is a hole.
    pub fn is_hole(&self, f: usize) -> bool {
        self.holes[f]
    }

    /// Scheme options.
    pub fn options(&self) -> SchemeOptions {
        self.options
    }

    /// Non-fatal findings: unreferenced vertices, and for files unknown or unsupported tags.
    pub fn warnings(&self) -> &[MeshWarning] {
        &self.warnings
    }

    /// Axis-aligned bounding box `(min, max)` of the positions.
    pub fn bounding_box(&self) -> (DVec3, DVec3) {
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for p in &self.positions {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        (lo, hi)
    }

    /// Length of the bounding-box diagonal: the unit in which accuracy figures are given.
    pub fn bbox_diagonal(&self) -> f64 {
        let (lo, hi) = self.bounding_box();
        (hi - lo).length()
    }
}

pub mod obj;
mod tags;
pub mod validate;
mod warning;

pub use obj::ObjOptions;
pub use warning::MeshWarning;

impl ControlMesh {
    /// Builds and validates a mesh. Errors name the offending vertex, face or edge.
    pub fn new(desc: ControlMeshDesc) -> crate::Result<ControlMesh> {
        let mut desc = desc;
        if desc.left_handed {
            let mut start = 0usize;
            for &n in &desc.face_sizes {
                let end = start.saturating_add(n as usize);
                if end <= desc.face_vertices.len() && n > 1 {
                    desc.face_vertices[start + 1..end].reverse();
                }
                start = end;
            }
        }
        let warnings = validate::validate(&desc)?;
        let mut face_offsets = Vec::with_capacity(desc.face_sizes.len() + 1);
        let mut acc = 0u32;
        face_offsets.push(0);
        for &n in &desc.face_sizes {
            acc += n;
            face_offsets.push(acc);
        }
        let mut holes = vec![false; desc.face_sizes.len()];
        for &h in &desc.holes {
            holes[h as usize] = true;
        }
        Ok(ControlMesh {
            positions: desc.positions,
            face_offsets,
            face_vertices: desc.face_vertices,
            creases: desc.creases,
            corners: desc.corners,
            holes,
            options: desc.options,
            warnings,
        })
    }

    /// Replaces the vertex positions, keeping topology and tags (animation).
    /// Errors if the count differs or a coordinate is not finite.
    pub fn set_positions(&mut self, positions: &[DVec3]) -> crate::Result<()> {
        if positions.len() != self.positions.len() {
            return Err(crate::Error::Invalid(format!(
                "set_positions: got {} positions, mesh has {} vertices",
                positions.len(),
                self.positions.len()
            )));
        }
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(crate::Error::Invalid(format!(
                "set_positions: vertex {i} has a non-finite coordinate"
            )));
        }
        self.positions.copy_from_slice(positions);
        Ok(())
    }
}
