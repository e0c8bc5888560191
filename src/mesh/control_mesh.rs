//! The validated control mesh.

use glam::DVec3;

use super::desc::{ControlMeshDesc, Corner, Crease, SchemeOptions};
use super::uv::FaceUvs;
use super::validate;
use super::warning::MeshWarning;

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
    pub(crate) uvs: Option<FaceUvs>,
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
            uvs: None,
        })
    }

    /// The mesh with face-varying texture coordinates (indices parallel to
    /// [`Self::face_vertices`], after any left-handed reversal). Errors name the face.
    pub fn with_uvs(mut self, uvs: FaceUvs) -> crate::Result<ControlMesh> {
        uvs.validate(&self.face_offsets)?;
        self.uvs = Some(uvs);
        Ok(self)
    }

    /// The face-varying texture coordinates, if the mesh has them ([`FaceUvs`]).
    pub fn uvs(&self) -> Option<&FaceUvs> {
        self.uvs.as_ref()
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
        super::validate::check_magnitude(positions, super::validate::MAX_COORDINATE)?;
        self.positions.copy_from_slice(positions);
        Ok(())
    }

    /// Sets the sharpness of every crease tag with sharpness `> 0` (semi-sharp or infinitely
    /// sharp) to `sharpness`, a mesh-wide override for experiments such as patch counts against
    /// sharpness (Nießner, Loop, Greiner 2012 §3). Tags of sharpness 0, untagged edges (boundary
    /// edges included: boundary interpolation is not a tag) and corner (vertex) tags are left
    /// as they are. Returns how many tags changed value; errors on a negative or NaN sharpness.
    pub fn set_crease_sharpness(&mut self, sharpness: f32) -> crate::Result<usize> {
        if sharpness.is_nan() || sharpness < 0.0 {
            return Err(crate::Error::Invalid(format!(
                "crease sharpness {sharpness}: must be >= 0"
            )));
        }
        let mut changed = 0;
        for c in self.creases.iter_mut().filter(|c| c.sharpness > 0.0) {
            changed += (c.sharpness != sharpness) as usize;
            c.sharpness = sharpness;
        }
        Ok(changed)
    }
}
