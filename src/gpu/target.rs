//! Offscreen render target: sRGB colour + depth, optional MSAA with resolve, PNG readback.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use ash::vk;

use super::context::{Context, Shared};
use super::error::{invalid, GpuError};
use super::memory::{Buffer, Image, ImageDesc, MemoryLocation};
use crate::Result;

/// Colour format of every render target (8-bit sRGB, so shaders write linear colour).
pub const COLOR_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;

const DEPTH_CANDIDATES: [vk::Format; 3] = [
    vk::Format::D32_SFLOAT,
    vk::Format::D32_SFLOAT_S8_UINT,
    vk::Format::D24_UNORM_S8_UINT,
];

/// An offscreen colour + depth target with its render pass and framebuffer.
///
/// The render pass clears colour and depth, and leaves the single-sample colour image in
/// `TRANSFER_SRC_OPTIMAL` for [`RenderTarget::read_rgba`]. Viewport and scissor are dynamic
/// state set by [`RenderTarget::begin`] (standard Vulkan viewport: clip-space +y points down the
/// image, depth 0..1).
pub struct RenderTarget {
    shared: Arc<Shared>,
    width: u32,
    height: u32,
    samples: u32,
    depth_format: vk::Format,
    color: Image,
    msaa_color: Option<Image>,
    depth: Image,
    render_pass: vk::RenderPass,
    framebuffer: vk::Framebuffer,
    /// Set once `begin` was recorded (before that the colour image has no defined layout).
    begun: AtomicBool,
}

impl std::fmt::Debug for RenderTarget {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RenderTarget")
            .field("width", &self.width)
            .field("height", &self.height)
            .field("samples", &self.samples)
            .finish()
    }
}

/// The formats/sample count a pipeline must match to be used with a render target.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct TargetFormat {
    /// Colour format.
    pub color: vk::Format,
    /// Depth format.
    pub depth: vk::Format,
    /// Samples per pixel.
    pub samples: u32,
}

fn pick_depth_format(ctx: &Context) -> Result<vk::Format> {
    for f in DEPTH_CANDIDATES {
        // SAFETY: valid physical device.
        let p = unsafe {
            ctx.instance()
                .get_physical_device_format_properties(ctx.physical_device(), f)
        };
        if p.optimal_tiling_features
            .contains(vk::FormatFeatureFlags::DEPTH_STENCIL_ATTACHMENT)
        {
            return Ok(f);
        }
    }
    Err(GpuError::MissingFeatures {
        name: ctx.info().name.clone(),
        missing: vec!["a depth attachment format (D32_SFLOAT / D24_UNORM_S8_UINT)".to_owned()],
        devices: Vec::new(),
    }
    .into())
}

fn depth_aspect(f: vk::Format) -> vk::ImageAspectFlags {
    if f == vk::Format::D32_SFLOAT {
        vk::ImageAspectFlags::DEPTH
    } else {
        vk::ImageAspectFlags::DEPTH | vk::ImageAspectFlags::STENCIL
    }
}

/// Creates the render pass shared by targets of one [`TargetFormat`].
pub(crate) fn create_render_pass(dev: &ash::Device, fmt: TargetFormat) -> Result<vk::RenderPass> {
    let msaa = fmt.samples > 1;
    let samples = vk::SampleCountFlags::from_raw(fmt.samples);
    let mut attachments = vec![
        vk::AttachmentDescription::default()
            .format(fmt.color)
            .samples(samples)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(if msaa {
                vk::AttachmentStoreOp::DONT_CARE
            } else {
                vk::AttachmentStoreOp::STORE
            })
            .stencil_load_op(vk::AttachmentLoadOp::DONT_CARE)
            .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
            .initial_layout(vk::ImageLayout::UNDEFINED)
            .final_layout(if msaa {
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL
            } else {
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL
            }),
        vk::AttachmentDescription::default()
            .format(fmt.depth)
            .samples(samples)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::DONT_CARE)
            .stencil_load_op(vk::AttachmentLoadOp::CLEAR)
            .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
            .initial_layout(vk::ImageLayout::UNDEFINED)
            .final_layout(vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL),
    ];
    if msaa {
        attachments.push(
            vk::AttachmentDescription::default()
                .format(fmt.color)
                .samples(vk::SampleCountFlags::TYPE_1)
                .load_op(vk::AttachmentLoadOp::DONT_CARE)
                .store_op(vk::AttachmentStoreOp::STORE)
                .stencil_load_op(vk::AttachmentLoadOp::DONT_CARE)
                .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
                .initial_layout(vk::ImageLayout::UNDEFINED)
                .final_layout(vk::ImageLayout::TRANSFER_SRC_OPTIMAL),
        );
    }
    let color_ref = [vk::AttachmentReference::default()
        .attachment(0)
        .layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)];
    let depth_ref = vk::AttachmentReference::default()
        .attachment(1)
        .layout(vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL);
    let resolve_ref = [vk::AttachmentReference::default()
        .attachment(2)
        .layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)];
    let mut subpass = vk::SubpassDescription::default()
        .pipeline_bind_point(vk::PipelineBindPoint::GRAPHICS)
        .color_attachments(&color_ref)
        .depth_stencil_attachment(&depth_ref);
    if msaa {
        subpass = subpass.resolve_attachments(&resolve_ref);
    }
    let attach_stages = vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT
        | vk::PipelineStageFlags::EARLY_FRAGMENT_TESTS
        | vk::PipelineStageFlags::LATE_FRAGMENT_TESTS;
    let deps = [
        // Earlier transfers (readback of the previous frame) before we overwrite attachments.
        vk::SubpassDependency::default()
            .src_subpass(vk::SUBPASS_EXTERNAL)
            .dst_subpass(0)
            .src_stage_mask(vk::PipelineStageFlags::TRANSFER | attach_stages)
            .dst_stage_mask(attach_stages)
            .src_access_mask(
                vk::AccessFlags::COLOR_ATTACHMENT_WRITE
                    | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE,
            )
            .dst_access_mask(
                vk::AccessFlags::COLOR_ATTACHMENT_WRITE
                    | vk::AccessFlags::COLOR_ATTACHMENT_READ
                    | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_READ
                    | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE,
            ),
        // Colour writes (incl. resolve) before the readback copy.
        vk::SubpassDependency::default()
            .src_subpass(0)
            .dst_subpass(vk::SUBPASS_EXTERNAL)
            .src_stage_mask(vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT)
            .dst_stage_mask(vk::PipelineStageFlags::TRANSFER)
            .src_access_mask(vk::AccessFlags::COLOR_ATTACHMENT_WRITE)
            .dst_access_mask(vk::AccessFlags::TRANSFER_READ),
    ];
    let subpasses = [subpass];
    let ci = vk::RenderPassCreateInfo::default()
        .attachments(&attachments)
        .subpasses(&subpasses)
        .dependencies(&deps);
    // SAFETY: valid create info.
    unsafe { dev.create_render_pass(&ci, None) }.map_err(GpuError::vk("vkCreateRenderPass"))
}

