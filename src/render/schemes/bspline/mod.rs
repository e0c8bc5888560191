//! Regular bicubic B-spline patches (`--scheme bspline-only` and the regular faces of every
//! Gregory scheme): regular quads, boundary-regular ones and those bounded by infinitely sharp
//! creases ([`RegularPatch`], phantom points mirrored), evaluated exactly by
//! `glsl/bspline/patch_bspline.{vert,tesc,tese}`.
//!
//! GPU data: the index buffer holds the 16 control-vertex ids per patch (`cvs` order); set 0
//! binding 1 the per-patch records ([`patch_info_bytes`], `PatchInfo` in
//! `glsl/common/frame.glsl`). Edges shared with any other patch are evaluated from the 12
//! B-spline points both sides hold, in the canonical direction (module docs of
//! [`crate::render`]).

use std::any::Any;
use std::sync::Arc;

use ash::vk;
use glam::DVec3;

use super::traits::{
    PassContext, PassPlan, PassTables, PatchPass, PatchScheme, ReferencePatch, Refusal,
    RefusalReason, SchemeLimits,
};
use crate::gpu::{Buffer, BufferBinding, Context, DescriptorKind, DescriptorPool, Pipeline};
use crate::patch::RegularPatch;
use crate::render::pass::frames::single_normal_vertex;
use crate::render::pass::pipeline::{patch_pipeline, PatchShaders};
use crate::render::pass::shared::set0_layout;
use crate::render::pass::upload::device_buffer;
use crate::render::pass::{
    bind_draw_state, record_patch_draws, NormalRule, PatchDraws, VertexFrames,
};
use crate::subdiv::bspline::eval_bspline;
use crate::topology::Topology;
use crate::Result;

/// The B-spline pass in the registry.
pub static BSPLINE: BSplineScheme = BSplineScheme;

/// Bytes of one `PatchInfo` record (`glsl/common/frame.glsl`).
pub const PATCH_INFO_BYTES: usize = 32;

/// Binding of the per-patch records in set 0.
const PATCH_INFO_BINDING: u32 = 1;

pub use crate::patch::edge_grid::PATCH_EDGES;

/// The `flags` word of the GPU record: bits 0-3 boundary mask, bit 4+e set when edge e
/// (see [`PATCH_EDGES`]) runs from the larger to the smaller vertex id.
pub fn gpu_flags(p: &RegularPatch) -> u32 {
    let c = p.corners();
    let mut flags = u32::from(p.boundary_mask & 0xf);
    for (e, &(a, b)) in PATCH_EDGES.iter().enumerate() {
        if c[a] > c[b] {
            flags |= 1 << (4 + e);
        }
    }
    flags
}

/// Per-patch GPU records (`PatchInfo`): face, flags, two pad words, corner vertex ids.
pub fn patch_info_bytes(patches: &[RegularPatch]) -> Vec<u8> {
    let mut out = Vec::with_capacity(patches.len() * PATCH_INFO_BYTES);
    for p in patches {
        let c = p.corners();
        for w in [p.face, gpu_flags(p), 0, 0, c[0], c[1], c[2], c[3]] {
            out.extend_from_slice(&w.to_le_bytes());
        }
    }
    out
}

/// The index buffer of the patch draw: 16 vertex ids per patch.
pub fn patch_index_bytes(patches: &[RegularPatch]) -> Vec<u8> {
    patches
        .iter()
        .flat_map(|p| p.cvs)
        .flat_map(u32::to_le_bytes)
        .collect()
}

/// Takes the faces that are (boundary-/crease-)regular quads ([`RegularPatch::gather`]).
#[derive(Debug, Clone, Copy)]
pub struct BSplineScheme;

impl PatchScheme for BSplineScheme {
    fn name(&self) -> &'static str {
        "bspline"
    }

    fn plan(&self, topo: &Arc<Topology>, candidates: &[u32], _: &SchemeLimits) -> PassPlan {
        let mut patches = Vec::new();
        let mut refused = Vec::new();
        for &f in candidates {
            match RegularPatch::gather(topo, f) {
                Some(p) => patches.push(p),
                None => refused.push(Refusal {
                    face: f,
                    pass: self.name(),
                    reason: RefusalReason::NotRegular,
                }),
            }
        }
        PassPlan {
            tables: (!patches.is_empty())
                .then(|| Arc::new(BSplineTables::new(patches)) as Arc<dyn PassTables>),
            refused,
        }
    }
}

