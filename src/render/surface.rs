//! What the renderer draws: control positions, the parts drawn by each pass (their CPU tables),
//! and the faces evaluated on the exact CPU path.

use std::sync::Arc;

use glam::DVec3;

use super::displace::DisplacementMap;
use super::fallback::{FallbackFace, FallbackMesh};
use super::pass::{NormalRule, VertexFrames};
use super::schemes::bspline::BSplineTables;
use super::schemes::{PassTables, Refusal};
use crate::mesh::FaceUvs;
use crate::patch::RegularPatch;
use crate::topology::Topology;
use crate::{Error, Result};

/// Per-vertex limit frames of `positions` for `parts` (first part first), the normal rule from
/// the topology when known.
pub fn vertex_frames(
    topology: Option<&Topology>,
    parts: &[Arc<dyn PassTables>],
    positions: &[DVec3],
) -> VertexFrames {
    let mut frames = VertexFrames::new(positions);
    let rule = match topology {
        Some(t) => NormalRule::Topology(t),
        None => NormalRule::PatchSides,
    };
    for p in parts {
        p.corner_frames(positions, rule, &mut frames);
    }
    frames
}

/// A surface ready for the GPU.
#[derive(Debug, Clone, Default)]
pub struct SurfaceData {
    /// Control-vertex positions (f64; converted to f32 on upload).
    pub positions: Vec<DVec3>,
    /// Topology the parts were planned on (`None` for patches given directly).
    pub topology: Option<Arc<Topology>>,
    /// One entry per pass, in draw order: its CPU tables.
    pub parts: Vec<Arc<dyn PassTables>>,
    /// Faces with a limit surface that no pass takes (evaluated on the CPU).
    pub fallback_faces: Vec<FallbackFace>,
    /// The CPU-evaluated triangles of `fallback_faces` at the current tessellation level.
    pub fallback: FallbackMesh,
    /// Faces that are not drawn at all (holes, faces without a limit surface).
    pub skipped_faces: usize,
    /// Why each fallback face was refused by each pass that was offered it.
    pub refusals: Vec<Refusal>,
    /// The mesh's face-varying texture coordinates (OBJ `vt`), when it has them and a
    /// topology: the evaluation stages interpolate them ([`crate::mesh::uv`]) and the capture
    /// records them.
    pub texcoords: Option<Arc<FaceUvs>>,
    /// The displacement map sampled at the texture coordinates when the render description
    /// asks for [`super::Displacement::Map`] ([`Self::set_displacement_map`]).
    pub displacement_map: Option<Arc<DisplacementMap>>,
}

impl SurfaceData {
    /// A surface of regular B-spline patches given directly (no topology), e.g. synthetic
    /// test grids.
    pub fn from_regular_patches(positions: Vec<DVec3>, patches: Vec<RegularPatch>) -> SurfaceData {
        let parts: Vec<Arc<dyn PassTables>> = if patches.is_empty() {
            Vec::new()
        } else {
            vec![Arc::new(BSplineTables::new(patches))]
        };
        SurfaceData {
            positions,
            parts,
            ..SurfaceData::default()
        }
    }

    /// Gives the surface a displacement map ([`super::Displacement::Map`] samples it at the
    /// face-varying texture coordinates). A surface without texture coordinates (a mesh
    /// without `vt`) is refused: [`Error::MissingTexCoords`].
    pub fn set_displacement_map(&mut self, map: DisplacementMap) -> Result<()> {
        if self.texcoords.is_none() || self.topology.is_none() {
            return Err(Error::MissingTexCoords {
                map: map.source().to_string(),
            });
        }
        self.displacement_map = Some(Arc::new(map));
        Ok(())
    }

