//! tessera inside someone else's renderer.
//!
//! The "engine" here owns everything: the ash instance, device and queue, a gpu-allocator it
//! shares with tessera, per-frame colour + depth attachments, its render pass (or dynamic
//! rendering with `--dynamic`), N frames in flight with its own fences and command buffers, and
//! a ground quad drawn by its own pipeline with its own descriptor set 0 and push constants.
//! tessera gets a [`Context::from_raw`] wrapper, the attachment formats and render pass
//! ([`DrawTarget`]; its sets start at set 1 and its push constants at byte 48, after the
//! engine's), and one command buffer per frame into which it records its compute pre-pass and
//! its draws. A few animated frames are rendered headless; the last is written as a PNG.
//!
//! ```text
//! cargo run --example engine -- [--dynamic] [--frames N] [--in-flight N] [--size WxH] [--out F.png]
//! ```
//!
//! `tests/engine_example.rs` runs [`run`] in both modes against a golden image.

use std::error::Error;
use std::ffi::c_char;
use std::sync::{Arc, Mutex};

use ash::vk;
use glam::{DVec3, Mat4, Vec3, Vec4};
use gpu_allocator::vulkan::{
    Allocation, AllocationCreateDesc, AllocationScheme, Allocator, AllocatorCreateDesc,
};
use gpu_allocator::MemoryLocation;
use image::RgbaImage;
use tessera::assets::EmbeddedMesh;
use tessera::gpu::{
    Context, DrawTarget, LayoutSlots, PassKind, PushRange, RawContextDesc, TargetFormat,
};
use tessera::render::{
    animate, plan_for_scheme, Camera, CameraSpec, ColorBy, EngineDesc, FrameUniforms, RenderDesc,
    Scheme, SchemeLimits, SurfaceRenderer, TessSettings,
};

/// The engine's shaders (`glsl/examples/`), compiled by tessera's build script but not part of
/// the library.
mod shaders {
    include!(concat!(env!("OUT_DIR"), "/test_shaders.rs"));
}

type Res<T> = Result<T, Box<dyn Error>>;

const COLOR_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;
/// Bytes of the engine's push constants (ground colours and cell size), before tessera's.
const ENGINE_PUSH_BYTES: u32 = 36;
/// Where tessera's push constants start (after the engine's, 16-byte aligned for clarity).
const TESSERA_PUSH_OFFSET: u32 = 48;

/// What to render.
#[derive(Debug, Clone)]
pub struct EngineOptions {
    /// Image size.
    pub width: u32,
    /// Image size.
    pub height: u32,
    /// Frames rendered (the twist animation runs once over them).
    pub frames: u32,
    /// Frames in flight (fences, command buffers, attachments and tessera frame slots).
    pub frames_in_flight: u32,
    /// Dynamic rendering instead of a render pass.
    pub dynamic_rendering: bool,
    /// Enable the Khronos validation layer.
    pub validation: bool,
}

impl Default for EngineOptions {
    fn default() -> Self {
        EngineOptions {
            width: 320,
            height: 240,
            frames: 6,
            frames_in_flight: 2,
            dynamic_rendering: false,
            validation: true,
        }
    }
}

/// What a run produced.
#[derive(Debug)]
pub struct EngineRun {
    /// The last frame.
    pub image: RgbaImage,
    /// Validation errors and warnings seen by tessera's messenger (on the engine's instance).
    pub validation_errors: usize,
    /// The messages.
    pub validation_messages: Vec<String>,
    /// Patches tessera drew per frame.
    pub patches: u32,
    /// Wall-clock milliseconds from the first frame's recording to the last frame's end.
    pub loop_ms: f64,
}

/// The engine's Vulkan objects (created in order, destroyed in reverse by `Drop`).
pub struct Gpu {
    _entry: ash::Entry,
    instance: ash::Instance,
    physical: vk::PhysicalDevice,
    device: ash::Device,
    queue: vk::Queue,
    family: u32,
    features: vk::PhysicalDeviceFeatures,
    allocator: Option<Arc<Mutex<Allocator>>>,
    debug_utils: bool,
}

