//! The compute refinement (Köbler 2013, section 4.3): uploads the subdivision tables of every
//! level once ([`RefinementTables::gpu_tables`]) and records, per level, the face, edge and
//! vertex kernels (`glsl/adaptive/refine_{face,edge,vertex}.comp`) into one vertex buffer
//! holding every level (tightly packed xyz `f32`, the layout draws read as a vertex buffer).
//!
//! Memory: the refined buffer is device-local (written and read only by the GPU); the control
//! points are written by the host into a small host-visible staging buffer and copied into
//! level 0 by [`GpuRefiner::record`], so only they cross the bus and the copy is ordered with the
//! kernels inside the command buffer.
//!
//! Barriers per level: face kernel, compute→compute barrier, edge and vertex kernels (the vertex
//! kernel reads the parent vertices and face points only, never edge points, so it needs no
//! barrier after the edge kernel), compute→compute barrier. The last one also makes the buffer
//! visible to vertex input, the tessellation stages and transfers.

use ash::vk;
use glam::DVec3;

use crate::gpu::{
    memory_barrier, Buffer, BufferBinding, ComputePipelineDesc, Context, DescriptorBinding,
    DescriptorKind, DescriptorPool, MemoryLocation, Pipeline, PushConstants,
};
use crate::render::pass::upload::{device_buffer, host_buffer, u32_bytes, vec3_bytes};
use crate::subdiv::tables::{GpuTables, KernelRange, RefinementTables};
use crate::{Error, Result};

/// Threads per workgroup (`local_size_x` in `glsl/adaptive/refine.glsl`).
const GROUP_SIZE: u32 = 64;
/// Workgroups per dispatch (the minimum `maxComputeWorkGroupCount[0]` Vulkan guarantees).
const MAX_GROUPS: u32 = 65_535;
/// The kernels in dispatch order (face, edge, vertex points).
const KERNELS: [&str; 3] = ["refine_face.comp", "refine_edge.comp", "refine_vertex.comp"];

/// GPU resources of the compute refinement of one topology.
pub struct GpuRefiner {
    tables: Buffer,
    table_words: usize,
    points: Buffer,
    staging: Buffer,
    control_count: u32,
    total_vertices: u32,
    steps: Vec<[KernelRange; 3]>,
    pipelines: Vec<Pipeline>,
    _pool: DescriptorPool,
    set: vk::DescriptorSet,
}

impl GpuRefiner {
    /// Uploads `tables` (device-local) and creates the vertex buffer of every level; level 0
    /// holds `control` (one point per base vertex).
    pub fn new(ctx: &Context, tables: &RefinementTables, control: &[DVec3]) -> Result<GpuRefiner> {
        let control_count = tables.level_len(0);
        check_count(control_count, control.len())?;
        let GpuTables { words, steps } = tables.gpu_tables();
        let table_buffer = device_buffer(
            ctx,
            &u32_bytes(&words),
            vk::BufferUsageFlags::STORAGE_BUFFER,
            "adaptive refinement tables",
        )?;
        let points = Buffer::new(
            ctx,
            u64::from(tables.total_vertices.max(1)) * 12,
            vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::VERTEX_BUFFER
                | vk::BufferUsageFlags::TRANSFER_DST
                | vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::GpuOnly,
            "adaptive refined points",
        )?;
        let staging = host_buffer(
            ctx,
            &vec3_bytes(control),
            vk::BufferUsageFlags::TRANSFER_SRC,
            "adaptive control points",
        )?;
        let pipelines = KERNELS
            .iter()
            .map(|shader| range_kernel(ctx, shader, 2))
            .collect::<Result<Vec<_>>>()?;
        let pool = DescriptorPool::new(ctx, 1, 2, 0)?;
        let set = pool.allocate(pipelines[0].set_layouts[0])?;
        ctx.write_buffer_descriptors(
            set,
            &[
                BufferBinding {
                    binding: 0,
                    kind: DescriptorKind::StorageBuffer,
                    buffer: &table_buffer,
                },
                BufferBinding {
                    binding: 1,
                    kind: DescriptorKind::StorageBuffer,
                    buffer: &points,
                },
            ],
        );
        Ok(GpuRefiner {
            tables: table_buffer,
            table_words: words.len(),
            points,
            staging,
            control_count,
            total_vertices: tables.total_vertices,
            steps,
            pipelines,
            _pool: pool,
            set,
        })
    }