impl RenderTarget {
    /// Creates a `width` x `height` target with `samples` samples per pixel (1 = no MSAA).
    pub fn new(ctx: &Context, width: u32, height: u32, samples: u32) -> Result<RenderTarget> {
        if !ctx.info().limits.supports_samples(samples) {
            return Err(GpuError::Limit(format!(
                "{samples} samples per pixel unsupported; device supports {:?}",
                ctx.info().limits.supported_sample_counts()
            ))
            .into());
        }
        let depth_format = pick_depth_format(ctx)?;
        let extent = vk::Extent2D { width, height };
        let msaa = samples > 1;
        let color = Image::new(
            ctx,
            &ImageDesc {
                extent,
                format: COLOR_FORMAT,
                usage: vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
                samples: 1,
                aspect: vk::ImageAspectFlags::COLOR,
            },
            "render target colour",
        )?;
        let msaa_color = if msaa {
            Some(Image::new(
                ctx,
                &ImageDesc {
                    extent,
                    format: COLOR_FORMAT,
                    usage: vk::ImageUsageFlags::COLOR_ATTACHMENT
                        | vk::ImageUsageFlags::TRANSIENT_ATTACHMENT,
                    samples,
                    aspect: vk::ImageAspectFlags::COLOR,
                },
                "render target colour (MSAA)",
            )?)
        } else {
            None
        };
        let depth = Image::new(
            ctx,
            &ImageDesc {
                extent,
                format: depth_format,
                usage: vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT
                    | vk::ImageUsageFlags::TRANSIENT_ATTACHMENT,
                samples,
                aspect: depth_aspect(depth_format),
            },
            "render target depth",
        )?;
        let fmt = TargetFormat {
            color: COLOR_FORMAT,
            depth: depth_format,
            samples,
        };
        let dev = ctx.device();
        let render_pass = create_render_pass(dev, fmt)?;
        let views: Vec<vk::ImageView> = match &msaa_color {
            Some(m) => vec![m.view(), depth.view(), color.view()],
            None => vec![color.view(), depth.view()],
        };
        let fi = vk::FramebufferCreateInfo::default()
            .render_pass(render_pass)
            .attachments(&views)
            .width(width)
            .height(height)
            .layers(1);
        // SAFETY: views match the render pass attachments.
        let framebuffer = match unsafe { dev.create_framebuffer(&fi, None) } {
            Ok(f) => f,
            Err(e) => {
                unsafe { dev.destroy_render_pass(render_pass, None) };
                return Err(GpuError::vk("vkCreateFramebuffer")(e));
            }
        };
        ctx.set_name(render_pass, "render target pass");
        ctx.set_name(framebuffer, "render target framebuffer");
        Ok(RenderTarget {
            shared: ctx.shared.clone(),
            width,
            height,
            samples,
            depth_format,
            color,
            msaa_color,
            depth,
            render_pass,
            framebuffer,
            begun: AtomicBool::new(false),
        })
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Samples per pixel.
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// Extent.
    pub fn extent(&self) -> vk::Extent2D {
        vk::Extent2D {
            width: self.width,
            height: self.height,
        }
    }

    /// Formats a pipeline must be built for.
    pub fn format(&self) -> TargetFormat {
        TargetFormat {
            color: COLOR_FORMAT,
            depth: self.depth_format,
            samples: self.samples,
        }
    }

    /// The render pass.
    pub fn render_pass(&self) -> vk::RenderPass {
        self.render_pass
    }

    /// The framebuffer.
    pub fn framebuffer(&self) -> vk::Framebuffer {
        self.framebuffer
    }

    /// The single-sample (resolved) colour image.
    pub fn color_image(&self) -> &Image {
        &self.color
    }

    /// The depth image.
    pub fn depth_image(&self) -> &Image {
        &self.depth
    }

    /// The multisampled colour image, if MSAA is on.
    pub fn msaa_color_image(&self) -> Option<&Image> {
        self.msaa_color.as_ref()
    }

    /// Begins the render pass, clearing colour to `clear` (linear RGBA; stored sRGB-encoded)
    /// and depth to 1.0, and sets the full-target viewport and scissor.
    pub fn begin(&self, dev: &ash::Device, cmd: vk::CommandBuffer, clear: [f32; 4]) {
        let clears = [
            vk::ClearValue {
                color: vk::ClearColorValue { float32: clear },
            },
            vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue {
                    depth: 1.0,
                    stencil: 0,
                },
            },
            vk::ClearValue {
                color: vk::ClearColorValue { float32: clear },
            },
        ];
        let n = if self.msaa_color.is_some() { 3 } else { 2 };
        let bi = vk::RenderPassBeginInfo::default()
            .render_pass(self.render_pass)
            .framebuffer(self.framebuffer)
            .render_area(vk::Rect2D {
                offset: vk::Offset2D { x: 0, y: 0 },
                extent: self.extent(),
            })
            .clear_values(&clears[..n]);
        let viewport = vk::Viewport {
            x: 0.0,
            y: 0.0,
            width: self.width as f32,
            height: self.height as f32,
            min_depth: 0.0,
            max_depth: 1.0,
        };
        let scissor = vk::Rect2D {
            offset: vk::Offset2D { x: 0, y: 0 },
            extent: self.extent(),
        };
        self.begun.store(true, Ordering::Relaxed);
        // SAFETY: cmd is recording, outside a render pass.
        unsafe {
            dev.cmd_begin_render_pass(cmd, &bi, vk::SubpassContents::INLINE);
            dev.cmd_set_viewport(cmd, 0, &[viewport]);
            dev.cmd_set_scissor(cmd, 0, &[scissor]);
        }
    }