impl Gpu {
    /// Instance (validation layer and debug utils with `validation`), the first device with
    /// tessellation shaders, created with `features` (and dynamicRendering when asked), one
    /// graphics queue, an allocator.
    pub fn new(
        validation: bool,
        dynamic_rendering: bool,
        features: vk::PhysicalDeviceFeatures,
    ) -> Res<Gpu> {
        // SAFETY: loading the system Vulkan loader.
        let entry = unsafe { ash::Entry::load()? };
        let layer = c"VK_LAYER_KHRONOS_validation";
        let layers: Vec<*const c_char> = if validation {
            vec![layer.as_ptr()]
        } else {
            Vec::new()
        };
        let exts = [ash::ext::debug_utils::NAME.as_ptr()];
        let app = vk::ApplicationInfo::default()
            .application_name(c"engine example")
            .api_version(vk::API_VERSION_1_3);
        let ici = vk::InstanceCreateInfo::default()
            .application_info(&app)
            .enabled_layer_names(&layers)
            .enabled_extension_names(if validation { &exts } else { &[] });
        // SAFETY: valid create info.
        let instance = unsafe { entry.create_instance(&ici, None)? };
        // SAFETY: valid instance.
        let physical = unsafe { instance.enumerate_physical_devices()? }
            .into_iter()
            .find(|pd| unsafe { instance.get_physical_device_features(*pd) }.tessellation_shader == vk::TRUE)
            .ok_or("no Vulkan device with tessellation shaders")?;
        // SAFETY: valid physical device.
        let family = unsafe { instance.get_physical_device_queue_family_properties(physical) }
            .iter()
            .position(|q| q.queue_flags.contains(vk::QueueFlags::GRAPHICS))
            .ok_or("no graphics queue")? as u32;
        let mut f13 = vk::PhysicalDeviceVulkan13Features::default().dynamic_rendering(true);
        let prio = [1.0];
        let queues = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(family)
            .queue_priorities(&prio)];
        let mut dci = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queues)
            .enabled_features(&features);
        if dynamic_rendering {
            dci = dci.push_next(&mut f13);
        }
        // SAFETY: valid create info for this physical device.
        let device = unsafe { instance.create_device(physical, &dci, None)? };
        // SAFETY: one queue of this family was created.
        let queue = unsafe { device.get_device_queue(family, 0) };
        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: instance.clone(),
            device: device.clone(),
            physical_device: physical,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: Default::default(),
        })?;
        Ok(Gpu {
            _entry: entry,
            instance,
            physical,
            device,
            queue,
            family,
            features,
            allocator: Some(Arc::new(Mutex::new(allocator))),
            debug_utils: validation,
        })
    }

    fn allocator(&self) -> std::sync::MutexGuard<'_, Allocator> {
        self.allocator
            .as_ref()
            .expect("allocator lives until drop")
            .lock()
            .unwrap_or_else(|p| p.into_inner())
    }

    fn depth_format(&self) -> Res<vk::Format> {
        [vk::Format::D32_SFLOAT, vk::Format::D24_UNORM_S8_UINT]
            .into_iter()
            .find(|f| {
                // SAFETY: valid physical device.
                unsafe {
                    self.instance
                        .get_physical_device_format_properties(self.physical, *f)
                }
                .optimal_tiling_features
                .contains(vk::FormatFeatureFlags::DEPTH_STENCIL_ATTACHMENT)
            })
            .ok_or_else(|| "no depth format".into())
    }

    fn image(
        &self,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
        w: u32,
        h: u32,
    ) -> Res<(vk::Image, Allocation, vk::ImageView)> {
        let ci = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(vk::Extent3D {
                width: w,
                height: h,
                depth: 1,
            })
            .mip_levels(1)
            .array_layers(1)
            .samples(vk::SampleCountFlags::TYPE_1)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(usage);
        // SAFETY: valid create info.
        let image = unsafe { self.device.create_image(&ci, None)? };
        // SAFETY: valid image.
        let requirements = unsafe { self.device.get_image_memory_requirements(image) };
        let allocation = self.allocator().allocate(&AllocationCreateDesc {
            name: "engine attachment",
            requirements,
            location: MemoryLocation::GpuOnly,
            linear: false,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        })?;
        // SAFETY: fresh allocation of the image's requirements.
        unsafe {
            self.device
                .bind_image_memory(image, allocation.memory(), allocation.offset())?
        };
        let view_ci = vk::ImageViewCreateInfo::default()
            .image(image)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(format)
            .subresource_range(range(aspect_of(format)));
        // SAFETY: valid image.
        let view = unsafe { self.device.create_image_view(&view_ci, None)? };
        Ok((image, allocation, view))
    }

    /// A buffer from the engine's allocator.
    pub fn buffer(
        &self,
        size: u64,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
    ) -> Res<(vk::Buffer, Allocation)> {
        let ci = vk::BufferCreateInfo::default().size(size).usage(usage);
        // SAFETY: valid create info.
        let buffer = unsafe { self.device.create_buffer(&ci, None)? };
        // SAFETY: valid buffer.
        let requirements = unsafe { self.device.get_buffer_memory_requirements(buffer) };
        let allocation = self.allocator().allocate(&AllocationCreateDesc {
            name: "engine buffer",
            requirements,
            location,
            linear: true,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        })?;
        // SAFETY: fresh allocation of the buffer's requirements.
        unsafe {
            self.device
                .bind_buffer_memory(buffer, allocation.memory(), allocation.offset())?
        };
        Ok((buffer, allocation))
    }

    /// Destroys a buffer made by [`Self::buffer`].
    pub fn free_buffer(&self, (buffer, allocation): (vk::Buffer, Allocation)) -> Res<()> {
        // SAFETY: the buffer is not in use.
        unsafe { self.device.destroy_buffer(buffer, None) };
        Ok(self.allocator().free(allocation)?)
    }

    /// The device.
    pub fn device(&self) -> &ash::Device {
        &self.device
    }

    /// tessera's view of this device.
    pub fn raw_desc(&self, dynamic_rendering: bool) -> RawContextDesc {
        RawContextDesc {
            entry: self._entry.clone(),
            instance: self.instance.clone(),
            instance_api_version: vk::API_VERSION_1_3,
            physical_device: self.physical,
            device: self.device.clone(),
            queue: self.queue,
            queue_family: self.family,
            enabled_features: self.features,
            dynamic_rendering,
            allocator: self.allocator.clone(),
            debug_utils: self.debug_utils,
            timeout_ms: 60_000,
        }
    }
}

