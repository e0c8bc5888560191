//! What both GPU constructions of Gregory patches (Loop, Schaefer, Ni, Castaño 2009) share: the
//! faces they take (triangles and quads the construction covers at level 0, [`check_face_level0`]), the tables
//! the shared evaluation shaders read ([`GregoryLayout`]: set-0 bindings 6 and 7), the limit
//! frames of their corners and the level limits of drawing triangles whole. The variants are
//! the schemes [`super::gregory_vs`] (§4.1-4.2) and [`super::gregory_stencil`] (§4.3).

pub mod layout;

use glam::DVec3;

pub use layout::{gregory_face_problem, gregory_vertex_frame, irregular_faces, GregoryLayout};

use super::traits::{ReferencePatch, Refusal, RefusalReason};
use crate::gpu::{Buffer, BufferBinding, Context, DescriptorKind};
use crate::patch::gregory::{check_face_level0, gregory_patch_at_with, GregoryPatch};
use crate::render::pass::frames::single_normal_vertex;
use crate::render::pass::upload::host_buffer;
use crate::render::pass::VertexFrames;
use crate::render::settings::{PatchLevelLimit, Spacing};
use crate::topology::Topology;
use crate::Result;

/// Set-0 binding of the `GregoryPatchInfo` records.
pub const PATCH_RECORDS_BINDING: u32 = 6;
/// Set-0 binding of the B-spline edge grids.
pub const GRIDS_BINDING: u32 = 7;
/// Set-0 binding the shared frame block declares for B-spline patch records; unused by the
/// Gregory stages, bound to the Gregory records so the layout is complete.
pub const UNUSED_PATCH_INFO_BINDING: u32 = 1;

/// Splits `candidates` into faces the Gregory construction covers and typed refusals.
pub fn covered_faces(
    pass: &'static str,
    topo: &Topology,
    candidates: &[u32],
) -> (Vec<u32>, Vec<Refusal>) {
    let mut ok = Vec::new();
    let mut refused = Vec::new();
    for &f in candidates {
        match check_face_level0(topo, f) {
            Ok(()) => ok.push(f),
            Err(e) => refused.push(Refusal {
                face: f,
                pass,
                reason: RefusalReason::NotGregory(e),
            }),
        }
    }
    (ok, refused)
}

/// Limit frames of the Gregory corners not written by an earlier pass (§3.2-3.3, §4.6); the
/// normal is shared where the vertex has one sector ([`single_normal_vertex`]: Gregory patches
/// always know their topology); where sharp edges split it, the sector takes the normal of its
/// first patch's corner ([`GregoryPatch::corner_normal`], what the TES computes there).
pub fn corner_frames(
    topo: &Topology,
    layout: &GregoryLayout,
    positions: &[DVec3],
    frames: &mut VertexFrames,
) {
    for (&f, c) in layout.faces.iter().zip(&layout.corners) {
        let mut patch = None;
        for (k, &v) in c.iter().take(topo.face_size(f)).enumerate() {
            if !frames.is_set(v) {
                let (p, n) = gregory_vertex_frame(topo, positions, v);
                frames.set(v, p, n, single_normal_vertex(topo, v));
            }
            if let Some(sector) = frames.pending_sector(topo, v, f) {
                let patch = patch.get_or_insert_with(|| {
                    gregory_patch_at_with(topo, positions, f, layout.tangents).ok()
                });
                if let Some(n) = patch.as_ref().map(|p| p.corner_normal(k)) {
                    if n != DVec3::ZERO {
                        frames.set_sector(v, &sector, n);
                    }
                }
            }
        }
    }
}

/// The CPU construction of the Gregory patch of `face` ([`gregory_patch_at_with`], §3-4, with
/// the layout's tangents), when `layout` draws it.
pub fn reference(
    topo: &Topology,
    layout: &GregoryLayout,
    positions: &[DVec3],
    face: u32,
) -> Option<ReferencePatch> {
    if !layout.faces.contains(&face) {
        return None;
    }
    let patch = gregory_patch_at_with(topo, positions, face, layout.tangents).ok()?;
    Some(Box::new(move |u, v| {
        let p = match &patch {
            GregoryPatch::Quad(q) => q.eval(u, v),
            GregoryPatch::Triangle(t) => t.eval(u, v),
        };
        (p.position, p.normal())
    }))
}

/// Limit positions of the Gregory corners (camera framing).
pub fn framing_points(layout: &GregoryLayout, frames: &VertexFrames) -> Vec<DVec3> {
    layout
        .corners
        .iter()
        .flatten()
        .map(|&v| frames.limits[v as usize])
        .collect()
}

/// With fractional spacing, sub-patch edges cannot meet a whole triangle's edge point for point:
/// a layout with triangles is then drawn unsplit.
pub fn level_limit(
    layout: &GregoryLayout,
    spacing: Spacing,
    max_patch_level: f32,
) -> PatchLevelLimit {
    let has_triangles = layout.patch_count() > layout.quad_count;
    PatchLevelLimit {
        max_patch_level,
        splittable: !(has_triangles && spacing != Spacing::Equal),
    }
}

/// The shared evaluation tables of `layout` (records, edge grids) for set 0.
pub struct GregoryTesBuffers {
    records: Buffer,
    grids: Buffer,
}

impl GregoryTesBuffers {
    /// Bytes of GPU memory of the records and grids.
    pub fn memory_bytes(&self) -> u64 {
        self.records.size() + self.grids.size()
    }

    /// Uploads the records and grids.
    pub fn new(ctx: &Context, layout: &GregoryLayout) -> Result<GregoryTesBuffers> {
        let storage = ash::vk::BufferUsageFlags::STORAGE_BUFFER;
        Ok(GregoryTesBuffers {
            records: host_buffer(
                ctx,
                &layout.patch_info_bytes(),
                storage,
                "gregory patch records",
            )?,
            grids: host_buffer(ctx, &layout.grid_bytes(), storage, "gregory edge grids")?,
        })
    }

    /// Their set-0 writes.
    pub fn bindings(&self) -> [BufferBinding<'_>; 3] {
        let sb = |binding, buffer| BufferBinding {
            binding,
            kind: DescriptorKind::StorageBuffer,
            buffer,
        };
        [
            sb(UNUSED_PATCH_INFO_BINDING, &self.records),
            sb(PATCH_RECORDS_BINDING, &self.records),
            sb(GRIDS_BINDING, &self.grids),
        ]
    }
}
