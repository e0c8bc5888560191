//! GPU memory through `gpu-allocator`: buffers, images, staging upload and readback.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
pub use gpu_allocator::MemoryLocation;

use super::context::{Context, Shared};
use super::error::{invalid, GpuError};
use crate::Result;

/// Plain-old-data that may be copied to and from GPU memory byte for byte.
///
/// # Safety
/// Implementors must be `Copy`, contain no padding-dependent invariants or pointers, and accept
/// every bit pattern (e.g. `#[repr(C)]` structs of `f32`/`u32`).
pub unsafe trait Pod: Copy + 'static {}
// SAFETY: primitive numbers accept every bit pattern.
unsafe impl Pod for u8 {}
// SAFETY: as above.
unsafe impl Pod for u16 {}
// SAFETY: as above.
unsafe impl Pod for u32 {}
// SAFETY: as above.
unsafe impl Pod for i32 {}
// SAFETY: as above.
unsafe impl Pod for u64 {}
// SAFETY: as above.
unsafe impl Pod for f32 {}
// SAFETY: as above.
unsafe impl Pod for f64 {}
// SAFETY: arrays of Pod are Pod.
unsafe impl<T: Pod, const N: usize> Pod for [T; N] {}

/// The bytes of a Pod slice.
pub fn as_bytes<T: Pod>(data: &[T]) -> &[u8] {
    // SAFETY: T is Pod; the byte view covers exactly the slice.
    unsafe { std::slice::from_raw_parts(data.as_ptr().cast::<u8>(), std::mem::size_of_val(data)) }
}

/// Copies bytes into a Vec of Pod values (`bytes.len()` must be a multiple of `size_of::<T>()`).
pub fn from_bytes<T: Pod>(bytes: &[u8]) -> Vec<T> {
    let n = bytes.len() / std::mem::size_of::<T>().max(1);
    let mut v: Vec<T> = Vec::with_capacity(n);
    // SAFETY: T is Pod (any bit pattern valid); we copy n * size_of::<T>() bytes into capacity.
    unsafe {
        std::ptr::copy_nonoverlapping(
            bytes.as_ptr(),
            v.as_mut_ptr().cast::<u8>(),
            n * std::mem::size_of::<T>(),
        );
        v.set_len(n);
    }
    v
}

/// A buffer with its memory. Freed on drop (or [`Buffer::destroy`]).
pub struct Buffer {
    shared: Arc<Shared>,
    raw: vk::Buffer,
    allocation: Option<Allocation>,
    size: u64,
    usage: vk::BufferUsageFlags,
    location: MemoryLocation,
}

impl std::fmt::Debug for Buffer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Buffer")
            .field("raw", &self.raw)
            .field("size", &self.size)
            .field("usage", &self.usage)
            .field("location", &self.location)
            .finish()
    }
}

impl Buffer {
    /// Creates a buffer of `size` bytes (> 0) in `location`, named `name` for debugging.
    pub fn new(
        ctx: &Context,
        size: u64,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
        name: &str,
    ) -> Result<Buffer> {
        if size == 0 {
            return invalid(format!("buffer \"{name}\" has size 0"));
        }
        let s = &ctx.shared;
        let ci = vk::BufferCreateInfo::default()
            .size(size)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: valid create info.
        let raw =
            unsafe { s.device.create_buffer(&ci, None) }.map_err(GpuError::vk("vkCreateBuffer"))?;
        // SAFETY: buffer just created.
        let requirements = unsafe { s.device.get_buffer_memory_requirements(raw) };
        let alloc = s.allocator().allocate(&AllocationCreateDesc {
            name,
            requirements,
            location,
            linear: true,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        });
        let allocation = match alloc {
            Ok(a) => a,
            Err(e) => {
                unsafe { s.device.destroy_buffer(raw, None) };
                return Err(
                    GpuError::Allocation(format!("buffer \"{name}\" ({size} bytes): {e}")).into(),
                );
            }
        };
        // SAFETY: memory is from this device, offset respects the requirements.
        if let Err(e) = unsafe {
            s.device
                .bind_buffer_memory(raw, allocation.memory(), allocation.offset())
        } {
            let _ = s.allocator().free(allocation);
            unsafe { s.device.destroy_buffer(raw, None) };
            return Err(GpuError::vk("vkBindBufferMemory")(e));
        }
        s.set_name(raw, name);
        Ok(Buffer {
            shared: s.clone(),
            raw,
            allocation: Some(allocation),
            size,
            usage,
            location,
        })
    }

    /// Creates a host-visible buffer holding `data`.
    pub fn from_slice<T: Pod>(
        ctx: &Context,
        data: &[T],
        usage: vk::BufferUsageFlags,
        name: &str,
    ) -> Result<Buffer> {
        let bytes = as_bytes(data);
        let mut b = Buffer::new(
            ctx,
            bytes.len() as u64,
            usage,
            MemoryLocation::CpuToGpu,
            name,
        )?;
        b.write(0, data)?;
        Ok(b)
    }