impl Drop for Gpu {
    fn drop(&mut self) {
        // SAFETY: every object made from the device is gone (Engine dropped first); tessera's
        // context is dropped, so this is the allocator's last reference.
        unsafe {
            let _ = self.device.device_wait_idle();
            drop(self.allocator.take());
            self.device.destroy_device(None);
            self.instance.destroy_instance(None);
        }
    }
}

fn aspect_of(format: vk::Format) -> vk::ImageAspectFlags {
    match format {
        vk::Format::D32_SFLOAT => vk::ImageAspectFlags::DEPTH,
        vk::Format::D24_UNORM_S8_UINT => {
            vk::ImageAspectFlags::DEPTH | vk::ImageAspectFlags::STENCIL
        }
        _ => vk::ImageAspectFlags::COLOR,
    }
}

fn range(aspect: vk::ImageAspectFlags) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange::default()
        .aspect_mask(aspect)
        .level_count(1)
        .layer_count(1)
}

/// One frame in flight: attachments, framebuffer, command buffer, fence, camera buffer + set.
struct Frame {
    color: (vk::Image, Option<Allocation>, vk::ImageView),
    depth: (vk::Image, Option<Allocation>, vk::ImageView),
    framebuffer: vk::Framebuffer,
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
    camera: (vk::Buffer, Option<Allocation>),
    set: vk::DescriptorSet,
}

/// The engine's own objects besides the device.
struct Engine<'g> {
    gpu: &'g Gpu,
    render_pass: vk::RenderPass,
    set_layout: vk::DescriptorSetLayout,
    layout: vk::PipelineLayout,
    pipeline: vk::Pipeline,
    pool: vk::DescriptorPool,
    commands: vk::CommandPool,
    frames: Vec<Frame>,
    depth_format: vk::Format,
    extent: vk::Extent2D,
}

impl Drop for Engine<'_> {
    fn drop(&mut self) {
        let d = &self.gpu.device;
        // SAFETY: the device is idle (waited below); objects are destroyed once.
        unsafe {
            let _ = d.device_wait_idle();
            for f in &mut self.frames {
                d.destroy_fence(f.fence, None);
                d.destroy_framebuffer(f.framebuffer, None);
                for (image, alloc, view) in [&mut f.color, &mut f.depth] {
                    d.destroy_image_view(*view, None);
                    d.destroy_image(*image, None);
                    if let Some(a) = alloc.take() {
                        let _ = self.gpu.allocator().free(a);
                    }
                }
                d.destroy_buffer(f.camera.0, None);
                if let Some(a) = f.camera.1.take() {
                    let _ = self.gpu.allocator().free(a);
                }
            }
            d.destroy_command_pool(self.commands, None);
            d.destroy_descriptor_pool(self.pool, None);
            d.destroy_pipeline(self.pipeline, None);
            d.destroy_pipeline_layout(self.layout, None);
            d.destroy_descriptor_set_layout(self.set_layout, None);
            if self.render_pass != vk::RenderPass::null() {
                d.destroy_render_pass(self.render_pass, None);
            }
        }
    }
}

fn shader(gpu: &Gpu, name: &str) -> Res<vk::ShaderModule> {
    let (_, code) = shaders::TEST_SHADERS
        .iter()
        .find(|(n, _)| *n == name)
        .ok_or_else(|| format!("shader {name} not built"))?;
    // SAFETY: SPIR-V from glslang (build.rs).
    let m = unsafe {
        gpu.device
            .create_shader_module(&vk::ShaderModuleCreateInfo::default().code(code), None)?
    };
    Ok(m)
}