/// The B-spline patches of a surface.
#[derive(Debug, Clone, PartialEq)]
pub struct BSplineTables {
    /// Patches in draw order.
    pub patches: Vec<RegularPatch>,
    faces: Vec<u32>,
}

impl BSplineTables {
    /// Tables drawing `patches` (e.g. gathered from a mesh, or built directly).
    pub fn new(patches: Vec<RegularPatch>) -> BSplineTables {
        let faces = patches.iter().map(|p| p.face).collect();
        BSplineTables { patches, faces }
    }
}

impl PassTables for BSplineTables {
    fn pass_name(&self) -> &'static str {
        BSPLINE.name()
    }

    fn faces(&self) -> &[u32] {
        &self.faces
    }

    fn patch_count(&self) -> usize {
        self.patches.len()
    }

    fn corner_frames(&self, positions: &[DVec3], rule: NormalRule<'_>, frames: &mut VertexFrames) {
        for p in &self.patches {
            for (k, (u, v)) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
                .into_iter()
                .enumerate()
            {
                let vid = p.corners()[k];
                if frames.is_set(vid) {
                    continue;
                }
                let s = p.eval(positions, u, v);
                let shared = match rule {
                    NormalRule::Topology(topo) => single_normal_vertex(topo, vid),
                    // The two patch sides meeting at corner k: bits of PATCH_EDGES.
                    NormalRule::PatchSides => p.boundary_mask & [9u8, 3, 6, 12][k] == 0,
                };
                frames.set(vid, s.position, s.normal, shared);
            }
        }
    }

    fn framing_points(&self, frames: &VertexFrames) -> Vec<DVec3> {
        self.patches
            .iter()
            .flat_map(|p| p.corners())
            .map(|v| frames.limits[v as usize])
            .collect()
    }

    fn reference(&self, positions: &[DVec3], face: u32) -> Option<ReferencePatch> {
        let p = self.patches.iter().find(|p| p.face == face)?;
        let cp = p.control_points(positions);
        Some(Box::new(move |u, v| {
            let s = eval_bspline(&cp, u, v);
            (s.position, s.normal)
        }))
    }

    fn create_pass(&self, pc: &PassContext<'_>) -> Result<Box<dyn PatchPass>> {
        Ok(Box::new(BSplinePass::new(pc, &self.patches)?))
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}

/// GPU resources of the B-spline patches of one surface.
pub struct BSplinePass {
    ctx: Context,
    count: u32,
    split: u32,
    positions: vk::Buffer,
    _patch_info: Buffer,
    indices: Buffer,
    _pool: DescriptorPool,
    set: vk::DescriptorSet,
    pipeline: Pipeline,
}

impl BSplinePass {
    fn new(pc: &PassContext<'_>, patches: &[RegularPatch]) -> Result<BSplinePass> {
        let ctx = pc.ctx;
        if let Some((p, v)) = patches.iter().find_map(|p| {
            p.cvs
                .iter()
                .find(|&&v| v as usize >= pc.positions.len())
                .map(|&v| (p, v))
        }) {
            return Err(crate::Error::Invalid(format!(
                "patch of face {} uses vertex {v}, mesh has {} vertices",
                p.face,
                pc.positions.len()
            )));
        }
        let patch_info = device_buffer(
            ctx,
            &patch_info_bytes(patches),
            vk::BufferUsageFlags::STORAGE_BUFFER,
            "bspline patch records",
        )?;
        let indices = device_buffer(
            ctx,
            &patch_index_bytes(patches),
            vk::BufferUsageFlags::INDEX_BUFFER,
            "bspline control-vertex indices",
        )?;
        let pipeline = patch_pipeline(
            ctx,
            pc.desc,
            pc.target,
            PatchShaders {
                label: "bspline patches".into(),
                vertex: "patch_bspline.vert".into(),
                tess_control: "patch_bspline.tesc".into(),
                tess_eval_stem: "patch_bspline",
                points: 16,
                position_input: true,
                set_layouts: vec![set0_layout(&[PATCH_INFO_BINDING])],
            },
        )?;
        let pool = DescriptorPool::new(ctx, 1, 6, 1)?;
        let set = pool.allocate(pipeline.set_layouts[0])?;
        pc.shared.write_set0(
            ctx,
            set,
            &[BufferBinding {
                binding: PATCH_INFO_BINDING,
                kind: DescriptorKind::StorageBuffer,
                buffer: &patch_info,
            }],
        );
        Ok(BSplinePass {
            ctx: ctx.clone(),
            count: patches.len() as u32,
            split: pc.desc.tess.split(),
            positions: pc.shared.positions(),
            _patch_info: patch_info,
            indices,
            _pool: pool,
            set,
            pipeline,
        })
    }
}

