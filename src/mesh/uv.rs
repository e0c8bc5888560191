//! Face-varying texture coordinates (OBJ `vt`): one (s, t) per face corner, through an index
//! into a list of values, so faces that share a `vt` share its value exactly.
//!
//! Mapping onto the surface (what the evaluation stages and `tessera sample` use): a quad's
//! (u, v) domain takes the bilinear blend of its four corner coordinates; a non-quad face's
//! sub-face k (the Ptex convention of the parameterisation contract: corner k, the midpoint of
//! edge k→k+1, the face centre, the midpoint of edge k−1→k) the bilinear blend of the corner's
//! coordinate, the edges' midpoint coordinates and the mean of all corner coordinates; a
//! triangle drawn as one patch (barycentric (u, v) of corners 1 and 2) the barycentric blend.
//! Along a face edge all three reduce to the linear blend of the edge's two corner coordinates.

use crate::{Error, Result};

/// Texture coordinates of a mesh's face corners.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FaceUvs {
    /// The coordinates (an OBJ file's `vt` lines, in order).
    pub values: Vec<[f32; 2]>,
    /// Per face corner, parallel to [`super::ControlMesh::face_vertices`], an index into
    /// `values`.
    pub indices: Vec<u32>,
}

impl FaceUvs {
    /// The coordinate of corner `corner` of face `face`, given the mesh's face offsets.
    pub fn corner(&self, face_offsets: &[u32], face: usize, corner: usize) -> [f32; 2] {
        self.values[self.indices[face_offsets[face] as usize + corner] as usize]
    }

    /// Checks the coordinates against a mesh's faces (`face_offsets`: length faces + 1):
    /// one index per corner, each in range, every value finite. Errors name the face.
    pub(crate) fn validate(&self, face_offsets: &[u32]) -> Result<()> {
        let corners = *face_offsets.last().unwrap_or(&0) as usize;
        if self.indices.len() != corners {
            return Err(Error::SizeMismatch {
                what: "texture-coordinate indices (one per face corner)",
                expected: corners as u64,
                found: self.indices.len() as u64,
            });
        }
        if let Some(k) = self
            .values
            .iter()
            .position(|v| !(v[0].is_finite() && v[1].is_finite()))
        {
            return Err(Error::NonFiniteTexCoord { index: k as u32 });
        }
        let count = self.values.len() as u32;
        for (f, w) in face_offsets.windows(2).enumerate() {
            for (c, &i) in self.indices[w[0] as usize..w[1] as usize]
                .iter()
                .enumerate()
            {
                if i >= count {
                    return Err(Error::TexCoordOutOfRange {
                        face: f as u32,
                        corner: c as u32,
                        index: i,
                        count,
                    });
                }
            }
        }
        Ok(())
    }
}