impl<'g> Engine<'g> {
    fn new(gpu: &'g Gpu, opts: &EngineOptions) -> Res<Engine<'g>> {
        let d = &gpu.device;
        let depth_format = gpu.depth_format()?;
        let extent = vk::Extent2D {
            width: opts.width,
            height: opts.height,
        };
        let mut e = Engine {
            gpu,
            render_pass: vk::RenderPass::null(),
            set_layout: vk::DescriptorSetLayout::null(),
            layout: vk::PipelineLayout::null(),
            pipeline: vk::Pipeline::null(),
            pool: vk::DescriptorPool::null(),
            commands: vk::CommandPool::null(),
            frames: Vec::new(),
            depth_format,
            extent,
        };
        if !opts.dynamic_rendering {
            e.render_pass = render_pass(d, depth_format)?;
        }
        let binding = [vk::DescriptorSetLayoutBinding::default()
            .binding(0)
            .descriptor_type(vk::DescriptorType::UNIFORM_BUFFER)
            .descriptor_count(1)
            .stage_flags(vk::ShaderStageFlags::VERTEX)];
        // SAFETY: valid create infos throughout.
        unsafe {
            e.set_layout = d.create_descriptor_set_layout(
                &vk::DescriptorSetLayoutCreateInfo::default().bindings(&binding),
                None,
            )?;
            let ranges = [vk::PushConstantRange::default()
                .stage_flags(vk::ShaderStageFlags::FRAGMENT)
                .size(ENGINE_PUSH_BYTES)];
            let set_layouts = [e.set_layout];
            e.layout = d.create_pipeline_layout(
                &vk::PipelineLayoutCreateInfo::default()
                    .set_layouts(&set_layouts)
                    .push_constant_ranges(&ranges),
                None,
            )?;
            let n = opts.frames_in_flight;
            let sizes = [vk::DescriptorPoolSize {
                ty: vk::DescriptorType::UNIFORM_BUFFER,
                descriptor_count: n,
            }];
            e.pool = d.create_descriptor_pool(
                &vk::DescriptorPoolCreateInfo::default()
                    .max_sets(n)
                    .pool_sizes(&sizes),
                None,
            )?;
            e.commands = d.create_command_pool(
                &vk::CommandPoolCreateInfo::default()
                    .queue_family_index(gpu.family)
                    .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER),
                None,
            )?;
        }
        e.pipeline = ground_pipeline(gpu, &e, opts.dynamic_rendering)?;
        for _ in 0..opts.frames_in_flight {
            let f = e.frame()?;
            e.frames.push(f);
        }
        Ok(e)
    }

    fn frame(&self) -> Res<Frame> {
        let (gpu, d) = (self.gpu, &self.gpu.device);
        let (w, h) = (self.extent.width, self.extent.height);
        let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC;
        let (ci, ca, cv) = gpu.image(COLOR_FORMAT, usage, w, h)?;
        let depth_usage = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT;
        let (di, da, dv) = gpu.image(self.depth_format, depth_usage, w, h)?;
        let (cam, cam_alloc) = gpu.buffer(
            80,
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            MemoryLocation::CpuToGpu,
        )?;
        // SAFETY: valid create infos; the set is written with a live buffer.
        unsafe {
            let framebuffer = if self.render_pass == vk::RenderPass::null() {
                vk::Framebuffer::null()
            } else {
                let views = [cv, dv];
                d.create_framebuffer(
                    &vk::FramebufferCreateInfo::default()
                        .render_pass(self.render_pass)
                        .attachments(&views)
                        .width(w)
                        .height(h)
                        .layers(1),
                    None,
                )?
            };
            let cmd = d.allocate_command_buffers(
                &vk::CommandBufferAllocateInfo::default()
                    .command_pool(self.commands)
                    .command_buffer_count(1),
            )?[0];
            let fence = d.create_fence(
                &vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED),
                None,
            )?;
            let layouts = [self.set_layout];
            let set = d.allocate_descriptor_sets(
                &vk::DescriptorSetAllocateInfo::default()
                    .descriptor_pool(self.pool)
                    .set_layouts(&layouts),
            )?[0];
            let info = [vk::DescriptorBufferInfo::default()
                .buffer(cam)
                .range(vk::WHOLE_SIZE)];
            let write = vk::WriteDescriptorSet::default()
                .dst_set(set)
                .descriptor_type(vk::DescriptorType::UNIFORM_BUFFER)
                .buffer_info(&info);
            d.update_descriptor_sets(&[write], &[]);
            Ok(Frame {
                color: (ci, Some(ca), cv),
                depth: (di, Some(da), dv),
                framebuffer,
                cmd,
                fence,
                camera: (cam, Some(cam_alloc)),
                set,
            })
        }
    }

    /// What tessera's pipelines must match: formats, the render pass or dynamic rendering,
    /// its sets after the engine's set 0 (the engine's layout below, so set 0 stays bound),
    /// its push constants after the engine's.
    fn draw_target(&self) -> DrawTarget {
        DrawTarget {
            format: TargetFormat {
                color: COLOR_FORMAT,
                depth: self.depth_format,
                samples: 1,
            },
            pass: if self.render_pass == vk::RenderPass::null() {
                PassKind::Dynamic
            } else {
                PassKind::RenderPass {
                    render_pass: self.render_pass,
                    subpass: 0,
                }
            },
            slots: LayoutSlots {
                first_set: 1,
                caller_set_layouts: vec![self.set_layout],
                push_offset: TESSERA_PUSH_OFFSET,
                caller_push_ranges: vec![PushRange {
                    stages: vk::ShaderStageFlags::FRAGMENT,
                    offset: 0,
                    size: ENGINE_PUSH_BYTES,
                }],
            },
        }
    }
}

