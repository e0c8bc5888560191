//! What the adaptive scheme derives from the refined points every frame, after the refinement
//! kernels ([`super::refine::GpuRefiner`]): the limit frames of the patch corners (one per frame
//! slot: position, and the normal where the vertex has one sector) and the control points of the
//! end caps, both as sparse stencil rows over the refined buffer
//! ([`crate::patch::adaptive::rows::SparseRows`]; `glsl/adaptive/limit_frames.comp`,
//! `endcap_points.comp`), after a first stage that computes the vertex points (per smooth
//! end-cap corner its limit point and two tangent sums, per dart its limit point and two
//! tangents, per crease sector of three or more faces its cross-boundary tangent) the other
//! rows read. The frames replace the shared per-vertex frames (set-0 bindings 2 and
//! 9) for the adaptive draws, so patches of every level meeting at a point read the same bits.

use ash::vk;

use super::refine::{dispatch_range, range_kernel};
use crate::gpu::{
    memory_barrier, Buffer, BufferBinding, Context, DescriptorKind, DescriptorPool, MemoryLocation,
    Pipeline,
};
use crate::patch::adaptive::AdaptiveDrawTables;
use crate::render::pass::upload::device_buffer;
use crate::Result;

/// Limit positions and normals per slot as the GPU wrote them (vec4 each).
pub type SlotFrames = (Vec<[f32; 4]>, Vec<[f32; 4]>);

/// Rows per end cap (20 Gregory points, 8 neighbour edge points, 8 neighbour face points).
pub const END_CAP_ROWS: u32 = 36;

/// GPU resources of the per-frame stencil rows of one adaptive surface.
pub struct DerivedPoints {
    rows: [Buffer; 4],
    row_lens: [usize; 4],
    limits: Buffer,
    normals: Buffer,
    end_cap_points: Buffer,
    vertex_points: Buffer,
    frames: u32,
    end_cap_first_row: u32,
    end_cap_rows: u32,
    vertex_first_row: u32,
    vertex_rows: u32,
    frames_kernel: Pipeline,
    points_kernel: Pipeline,
    _pool: DescriptorPool,
    /// Frames, end-cap points, vertex points.
    sets: [vk::DescriptorSet; 3],
}

/// Labels of the four row tables (offsets, ids, weights, slot flags).
const ROW_LABELS: [&str; 4] = [
    "adaptive row offsets",
    "adaptive row ids",
    "adaptive row weights",
    "adaptive slot flags",
];

/// A device-local buffer of `count` vec4 (at least one) written and read only by the GPU.
fn vec4_storage(ctx: &Context, count: u32, label: &str) -> Result<Buffer> {
    Buffer::new(
        ctx,
        u64::from(count.max(1)) * 16,
        vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC,
        MemoryLocation::GpuOnly,
        label,
    )
}

/// `bytes` as a device-local storage buffer (one zero word when empty).
fn words_buffer(ctx: &Context, bytes: Vec<u8>, label: &str) -> Result<Buffer> {
    let bytes = if bytes.is_empty() {
        vec![0u8; 4]
    } else {
        bytes
    };
    device_buffer(ctx, &bytes, vk::BufferUsageFlags::STORAGE_BUFFER, label)
}

impl DerivedPoints {
    /// Uploads the stencil rows of `d` and creates the output buffers: per frame slot `s` the
    /// rows `3 s .. 3 s + 2` and its shared-normal flag; [`END_CAP_ROWS`] rows per end cap
    /// from `d.end_cap_first_row`. `refined` is the refinement's point buffer.
    pub fn new(ctx: &Context, d: &AdaptiveDrawTables, refined: &Buffer) -> Result<DerivedPoints> {
        let frames = d.frame_count() as u32;
        let end_cap_first_row = d.end_cap_first_row;
        let end_cap_rows = d.end_caps.len() as u32 * END_CAP_ROWS;
        let (vertex_first_row, vertex_rows) = (d.vertex_first_row, d.vertex_point_count() as u32);
        let [offsets, ids, weights, flags] = Self::row_bytes(d);
        let row_lens = [offsets.len(), ids.len(), weights.len(), flags.len()];
        let row_buffers = [
            words_buffer(ctx, offsets, ROW_LABELS[0])?,
            words_buffer(ctx, ids, ROW_LABELS[1])?,
            words_buffer(ctx, weights, ROW_LABELS[2])?,
            words_buffer(ctx, flags, ROW_LABELS[3])?,
        ];
        let limits = vec4_storage(ctx, frames, "adaptive vertex limits")?;
        let normals = vec4_storage(ctx, frames, "adaptive vertex normals")?;
        let end_cap_points = vec4_storage(ctx, end_cap_rows, "adaptive end-cap points")?;
        let vertex_points = vec4_storage(ctx, vertex_rows, "adaptive vertex points")?;
        let frames_kernel = range_kernel(ctx, "limit_frames.comp", 8)?;
        let points_kernel = range_kernel(ctx, "endcap_points.comp", 8)?;
        let pool = DescriptorPool::new(ctx, 3, 24, 0)?;
        let sets = [
            pool.allocate(frames_kernel.set_layouts[0])?,
            pool.allocate(points_kernel.set_layouts[0])?,
            pool.allocate(points_kernel.set_layouts[0])?,
        ];
        // The first stage writes the vertex points (binding 4) and reads none (binding 7).
        for (set, (a, b)) in sets.iter().zip([
            (&limits, &normals),
            (&end_cap_points, &normals),
            (&vertex_points, &normals),
        ]) {
            let sb = |binding, buffer| BufferBinding {
                binding,
                kind: DescriptorKind::StorageBuffer,
                buffer,
            };
            ctx.write_buffer_descriptors(
                *set,
                &[
                    sb(0, &row_buffers[0]),
                    sb(1, &row_buffers[1]),
                    sb(2, &row_buffers[2]),
                    sb(3, refined),
                    sb(4, a),
                    sb(5, b),
                    sb(6, &row_buffers[3]),
                    sb(7, &vertex_points),
                ],
            );
        }
        Ok(DerivedPoints {
            rows: row_buffers,
            row_lens,
            limits,
            normals,
            end_cap_points,
            vertex_points,
            frames,
            end_cap_first_row,
            end_cap_rows,
            vertex_first_row,
            vertex_rows,
            frames_kernel,
            points_kernel,
            _pool: pool,
            sets,
        })
    }