    /// New control points (animation): copied into level 0 by the next [`Self::record`]. The
    /// GPU must be done with the previous frame's copy.
    pub fn update_control_points(&mut self, control: &[DVec3]) -> Result<()> {
        check_count(self.control_count, control.len())?;
        self.staging.write(0, &vec3_bytes(control))
    }

    /// The vertex buffer of every level (`STORAGE | VERTEX_BUFFER`, 12 bytes per point).
    pub fn points(&self) -> &Buffer {
        &self.points
    }

    /// Number of points in [`Self::points`].
    pub fn total_vertices(&self) -> u32 {
        self.total_vertices
    }

    /// Words in the table buffer and the kernels' dispatch ranges per level (what a run-time
    /// table rewrite must keep).
    pub fn table_layout(&self) -> (usize, &[[KernelRange; 3]]) {
        (self.table_words, &self.steps)
    }

    /// Overwrites the subdivision tables with `tables` of the same layout
    /// ([`Self::table_layout`]; new crease weights). Call while no submitted work uses them.
    pub fn rewrite_tables(&self, ctx: &Context, tables: &GpuTables) -> Result<()> {
        if (tables.words.len(), tables.steps.as_slice()) != self.table_layout() {
            return Err(Error::Invalid(
                "adaptive refinement: new subdivision tables of another layout".into(),
            ));
        }
        ctx.rewrite_buffer(&self.tables, &tables.words, "adaptive refinement tables")
    }

    /// Bytes of GPU memory held (tables, points, staging).
    pub fn memory_bytes(&self) -> u64 {
        self.tables.size() + self.points.size() + self.staging.size()
    }

    /// Records the level-0 copy from the points of [`Self::update_control_points`] and every
    /// level's kernels into `cmd` ([`Self::record_from`]).
    pub fn record(&self, dev: &ash::Device, cmd: vk::CommandBuffer) {
        self.record_from(dev, cmd, self.staging.raw());
    }

