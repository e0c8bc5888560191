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
    PassContext, PassPlan, PassTables, PatchPass, PatchScheme, PlanOptions, ReferencePatch,
    Refusal, RefusalReason,
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
use crate::subdiv::bspline::{eval_bspline, LimitSample};
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

/// One `PatchInfo` record: face, flags, two pad words, the corner vertex ids (cvs 5, 6, 10, 9).
pub fn patch_record(face: u32, flags: u32, cvs: &[u32; 16]) -> [u8; PATCH_INFO_BYTES] {
    let mut out = [0u8; PATCH_INFO_BYTES];
    for (k, w) in [face, flags, 0, 0, cvs[5], cvs[6], cvs[10], cvs[9]]
        .into_iter()
        .enumerate()
    {
        out[4 * k..4 * k + 4].copy_from_slice(&w.to_le_bytes());
    }
    out
}

/// Per-patch GPU records (`PatchInfo`): face, flags, two pad words, corner vertex ids.
pub fn patch_info_bytes(patches: &[RegularPatch]) -> Vec<u8> {
    patches
        .iter()
        .flat_map(|p| patch_record(p.face, gpu_flags(p), &p.cvs))
        .collect()
}

/// The index buffer of the patch draw: 16 vertex ids per patch.
pub fn patch_index_bytes(patches: &[RegularPatch]) -> Vec<u8> {
    grid_index_bytes(patches.iter().map(|p| &p.cvs))
}

/// 16 vertex ids per patch, as u32 indices.
pub fn grid_index_bytes<'a>(cvs: impl Iterator<Item = &'a [u32; 16]>) -> Vec<u8> {
    cvs.flatten().flat_map(|v| v.to_le_bytes()).collect()
}

/// Writes the limit frames of the corners of a 16-point patch of `face` (`cvs` 5, 6, 10, 9 at
/// `(u, v)` = (0, 0), (1, 0), (1, 1), (0, 1)) that no earlier patch wrote, from `eval(u, v)`:
/// with topology, the normal of the corner's sector where sharp edges split the vertex
/// ([`VertexFrames::set_sector`]); without, corner `k` gets a shared normal when
/// `sides_smooth(k)`.
pub(crate) fn grid_corner_frames(
    cvs: &[u32; 16],
    face: u32,
    rule: NormalRule<'_>,
    frames: &mut VertexFrames,
    eval: impl Fn(f64, f64) -> LimitSample,
    sides_smooth: impl Fn(usize) -> bool,
) {
    for (k, (slot, (u, v))) in [
        (5, (0.0, 0.0)),
        (6, (1.0, 0.0)),
        (10, (1.0, 1.0)),
        (9, (0.0, 1.0)),
    ]
    .into_iter()
    .enumerate()
    {
        let vid = cvs[slot];
        let sector = match rule {
            NormalRule::Topology(topo) => frames.pending_sector(topo, vid, face),
            NormalRule::PatchSides => None,
        };
        if frames.is_set(vid) && sector.is_none() {
            continue;
        }
        let s = eval(u, v);
        let shared = match rule {
            NormalRule::Topology(topo) => single_normal_vertex(topo, vid),
            NormalRule::PatchSides => sides_smooth(k),
        };
        frames.set(vid, s.position, s.normal, shared);
        if let Some(sector) = sector {
            frames.set_sector(vid, &sector, s.normal);
        }
    }
}

/// Takes the faces that are (boundary-/crease-)regular quads ([`RegularPatch::gather`]).
#[derive(Debug, Clone, Copy)]
pub struct BSplineScheme;

impl PatchScheme for BSplineScheme {
    fn name(&self) -> &'static str {
        "bspline"
    }

    fn plan(&self, topo: &Arc<Topology>, candidates: &[u32], _: &PlanOptions) -> PassPlan {
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

    fn exact(&self) -> bool {
        true
    }

    fn corner_frames(&self, positions: &[DVec3], rule: NormalRule<'_>, frames: &mut VertexFrames) {
        for p in &self.patches {
            grid_corner_frames(
                &p.cvs,
                p.face,
                rule,
                frames,
                |u, v| p.eval(positions, u, v),
                |k| {
                    // The two patch sides meeting at corner k: bits of PATCH_EDGES.
                    p.boundary_mask & [9u8, 3, 6, 12][k] == 0
                },
            );
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
        Ok(Box::new(GridPatchPass::new(
            pc,
            GridPatchSpec {
                label: "bspline patches",
                tess_control: "patch_bspline.tesc",
                tess_eval_stem: "patch_bspline",
                patches: self.patches.iter().map(|p| (p.face, p.cvs)).collect(),
                records: patch_info_bytes(&self.patches),
                own: &[],
            },
        )?))
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}

/// What a pass of 16-control-vertex patches (the B-spline pass, the single-crease pass) is drawn
/// with: the index buffer holds each patch's 16 vertex ids, set 0 binding 1 its `PatchInfo`
/// records, `own` further bindings of the pass; the vertex stage is `patch_bspline.vert`.
pub(crate) struct GridPatchSpec<'a> {
    /// Debug and timing label.
    pub label: &'static str,
    /// Tessellation control shader.
    pub tess_control: &'static str,
    /// Evaluation-shader stem.
    pub tess_eval_stem: &'static str,
    /// Face and 16 control-vertex ids per patch, in draw order.
    pub patches: Vec<(u32, [u32; 16])>,
    /// The `PatchInfo` records, one per patch.
    pub records: Vec<u8>,
    /// The pass's own set-0 bindings besides binding 1.
    pub own: &'a [BufferBinding<'a>],
}