    /// Ends the render pass begun by [`RenderTarget::begin`].
    pub fn end(&self, dev: &ash::Device, cmd: vk::CommandBuffer) {
        // SAFETY: inside the render pass begun by `begin`.
        unsafe { dev.cmd_end_render_pass(cmd) };
    }

    /// Copies the colour image (which must have been rendered with `begin`/`end`) to the CPU.
    pub fn read_rgba(&self, ctx: &Context) -> Result<image::RgbaImage> {
        if !Arc::ptr_eq(&ctx.shared, &self.shared) {
            return invalid("read_rgba: render target belongs to another context");
        }
        if !self.begun.load(Ordering::Relaxed) {
            return invalid("read_rgba: nothing was rendered into this target yet");
        }
        let bytes = u64::from(self.width) * u64::from(self.height) * 4;
        let staging = Buffer::new(
            ctx,
            bytes,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
            "render target readback",
        )?;
        ctx.submit_once(|dev, cmd| {
            let region = super::texture::whole_color_image(self.width, self.height);
            // SAFETY: the image is in TRANSFER_SRC_OPTIMAL after the render pass.
            unsafe {
                dev.cmd_copy_image_to_buffer(
                    cmd,
                    self.color.raw(),
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    staging.raw(),
                    &[region],
                );
            }
            super::memory_barrier(
                dev,
                cmd,
                (
                    vk::PipelineStageFlags::TRANSFER,
                    vk::AccessFlags::TRANSFER_WRITE,
                ),
                (vk::PipelineStageFlags::HOST, vk::AccessFlags::HOST_READ),
            );
            Ok(())
        })?;
        let data: Vec<u8> = staging.read()?;
        image::RgbaImage::from_raw(self.width, self.height, data)
            .ok_or_else(|| GpuError::Output("readback size mismatch".to_owned()).into())
    }

    /// Reads the colour image back and writes it as PNG to `path`.
    pub fn write_png(&self, ctx: &Context, path: &Path) -> Result<()> {
        let img = self.read_rgba(ctx)?;
        img.save_with_format(path, image::ImageFormat::Png)
            .map_err(|e| GpuError::Output(format!("{}: {e}", path.display())).into())
    }
}

impl Drop for RenderTarget {
    fn drop(&mut self) {
        if !self.shared.wait_pending() {
            return;
        }
        // SAFETY: no GPU work uses the target any more; images drop after this.
        unsafe {
            self.shared
                .device
                .destroy_framebuffer(self.framebuffer, None);
            self.shared
                .device
                .destroy_render_pass(self.render_pass, None);
        }
    }
}