    /// Limit positions per slot (vec4; set-0 binding 2 of the adaptive draws).
    pub fn limits(&self) -> &Buffer {
        &self.limits
    }

    /// Unit normals per slot, zero where each patch keeps its own (binding 9).
    pub fn normals(&self) -> &Buffer {
        &self.normals
    }

    /// End-cap control points (vec4, [`END_CAP_ROWS`] per end cap).
    pub fn end_cap_points(&self) -> &Buffer {
        &self.end_cap_points
    }

    /// The stencil-row tables of `d` as uploaded: row offsets, ids, weights, slot flags.
    pub fn row_bytes(d: &AdaptiveDrawTables) -> [Vec<u8>; 4] {
        [
            d.row_offset_bytes(),
            d.row_id_bytes(),
            d.row_weight_bytes(),
            d.slot_flag_bytes(),
        ]
    }

    /// Byte lengths of the row tables uploaded ([`Self::row_bytes`]).
    pub fn row_lens(&self) -> [usize; 4] {
        self.row_lens
    }

    /// Overwrites the row tables with `rows` of the same lengths ([`Self::row_lens`]; a
    /// run-time data change, e.g. new crease sharpness). Call while no submitted work uses them.
    pub fn rewrite_rows(&self, ctx: &Context, rows: &[Vec<u8>; 4]) -> Result<()> {
        for ((buffer, bytes), label) in self.rows.iter().zip(rows).zip(ROW_LABELS) {
            ctx.rewrite_buffer(buffer, bytes, label)?;
        }
        Ok(())
    }

    /// Bytes of GPU memory held.
    pub fn memory_bytes(&self) -> u64 {
        self.rows.iter().map(Buffer::size).sum::<u64>()
            + self.limits.size()
            + self.normals.size()
            + self.end_cap_points.size()
            + self.vertex_points.size()
    }

    /// Records the kernels after the refinement (its points written by compute): the vertex
    /// points, then the frames and end-cap points that read them, ending with a barrier to the
    /// tessellation stages.
    pub fn record(&self, dev: &ash::Device, cmd: vk::CommandBuffer) {
        use vk::{AccessFlags as A, PipelineStageFlags as S};
        let written = (S::COMPUTE_SHADER, A::SHADER_WRITE);
        memory_barrier(dev, cmd, written, (S::COMPUTE_SHADER, A::SHADER_READ));
        let stages = [
            (
                2,
                &self.points_kernel,
                self.vertex_first_row,
                self.vertex_rows,
            ),
            (0, &self.frames_kernel, 0, self.frames),
            (
                1,
                &self.points_kernel,
                self.end_cap_first_row,
                self.end_cap_rows,
            ),
        ];
        for (k, pipeline, first, count) in stages {
            if count == 0 {
                continue;
            }
            // SAFETY: the set matches the pipeline's layout; its buffers live as long as `self`.
            unsafe {
                dev.cmd_bind_descriptor_sets(
                    cmd,
                    vk::PipelineBindPoint::COMPUTE,
                    pipeline.layout,
                    0,
                    &[self.sets[k]],
                    &[],
                );
            }
            dispatch_range(dev, cmd, pipeline, first, count);
            if k == 2 {
                // The frames and end-cap points read the vertex points.
                memory_barrier(dev, cmd, written, (S::COMPUTE_SHADER, A::SHADER_READ));
            }
        }
        let tess = S::TESSELLATION_CONTROL_SHADER | S::TESSELLATION_EVALUATION_SHADER;
        memory_barrier(
            dev,
            cmd,
            written,
            (tess | S::TRANSFER, A::SHADER_READ | A::TRANSFER_READ),
        );
    }

    /// Reads the limit positions and normals back (after the recorded work finished).
    pub fn read_frames(&self, ctx: &Context) -> Result<SlotFrames> {
        let read = |b: &Buffer| -> Result<Vec<[f32; 4]>> {
            let f: Vec<f32> = ctx.read_buffer(b)?;
            Ok(f.chunks_exact(4)
                .take(self.frames as usize)
                .map(|c| [c[0], c[1], c[2], c[3]])
                .collect())
        };
        Ok((read(&self.limits)?, read(&self.normals)?))
    }
}