    /// A host-visible transfer source holding `bytes`, named after what it fills.
    pub(super) fn staging(ctx: &Context, bytes: &[u8], name: &str) -> Result<Buffer> {
        Buffer::from_slice(
            ctx,
            bytes,
            vk::BufferUsageFlags::TRANSFER_SRC,
            &format!("{name} (staging)"),
        )
    }

    /// The Vulkan handle.
    pub fn raw(&self) -> vk::Buffer {
        self.raw
    }

    /// Size in bytes.
    pub fn size(&self) -> u64 {
        self.size
    }

    /// Usage flags.
    pub fn usage(&self) -> vk::BufferUsageFlags {
        self.usage
    }

    /// Memory location.
    pub fn location(&self) -> MemoryLocation {
        self.location
    }

    /// Whether the buffer is mapped (host visible).
    pub fn is_host_visible(&self) -> bool {
        self.allocation
            .as_ref()
            .is_some_and(|a| a.mapped_ptr().is_some())
    }

    /// Writes `data` at byte `offset` of a host-visible buffer.
    pub fn write<T: Pod>(&mut self, offset: u64, data: &[T]) -> Result<()> {
        let bytes = as_bytes(data);
        let size = self.size;
        let Some(slice) = self.allocation.as_mut().and_then(|a| a.mapped_slice_mut()) else {
            return invalid("Buffer::write on a buffer that is not host visible");
        };
        let end = offset
            .checked_add(bytes.len() as u64)
            .filter(|e| *e <= size);
        let Some(end) = end else {
            return invalid(format!(
                "write of {} bytes at {offset} exceeds buffer size {size}",
                bytes.len()
            ));
        };
        slice[offset as usize..end as usize].copy_from_slice(bytes);
        Ok(())
    }

    /// Reads the whole host-visible buffer as `T` values (after the GPU work finished).
    pub fn read<T: Pod>(&self) -> Result<Vec<T>> {
        let Some(slice) = self.allocation.as_ref().and_then(|a| a.mapped_slice()) else {
            return invalid("Buffer::read on a buffer that is not host visible");
        };
        Ok(from_bytes(&slice[..self.size as usize]))
    }

    /// Frees the buffer now (same as dropping it).
    pub fn destroy(self) {}
}

impl Drop for Buffer {
    fn drop(&mut self) {
        if !self.shared.wait_pending() {
            return;
        }
        // SAFETY: the caller guarantees the GPU no longer uses the buffer (submit_once waits).
        unsafe { self.shared.device.destroy_buffer(self.raw, None) };
        if let Some(a) = self.allocation.take() {
            let _ = self.shared.allocator().free(a);
        }
    }
}

impl Context {
    /// Creates a device-local buffer filled with `data` through a staging buffer.
    /// `TRANSFER_DST` is added to `usage`.
    pub fn upload_buffer<T: Pod>(
        &self,
        data: &[T],
        usage: vk::BufferUsageFlags,
        name: &str,
    ) -> Result<Buffer> {
        let bytes = as_bytes(data);
        if bytes.is_empty() {
            return invalid(format!("upload of empty data to buffer \"{name}\""));
        }
        let dst = Buffer::new(
            self,
            bytes.len() as u64,
            usage | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
            name,
        )?;
        self.rewrite_buffer(&dst, data, name)?;
        Ok(dst)
    }

    /// Overwrites the start of the existing buffer `dst` (with `TRANSFER_DST` usage, at least as
    /// large as `data`) with `data` through a staging buffer, then makes it visible to every
    /// later command. Call while no submitted work reads `dst`.
    pub fn rewrite_buffer<T: Pod>(&self, dst: &Buffer, data: &[T], name: &str) -> Result<()> {
        let bytes = as_bytes(data);
        if bytes.is_empty() {
            return Ok(());
        }
        if bytes.len() as u64 > dst.size()
            || !dst.usage().contains(vk::BufferUsageFlags::TRANSFER_DST)
        {
            return invalid(format!(
                "rewrite of buffer \"{name}\": {} bytes into {} (needs TRANSFER_DST usage)",
                bytes.len(),
                dst.size()
            ));
        }
        let staging = Buffer::staging(self, bytes, name)?;
        self.submit_once(|dev, cmd| {
            let region = vk::BufferCopy::default().size(bytes.len() as u64);
            // SAFETY: both buffers are valid and large enough.
            unsafe { dev.cmd_copy_buffer(cmd, staging.raw(), dst.raw(), &[region]) };
            super::memory_barrier(
                dev,
                cmd,
                (
                    vk::PipelineStageFlags::TRANSFER,
                    vk::AccessFlags::TRANSFER_WRITE,
                ),
                (
                    vk::PipelineStageFlags::ALL_COMMANDS,
                    vk::AccessFlags::MEMORY_READ,
                ),
            );
            Ok(())
        })
    }

