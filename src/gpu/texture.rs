//! Sampled images: a 2D image uploaded once through a staging buffer, kept in
//! `SHADER_READ_ONLY_OPTIMAL`, with its sampler (linear filtering, repeat addressing, level 0
//! only), bound as a combined image sampler.

use std::sync::Arc;

use ash::vk;

use super::context::{Context, Shared};
use super::error::GpuError;
use super::memory::{Buffer, Image, ImageDesc};
use crate::Result;

/// A sampled 2D image and its sampler. Freed on drop (after timed-out work, as every
/// resource: [`super::Buffer`]).
pub struct SampledImage {
    shared: Arc<Shared>,
    image: Image,
    sampler: vk::Sampler,
}

impl std::fmt::Debug for SampledImage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SampledImage")
            .field("image", &self.image)
            .finish()
    }
}

impl SampledImage {
    /// The image (its view is what the descriptor binds).
    pub fn image(&self) -> &Image {
        &self.image
    }

    /// The sampler.
    pub fn sampler(&self) -> vk::Sampler {
        self.sampler
    }
}

impl Drop for SampledImage {
    fn drop(&mut self) {
        if self.shared.wait_pending() {
            // SAFETY: no pending work uses the sampler.
            unsafe { self.shared.device.destroy_sampler(self.sampler, None) };
        }
    }
}

/// The copy region of a whole single-level colour image, tightly packed in the buffer.
pub(super) fn whole_color_image(width: u32, height: u32) -> vk::BufferImageCopy {
    vk::BufferImageCopy::default()
        .image_subresource(
            vk::ImageSubresourceLayers::default()
                .aspect_mask(vk::ImageAspectFlags::COLOR)
                .layer_count(1),
        )
        .image_extent(vk::Extent3D {
            width,
            height,
            depth: 1,
        })
}

impl Context {
    /// Uploads `width x height` texels of `format` (tightly packed `bytes`, row 0 first) into a
    /// device-local image sampled with linear filtering and repeat addressing at level 0. The
    /// size must be within the device's `maxImageDimension2D` and the format must support
    /// linear filtering of sampled images (both errors name the numbers or the format).
    pub fn upload_sampled_image(
        &self,
        width: u32,
        height: u32,
        format: vk::Format,
        bytes: &[u8],
        name: &str,
    ) -> Result<SampledImage> {
        let s = &self.shared;
        // SAFETY: valid physical device.
        let props = unsafe {
            s.instance
                .get_physical_device_format_properties(s.physical, format)
        };
        let needed = vk::FormatFeatureFlags::SAMPLED_IMAGE
            | vk::FormatFeatureFlags::SAMPLED_IMAGE_FILTER_LINEAR
            | vk::FormatFeatureFlags::TRANSFER_DST;
        if !props.optimal_tiling_features.contains(needed) {
            return Err(GpuError::Limit(format!(
                "image \"{name}\": format {format:?} cannot be sampled with linear filtering on this device"
            ))
            .into());
        }
        let image = Image::new(
            self,
            &ImageDesc {
                extent: vk::Extent2D { width, height },
                format,
                usage: vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST,
                samples: 1,
                aspect: vk::ImageAspectFlags::COLOR,
            },
            name,
        )?;
        let staging = Buffer::staging(self, bytes, name)?;
        let range = vk::ImageSubresourceRange::default()
            .aspect_mask(vk::ImageAspectFlags::COLOR)
            .level_count(1)
            .layer_count(1);
        self.submit_once(|dev, cmd| {
            let to_dst = vk::ImageMemoryBarrier::default()
                .image(image.raw())
                .subresource_range(range)
                .old_layout(vk::ImageLayout::UNDEFINED)
                .new_layout(vk::ImageLayout::TRANSFER_DST_OPTIMAL)
                .dst_access_mask(vk::AccessFlags::TRANSFER_WRITE);
            let region = whole_color_image(width, height);
            let to_read = vk::ImageMemoryBarrier::default()
                .image(image.raw())
                .subresource_range(range)
                .old_layout(vk::ImageLayout::TRANSFER_DST_OPTIMAL)
                .new_layout(vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)
                .src_access_mask(vk::AccessFlags::TRANSFER_WRITE)
                .dst_access_mask(vk::AccessFlags::SHADER_READ);
            // SAFETY: the image and the staging buffer are valid and large enough.
            unsafe {
                dev.cmd_pipeline_barrier(
                    cmd,
                    vk::PipelineStageFlags::TOP_OF_PIPE,
                    vk::PipelineStageFlags::TRANSFER,
                    vk::DependencyFlags::empty(),
                    &[],
                    &[],
                    &[to_dst],
                );
                dev.cmd_copy_buffer_to_image(
                    cmd,
                    staging.raw(),
                    image.raw(),
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    &[region],
                );
                dev.cmd_pipeline_barrier(
                    cmd,
                    vk::PipelineStageFlags::TRANSFER,
                    vk::PipelineStageFlags::ALL_COMMANDS,
                    vk::DependencyFlags::empty(),
                    &[],
                    &[],
                    &[to_read],
                );
            }
            Ok(())
        })?;
        let ci = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
            .address_mode_u(vk::SamplerAddressMode::REPEAT)
            .address_mode_v(vk::SamplerAddressMode::REPEAT)
            .address_mode_w(vk::SamplerAddressMode::REPEAT)
            .min_lod(0.0)
            .max_lod(0.0);
        // SAFETY: valid create info.
        let sampler = unsafe { s.device.create_sampler(&ci, None) }
            .map_err(GpuError::vk("vkCreateSampler"))?;
        s.set_name(sampler, &format!("{name} (sampler)"));
        Ok(SampledImage {
            shared: s.clone(),
            image,
            sampler,
        })
    }

    /// Writes `image` into `binding` of `set` as a combined image sampler (the set not in use
    /// by pending work).
    pub fn write_image_descriptor(
        &self,
        set: vk::DescriptorSet,
        binding: u32,
        image: &SampledImage,
    ) {
        let info = [vk::DescriptorImageInfo::default()
            .sampler(image.sampler)
            .image_view(image.image.view())
            .image_layout(vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)];
        let write = vk::WriteDescriptorSet::default()
            .dst_set(set)
            .dst_binding(binding)
            .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
            .image_info(&info);
        // SAFETY: set, view and sampler are valid; the set is not in use by pending work.
        unsafe { self.device().update_descriptor_sets(&[write], &[]) };
    }
}
