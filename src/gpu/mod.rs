//! Vulkan core (ash): context with validation, device selection and limits, memory through
//! gpu-allocator, one-shot submission, offscreen render target, embedded SPIR-V, cached
//! pipelines, descriptors and queries. See `src/gpu/README.md` for a usage sequence.

mod commands;
mod context;
mod debug;
mod descriptors;
mod device;
mod draw;
mod draw_target;
mod error;
mod external;
mod memory;
mod pipeline;
mod query;
pub mod shaders;
pub mod spirv;
mod target;
mod texture;

pub use ash::vk;
pub use commands::{geometry_writes_to_host, memory_barrier, tes_writes_to_host};
pub use context::{validation_default, Context, ContextDesc};
pub use debug::ValidationLog;
pub use descriptors::{BufferBinding, DescriptorPool};
pub use device::{DeviceFeatures, DeviceInfo, DeviceLimits, Feature};
pub use draw::{
    max_patches_per_draw, patch_draw_chunks, patches_per_draw, patches_per_draw_at_level,
    quad_domain_points, MAX_DOMAIN_POINTS_PER_DRAW, MAX_INDICES_PER_PATCH_DRAW,
    MAX_VERTICES_PER_PATCH_DRAW,
};
pub use draw_target::{DrawTarget, LayoutSlots, PassKind, PushRange};
pub use error::{DeviceReport, GpuError, VkResultCode};
pub use external::{check_raw_device, RawContextDesc, MIN_PATCH_SIZE};
pub use memory::{as_bytes, from_bytes, Buffer, Image, ImageDesc, MemoryLocation, Pod};
pub use pipeline::{
    ComputePipelineDesc, DescriptorBinding, DescriptorKind, GraphicsPipelineDesc, Pipeline,
    PushConstants, VertexAttribute, VertexBinding,
};
pub use query::{ticks_to_ms, GpuTimer, PipelineStats, StatsQuery};
pub use target::{RenderTarget, TargetFormat, COLOR_FORMAT};
pub use texture::SampledImage;