    /// The words of the evaluation stages' texture-coordinate table
    /// (`glsl/common/texcoord.glsl`): per face `(first entry, corner count, 0, 0)`, then per
    /// face corner `(s bits, t bits, vertex id, 0)`. One zero word set without texture
    /// coordinates.
    pub fn texcoord_words(&self) -> Vec<[u32; 4]> {
        let (Some(uvs), Some(topo)) = (&self.texcoords, &self.topology) else {
            return vec![[0; 4]];
        };
        let faces = topo.face_count();
        let offsets = topo.face_offsets();
        let mut words = Vec::with_capacity(faces + offsets[faces] as usize);
        for f in 0..faces {
            words.push([
                (faces as u32) + offsets[f],
                offsets[f + 1] - offsets[f],
                0,
                0,
            ]);
        }
        for f in 0..faces {
            for (k, &v) in topo.face_vertices(f as u32).iter().enumerate() {
                let st = uvs.corner(offsets, f, k);
                words.push([st[0].to_bits(), st[1].to_bits(), v, 0]);
            }
        }
        words
    }

    /// The part drawn by the pass named `pass` (e.g. `"bspline"`, `"gregory-vs"`).
    pub fn part(&self, pass: &str) -> Option<&Arc<dyn PassTables>> {
        self.parts.iter().find(|p| p.pass_name() == pass)
    }

    /// The part of type `T` (typed access to a scheme's tables).
    pub fn tables<T: PassTables>(&self) -> Option<&T> {
        self.parts
            .iter()
            .find_map(|p| p.as_any().downcast_ref::<T>())
    }

    /// The regular B-spline patches (empty when the surface has none).
    pub fn regular_patches(&self) -> &[RegularPatch] {
        self.tables::<BSplineTables>()
            .map_or(&[], |t| t.patches.as_slice())
    }

    /// Faces drawn by the passes whose patches approximate the limit (the Gregory passes; not
    /// the exact B-spline and single-crease passes, [`PassTables::exact`]), in draw order.
    pub fn irregular_gpu_faces(&self) -> Vec<u32> {
        self.parts
            .iter()
            .filter(|p| !p.exact())
            .flat_map(|p| p.faces().iter().copied())
            .collect()
    }

    /// Patches drawn through the tessellation stages, over every pass.
    pub fn patch_count(&self) -> usize {
        self.parts.iter().map(|p| p.patch_count()).sum()
    }

    /// Per-vertex limit frames of `positions` (the corners of every part, first part first).
    pub fn vertex_frames(&self, positions: &[DVec3]) -> VertexFrames {
        vertex_frames(self.topology.as_deref(), &self.parts, positions)
    }

    /// Points to frame the camera on: patch corner limits and the CPU-evaluated points
    /// (subsampled).
    pub fn framing_points(&self, frames: &VertexFrames) -> Vec<DVec3> {
        let mut points: Vec<DVec3> = self
            .parts
            .iter()
            .flat_map(|p| p.framing_points(frames))
            .collect();
        let step = (self.fallback.positions.len() / 4096).max(1);
        points.extend(self.fallback.positions.iter().step_by(step));
        points
    }

    /// Bounding box `(min, max)` of `points`; `(0, 0)` when empty.
    pub fn bounding_box_of(points: &[DVec3]) -> (DVec3, DVec3) {
        let lo = points.iter().fold(DVec3::INFINITY, |a, &b| a.min(b));
        let hi = points.iter().fold(DVec3::NEG_INFINITY, |a, &b| a.max(b));
        if lo.x > hi.x {
            return (DVec3::ZERO, DVec3::ZERO);
        }
        (lo, hi)
    }

    /// Bounding box of the patch corner limits and the CPU-evaluated points (what is drawn, up
    /// to the bulge of patch interiors); `(0, 0)` when empty.
    pub fn bounding_box(&self) -> (DVec3, DVec3) {
        self.bounding_box_with(&self.vertex_frames(&self.positions))
    }

    /// [`Self::bounding_box`] with the frames of [`Self::positions`] already computed.
    pub fn bounding_box_with(&self, frames: &VertexFrames) -> (DVec3, DVec3) {
        let mut points: Vec<DVec3> = self
            .parts
            .iter()
            .flat_map(|p| p.framing_points(frames))
            .collect();
        points.extend(self.fallback.positions.iter().copied());
        Self::bounding_box_of(&points)
    }
}
