//! [`Context::from_raw`]: a context over the caller's instance, device and queue (an engine's),
//! checked up front for what tessera needs, destroying only what tessera created.

use std::mem::ManuallyDrop;
use std::sync::{Arc, Mutex};

use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};
use gpu_allocator::{AllocationSizes, AllocatorDebugSettings};

use super::context::{Context, Shared};
use super::debug::{self, SharedLog, ValidationLog};
use super::device::{self, DeviceFeatures, DeviceInfo};
use super::error::GpuError;
use super::pipeline::PipelineCache;
use crate::Result;

/// Control points of the smallest patch tessera draws (bicubic B-spline).
pub const MIN_PATCH_SIZE: u32 = 16;

/// The caller's Vulkan objects for [`Context::from_raw`]. tessera keeps clones of the `ash`
/// handles and never destroys the instance, device or queue; the caller destroys them after
/// every tessera object (renderers, buffers, the context itself) is dropped.
#[derive(Clone)]
pub struct RawContextDesc {
    /// The loader entry the instance was created from.
    pub entry: ash::Entry,
    /// The caller's instance.
    pub instance: ash::Instance,
    /// The `apiVersion` the instance was created with (1.2 or newer).
    pub instance_api_version: u32,
    /// The physical device of `device`.
    pub physical_device: vk::PhysicalDevice,
    /// The caller's device.
    pub device: ash::Device,
    /// A graphics queue of `device`. tessera submits its one-shot uploads to it, holding the
    /// context's queue lock: the caller must not submit to it concurrently from another thread
    /// while tessera creates or updates resources.
    pub queue: vk::Queue,
    /// The queue's family index.
    pub queue_family: u32,
    /// The core features the device was created with (Vulkan cannot report them afterwards).
    pub enabled_features: vk::PhysicalDeviceFeatures,
    /// Whether `dynamicRendering` was enabled (Vulkan 1.3 feature or VK_KHR_dynamic_rendering).
    pub dynamic_rendering: bool,
    /// The caller's allocator for `device`, shared; `None`: tessera creates its own.
    pub allocator: Option<Arc<Mutex<Allocator>>>,
    /// Whether the instance has VK_EXT_debug_utils enabled: tessera then names its objects and
    /// counts validation messages through a messenger of its own
    /// ([`Context::validation_errors`]), destroyed with the context.
    pub debug_utils: bool,
    /// Timeout for tessera's own waits on GPU work, in milliseconds.
    pub timeout_ms: u64,
}

impl std::fmt::Debug for RawContextDesc {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RawContextDesc")
            .field("queue_family", &self.queue_family)
            .field("dynamic_rendering", &self.dynamic_rendering)
            .field("own_allocator", &self.allocator.is_none())
            .field("debug_utils", &self.debug_utils)
            .finish()
    }
}

/// What a device brought by the caller must offer for any tessera surface: the
/// `tessellationShader` feature, patches of [`MIN_PATCH_SIZE`] control points and a graphics
/// queue family. Every lack is named in one typed error. Wireframe (`fillModeNonSolid`), TES
/// capture (`vertexPipelineStoresAndAtomics`), dynamic rendering and the Gregory stencil
/// variants' patch size are checked when a renderer needs them.
pub fn check_raw_device(info: &DeviceInfo, queue_is_graphics: bool) -> Result<()> {
    let mut missing = info
        .features
        .missing(&[super::device::Feature::TessellationShader]);
    let size = info.limits.max_tessellation_patch_size;
    if size < MIN_PATCH_SIZE {
        missing.push(format!(
            "maxTessellationPatchSize >= {MIN_PATCH_SIZE} (has {size})"
        ));
    }
    if !queue_is_graphics {
        missing.push(format!(
            "a graphics queue (family {} has no GRAPHICS flag)",
            info.queue_family
        ));
    }
    if missing.is_empty() {
        return Ok(());
    }
    Err(GpuError::MissingFeatures {
        name: info.name.clone(),
        missing,
        devices: Vec::new(),
    }
    .into())
}

/// The features of `supported` that the caller also enabled.
fn enabled(supported: DeviceFeatures, f: &vk::PhysicalDeviceFeatures, dr: bool) -> DeviceFeatures {
    let on = |b: vk::Bool32| b == vk::TRUE;
    DeviceFeatures {
        tessellation_shader: supported.tessellation_shader && on(f.tessellation_shader),
        fill_mode_non_solid: supported.fill_mode_non_solid && on(f.fill_mode_non_solid),
        pipeline_statistics_query: supported.pipeline_statistics_query
            && on(f.pipeline_statistics_query),
        vertex_pipeline_stores_and_atomics: supported.vertex_pipeline_stores_and_atomics
            && on(f.vertex_pipeline_stores_and_atomics),
        geometry_shader: supported.geometry_shader && on(f.geometry_shader),
        timestamps: supported.timestamps,
        shader_float64: supported.shader_float64 && on(f.shader_float64),
        dynamic_rendering: supported.dynamic_rendering && dr,
    }
}