    /// Reads any buffer (host visible or not; non-host-visible ones need `TRANSFER_SRC` usage)
    /// back to the CPU as `T` values. Must be called after the GPU work writing it finished.
    pub fn read_buffer<T: Pod>(&self, buffer: &Buffer) -> Result<Vec<T>> {
        if buffer.is_host_visible() {
            return buffer.read();
        }
        if !buffer.usage().contains(vk::BufferUsageFlags::TRANSFER_SRC) {
            return invalid("read_buffer: device-local buffer lacks TRANSFER_SRC usage");
        }
        let staging = Buffer::new(
            self,
            buffer.size(),
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
            "readback staging",
        )?;
        self.submit_once(|dev, cmd| {
            let region = vk::BufferCopy::default().size(buffer.size());
            // SAFETY: valid buffers of equal size.
            unsafe { dev.cmd_copy_buffer(cmd, buffer.raw(), staging.raw(), &[region]) };
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
        staging.read()
    }
}

/// How to create an [`Image`].
#[derive(Debug, Clone)]
pub struct ImageDesc {
    /// Width and height in pixels.
    pub extent: vk::Extent2D,
    /// Pixel format.
    pub format: vk::Format,
    /// Usage flags.
    pub usage: vk::ImageUsageFlags,
    /// Samples per pixel (1 = no MSAA).
    pub samples: u32,
    /// Aspect of the view (COLOR or DEPTH).
    pub aspect: vk::ImageAspectFlags,
}

/// A 2D image with one mip level, its memory and a view. Freed on drop.
pub struct Image {
    shared: Arc<Shared>,
    raw: vk::Image,
    view: vk::ImageView,
    allocation: Option<Allocation>,
    desc: ImageDesc,
}

impl std::fmt::Debug for Image {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Image")
            .field("raw", &self.raw)
            .field("desc", &self.desc)
            .finish()
    }
}

impl Image {
    /// Creates a device-local 2D image and its view.
    pub fn new(ctx: &Context, desc: &ImageDesc, name: &str) -> Result<Image> {
        let s = &ctx.shared;
        let lim = &s.info.limits;
        let (w, h) = (desc.extent.width, desc.extent.height);
        if w == 0 || h == 0 || w > lim.max_image_dimension_2d || h > lim.max_image_dimension_2d {
            return Err(GpuError::Limit(format!(
                "image \"{name}\" size {w}x{h} must be within 1..={} per side",
                lim.max_image_dimension_2d
            ))
            .into());
        }
        if !lim.supports_samples(desc.samples) {
            return Err(GpuError::Limit(format!(
                "image \"{name}\": {} samples unsupported (device supports {:?})",
                desc.samples,
                lim.supported_sample_counts()
            ))
            .into());
        }
        let ci = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(desc.format)
            .extent(vk::Extent3D {
                width: w,
                height: h,
                depth: 1,
            })
            .mip_levels(1)
            .array_layers(1)
            .samples(vk::SampleCountFlags::from_raw(desc.samples))
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(desc.usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: valid create info.
        let raw =
            unsafe { s.device.create_image(&ci, None) }.map_err(GpuError::vk("vkCreateImage"))?;
        // SAFETY: image just created.
        let requirements = unsafe { s.device.get_image_memory_requirements(raw) };
        let allocation = match s.allocator().allocate(&AllocationCreateDesc {
            name,
            requirements,
            location: MemoryLocation::GpuOnly,
            linear: false,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        }) {
            Ok(a) => a,
            Err(e) => {
                unsafe { s.device.destroy_image(raw, None) };
                return Err(GpuError::Allocation(format!("image \"{name}\": {e}")).into());
            }
        };
        let bound = unsafe {
            s.device
                .bind_image_memory(raw, allocation.memory(), allocation.offset())
        };
        let view = bound.and_then(|()| {
            let vi = vk::ImageViewCreateInfo::default()
                .image(raw)
                .view_type(vk::ImageViewType::TYPE_2D)
                .format(desc.format)
                .subresource_range(
                    vk::ImageSubresourceRange::default()
                        .aspect_mask(desc.aspect)
                        .level_count(1)
                        .layer_count(1),
                );
            // SAFETY: image bound to memory.
            unsafe { s.device.create_image_view(&vi, None) }
        });
        let view = match view {
            Ok(v) => v,
            Err(e) => {
                let _ = s.allocator().free(allocation);
                unsafe { s.device.destroy_image(raw, None) };
                return Err(GpuError::vk("vkBindImageMemory/vkCreateImageView")(e));
            }
        };
        s.set_name(raw, name);
        s.set_name(view, &format!("{name} (view)"));
        Ok(Image {
            shared: s.clone(),
            raw,
            view,
            allocation: Some(allocation),
            desc: desc.clone(),
        })
    }

    /// The Vulkan image.
    pub fn raw(&self) -> vk::Image {
        self.raw
    }

    /// The image view.
    pub fn view(&self) -> vk::ImageView {
        self.view
    }

    /// The creation description.
    pub fn desc(&self) -> &ImageDesc {
        &self.desc
    }
}

impl Drop for Image {
    fn drop(&mut self) {
        if !self.shared.wait_pending() {
            return;
        }
        // SAFETY: the GPU no longer uses the image (all submissions are waited on).
        unsafe {
            self.shared.device.destroy_image_view(self.view, None);
            self.shared.device.destroy_image(self.raw, None);
        }
        if let Some(a) = self.allocation.take() {
            let _ = self.shared.allocator().free(a);
        }
    }
}