fn render_pass(d: &ash::Device, depth: vk::Format) -> Res<vk::RenderPass> {
    let attachments = [
        vk::AttachmentDescription::default()
            .format(COLOR_FORMAT)
            .samples(vk::SampleCountFlags::TYPE_1)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::STORE)
            .stencil_load_op(vk::AttachmentLoadOp::DONT_CARE)
            .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
            .initial_layout(vk::ImageLayout::UNDEFINED)
            .final_layout(vk::ImageLayout::TRANSFER_SRC_OPTIMAL),
        vk::AttachmentDescription::default()
            .format(depth)
            .samples(vk::SampleCountFlags::TYPE_1)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::DONT_CARE)
            .stencil_load_op(vk::AttachmentLoadOp::CLEAR)
            .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
            .initial_layout(vk::ImageLayout::UNDEFINED)
            .final_layout(vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL),
    ];
    let color_ref = [vk::AttachmentReference::default()
        .attachment(0)
        .layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)];
    let depth_ref = vk::AttachmentReference::default()
        .attachment(1)
        .layout(vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL);
    let subpass = [vk::SubpassDescription::default()
        .pipeline_bind_point(vk::PipelineBindPoint::GRAPHICS)
        .color_attachments(&color_ref)
        .depth_stencil_attachment(&depth_ref)];
    use vk::{AccessFlags as A, PipelineStageFlags as S};
    let attach_stages =
        S::COLOR_ATTACHMENT_OUTPUT | S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS;
    let attach_writes = A::COLOR_ATTACHMENT_WRITE | A::DEPTH_STENCIL_ATTACHMENT_WRITE;
    let deps = [
        vk::SubpassDependency::default()
            .src_subpass(vk::SUBPASS_EXTERNAL)
            .dst_subpass(0)
            .src_stage_mask(attach_stages | S::TRANSFER)
            .dst_stage_mask(attach_stages)
            .src_access_mask(attach_writes)
            .dst_access_mask(attach_writes | A::DEPTH_STENCIL_ATTACHMENT_READ),
        vk::SubpassDependency::default()
            .src_subpass(0)
            .dst_subpass(vk::SUBPASS_EXTERNAL)
            .src_stage_mask(S::COLOR_ATTACHMENT_OUTPUT)
            .dst_stage_mask(S::TRANSFER)
            .src_access_mask(A::COLOR_ATTACHMENT_WRITE)
            .dst_access_mask(A::TRANSFER_READ),
    ];
    let ci = vk::RenderPassCreateInfo::default()
        .attachments(&attachments)
        .subpasses(&subpass)
        .dependencies(&deps);
    // SAFETY: valid create info.
    Ok(unsafe { d.create_render_pass(&ci, None)? })
}

fn ground_pipeline(gpu: &Gpu, e: &Engine<'_>, dynamic: bool) -> Res<vk::Pipeline> {
    let d = &gpu.device;
    let vs = shader(gpu, "engine_ground.vert")?;
    let fs = shader(gpu, "engine_ground.frag")?;
    let stages = [
        vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::VERTEX)
            .module(vs)
            .name(c"main"),
        vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::FRAGMENT)
            .module(fs)
            .name(c"main"),
    ];
    let vertex_input = vk::PipelineVertexInputStateCreateInfo::default();
    let input_assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
        .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
    let viewport = vk::PipelineViewportStateCreateInfo::default()
        .viewport_count(1)
        .scissor_count(1);
    let raster = vk::PipelineRasterizationStateCreateInfo::default()
        .polygon_mode(vk::PolygonMode::FILL)
        .line_width(1.0);
    let multisample = vk::PipelineMultisampleStateCreateInfo::default()
        .rasterization_samples(vk::SampleCountFlags::TYPE_1);
    let depth = vk::PipelineDepthStencilStateCreateInfo::default()
        .depth_test_enable(true)
        .depth_write_enable(true)
        .depth_compare_op(vk::CompareOp::LESS_OR_EQUAL);
    let blend_att = [vk::PipelineColorBlendAttachmentState::default()
        .color_write_mask(vk::ColorComponentFlags::RGBA)];
    let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_att);
    let dyn_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
    let dynamic_state = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dyn_states);
    let colors = [COLOR_FORMAT];
    let mut rendering = vk::PipelineRenderingCreateInfo::default()
        .color_attachment_formats(&colors)
        .depth_attachment_format(e.depth_format);
    let mut ci = vk::GraphicsPipelineCreateInfo::default()
        .stages(&stages)
        .vertex_input_state(&vertex_input)
        .input_assembly_state(&input_assembly)
        .viewport_state(&viewport)
        .rasterization_state(&raster)
        .multisample_state(&multisample)
        .depth_stencil_state(&depth)
        .color_blend_state(&blend)
        .dynamic_state(&dynamic_state)
        .layout(e.layout)
        .render_pass(e.render_pass);
    if dynamic {
        ci = ci.push_next(&mut rendering);
    }
    // SAFETY: every referenced state lives until the call returns; modules are freed after.
    let result = unsafe { d.create_graphics_pipelines(vk::PipelineCache::null(), &[ci], None) };
    unsafe {
        d.destroy_shader_module(vs, None);
        d.destroy_shader_module(fs, None);
    }
    Ok(result.map_err(|(_, e)| e)?[0])
}

