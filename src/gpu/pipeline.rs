//! Graphics / compute pipelines built from hashable descriptions, cached in the context.

use std::collections::HashMap;
use std::ffi::CStr;

use ash::vk;

use super::context::Context;
use super::device::Feature;
use super::draw_target::{DrawTarget, LayoutSlots, PassKind};
use super::error::{invalid, GpuError};
use super::shaders::stage_of;
use super::target::{create_render_pass, RenderTarget, TargetFormat};
use crate::Result;

const ENTRY: &CStr = c"main";

/// Kind of a descriptor.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DescriptorKind {
    /// `layout(std430) buffer` (storage buffer).
    StorageBuffer,
    /// `uniform` block (uniform buffer).
    UniformBuffer,
    /// `uniform sampler2D` (combined image sampler, [`super::SampledImage`]).
    CombinedImageSampler,
}

impl DescriptorKind {
    /// The Vulkan descriptor type.
    pub fn vk(self) -> vk::DescriptorType {
        match self {
            DescriptorKind::StorageBuffer => vk::DescriptorType::STORAGE_BUFFER,
            DescriptorKind::UniformBuffer => vk::DescriptorType::UNIFORM_BUFFER,
            DescriptorKind::CombinedImageSampler => vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
        }
    }
}

/// One binding of a descriptor set layout.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct DescriptorBinding {
    /// `binding = N` in GLSL.
    pub binding: u32,
    /// Buffer kind.
    pub kind: DescriptorKind,
    /// Stages that access it.
    pub stages: vk::ShaderStageFlags,
}

/// A vertex buffer binding.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct VertexBinding {
    /// Binding index (`cmd_bind_vertex_buffers` slot).
    pub binding: u32,
    /// Bytes between consecutive elements.
    pub stride: u32,
    /// Advance per instance instead of per vertex.
    pub per_instance: bool,
}

/// A vertex attribute.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct VertexAttribute {
    /// `layout(location = N)`.
    pub location: u32,
    /// Source binding.
    pub binding: u32,
    /// Format, e.g. `R32G32B32_SFLOAT`.
    pub format: vk::Format,
    /// Byte offset inside the element.
    pub offset: u32,
}

/// Push-constant range shared by the listed stages.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PushConstants {
    /// Stages reading the block.
    pub stages: vk::ShaderStageFlags,
    /// Size in bytes (multiple of 4, within `maxPushConstantsSize`).
    pub size: u32,
}

/// Everything that defines a graphics pipeline. Shader names are looked up by
/// [`Context::shader_module`] (embedded, then added with [`Context::add_shaders`]).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct GraphicsPipelineDesc {
    /// Debug name.
    pub label: String,
    /// Vertex shader, e.g. `"patch_bspline.vert"`.
    pub vertex: String,
    /// Tessellation control shader (both tessellation stages or neither).
    pub tess_control: Option<String>,
    /// Tessellation evaluation shader.
    pub tess_eval: Option<String>,
    /// Geometry shader (needs `geometryShader`).
    pub geometry: Option<String>,
    /// Fragment shader.
    pub fragment: String,
    /// Vertex buffer bindings.
    pub vertex_bindings: Vec<VertexBinding>,
    /// Vertex attributes.
    pub vertex_attributes: Vec<VertexAttribute>,
    /// Topology (`PATCH_LIST` with tessellation).
    pub topology: vk::PrimitiveTopology,
    /// Control points per patch (tessellation only).
    pub patch_control_points: u32,
    /// `FILL` or `LINE` (LINE needs fillModeNonSolid).
    pub polygon_mode: vk::PolygonMode,
    /// Cull mode.
    pub cull_mode: vk::CullModeFlags,
    /// Front-face winding.
    pub front_face: vk::FrontFace,
    /// Enable depth test (LESS_OR_EQUAL).
    pub depth_test: bool,
    /// Enable depth writes.
    pub depth_write: bool,
    /// Descriptor set layouts, set 0 first.
    pub set_layouts: Vec<Vec<DescriptorBinding>>,
    /// Push-constant range (offset 0).
    pub push_constants: Option<PushConstants>,
}

