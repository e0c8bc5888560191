//! The draw loop every patch pass shares: patches in chunks (the lavapipe workaround of
//! [`crate::gpu::patch_draw_chunks`]), each chunk once per sub-patch of the uniform split, the
//! chunk's first patch and the sub-patch in the push constants.

use ash::vk;

use super::pipeline::push_patch_chunk;
use crate::gpu::{patch_draw_chunks, Pipeline};

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
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
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
}

/// Records the indexed draws of `d` with `pipeline` bound (its push-constant range
/// is `pipeline::patch_push_constants`), telling the shaders the uniform `split`.
pub fn record_patch_draws(
    dev: &ash::Device,
    cmd: vk::CommandBuffer,
    pipeline: &Pipeline,
    d: &PatchDraws,
    split: u32,
) {
    for (first, n) in patch_draw_chunks(d.count, d.points, true) {
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