/// GPU resources of a pass of 16-control-vertex patches (`GridPatchSpec`).
pub struct GridPatchPass {
    ctx: Context,
    label: &'static str,
    count: u32,
    split: u32,
    /// Largest level of a sub-patch (`PatchDraws::max_level`).
    max_level: f32,
    positions: Vec<vk::Buffer>,
    _patch_info: Buffer,
    indices: Buffer,
    _pool: DescriptorPool,
    sets: Vec<vk::DescriptorSet>,
    pipeline: Pipeline,
}

impl GridPatchPass {
    pub(crate) fn new(pc: &PassContext<'_>, spec: GridPatchSpec<'_>) -> Result<GridPatchPass> {
        let ctx = pc.ctx;
        if let Some((f, v)) = spec.patches.iter().find_map(|(f, cvs)| {
            cvs.iter()
                .find(|&&v| v as usize >= pc.positions.len())
                .map(|&v| (f, v))
        }) {
            return Err(crate::Error::Invalid(format!(
                "patch of face {f} uses vertex {v}, mesh has {} vertices",
                pc.positions.len()
            )));
        }
        let patch_info = device_buffer(
            ctx,
            &spec.records,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            &format!("{} records", spec.label),
        )?;
        let indices = device_buffer(
            ctx,
            &grid_index_bytes(spec.patches.iter().map(|(_, cvs)| cvs)),
            vk::BufferUsageFlags::INDEX_BUFFER,
            &format!("{} control-vertex indices", spec.label),
        )?;
        let mut own_bindings = vec![PATCH_INFO_BINDING];
        own_bindings.extend(spec.own.iter().map(|b| b.binding));
        let pipeline = patch_pipeline(
            ctx,
            pc.desc,
            pc.target,
            PatchShaders {
                label: spec.label.into(),
                vertex: "patch_bspline.vert".into(),
                tess_control: spec.tess_control.into(),
                tess_eval_stem: spec.tess_eval_stem,
                points: 16,
                position_input: true,
                set_layouts: vec![set0_layout(&own_bindings)],
            },
        )?;
        let n = pc.shared.slot_count() as u32;
        let pool = DescriptorPool::new(ctx, n, n * (5 + own_bindings.len() as u32), n)?;
        let mut own = vec![BufferBinding {
            binding: PATCH_INFO_BINDING,
            kind: DescriptorKind::StorageBuffer,
            buffer: &patch_info,
        }];
        own.extend_from_slice(spec.own);
        let sets = pc
            .shared
            .set0_per_slot(ctx, &pool, pipeline.set_layouts[0], &own)?;
        Ok(GridPatchPass {
            ctx: ctx.clone(),
            label: spec.label,
            count: spec.patches.len() as u32,
            split: pc.desc.tess.split(),
            max_level: pc.largest_level(pc.desc.tess.split()),
            positions: (0..n as usize).map(|k| pc.shared.positions(k)).collect(),
            _patch_info: patch_info,
            indices,
            _pool: pool,
            sets,
            pipeline,
        })
    }
}

impl PatchPass for GridPatchPass {
    fn label(&self) -> &'static str {
        self.label
    }

    fn memory_bytes(&self) -> u64 {
        self._patch_info.size() + self.indices.size()
    }

    fn patch_count(&self) -> u32 {
        self.count
    }

    fn record(&self, cmd: vk::CommandBuffer, slot: usize) {
        let dev = self.ctx.device();
        bind_draw_state(
            dev,
            cmd,
            &self.pipeline,
            &[self.sets[slot]],
            Some(self.positions[slot]),
            self.indices.raw(),
        );
        let draws = PatchDraws {
            first_patch: 0,
            first_index: 0,
            count: self.count,
            points: 16,
            sub_draws: self.split * self.split,
            sub_flag: 0,
            max_level: self.max_level,
        };
        record_patch_draws(dev, cmd, &self.pipeline, &draws, self.split);
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