/// The engine's per-frame camera block: view-projection, ground centre and half extent.
fn camera_bytes(view_proj: Mat4, ground: Vec4) -> Vec<u8> {
    view_proj
        .to_cols_array()
        .iter()
        .chain(ground.to_array().iter())
        .flat_map(|x| x.to_le_bytes())
        .collect()
}

fn image_barrier(
    d: &ash::Device,
    cmd: vk::CommandBuffer,
    image: vk::Image,
    aspect: vk::ImageAspectFlags,
    (src_stage, src_access, old): (vk::PipelineStageFlags, vk::AccessFlags, vk::ImageLayout),
    (dst_stage, dst_access, new): (vk::PipelineStageFlags, vk::AccessFlags, vk::ImageLayout),
) {
    let b = vk::ImageMemoryBarrier::default()
        .src_access_mask(src_access)
        .dst_access_mask(dst_access)
        .old_layout(old)
        .new_layout(new)
        .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .image(image)
        .subresource_range(range(aspect));
    // SAFETY: recording into a command buffer outside a render pass.
    unsafe {
        d.cmd_pipeline_barrier(
            cmd,
            src_stage,
            dst_stage,
            vk::DependencyFlags::empty(),
            &[],
            &[],
            &[b],
        )
    };
}

/// Renders `opts.frames` animated frames of the embedded `mixed` mesh (adaptive scheme, tessera)
/// over a checkered ground (the engine) and returns the last.
pub fn run(opts: &EngineOptions) -> Res<EngineRun> {
    let features = vk::PhysicalDeviceFeatures::default().tessellation_shader(true);
    let gpu = Gpu::new(opts.validation, opts.dynamic_rendering, features)?;
    let ctx = Context::from_raw(&gpu.raw_desc(opts.dynamic_rendering))?;
    let result = render(&gpu, &ctx, opts);
    let run = result.map(|(image, patches, loop_ms)| EngineRun {
        image,
        loop_ms,
        validation_errors: ctx.validation_errors() + ctx.validation_warnings(),
        validation_messages: ctx.validation_messages(),
        patches,
    });
    drop(ctx);
    run
}

fn render(gpu: &Gpu, ctx: &Context, opts: &EngineOptions) -> Res<(RgbaImage, u32, f64)> {
    let engine = Engine::new(gpu, opts)?;
    let d = &gpu.device;
    let mesh = EmbeddedMesh::Mixed.load()?;
    let surface = plan_for_scheme(&mesh, Scheme::Adaptive, &SchemeLimits::from_context(ctx))?;
    let desc = RenderDesc {
        tess: TessSettings {
            level: 6.0,
            ..TessSettings::default()
        },
        color_by: ColorBy::PatchType,
        ..RenderDesc::default()
    };
    let mut renderer = SurfaceRenderer::for_engine(
        ctx,
        &surface,
        &desc,
        &EngineDesc {
            target: engine.draw_target(),
            frames_in_flight: opts.frames_in_flight,
        },
    )?;
    let (lo, hi) = surface.bounding_box();
    let size = (hi - lo).max_element() as f32;
    let aspect = f64::from(opts.width) / f64::from(opts.height);
    let camera = Camera::frame(
        CameraSpec::Auto,
        lo - DVec3::Y * 0.2 * (hi - lo).y,
        hi,
        aspect,
    );
    let view_proj = camera.view_proj();
    let centre = (0.5 * (lo + hi)).as_vec3();
    let ground = Vec4::new(centre.x, lo.y as f32 - 0.02 * size, centre.z, 1.2 * size);
    let mut push = Vec::new();
    for x in [0.80f32, 0.78, 0.72, 1.0, 0.45, 0.47, 0.52, 1.0, 0.25 * size] {
        push.extend_from_slice(&x.to_le_bytes());
    }
    let (w, h) = (opts.width, opts.height);
    let viewport = vk::Viewport::default()
        .width(w as f32)
        .height(h as f32)
        .max_depth(1.0);
    let scissor = vk::Rect2D::default().extent(engine.extent);
    let clears = [
        vk::ClearValue {
            color: vk::ClearColorValue {
                float32: [0.12, 0.14, 0.18, 1.0],
            },
        },
        vk::ClearValue {
            depth_stencil: vk::ClearDepthStencilValue {
                depth: 1.0,
                stencil: 0,
            },
        },
    ];
    let n = engine.frames.len();
    let mut last = 0;
    let start = std::time::Instant::now();
    for i in 0..opts.frames {
        let f = &engine.frames[i as usize % n];
        last = i as usize % n;
        // SAFETY: the fence belongs to this device; waiting makes the slot's objects free.
        unsafe {
            d.wait_for_fences(&[f.fence], true, u64::MAX)?;
            d.reset_fences(&[f.fence])?;
        }
        // Animation: tessera keeps the new positions until this frame's slot is prepared.
        let phase = f64::from(i) / f64::from(opts.frames.max(1));
        renderer.update_positions(
            &animate::twist(mesh.positions(), DVec3::Y, 0.5, phase),
            None,
        )?;
        renderer.set_frame(&FrameUniforms {
            view_proj,
            eye: camera.eye.as_vec3(),
            viewport: [w as f32, h as f32],
            light_dir: Vec3::new(0.4, 0.8, 0.45),
            color_by: desc.color_by,
        })?;
        let cam = f.camera.1.as_ref().ok_or("camera buffer")?;
        let mapped = cam.mapped_slice().ok_or("camera buffer not mapped")?;
        // SAFETY: the slot's fence was waited: no GPU work reads this buffer now.
        unsafe {
            std::ptr::copy_nonoverlapping(
                camera_bytes(view_proj, ground).as_ptr(),
                mapped.as_ptr() as *mut u8,
                80,
            )
        };
        // SAFETY: recording into the slot's command buffer, whose last use finished (fence).
        unsafe {
            d.begin_command_buffer(f.cmd, &vk::CommandBufferBeginInfo::default())?;
            renderer.record_compute(f.cmd);
            begin(d, &engine, f, &clears);
            d.cmd_set_viewport(f.cmd, 0, &[viewport]);
            d.cmd_set_scissor(f.cmd, 0, &[scissor]);
            d.cmd_bind_pipeline(f.cmd, vk::PipelineBindPoint::GRAPHICS, engine.pipeline);
            d.cmd_bind_descriptor_sets(
                f.cmd,
                vk::PipelineBindPoint::GRAPHICS,
                engine.layout,
                0,
                &[f.set],
                &[],
            );
            d.cmd_push_constants(
                f.cmd,
                engine.layout,
                vk::ShaderStageFlags::FRAGMENT,
                0,
                &push,
            );
            d.cmd_draw(f.cmd, 6, 1, 0, 0);
            renderer.record(f.cmd);
            end(d, &engine, f);
            d.end_command_buffer(f.cmd)?;
            let cmds = [f.cmd];
            let submit = vk::SubmitInfo::default().command_buffers(&cmds);
            d.queue_submit(gpu.queue, &[submit], f.fence)?;
        }
    }
    let patches = renderer.patch_count();
    // Dropping tessera's renderer while frames are in flight is safe: it waits for the device
    // before freeing its buffers (a lost device is logged, not a crash).
    drop(renderer);
    let fences: Vec<_> = engine.frames.iter().map(|f| f.fence).collect();
    // SAFETY: the engine's fences.
    unsafe { d.wait_for_fences(&fences, true, u64::MAX)? };
    let loop_ms = start.elapsed().as_secs_f64() * 1e3;
    let image = read_back(gpu, &engine, &engine.frames[last])?;
    Ok((image, patches, loop_ms))
}