impl PatchPass for BSplinePass {
    fn label(&self) -> &'static str {
        "bspline patches"
    }

    fn patch_count(&self) -> u32 {
        self.count
    }

    fn record(&self, cmd: vk::CommandBuffer) {
        let dev = self.ctx.device();
        bind_draw_state(
            dev,
            cmd,
            &self.pipeline,
            &[self.set],
            Some(self.positions),
            self.indices.raw(),
        );
        let draws = PatchDraws {
            first_patch: 0,
            first_index: 0,
            count: self.count,
            points: 16,
            sub_draws: self.split * self.split,
            sub_flag: 0,
        };
        record_patch_draws(dev, cmd, self.pipeline.layout, &draws, self.split);
    }

    fn update_positions(&mut self, _: &[DVec3], _: &VertexFrames) -> Result<()> {
        // Positions and corner frames live in the shared buffers.
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 4x4 grid patch with ids 0..15 in cvs order.
    fn grid_patch(mask: u8) -> RegularPatch {
        let mut cvs = [0u32; 16];
        for (k, c) in cvs.iter_mut().enumerate() {
            *c = k as u32;
        }
        RegularPatch {
            face: 7,
            cvs,
            boundary_mask: mask,
        }
    }

    #[test]
    fn flags_encode_mask_and_edge_direction() {
        let p = grid_patch(0b0101);
        // corners 5, 6, 10, 9: edges (5,6) (6,10) (9,10) (5,9) all increasing.
        assert_eq!(gpu_flags(&p), 0b0101);
        let mut q = p;
        q.cvs.swap(5, 10); // corners 10, 6, 5, 9: every edge runs downwards
        assert_eq!(gpu_flags(&q) >> 4, 0b1111);
        let mut r = p;
        r.cvs.swap(5, 6); // corners 6, 5, 10, 9: only edge 0 (6 -> 5) runs downwards
        assert_eq!(gpu_flags(&r) >> 4, 0b0001);
    }

    #[test]
    fn planar_grid_corner_limits_are_the_vertices() {
        // On an affine grid the B-spline reproduces the affine map: limit of vertex = vertex.
        let pos: Vec<DVec3> = (0..16)
            .map(|k| DVec3::new((k % 4) as f64, (k / 4) as f64 * 2.0, 0.5))
            .collect();
        let lim = grid_patch(0).corner_limits(&pos);
        for (k, v) in grid_patch(0).corners().iter().enumerate() {
            assert!((lim[k] - pos[*v as usize]).length() < 1e-12);
        }
    }

    #[test]
    fn byte_layouts() {
        let p = grid_patch(0);
        let info = patch_info_bytes(&[p]);
        assert_eq!(info.len(), PATCH_INFO_BYTES);
        assert_eq!(u32::from_le_bytes(info[0..4].try_into().unwrap()), 7);
        assert_eq!(u32::from_le_bytes(info[16..20].try_into().unwrap()), 5);
        assert_eq!(u32::from_le_bytes(info[28..32].try_into().unwrap()), 9);
        assert_eq!(patch_index_bytes(&[p]).len(), 64);
        let v = crate::render::pass::upload::vec4_bytes(&[DVec3::new(1.0, 2.0, 3.0)]);
        assert_eq!(f32::from_le_bytes(v[12..16].try_into().unwrap()), 1.0);
        assert_eq!(f32::from_le_bytes(v[4..8].try_into().unwrap()), 2.0);
    }
}
