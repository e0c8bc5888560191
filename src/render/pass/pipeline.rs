//! What every tessellated patch pipeline shares (regular B-spline, Gregory two-stage and
//! stencil): raster state from [`RenderDesc`], the evaluation-shader variant name, the
//! push-constant block of a draw chunk and the position vertex input.

use ash::vk;

use super::shared::with_geometry_capture;
use crate::gpu::{
    Context, DescriptorBinding, DrawTarget, GraphicsPipelineDesc, Pipeline, PushConstants,
    VertexAttribute, VertexBinding,
};
use crate::render::renderer::RenderDesc;
use crate::Result;

/// Shader stages that read the patch push constants.
fn patch_push_stages() -> vk::ShaderStageFlags {
    vk::ShaderStageFlags::TESSELLATION_CONTROL | vk::ShaderStageFlags::TESSELLATION_EVALUATION
}

impl RenderDesc {
    /// `LINE` for wireframe, else `FILL`.
    pub(crate) fn polygon_mode(&self) -> vk::PolygonMode {
        if self.wireframe {
            vk::PolygonMode::LINE
        } else {
            vk::PolygonMode::FILL
        }
    }

    /// `BACK` when back faces are culled, else `NONE`.
    pub(crate) fn cull_mode(&self) -> vk::CullModeFlags {
        if self.cull_back_faces {
            vk::CullModeFlags::BACK
        } else {
            vk::CullModeFlags::NONE
        }
    }

    /// The evaluation-shader variant `{stem}_{spacing}[_capture].tese` (glsl/variants.txt).
    pub(crate) fn tese_name(&self, stem: &str) -> String {
        format!(
            "{stem}_{}{}.tese",
            self.tess.spacing.shader_suffix(),
            if self.capture_capacity.is_some() {
                "_capture"
            } else {
                ""
            }
        )
    }
}

/// The push-constant range of every patch pipeline: three `u32` (first patch of the draw chunk,
/// sub-patch index, split).
pub(crate) fn patch_push_constants() -> PushConstants {
    PushConstants {
        stages: patch_push_stages(),
        size: 12,
    }
}

/// Records the push constants of one draw chunk for `pipeline` (bound): first patch `base` (gl_PrimitiveID restarts
/// per draw), sub-patch index `sub`, sub-patches per side `split`.
pub(crate) fn push_patch_chunk(
    dev: &ash::Device,
    cmd: vk::CommandBuffer,
    pipeline: &Pipeline,
    base: u32,
    sub: u32,
    split: u32,
) {
    let mut pc = [0u8; 12];
    for (k, w) in [base, sub, split].iter().enumerate() {
        pc[4 * k..4 * k + 4].copy_from_slice(&w.to_le_bytes());
    }
    // SAFETY: the caller records into a valid command buffer with a pipeline of `layout`
    // bound, whose push-constant range is [`patch_push_constants`] at its push offset.
    unsafe {
        dev.cmd_push_constants(
            cmd,
            pipeline.layout,
            patch_push_stages(),
            pipeline.push_offset,
            &pc,
        )
    };
}

/// Vertex input of pipelines that read control positions from binding 0 (tightly packed f32
/// xyz) at location 0.
pub(crate) fn position_input() -> (Vec<VertexBinding>, Vec<VertexAttribute>) {
    (
        vec![VertexBinding {
            binding: 0,
            stride: 12,
            per_instance: false,
        }],
        vec![VertexAttribute {
            location: 0,
            binding: 0,
            format: vk::Format::R32G32B32_SFLOAT,
            offset: 0,
        }],
    )
}

/// The stages and inputs of one patch pipeline; everything else comes from the [`RenderDesc`].
pub(crate) struct PatchShaders {
    /// Debug label.
    pub label: String,
    /// Vertex shader.
    pub vertex: String,
    /// Tessellation control shader.
    pub tess_control: String,
    /// Evaluation-shader stem; the spacing × capture variant is picked from the description.
    pub tess_eval_stem: &'static str,
    /// Control points per patch.
    pub points: u32,
    /// Whether the vertex stage reads control positions from vertex binding 0.
    pub position_input: bool,
    /// Descriptor set layouts, set 0 first.
    pub set_layouts: Vec<Vec<DescriptorBinding>>,
}

/// Creates (or fetches from the context's cache) a patch pipeline: `PATCH_LIST`, the raster
/// state of `desc`, depth test and write, counter-clockwise front faces, the shared fragment
/// shader and the patch push constants; with `desc.capture_triangles` the pass-through geometry
/// stage that captures the triangles.
pub(crate) fn patch_pipeline(
    ctx: &Context,
    desc: &RenderDesc,
    target: &DrawTarget,
    s: PatchShaders,
) -> Result<Pipeline> {
    let tese = desc.tese_name(s.tess_eval_stem);
    let (vertex_bindings, vertex_attributes) = if s.position_input {
        position_input()
    } else {
        (Vec::new(), Vec::new())
    };
    let p = GraphicsPipelineDesc {
        label: format!("{} ({tese})", s.label),
        vertex: s.vertex,
        tess_control: Some(s.tess_control),
        tess_eval: Some(tese),
        geometry: desc
            .capture_triangles
            .map(|_| "capture_triangles.geom".to_string()),
        fragment: "shade.frag".into(),
        vertex_bindings,
        vertex_attributes,
        topology: vk::PrimitiveTopology::PATCH_LIST,
        patch_control_points: s.points,
        polygon_mode: desc.polygon_mode(),
        cull_mode: desc.cull_mode(),
        front_face: vk::FrontFace::COUNTER_CLOCKWISE,
        depth_test: true,
        depth_write: true,
        set_layouts: match desc.capture_triangles {
            Some(_) => with_geometry_capture(s.set_layouts),
            None => s.set_layouts,
        },
        push_constants: Some(patch_push_constants()),
    };
    ctx.graphics_pipeline_in(&p, target)
}