impl Context {
    /// A context over the caller's instance, device and queue ([`RawContextDesc`]). Checks the
    /// device up front ([`check_raw_device`]); creates only a command pool for its uploads, a
    /// pipeline cache, its allocator unless given one, and with `debug_utils` a messenger: these
    /// are what it destroys when the last clone of the context (and of every resource made
    /// from it) drops.
    pub fn from_raw(desc: &RawContextDesc) -> Result<Context> {
        if desc.instance_api_version < vk::API_VERSION_1_2 {
            return Err(GpuError::Invalid(format!(
                "from_raw: the instance was created for Vulkan {}.{}; tessera needs 1.2 or newer",
                vk::api_version_major(desc.instance_api_version),
                vk::api_version_minor(desc.instance_api_version)
            ))
            .into());
        }
        let candidate = device::describe(&desc.instance, desc.physical_device);
        // SAFETY: the physical device belongs to the caller's instance.
        let families = unsafe {
            desc.instance
                .get_physical_device_queue_family_properties(desc.physical_device)
        };
        let family = families.get(desc.queue_family as usize);
        let mut info = candidate.info;
        info.queue_family = desc.queue_family;
        info.limits.timestamp_valid_bits = family.map_or(0, |q| q.timestamp_valid_bits);
        info.features = enabled(
            info.features,
            &desc.enabled_features,
            desc.dynamic_rendering,
        );
        info.features.timestamps &= info.limits.timestamp_valid_bits > 0;
        let graphics = family.is_some_and(|q| q.queue_flags.contains(vk::QueueFlags::GRAPHICS));
        check_raw_device(&info, graphics)?;

        let log: Box<SharedLog> = Box::new(Mutex::new(ValidationLog::default()));
        let debug_instance = desc
            .debug_utils
            .then(|| ash::ext::debug_utils::Instance::new(&desc.entry, &desc.instance));
        let mut messenger = vk::DebugUtilsMessengerEXT::null();
        if let Some(di) = &debug_instance {
            let mi = debug::messenger_info(&log);
            // SAFETY: valid create info pointing at the boxed log, which the context owns.
            messenger = unsafe { di.create_debug_utils_messenger(&mi, None) }
                .map_err(GpuError::vk("vkCreateDebugUtilsMessengerEXT"))?;
        }
        let destroy_messenger = || {
            if let Some(di) = &debug_instance {
                // SAFETY: created above; nothing else uses it yet.
                unsafe { di.destroy_debug_utils_messenger(messenger, None) };
            }
        };
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(desc.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: valid device and queue family.
        let command_pool = match unsafe { desc.device.create_command_pool(&pool_info, None) } {
            Ok(p) => p,
            Err(e) => {
                destroy_messenger();
                return Err(GpuError::vk("vkCreateCommandPool")(e));
            }
        };
        let allocator = match &desc.allocator {
            Some(a) => a.clone(),
            None => match Allocator::new(&AllocatorCreateDesc {
                instance: desc.instance.clone(),
                device: desc.device.clone(),
                physical_device: desc.physical_device,
                debug_settings: AllocatorDebugSettings::default(),
                buffer_device_address: false,
                allocation_sizes: AllocationSizes::default(),
            }) {
                Ok(a) => Arc::new(Mutex::new(a)),
                Err(e) => {
                    // SAFETY: created above, unused.
                    unsafe { desc.device.destroy_command_pool(command_pool, None) };
                    destroy_messenger();
                    return Err(GpuError::Allocation(e.to_string()).into());
                }
            },
        };
        let debug_device = desc
            .debug_utils
            .then(|| ash::ext::debug_utils::Device::new(&desc.instance, &desc.device));
        let shared = Shared {
            _entry: desc.entry.clone(),
            instance: desc.instance.clone(),
            debug_instance,
            messenger,
            log,
            physical: desc.physical_device,
            device: desc.device.clone(),
            debug_device,
            owns_device: false,
            queue: Mutex::new(desc.queue),
            command_pool: Mutex::new(command_pool),
            pending: Mutex::new(Vec::new()),
            leaked: std::sync::atomic::AtomicU64::new(0),
            gave_up: std::sync::atomic::AtomicBool::new(false),
            allocator: ManuallyDrop::new(allocator),
            pipelines: Mutex::new(PipelineCache::default()),
            added_shaders: Mutex::new(Vec::new()),
            info,
            timeout_ms: desc.timeout_ms.max(1),
            validation: desc.debug_utils,
        };
        shared.set_name(command_pool, "tessera one-shot command pool");
        log::debug!("tessera context over the caller's device: {}", shared.info);
        Ok(Context {
            shared: Arc::new(shared),
        })
    }

    /// Whether the context owns its instance and device (false for [`Context::from_raw`]).
    pub fn owns_device(&self) -> bool {
        self.shared.owns_device
    }

    /// The queue tessera submits its one-shot work to.
    pub fn queue(&self) -> vk::Queue {
        *self.shared.queue.lock().unwrap_or_else(|p| p.into_inner())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn caller_features_are_intersected_with_support() {
        let supported = DeviceFeatures {
            tessellation_shader: true,
            fill_mode_non_solid: true,
            dynamic_rendering: true,
            ..DeviceFeatures::default()
        };
        let f = vk::PhysicalDeviceFeatures::default().fill_mode_non_solid(true);
        let e = enabled(supported, &f, false);
        assert!(!e.tessellation_shader && e.fill_mode_non_solid && !e.dynamic_rendering);
    }
}