/// Begins the render pass, or dynamic rendering after moving the attachments to their layouts.
unsafe fn begin(d: &ash::Device, e: &Engine<'_>, f: &Frame, clears: &[vk::ClearValue; 2]) {
    let area = vk::Rect2D::default().extent(e.extent);
    if e.render_pass != vk::RenderPass::null() {
        let bi = vk::RenderPassBeginInfo::default()
            .render_pass(e.render_pass)
            .framebuffer(f.framebuffer)
            .render_area(area)
            .clear_values(clears);
        // SAFETY: valid begin info; outside any render pass.
        unsafe { d.cmd_begin_render_pass(f.cmd, &bi, vk::SubpassContents::INLINE) };
        return;
    }
    use vk::{AccessFlags as A, ImageLayout as L, PipelineStageFlags as S};
    let color_out = S::COLOR_ATTACHMENT_OUTPUT;
    image_barrier(
        d,
        f.cmd,
        f.color.0,
        vk::ImageAspectFlags::COLOR,
        (S::TRANSFER | color_out, A::empty(), L::UNDEFINED),
        (
            color_out,
            A::COLOR_ATTACHMENT_WRITE,
            L::COLOR_ATTACHMENT_OPTIMAL,
        ),
    );
    let tests = S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS;
    let depth_access = A::DEPTH_STENCIL_ATTACHMENT_WRITE | A::DEPTH_STENCIL_ATTACHMENT_READ;
    image_barrier(
        d,
        f.cmd,
        f.depth.0,
        aspect_of(e.depth_format),
        (tests, A::DEPTH_STENCIL_ATTACHMENT_WRITE, L::UNDEFINED),
        (tests, depth_access, L::DEPTH_STENCIL_ATTACHMENT_OPTIMAL),
    );
    let color = [vk::RenderingAttachmentInfo::default()
        .image_view(f.color.2)
        .image_layout(L::COLOR_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::STORE)
        .clear_value(clears[0])];
    let depth = vk::RenderingAttachmentInfo::default()
        .image_view(f.depth.2)
        .image_layout(L::DEPTH_STENCIL_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::DONT_CARE)
        .clear_value(clears[1]);
    let ri = vk::RenderingInfo::default()
        .render_area(area)
        .layer_count(1)
        .color_attachments(&color)
        .depth_attachment(&depth);
    // SAFETY: attachments in the layouts named; dynamicRendering enabled on this device.
    unsafe { d.cmd_begin_rendering(f.cmd, &ri) };
}

