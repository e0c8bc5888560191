//! The draw loop every patch pass shares: patches in chunks (the lavapipe workarounds of
//! [`crate::gpu::patch_draw_chunks`]: control points and domain points per draw), each chunk
//! once per sub-patch of the uniform split, the chunk's first patch and the sub-patch in the
//! push constants.

use ash::vk;

use super::pipeline::push_patch_chunk;
use crate::gpu::{patch_draw_chunks, Pipeline};
use crate::render::settings::{TessMode, TessSettings};

/// Binds `pipeline` with `sets` (tessera's, from its first set [`Pipeline::first_set`]), the vertex buffer `vertices` at binding 0 (when
/// the pipeline reads vertex input) and the u32 index buffer `indices`.
pub fn bind_draw_state(
    dev: &ash::Device,
    cmd: vk::CommandBuffer,
    pipeline: &Pipeline,
    sets: &[vk::DescriptorSet],
    vertices: Option<vk::Buffer>,
    indices: vk::Buffer,
) {
    // SAFETY: the caller records into a command buffer inside a render pass compatible with the
    // pipeline's target format, and keeps every bound object alive until the submission ends.
    unsafe {
        dev.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline.raw);
        dev.cmd_bind_descriptor_sets(
            cmd,
            vk::PipelineBindPoint::GRAPHICS,
            pipeline.layout,
            pipeline.first_set,
            sets,
            &[],
        );
        if let Some(v) = vertices {
            dev.cmd_bind_vertex_buffers(cmd, 0, &[v], &[0]);
        }
        dev.cmd_bind_index_buffer(cmd, indices, 0, vk::IndexType::UINT32);
    }
}

/// A run of patches of one pipeline in the bound index buffer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PatchDraws {
    /// Index of the run's first patch in the pass's per-patch records (`patch_base` + chunk
    /// offset reaches the shaders: `gl_PrimitiveID` restarts per draw).
    pub first_patch: u32,
    /// First index of the run in the index buffer.
    pub first_index: u32,
    /// Patches in the run.
    pub count: u32,
    /// Control points (indices) per patch.
    pub points: u32,
    /// Draws per chunk: `split²` for patches drawn as sub-patches, 1 for patches drawn whole.
    pub sub_draws: u32,
    /// Bits or-ed into the sub-patch index (e.g. a scheme's sub-triangle mode).
    pub sub_flag: u32,
    /// Largest tessellation level a drawn (sub-)patch of the run can get ([`largest_level`]):
    /// bounds the domain points of a draw ([`crate::gpu::patches_per_draw_at_level`]).
    pub max_level: f32,
}

impl PatchDraws {
    /// `count` patches of `points` indices from patch `first_patch` and index `first_index`,
    /// drawn whole (one draw per chunk) at levels up to `max_level`.
    pub fn whole(
        first_patch: u32,
        first_index: u32,
        count: u32,
        points: u32,
        max_level: f32,
    ) -> Self {
        PatchDraws {
            first_patch,
            first_index,
            count,
            points,
            sub_draws: 1,
            sub_flag: 0,
            max_level,
        }
    }
}

/// The largest level a (sub-)patch drawn with `tess` can get: in uniform mode the level over the
/// sub-patches per side `split` (1 for patches drawn whole), in screen-space and distance modes
/// `device_max_level` (the shaders clamp to it).
pub fn largest_level(tess: &TessSettings, device_max_level: f32, split: u32) -> f32 {
    match tess.mode {
        TessMode::Uniform => tess.level / split.max(1) as f32,
        _ => device_max_level,
    }
}

/// Records the indexed draws of `d` with `pipeline` bound (its push-constant range
/// is `pipeline::patch_push_constants`), telling the shaders the uniform `split`: chunks of at
/// most [`crate::gpu::patches_per_draw`] patches (control points and `d.max_level`'s domain
/// points per draw).
pub fn record_patch_draws(
    dev: &ash::Device,
    cmd: vk::CommandBuffer,
    pipeline: &Pipeline,
    d: &PatchDraws,
    split: u32,
) {
    for (first, n) in patch_draw_chunks(d.count, d.points, true, d.max_level) {
        for sub in 0..d.sub_draws {
            push_patch_chunk(
                dev,
                cmd,
                pipeline,
                d.first_patch + first,
                sub | d.sub_flag,
                split,
            );
            // SAFETY: the caller records inside a render pass with `pipeline`, its
            // descriptor sets, vertex and index buffers bound; the range lies in the bound
            // index buffer (chunks of the run).
            unsafe {
                dev.cmd_draw_indexed(cmd, n * d.points, 1, d.first_index + first * d.points, 0, 0)
            };
        }
    }
}