impl Default for GraphicsPipelineDesc {
    fn default() -> Self {
        GraphicsPipelineDesc {
            label: String::from("pipeline"),
            vertex: String::new(),
            tess_control: None,
            tess_eval: None,
            geometry: None,
            fragment: String::new(),
            vertex_bindings: Vec::new(),
            vertex_attributes: Vec::new(),
            topology: vk::PrimitiveTopology::TRIANGLE_LIST,
            patch_control_points: 0,
            polygon_mode: vk::PolygonMode::FILL,
            cull_mode: vk::CullModeFlags::NONE,
            front_face: vk::FrontFace::COUNTER_CLOCKWISE,
            depth_test: true,
            depth_write: true,
            set_layouts: Vec::new(),
            push_constants: None,
        }
    }
}

/// Description of a compute pipeline.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct ComputePipelineDesc {
    /// Debug name.
    pub label: String,
    /// Compute shader name, e.g. `"foo.comp"`.
    pub shader: String,
    /// Descriptor set layouts, set 0 first.
    pub set_layouts: Vec<Vec<DescriptorBinding>>,
    /// Push-constant range (offset 0).
    pub push_constants: Option<PushConstants>,
}

/// A created pipeline. Owned by the context's cache (destroyed with the context); copy freely.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Pipeline {
    /// The pipeline.
    pub raw: vk::Pipeline,
    /// Its layout.
    pub layout: vk::PipelineLayout,
    /// Its descriptor set layouts (tessera's set 0 first), for allocating sets.
    pub set_layouts: Vec<vk::DescriptorSetLayout>,
    /// Bind point (GRAPHICS or COMPUTE).
    pub bind_point: vk::PipelineBindPoint,
    /// Set index of `set_layouts[0]` in the layout ([`LayoutSlots::first_set`]; 0 for compute).
    pub first_set: u32,
    /// Byte offset of the pipeline's push constants ([`LayoutSlots::push_offset`]).
    pub push_offset: u32,
}

type LayoutKey = (
    Vec<Vec<DescriptorBinding>>,
    Option<PushConstants>,
    LayoutSlots,
);

/// Cache of everything pipeline-related; destroyed with the context.
#[derive(Default)]
pub(crate) struct PipelineCache {
    set_layouts: HashMap<Vec<DescriptorBinding>, vk::DescriptorSetLayout>,
    layouts: HashMap<LayoutKey, vk::PipelineLayout>,
    render_passes: HashMap<TargetFormat, vk::RenderPass>,
    graphics: HashMap<(GraphicsPipelineDesc, DrawTarget), Pipeline>,
    compute: HashMap<ComputePipelineDesc, Pipeline>,
}

impl PipelineCache {
    pub fn destroy(&mut self, dev: &ash::Device) {
        // SAFETY: called once at context teardown after the device is idle.
        unsafe {
            for p in self.graphics.values().chain(self.compute.values()) {
                dev.destroy_pipeline(p.raw, None);
            }
            for l in self.layouts.values() {
                dev.destroy_pipeline_layout(*l, None);
            }
            for l in self.set_layouts.values() {
                dev.destroy_descriptor_set_layout(*l, None);
            }
            for r in self.render_passes.values() {
                dev.destroy_render_pass(*r, None);
            }
        }
        *self = PipelineCache::default();
    }

