//! Descriptor pools and buffer descriptor writes.

use std::sync::Arc;

use ash::vk;

use super::context::{Context, Shared};
use super::error::GpuError;
use super::memory::Buffer;
use super::pipeline::DescriptorKind;
use crate::Result;

/// A descriptor pool for storage / uniform buffer descriptors. Sets are freed with
/// [`DescriptorPool::reset`] or when the pool drops.
pub struct DescriptorPool {
    shared: Arc<Shared>,
    raw: vk::DescriptorPool,
}

impl DescriptorPool {
    /// A pool for `max_sets` sets holding at most `storage` storage-buffer and `uniform`
    /// uniform-buffer descriptors in total, and one combined image sampler per set.
    pub fn new(ctx: &Context, max_sets: u32, storage: u32, uniform: u32) -> Result<Self> {
        let mut sizes = Vec::new();
        if storage > 0 {
            sizes.push(vk::DescriptorPoolSize {
                ty: vk::DescriptorType::STORAGE_BUFFER,
                descriptor_count: storage,
            });
        }
        if uniform > 0 {
            sizes.push(vk::DescriptorPoolSize {
                ty: vk::DescriptorType::UNIFORM_BUFFER,
                descriptor_count: uniform,
            });
        }
        // One combined image sampler per set (set 0 of the surface passes samples the
        // displacement map).
        sizes.push(vk::DescriptorPoolSize {
            ty: vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
            descriptor_count: max_sets.max(1),
        });
        let ci = vk::DescriptorPoolCreateInfo::default()
            .max_sets(max_sets.max(1))
            .pool_sizes(&sizes);
        // SAFETY: valid create info.
        let raw = unsafe { ctx.device().create_descriptor_pool(&ci, None) }
            .map_err(GpuError::vk("vkCreateDescriptorPool"))?;
        ctx.set_name(raw, "descriptor pool");
        Ok(DescriptorPool {
            shared: ctx.shared.clone(),
            raw,
        })
    }

    /// The Vulkan handle.
    pub fn raw(&self) -> vk::DescriptorPool {
        self.raw
    }

    /// Allocates one set with `layout` (e.g. `pipeline.set_layouts[0]`).
    pub fn allocate(&self, layout: vk::DescriptorSetLayout) -> Result<vk::DescriptorSet> {
        let layouts = [layout];
        let ai = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(self.raw)
            .set_layouts(&layouts);
        // SAFETY: valid pool and layout.
        let sets = unsafe { self.shared.device.allocate_descriptor_sets(&ai) }
            .map_err(GpuError::vk("vkAllocateDescriptorSets"))?;
        Ok(sets[0])
    }

    /// Frees every set of the pool (the GPU must be done with them).
    pub fn reset(&self) -> Result<()> {
        // SAFETY: caller guarantees no set is in use.
        unsafe {
            self.shared
                .device
                .reset_descriptor_pool(self.raw, vk::DescriptorPoolResetFlags::empty())
        }
        .map_err(GpuError::vk("vkResetDescriptorPool"))
    }
}

impl Drop for DescriptorPool {
    fn drop(&mut self) {
        if !self.shared.wait_pending() {
            return;
        }
        // SAFETY: sets from this pool are no longer used.
        unsafe { self.shared.device.destroy_descriptor_pool(self.raw, None) };
    }
}

/// One buffer to bind: whole buffer at `binding`.
#[derive(Debug, Clone, Copy)]
pub struct BufferBinding<'a> {
    /// `binding = N` in GLSL.
    pub binding: u32,
    /// Storage or uniform.
    pub kind: DescriptorKind,
    /// The buffer (bound whole).
    pub buffer: &'a Buffer,
}

impl Context {
    /// Points the bindings of `set` at the given buffers.
    pub fn write_buffer_descriptors(&self, set: vk::DescriptorSet, bindings: &[BufferBinding<'_>]) {
        let infos: Vec<[vk::DescriptorBufferInfo; 1]> = bindings
            .iter()
            .map(|b| {
                [vk::DescriptorBufferInfo::default()
                    .buffer(b.buffer.raw())
                    .offset(0)
                    .range(vk::WHOLE_SIZE)]
            })
            .collect();
        let writes: Vec<_> = bindings
            .iter()
            .zip(&infos)
            .map(|(b, info)| {
                vk::WriteDescriptorSet::default()
                    .dst_set(set)
                    .dst_binding(b.binding)
                    .descriptor_type(b.kind.vk())
                    .buffer_info(info)
            })
            .collect();
        // SAFETY: set and buffers are valid; set not in use by pending work.
        unsafe { self.device().update_descriptor_sets(&writes, &[]) };
    }
}
