//! GPU side of the exact CPU path: the triangles [`super::fallback`] evaluated on the CPU,
//! drawn with `glsl/surface/mesh.vert` (no tessellation).

use ash::vk;

use super::fallback::FallbackMesh;
use super::pass::shared::set0_layout;
use super::pass::upload::{device_buffer, host_buffer, u32_bytes};
use super::pass::{bind_draw_state, SharedResources};
use super::renderer::RenderDesc;
use crate::gpu::{
    Buffer, Context, DescriptorPool, GraphicsPipelineDesc, Pipeline, TargetFormat, VertexAttribute,
    VertexBinding,
};
use crate::{Error, Result};

/// Bytes per vertex: position (3 f32), normal (3 f32), class (u32).
const VERTEX_BYTES: usize = 28;

fn vertex_bytes(mesh: &FallbackMesh) -> Vec<u8> {
    let mut out = Vec::with_capacity(mesh.positions.len() * VERTEX_BYTES);
    for ((p, n), c) in mesh.positions.iter().zip(&mesh.normals).zip(&mesh.classes) {
        for x in p
            .as_vec3()
            .to_array()
            .into_iter()
            .chain(n.as_vec3().to_array())
        {
            out.extend_from_slice(&x.to_le_bytes());
        }
        out.extend_from_slice(&c.to_le_bytes());
    }
    out
}

/// The CPU-evaluated triangles of one surface on the GPU.
pub struct CpuPathPass {
    ctx: Context,
    index_count: u32,
    vertices: Buffer,
    indices: Buffer,
    _pool: DescriptorPool,
    set: vk::DescriptorSet,
    pipeline: Pipeline,
}

impl CpuPathPass {
    /// Uploads `mesh` and creates the pipeline.
    pub fn new(
        ctx: &Context,
        mesh: &FallbackMesh,
        shared: &SharedResources,
        desc: &RenderDesc,
        target: TargetFormat,
    ) -> Result<CpuPathPass> {
        let vertices = host_buffer(
            ctx,
            &vertex_bytes(mesh),
            vk::BufferUsageFlags::VERTEX_BUFFER,
            "cpu-evaluated vertices",
        )?;
        let indices = device_buffer(
            ctx,
            &u32_bytes(&mesh.indices),
            vk::BufferUsageFlags::INDEX_BUFFER,
            "cpu-evaluated indices",
        )?;
        let p = GraphicsPipelineDesc {
            label: "cpu-evaluated triangles".into(),
            vertex: "mesh.vert".into(),
            tess_control: None,
            tess_eval: None,
            fragment: "shade.frag".into(),
            vertex_bindings: vec![VertexBinding {
                binding: 0,
                stride: VERTEX_BYTES as u32,
                per_instance: false,
            }],
            vertex_attributes: [
                (0, vk::Format::R32G32B32_SFLOAT, 0),
                (1, vk::Format::R32G32B32_SFLOAT, 12),
                (2, vk::Format::R32_UINT, 24),
            ]
            .map(|(location, format, offset)| VertexAttribute {
                location,
                binding: 0,
                format,
                offset,
            })
            .to_vec(),
            topology: vk::PrimitiveTopology::TRIANGLE_LIST,
            patch_control_points: 0,
            polygon_mode: desc.polygon_mode(),
            cull_mode: desc.cull_mode(),
            front_face: vk::FrontFace::COUNTER_CLOCKWISE,
            depth_test: true,
            depth_write: true,
            set_layouts: vec![set0_layout(&[])],
            push_constants: None,
        };
        let pipeline = ctx.graphics_pipeline_for(&p, target)?;
        let pool = DescriptorPool::new(ctx, 1, 5, 1)?;
        let set = pool.allocate(pipeline.set_layouts[0])?;
        shared.write_set0(ctx, set, &[]);
        Ok(CpuPathPass {
            ctx: ctx.clone(),
            index_count: mesh.indices.len() as u32,
            vertices,
            indices,
            _pool: pool,
            set,
            pipeline,
        })
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> u32 {
        self.index_count / 3
    }

    /// Animation: the triangles re-evaluated at new positions (same count).
    pub fn update(&mut self, mesh: &FallbackMesh) -> Result<()> {
        if mesh.indices.len() as u32 != self.index_count {
            return Err(Error::Invalid(format!(
                "update_positions: fallback mesh has {} indices, expected {}",
                mesh.indices.len(),
                self.index_count
            )));
        }
        let vb = vertex_bytes(mesh);
        if vb.len() as u64 > self.vertices.size() {
            return Err(Error::Invalid(
                "update_positions: fallback mesh has more vertices than before".into(),
            ));
        }
        self.vertices.write(0, &vb)
    }

    /// Bytes of GPU memory of the triangles' vertex and index buffers.
    pub fn memory_bytes(&self) -> u64 {
        self.vertices.size() + self.indices.size()
    }

    /// Records the draw (inside the caller's render pass).
    pub fn record(&self, cmd: vk::CommandBuffer) {
        if self.index_count == 0 {
            return;
        }
        let dev = self.ctx.device();
        bind_draw_state(
            dev,
            cmd,
            &self.pipeline,
            &[self.set],
            Some(self.vertices.raw()),
            self.indices.raw(),
        );
        // SAFETY: inside the caller's render pass with this pass's state bound; the indices lie
        // in the bound index buffer.
        unsafe { dev.cmd_draw_indexed(cmd, self.index_count, 1, 0, 0, 0) };
    }
}