    fn set_layout(
        &mut self,
        ctx: &Context,
        bindings: &[DescriptorBinding],
    ) -> Result<vk::DescriptorSetLayout> {
        if let Some(l) = self.set_layouts.get(bindings) {
            return Ok(*l);
        }
        let vkb: Vec<_> = bindings
            .iter()
            .map(|b| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(b.binding)
                    .descriptor_type(b.kind.vk())
                    .descriptor_count(1)
                    .stage_flags(b.stages)
            })
            .collect();
        let ci = vk::DescriptorSetLayoutCreateInfo::default().bindings(&vkb);
        // SAFETY: valid create info.
        let l = unsafe { ctx.device().create_descriptor_set_layout(&ci, None) }
            .map_err(GpuError::vk("vkCreateDescriptorSetLayout"))?;
        self.set_layouts.insert(bindings.to_vec(), l);
        Ok(l)
    }

    fn layout(
        &mut self,
        ctx: &Context,
        sets: &[Vec<DescriptorBinding>],
        push: Option<PushConstants>,
        slots: &LayoutSlots,
    ) -> Result<(vk::PipelineLayout, Vec<vk::DescriptorSetLayout>)> {
        let lim = &ctx.info().limits;
        slots.check(
            sets.len(),
            push.map(|p| (p.stages, p.size)),
            lim.max_bound_descriptor_sets,
            lim.max_push_constants_size,
        )?;
        if let Some(p) = push {
            if p.size == 0 || p.size % 4 != 0 || p.size > lim.max_push_constants_size {
                return Err(GpuError::Limit(format!(
                    "push-constant size {} must be a non-zero multiple of 4 within maxPushConstantsSize {}",
                    p.size, lim.max_push_constants_size
                ))
                .into());
            }
        }
        let set_layouts = sets
            .iter()
            .map(|s| self.set_layout(ctx, s))
            .collect::<Result<Vec<_>>>()?;
        let key = (sets.to_vec(), push, slots.clone());
        if let Some(l) = self.layouts.get(&key) {
            return Ok((*l, set_layouts));
        }
        let mut all_sets = slots.caller_set_layouts.clone();
        if all_sets.is_empty() && slots.first_set > 0 {
            all_sets = vec![self.set_layout(ctx, &[])?; slots.first_set as usize];
        }
        all_sets.extend_from_slice(&set_layouts);
        let range = |stages, offset, size| {
            vk::PushConstantRange::default()
                .stage_flags(stages)
                .offset(offset)
                .size(size)
        };
        let ranges: Vec<_> = push
            .iter()
            .map(|p| range(p.stages, slots.push_offset, p.size))
            .chain(
                slots
                    .caller_push_ranges
                    .iter()
                    .map(|r| range(r.stages, r.offset, r.size)),
            )
            .collect();
        let ci = vk::PipelineLayoutCreateInfo::default()
            .set_layouts(&all_sets)
            .push_constant_ranges(&ranges);
        // SAFETY: valid create info.
        let l = unsafe { ctx.device().create_pipeline_layout(&ci, None) }
            .map_err(GpuError::vk("vkCreatePipelineLayout"))?;
        self.layouts.insert(key, l);
        Ok((l, set_layouts))
    }

    fn render_pass(&mut self, ctx: &Context, fmt: TargetFormat) -> Result<vk::RenderPass> {
        if let Some(r) = self.render_passes.get(&fmt) {
            return Ok(*r);
        }
        let r = create_render_pass(ctx.device(), fmt)?;
        self.render_passes.insert(fmt, r);
        Ok(r)
    }
}

fn check_stage(name: &str, want: vk::ShaderStageFlags, what: &str) -> Result<()> {
    if stage_of(name) != Some(want) {
        return invalid(format!(
            "{what} shader \"{name}\" must have the extension of that stage"
        ));
    }
    Ok(())
}