/// Ends the render pass or dynamic rendering; the colour image ends in TRANSFER_SRC_OPTIMAL.
unsafe fn end(d: &ash::Device, e: &Engine<'_>, f: &Frame) {
    if e.render_pass != vk::RenderPass::null() {
        // SAFETY: inside the render pass begun by `begin`.
        unsafe { d.cmd_end_render_pass(f.cmd) };
        return;
    }
    // SAFETY: inside the rendering begun by `begin`.
    unsafe { d.cmd_end_rendering(f.cmd) };
    use vk::{AccessFlags as A, ImageLayout as L, PipelineStageFlags as S};
    image_barrier(
        d,
        f.cmd,
        f.color.0,
        vk::ImageAspectFlags::COLOR,
        (
            S::COLOR_ATTACHMENT_OUTPUT,
            A::COLOR_ATTACHMENT_WRITE,
            L::COLOR_ATTACHMENT_OPTIMAL,
        ),
        (S::TRANSFER, A::TRANSFER_READ, L::TRANSFER_SRC_OPTIMAL),
    );
}

/// Copies the colour attachment of `f` (in TRANSFER_SRC_OPTIMAL, its frame finished) to an RGBA
/// image.
fn read_back(gpu: &Gpu, e: &Engine<'_>, f: &Frame) -> Res<RgbaImage> {
    let d = &gpu.device;
    let (w, h) = (e.extent.width, e.extent.height);
    let (buffer, alloc) = gpu.buffer(
        u64::from(w * h * 4),
        vk::BufferUsageFlags::TRANSFER_DST,
        MemoryLocation::GpuToCpu,
    )?;
    let region = vk::BufferImageCopy::default()
        .image_subresource(
            vk::ImageSubresourceLayers::default()
                .aspect_mask(vk::ImageAspectFlags::COLOR)
                .layer_count(1),
        )
        .image_extent(vk::Extent3D {
            width: w,
            height: h,
            depth: 1,
        });
    // SAFETY: the frame's fence was waited; one-shot command buffer, waited by a fence.
    let pixels = unsafe {
        let cmd = d.allocate_command_buffers(
            &vk::CommandBufferAllocateInfo::default()
                .command_pool(e.commands)
                .command_buffer_count(1),
        )?[0];
        d.begin_command_buffer(cmd, &vk::CommandBufferBeginInfo::default())?;
        d.cmd_copy_image_to_buffer(
            cmd,
            f.color.0,
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            buffer,
            &[region],
        );
        use vk::{AccessFlags as A, PipelineStageFlags as S};
        let to_host = vk::MemoryBarrier::default()
            .src_access_mask(A::TRANSFER_WRITE)
            .dst_access_mask(A::HOST_READ);
        d.cmd_pipeline_barrier(
            cmd,
            S::TRANSFER,
            S::HOST,
            vk::DependencyFlags::empty(),
            &[to_host],
            &[],
            &[],
        );
        d.end_command_buffer(cmd)?;
        let fence = d.create_fence(&vk::FenceCreateInfo::default(), None)?;
        let cmds = [cmd];
        d.queue_submit(
            gpu.queue,
            &[vk::SubmitInfo::default().command_buffers(&cmds)],
            fence,
        )?;
        d.wait_for_fences(&[fence], true, u64::MAX)?;
        d.destroy_fence(fence, None);
        d.free_command_buffers(e.commands, &cmds);
        let bytes = alloc
            .mapped_slice()
            .ok_or("readback buffer not mapped")?
            .to_vec();
        d.destroy_buffer(buffer, None);
        bytes
    };
    gpu.allocator().free(alloc)?;
    RgbaImage::from_raw(w, h, pixels[..(w * h * 4) as usize].to_vec())
        .ok_or_else(|| "readback size".into())
}

/// The command line: `[--dynamic] [--frames N] [--in-flight N] [--size WxH] [--out FILE.png]`.
#[allow(dead_code)]
fn main() -> Res<()> {
    let mut opts = EngineOptions {
        validation: tessera::gpu::validation_default(),
        ..EngineOptions::default()
    };
    let mut out = String::from("engine.png");
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = |name: &str| args.next().ok_or(format!("{name} needs a value"));
        match a.as_str() {
            "--dynamic" => opts.dynamic_rendering = true,
            "--frames" => opts.frames = value("--frames")?.parse()?,
            "--in-flight" => opts.frames_in_flight = value("--in-flight")?.parse()?,
            "--out" => out = value("--out")?,
            "--size" => {
                let v = value("--size")?;
                let (w, h) = v.split_once('x').ok_or("--size takes WxH")?;
                (opts.width, opts.height) = (w.parse()?, h.parse()?);
            }
            other => return Err(format!("unknown argument {other}").into()),
        }
    }
    let run = run(&opts)?;
    run.image.save(&out)?;
    println!(
        "{out}: {} frames in {:.1} ms, {} in flight, {}; {} patches; {} validation messages",
        opts.frames,
        run.loop_ms,
        opts.frames_in_flight,
        if opts.dynamic_rendering {
            "dynamic rendering"
        } else {
            "render pass"
        },
        run.patches,
        run.validation_errors
    );
    Ok(())
}
