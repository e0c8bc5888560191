//! GPU side of the exact CPU path: the triangles [`super::fallback`] evaluated on the CPU,
//! drawn with `glsl/surface/mesh.vert` (no tessellation).

use ash::vk;

use super::fallback::{DomainPoint, FallbackMesh};
use super::pass::shared::set0_layout;
use super::pass::upload::{device_buffer, host_buffer, u32_bytes};
use super::pass::{bind_draw_state, SharedResources};
use super::renderer::RenderDesc;
use crate::gpu::{
    Buffer, Context, DescriptorPool, DrawTarget, GraphicsPipelineDesc, Pipeline, VertexAttribute,
    VertexBinding,
};
use crate::{Error, Result};

/// Bytes per vertex: position (3 f32), normal (3 f32), class (u32), face and sub-face (2 u32),
/// (u, v) (2 f32): the domain point the texture coordinate is looked up from (face u32::MAX:
/// none), dP/du and dP/dv there (2 x 3 f32; zero without a domain point): the displacement
/// map's shading normal.
const VERTEX_BYTES: usize = 68;

fn vertex_bytes(mesh: &FallbackMesh) -> Vec<u8> {
    let mut out = Vec::with_capacity(mesh.positions.len() * VERTEX_BYTES);
    let none = DomainPoint {
        face: u32::MAX,
        sub_face: u32::MAX,
        uv: [0.0; 2],
    };
    for (k, ((p, n), c)) in mesh
        .positions
        .iter()
        .zip(&mesh.normals)
        .zip(&mesh.classes)
        .enumerate()
    {
        for x in p
            .as_vec3()
            .to_array()
            .into_iter()
            .chain(n.as_vec3().to_array())
        {
            out.extend_from_slice(&x.to_le_bytes());
        }
        out.extend_from_slice(&c.to_le_bytes());
        let d = mesh.domain.get(k).unwrap_or(&none);
        for w in [d.face, d.sub_face, d.uv[0].to_bits(), d.uv[1].to_bits()] {
            out.extend_from_slice(&w.to_le_bytes());
        }
        let t = mesh.tangents.get(k).copied().unwrap_or_default();
        for x in t.iter().flat_map(|d| d.as_vec3().to_array()) {
            out.extend_from_slice(&x.to_le_bytes());
        }
    }
    out
}

/// The CPU-evaluated triangles of one surface on the GPU: one vertex buffer per frame slot,
/// brought to the latest triangles ([`Self::update`]) when the slot is next prepared
/// ([`Self::sync`]), as the shared buffers are.
pub struct CpuPathPass {
    ctx: Context,
    index_count: u32,
    /// Per frame slot: the vertex buffer and the version of the triangles it holds.
    vertices: Vec<(Buffer, u64)>,
    /// The latest triangles' vertex bytes and their version.
    staged: (Vec<u8>, u64),
    indices: Buffer,
    _pool: DescriptorPool,
    sets: Vec<vk::DescriptorSet>,
    pipeline: Pipeline,
}

impl CpuPathPass {
    /// Uploads `mesh` and creates the pipeline.
    pub fn new(
        ctx: &Context,
        mesh: &FallbackMesh,
        shared: &SharedResources,
        desc: &RenderDesc,
        target: &DrawTarget,
    ) -> Result<CpuPathPass> {
        let bytes = vertex_bytes(mesh);
        let n = shared.slot_count();
        let vertices = (0..n)
            .map(|k| {
                let name = format!("cpu-evaluated vertices (frame slot {k})");
                Ok((
                    host_buffer(ctx, &bytes, vk::BufferUsageFlags::VERTEX_BUFFER, &name)?,
                    0,
                ))
            })
            .collect::<Result<Vec<_>>>()?;
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
            geometry: None,
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
                (3, vk::Format::R32G32_UINT, 28),
                (4, vk::Format::R32G32_SFLOAT, 36),
                (5, vk::Format::R32G32B32_SFLOAT, 44),
                (6, vk::Format::R32G32B32_SFLOAT, 56),
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
        let pipeline = ctx.graphics_pipeline_in(&p, target)?;
        let pool = DescriptorPool::new(ctx, n as u32, 5 * n as u32, n as u32)?;
        let sets = shared.set0_per_slot(ctx, &pool, pipeline.set_layouts[0], &[])?;
        Ok(CpuPathPass {
            ctx: ctx.clone(),
            index_count: mesh.indices.len() as u32,
            vertices,
            staged: (bytes, 0),
            indices,
            _pool: pool,
            sets,
            pipeline,
        })
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> u32 {
        self.index_count / 3
    }

    /// Animation: the triangles re-evaluated at new positions (same count), kept on the host
    /// until each frame slot is prepared.
    pub fn update(&mut self, mesh: &FallbackMesh) -> Result<()> {
        if mesh.indices.len() as u32 != self.index_count {
            return Err(Error::Invalid(format!(
                "update_positions: fallback mesh has {} indices, expected {}",
                mesh.indices.len(),
                self.index_count
            )));
        }
        let vb = vertex_bytes(mesh);
        if vb.len() as u64 > self.vertices[0].0.size() {
            return Err(Error::Invalid(
                "update_positions: fallback mesh has more vertices than before".into(),
            ));
        }
        self.staged = (vb, self.staged.1 + 1);
        Ok(())
    }

    /// Brings frame slot `slot` to the latest triangles (the GPU must be done with it).
    pub fn sync(&mut self, slot: usize) -> Result<()> {
        let (buffer, version) = &mut self.vertices[slot];
        if *version != self.staged.1 {
            buffer.write(0, &self.staged.0)?;
            *version = self.staged.1;
        }
        Ok(())
    }

    /// Bytes of GPU memory of the triangles' vertex and index buffers.
    pub fn memory_bytes(&self) -> u64 {
        self.vertices.iter().map(|(b, _)| b.size()).sum::<u64>() + self.indices.size()
    }

    /// Records the draw of frame slot `slot` (inside the caller's render pass).
    pub fn record(&self, cmd: vk::CommandBuffer, slot: usize) {
        if self.index_count == 0 {
            return;
        }
        let dev = self.ctx.device();
        bind_draw_state(
            dev,
            cmd,
            &self.pipeline,
            &[self.sets[slot]],
            Some(self.vertices[slot].0.raw()),
            self.indices.raw(),
        );
        // SAFETY: inside the caller's render pass with this pass's state bound; the indices lie
        // in the bound index buffer.
        unsafe { dev.cmd_draw_indexed(cmd, self.index_count, 1, 0, 0, 0) };
    }
}