fn validate(ctx: &Context, d: &GraphicsPipelineDesc) -> Result<()> {
    check_stage(&d.vertex, vk::ShaderStageFlags::VERTEX, "vertex")?;
    check_stage(&d.fragment, vk::ShaderStageFlags::FRAGMENT, "fragment")?;
    match (&d.tess_control, &d.tess_eval) {
        (Some(c), Some(e)) => {
            ctx.require(&[Feature::TessellationShader])?;
            check_stage(
                c,
                vk::ShaderStageFlags::TESSELLATION_CONTROL,
                "tessellation control",
            )?;
            check_stage(
                e,
                vk::ShaderStageFlags::TESSELLATION_EVALUATION,
                "tessellation evaluation",
            )?;
            if d.topology != vk::PrimitiveTopology::PATCH_LIST {
                return invalid(format!(
                    "{}: tessellation needs PATCH_LIST topology",
                    d.label
                ));
            }
            let max = ctx.info().limits.max_tessellation_patch_size;
            if d.patch_control_points == 0 || d.patch_control_points > max {
                return Err(GpuError::Limit(format!(
                    "{}: {} control points per patch; device allows 1..={max} (maxTessellationPatchSize)",
                    d.label, d.patch_control_points
                ))
                .into());
            }
        }
        (None, None) => {
            if d.topology == vk::PrimitiveTopology::PATCH_LIST {
                return invalid(format!(
                    "{}: PATCH_LIST topology without tessellation shaders",
                    d.label
                ));
            }
        }
        _ => {
            return invalid(format!(
                "{}: give both tessellation shaders or neither",
                d.label
            ))
        }
    }
    if let Some(g) = &d.geometry {
        ctx.require(&[Feature::GeometryShader])?;
        check_stage(g, vk::ShaderStageFlags::GEOMETRY, "geometry")?;
    }
    if d.polygon_mode != vk::PolygonMode::FILL {
        ctx.require(&[Feature::FillModeNonSolid])?;
    }
    check_storage_per_stage(ctx, &d.label, &d.set_layouts)
}

/// Storage buffers visible to one stage must fit `maxPerStageDescriptorStorageBuffers` (the
/// tessellation stages read up to a dozen tables).
fn check_storage_per_stage(
    ctx: &Context,
    label: &str,
    sets: &[Vec<DescriptorBinding>],
) -> Result<()> {
    let max = ctx.info().limits.max_per_stage_storage_buffers;
    let storage = || {
        sets.iter()
            .flatten()
            .filter(|b| b.kind == DescriptorKind::StorageBuffer)
    };
    for (stage, name) in [
        (vk::ShaderStageFlags::VERTEX, "vertex"),
        (
            vk::ShaderStageFlags::TESSELLATION_CONTROL,
            "tessellation control",
        ),
        (
            vk::ShaderStageFlags::TESSELLATION_EVALUATION,
            "tessellation evaluation",
        ),
        (vk::ShaderStageFlags::GEOMETRY, "geometry"),
        (vk::ShaderStageFlags::FRAGMENT, "fragment"),
    ] {
        let n = storage().filter(|b| b.stages.contains(stage)).count() as u32;
        if n > max {
            return Err(GpuError::Limit(format!(
                "{label}: {n} storage buffers in the {name} stage; the device allows {max} \
                 (maxPerStageDescriptorStorageBuffers)"
            ))
            .into());
        }
    }
    Ok(())
}

impl Context {
    /// The graphics pipeline for `desc`, usable with `target` (created once, then cached).
    pub fn graphics_pipeline(
        &self,
        desc: &GraphicsPipelineDesc,
        target: &RenderTarget,
    ) -> Result<Pipeline> {
        self.graphics_pipeline_for(desc, target.format())
    }

    /// The graphics pipeline for `desc`, compatible with render targets of format `fmt`.
    pub fn graphics_pipeline_for(
        &self,
        desc: &GraphicsPipelineDesc,
        fmt: TargetFormat,
    ) -> Result<Pipeline> {
        self.graphics_pipeline_in(desc, &fmt.into())
    }