    /// Records the level-0 copy from `control` (a `TRANSFER_SRC` buffer of at least the base
    /// vertices' tightly packed f32 xyz, host writes to it made before submission) and every
    /// level's kernels into `cmd` (recording, outside a render pass), ending with a barrier to
    /// vertex input, tessellation and transfer reads.
    pub fn record_from(&self, dev: &ash::Device, cmd: vk::CommandBuffer, control: vk::Buffer) {
        use vk::{AccessFlags as A, PipelineStageFlags as S};
        let readers = S::VERTEX_INPUT
            | S::VERTEX_SHADER
            | S::TESSELLATION_CONTROL_SHADER
            | S::TESSELLATION_EVALUATION_SHADER;
        // Earlier draws and kernels read the buffer this copy and these kernels overwrite.
        memory_barrier(
            dev,
            cmd,
            (readers | S::COMPUTE_SHADER | S::TRANSFER, A::empty()),
            (S::TRANSFER | S::COMPUTE_SHADER, A::empty()),
        );
        let region = vk::BufferCopy::default().size(u64::from(self.control_count) * 12);
        // SAFETY: both buffers are valid, the region lies inside both.
        unsafe { dev.cmd_copy_buffer(cmd, control, self.points.raw(), &[region]) };
        let compute = (S::COMPUTE_SHADER, A::SHADER_READ | A::SHADER_WRITE);
        memory_barrier(dev, cmd, (S::TRANSFER, A::TRANSFER_WRITE), compute);
        let layout = self.pipelines[0].layout;
        // SAFETY: the set matches the (shared) layout of the three pipelines.
        unsafe {
            dev.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::COMPUTE,
                layout,
                0,
                &[self.set],
                &[],
            );
        }
        let written = (S::COMPUTE_SHADER, A::SHADER_WRITE);
        for (l, step) in self.steps.iter().enumerate() {
            dispatch_range(dev, cmd, &self.pipelines[0], step[0].first, step[0].count);
            memory_barrier(dev, cmd, written, compute);
            dispatch_range(dev, cmd, &self.pipelines[1], step[1].first, step[1].count);
            dispatch_range(dev, cmd, &self.pipelines[2], step[2].first, step[2].count);
            if l + 1 < self.steps.len() {
                memory_barrier(dev, cmd, written, compute);
            }
        }
        memory_barrier(
            dev,
            cmd,
            written,
            (
                readers | S::TRANSFER,
                A::VERTEX_ATTRIBUTE_READ | A::SHADER_READ | A::TRANSFER_READ,
            ),
        );
    }

    /// Reads the whole buffer back (after the work recorded by [`Self::record`] finished).
    pub fn read_points(&self, ctx: &Context) -> Result<Vec<DVec3>> {
        let floats: Vec<f32> = ctx.read_buffer(&self.points)?;
        Ok(floats
            .chunks_exact(3)
            .take(self.total_vertices as usize)
            .map(|c| DVec3::new(c[0].into(), c[1].into(), c[2].into()))
            .collect())
    }
}

/// Records a kernel of `pipeline` (descriptor sets bound) over `count` items starting at `first`:
/// push constants (first, count, first item of the dispatch), split into dispatches of at most
/// [`MAX_GROUPS`] workgroups of [`GROUP_SIZE`] threads (the `Range` block of
/// `glsl/adaptive/refine.glsl` and `stencil_rows.glsl`).
pub(super) fn dispatch_range(
    dev: &ash::Device,
    cmd: vk::CommandBuffer,
    pipeline: &Pipeline,
    first: u32,
    count: u32,
) {
    if count == 0 {
        return;
    }
    // SAFETY: compute pipeline of this device; push constants within the declared range.
    unsafe { dev.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline.raw) };
    let per_dispatch = MAX_GROUPS * GROUP_SIZE;
    let mut start = 0u32;
    while start < count {
        let n = (count - start).min(per_dispatch);
        let push = [first, count, start];
        // SAFETY: 12 bytes of push constants, the range the pipeline layout declares.
        unsafe {
            dev.cmd_push_constants(
                cmd,
                pipeline.layout,
                vk::ShaderStageFlags::COMPUTE,
                0,
                crate::gpu::as_bytes(&push),
            );
            dev.cmd_dispatch(cmd, n.div_ceil(GROUP_SIZE), 1, 1);
        }
        start += n;
    }
}

/// A compute pipeline over set 0 `bindings` (storage buffers) with the 12-byte range push
/// constants of [`dispatch_range`].
pub(super) fn range_kernel(ctx: &Context, shader: &str, bindings: u32) -> Result<Pipeline> {
    let storage = |binding| DescriptorBinding {
        binding,
        kind: DescriptorKind::StorageBuffer,
        stages: vk::ShaderStageFlags::COMPUTE,
    };
    ctx.compute_pipeline(&ComputePipelineDesc {
        label: format!("adaptive {shader}"),
        shader: shader.to_string(),
        set_layouts: vec![(0..bindings).map(storage).collect()],
        push_constants: Some(PushConstants {
            stages: vk::ShaderStageFlags::COMPUTE,
            size: 12,
        }),
    })
}

fn check_count(expected: u32, got: usize) -> Result<()> {
    if got == expected as usize {
        return Ok(());
    }
    Err(Error::Invalid(format!(
        "adaptive refinement: {got} control points for {expected} base vertices"
    )))
}