    /// The graphics pipeline for `desc`, drawing into the caller's rendering `target` (its
    /// render pass or dynamic rendering, with tessera's sets and push constants in the
    /// target's slots). Created once, then cached.
    pub fn graphics_pipeline_in(
        &self,
        desc: &GraphicsPipelineDesc,
        target: &DrawTarget,
    ) -> Result<Pipeline> {
        let mut cache = self
            .shared
            .pipelines
            .lock()
            .unwrap_or_else(|p| p.into_inner());
        let key = (desc.clone(), target.clone());
        if let Some(p) = cache.graphics.get(&key) {
            return Ok(p.clone());
        }
        validate(self, desc)?;
        let fmt = target.format;
        let (layout, set_layouts) =
            cache.layout(self, &desc.set_layouts, desc.push_constants, &target.slots)?;
        let (render_pass, subpass) = match target.pass {
            PassKind::Tessera => (cache.render_pass(self, fmt)?, 0),
            PassKind::RenderPass {
                render_pass,
                subpass,
            } => (render_pass, subpass),
            PassKind::Dynamic => {
                self.require(&[Feature::DynamicRendering])?;
                (vk::RenderPass::null(), 0)
            }
        };
        let remap = target.slots.remap();

        let mut names = vec![(vk::ShaderStageFlags::VERTEX, desc.vertex.as_str())];
        if let (Some(c), Some(e)) = (&desc.tess_control, &desc.tess_eval) {
            names.push((vk::ShaderStageFlags::TESSELLATION_CONTROL, c));
            names.push((vk::ShaderStageFlags::TESSELLATION_EVALUATION, e));
        }
        if let Some(g) = &desc.geometry {
            names.push((vk::ShaderStageFlags::GEOMETRY, g));
        }
        names.push((vk::ShaderStageFlags::FRAGMENT, desc.fragment.as_str()));
        let mut modules = Vec::new();
        for (_, n) in &names {
            match self.shader_module_remapped(n, &remap) {
                Ok(m) => modules.push(m),
                Err(e) => {
                    destroy_modules(self, &modules);
                    return Err(e);
                }
            }
        }
        let stages: Vec<_> = names
            .iter()
            .zip(&modules)
            .map(|((s, _), m)| {
                vk::PipelineShaderStageCreateInfo::default()
                    .stage(*s)
                    .module(*m)
                    .name(ENTRY)
            })
            .collect();
        let vb: Vec<_> = desc
            .vertex_bindings
            .iter()
            .map(|b| {
                vk::VertexInputBindingDescription::default()
                    .binding(b.binding)
                    .stride(b.stride)
                    .input_rate(if b.per_instance {
                        vk::VertexInputRate::INSTANCE
                    } else {
                        vk::VertexInputRate::VERTEX
                    })
            })
            .collect();
        let va: Vec<_> = desc
            .vertex_attributes
            .iter()
            .map(|a| {
                vk::VertexInputAttributeDescription::default()
                    .location(a.location)
                    .binding(a.binding)
                    .format(a.format)
                    .offset(a.offset)
            })
            .collect();
        let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
            .vertex_binding_descriptions(&vb)
            .vertex_attribute_descriptions(&va);
        let input_assembly =
            vk::PipelineInputAssemblyStateCreateInfo::default().topology(desc.topology);
        let tess = vk::PipelineTessellationStateCreateInfo::default()
            .patch_control_points(desc.patch_control_points);
        let viewport = vk::PipelineViewportStateCreateInfo::default()
            .viewport_count(1)
            .scissor_count(1);
        let raster = vk::PipelineRasterizationStateCreateInfo::default()
            .polygon_mode(desc.polygon_mode)
            .cull_mode(desc.cull_mode)
            .front_face(desc.front_face)
            .line_width(1.0);
        let multisample = vk::PipelineMultisampleStateCreateInfo::default()
            .rasterization_samples(vk::SampleCountFlags::from_raw(fmt.samples));
        let depth = vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(desc.depth_test)
            .depth_write_enable(desc.depth_write)
            .depth_compare_op(vk::CompareOp::LESS_OR_EQUAL);
        let blend_att = [vk::PipelineColorBlendAttachmentState::default()
            .color_write_mask(vk::ColorComponentFlags::RGBA)];
        let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_att);
        let dyn_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dyn_states);
        let mut ci = vk::GraphicsPipelineCreateInfo::default()
            .stages(&stages)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&input_assembly)
            .viewport_state(&viewport)
            .rasterization_state(&raster)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth)
            .color_blend_state(&blend)
            .dynamic_state(&dynamic)
            .layout(layout)
            .render_pass(render_pass)
            .subpass(subpass);
        if desc.tess_control.is_some() {
            ci = ci.tessellation_state(&tess);
        }
        let colors = [fmt.color];
        let mut rendering = vk::PipelineRenderingCreateInfo::default()
            .color_attachment_formats(&colors)
            .depth_attachment_format(fmt.depth)
            .stencil_attachment_format(stencil_format(fmt.depth));
        if target.pass == PassKind::Dynamic {
            ci = ci.push_next(&mut rendering);
        }
        // SAFETY: all referenced state lives until the call returns.
        let result = unsafe {
            self.device()
                .create_graphics_pipelines(vk::PipelineCache::null(), &[ci], None)
        };
        destroy_modules(self, &modules);
        let raw = result.map_err(|(_, e)| GpuError::vk("vkCreateGraphicsPipelines")(e))?[0];
        self.set_name(raw, &desc.label);
        let p = Pipeline {
            raw,
            layout,
            set_layouts,
            bind_point: vk::PipelineBindPoint::GRAPHICS,
            first_set: target.slots.first_set,
            push_offset: target.slots.push_offset,
        };
        cache.graphics.insert(key, p.clone());
        Ok(p)
    }

    /// The compute pipeline for `desc` (created once, then cached).
    pub fn compute_pipeline(&self, desc: &ComputePipelineDesc) -> Result<Pipeline> {
        let mut cache = self
            .shared
            .pipelines
            .lock()
            .unwrap_or_else(|p| p.into_inner());
        if let Some(p) = cache.compute.get(desc) {
            return Ok(p.clone());
        }
        check_stage(&desc.shader, vk::ShaderStageFlags::COMPUTE, "compute")?;
        let (layout, set_layouts) = cache.layout(
            self,
            &desc.set_layouts,
            desc.push_constants,
            &LayoutSlots::default(),
        )?;
        let module = self.shader_module(&desc.shader)?;
        let stage = vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::COMPUTE)
            .module(module)
            .name(ENTRY);
        let ci = vk::ComputePipelineCreateInfo::default()
            .stage(stage)
            .layout(layout);
        // SAFETY: valid create info.
        let result = unsafe {
            self.device()
                .create_compute_pipelines(vk::PipelineCache::null(), &[ci], None)
        };
        destroy_modules(self, &[module]);
        let raw = result.map_err(|(_, e)| GpuError::vk("vkCreateComputePipelines")(e))?[0];
        self.set_name(raw, &desc.label);
        let p = Pipeline {
            raw,
            layout,
            set_layouts,
            bind_point: vk::PipelineBindPoint::COMPUTE,
            first_set: 0,
            push_offset: 0,
        };
        cache.compute.insert(desc.clone(), p.clone());
        Ok(p)
    }
}

/// The stencil attachment format of dynamic rendering for depth format `depth`.
fn stencil_format(depth: vk::Format) -> vk::Format {
    match depth {
        vk::Format::D32_SFLOAT_S8_UINT | vk::Format::D24_UNORM_S8_UINT => depth,
        _ => vk::Format::UNDEFINED,
    }
}

fn destroy_modules(ctx: &Context, modules: &[vk::ShaderModule]) {
    for m in modules {
        // SAFETY: modules are not needed after pipeline creation.
        unsafe { ctx.device().destroy_shader_module(*m, None) };
    }
}
