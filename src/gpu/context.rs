//! Vulkan instance, validation, device selection and the shared context handle.

use std::ffi::{CStr, CString};
use std::mem::ManuallyDrop;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};

use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};
use gpu_allocator::{AllocationSizes, AllocatorDebugSettings};

use super::debug::{self, SharedLog, ValidationLog};
use super::device::{self, DeviceInfo, Feature};
use super::error::GpuError;
use super::pipeline::PipelineCache;
use super::shaders::ShaderTable;
use crate::Result;

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// How to create a [`Context`].
#[derive(Debug, Clone)]
pub struct ContextDesc {
    /// Enable the Khronos validation layer and the messenger. Default: [`validation_default`].
    pub validation: bool,
    /// Substring of the device name; `None` reads `TESSERA_DEVICE`, then picks the first device
    /// with every required feature.
    pub device: Option<String>,
    /// With `validation`, also enable the layer's synchronization validation (missing barriers,
    /// hazards) when the layer offers VK_EXT_validation_features. Default: true.
    pub sync_validation: bool,
    /// Features a device must have to be selected (default: tessellationShader only).
    pub required: Vec<Feature>,
    /// Timeout for waiting on GPU work, in milliseconds (default 120 s).
    pub timeout_ms: u64,
}

impl Default for ContextDesc {
    fn default() -> Self {
        ContextDesc {
            validation: validation_default(),
            device: None,
            sync_validation: true,
            required: vec![Feature::TessellationShader],
            timeout_ms: 120_000,
        }
    }
}

/// Validation default: `TESSERA_VALIDATION=1`/`0` if set, else on in debug builds only.
pub fn validation_default() -> bool {
    match std::env::var("TESSERA_VALIDATION").as_deref() {
        Ok("1") | Ok("true") | Ok("on") => true,
        Ok("0") | Ok("false") | Ok("off") => false,
        _ => cfg!(debug_assertions),
    }
}

/// Everything the context owns; resources keep an `Arc` to it so it is destroyed last.
pub(crate) struct Shared {
    pub(super) _entry: ash::Entry,
    pub instance: ash::Instance,
    pub(super) debug_instance: Option<ash::ext::debug_utils::Instance>,
    pub(super) messenger: vk::DebugUtilsMessengerEXT,
    pub(super) log: Box<SharedLog>,
    pub physical: vk::PhysicalDevice,
    pub device: ash::Device,
    pub(super) debug_device: Option<ash::ext::debug_utils::Device>,
    /// Whether the context created the instance and device (and so destroys them): false for
    /// [`Context::from_raw`], whose caller keeps them.
    pub(super) owns_device: bool,
    pub queue: Mutex<vk::Queue>,
    pub command_pool: Mutex<vk::CommandPool>,
    /// Submissions that timed out: (fence, command buffer), released when signalled.
    pub pending: Mutex<Vec<(vk::Fence, vk::CommandBuffer)>>,
    /// tessera's allocator or the caller's ([`super::RawContextDesc::allocator`]).
    pub allocator: ManuallyDrop<Arc<Mutex<Allocator>>>,
    pub pipelines: Mutex<PipelineCache>,
    /// Shader tables registered with [`Context::add_shaders`], searched after the embedded one.
    pub added_shaders: Mutex<Vec<ShaderTable>>,
    pub info: DeviceInfo,
    pub timeout_ms: u64,
    pub validation: bool,
    /// Objects left undestroyed because timed-out work might still use them.
    pub leaked: AtomicU64,
    /// A wait for timed-out work ran out of time: later waits only poll.
    pub gave_up: AtomicBool,
}

impl Shared {
    /// Called before an object is destroyed; returns whether it may be destroyed now. Without
    /// a timed-out submission this is one uncontended lock and `true`. When a submission timed
    /// out (its work may still be running and may use the object), waits for every such
    /// submission, at most the context's timeout: finished, `true`; the device lost, the error
    /// is logged and `true` (a lost device executes nothing any more, and Vulkan allows
    /// destroying its objects); still running (or another wait error), the error is logged and
    /// `false`: the caller leaves the object alive (leaked, counted by
    /// [`Context::leaked_objects`]) rather than destroy memory the GPU may still use. Never
    /// panics, never waits unboundedly.
    pub fn wait_pending(&self) -> bool {
        let pending = self.pending.lock().unwrap_or_else(|p| p.into_inner());
        if pending.is_empty() {
            return true;
        }
        let fences: Vec<vk::Fence> = pending.iter().map(|(f, _)| *f).collect();
        // Once a wait gave up, later drops only poll: dropping many objects costs one timeout.
        let timeout_ns = if self.gave_up.load(Ordering::Relaxed) {
            0
        } else {
            self.timeout_ms.saturating_mul(1_000_000)
        };
        // SAFETY: the fences belong to this device and stay alive while the lock is held.
        let waited = unsafe { self.device.wait_for_fences(&fences, true, timeout_ns) };
        let destroy = may_destroy_after(waited);
        if !destroy {
            self.leaked.fetch_add(1, Ordering::Relaxed);
            self.gave_up.store(true, Ordering::Relaxed);
        }
        destroy
    }

    pub fn allocator(&self) -> MutexGuard<'_, Allocator> {
        self.allocator.lock().unwrap_or_else(|p| p.into_inner())
    }

    pub fn set_name<H: vk::Handle>(&self, handle: H, name: &str) {
        let Some(du) = &self.debug_device else {
            return;
        };
        let Ok(cname) = CString::new(name.replace('\0', " ")) else {
            return;
        };
        let info = vk::DebugUtilsObjectNameInfoEXT::default()
            .object_handle(handle)
            .object_name(&cname);
        // SAFETY: the handle belongs to this device; naming failures are harmless.
        let _ = unsafe { du.set_debug_utils_object_name(&info) };
    }
}

/// The drop path's decision after waiting for timed-out GPU work ([`Shared::wait_pending`]):
/// whether the object may be destroyed. Errors are logged.
pub(super) fn may_destroy_after(waited: std::result::Result<(), vk::Result>) -> bool {
    match waited {
        Ok(()) => true,
        Err(vk::Result::ERROR_DEVICE_LOST) => {
            log::error!(
                "the device was lost while timed-out GPU work was pending; destroying its objects"
            );
            true
        }
        Err(e) => {
            log::error!(
                "timed-out GPU work is still pending ({e}); leaving an object undestroyed rather than free memory the GPU may use"
            );
            false
        }
    }
}

impl Drop for Shared {
    fn drop(&mut self) {
        // SAFETY: every resource holding an Arc<Shared> is gone; destroy in reverse order.
        unsafe {
            if let Err(e) = self.device.device_wait_idle() {
                log::error!("destroying the context: waiting for the device failed ({e}); destroying its objects anyway");
            }
            for (fence, _) in self
                .pending
                .get_mut()
                .unwrap_or_else(|p| p.into_inner())
                .drain(..)
            {
                self.device.destroy_fence(fence, None);
            }
            self.pipelines
                .get_mut()
                .unwrap_or_else(|p| p.into_inner())
                .destroy(&self.device);
            self.device.destroy_command_pool(
                *self
                    .command_pool
                    .get_mut()
                    .unwrap_or_else(|p| p.into_inner()),
                None,
            );
            ManuallyDrop::drop(&mut self.allocator);
            if self.owns_device {
                self.device.destroy_device(None);
            }
            if let Some(di) = &self.debug_instance {
                if self.messenger != vk::DebugUtilsMessengerEXT::null() {
                    di.destroy_debug_utils_messenger(self.messenger, None);
                }
            }
            if self.owns_device {
                self.instance.destroy_instance(None);
            }
        }
    }
}

/// The Vulkan context: instance, device, queue, allocator, validation log, pipeline cache.
/// Cheap to clone (shared handle). Resources created from it keep it alive.
///
/// Dropping never panics, also after a timeout or device loss: a resource dropped while one of
/// the context's submissions has timed out waits for that work at most the context's timeout;
/// finished or the device lost (logged), it is destroyed; still running, the error is logged
/// and the resource is left alive ([`Self::leaked_objects`]) rather than freed under the GPU.
/// The last handle's drop waits for the device (a failure is logged) and destroys the rest.
#[derive(Clone)]
pub struct Context {
    pub(crate) shared: Arc<Shared>,
}

impl std::fmt::Debug for Context {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Context")
            .field("device", &self.shared.info.name)
            .field("validation", &self.shared.validation)
            .finish()
    }
}

fn vkerr(call: &'static str) -> impl FnOnce(vk::Result) -> crate::Error {
    GpuError::vk(call)
}

impl Context {
    /// Creates a context as described by `desc`.
    pub fn new(desc: &ContextDesc) -> Result<Context> {
        // SAFETY: loading the system Vulkan loader; it stays loaded for the Entry's lifetime.
        let entry = unsafe { ash::Entry::load() }.map_err(|e| GpuError::Loader(e.to_string()))?;
        let log: Box<SharedLog> = Box::new(Mutex::new(ValidationLog::default()));

        // SAFETY: plain enumeration calls on a loaded entry.
        let (layers, exts, inst_version) = unsafe {
            (
                entry
                    .enumerate_instance_layer_properties()
                    .map_err(vkerr("vkEnumerateInstanceLayerProperties"))?,
                entry
                    .enumerate_instance_extension_properties(None)
                    .map_err(vkerr("vkEnumerateInstanceExtensionProperties"))?,
                entry
                    .try_enumerate_instance_version()
                    .map_err(vkerr("vkEnumerateInstanceVersion"))?
                    .unwrap_or(vk::API_VERSION_1_0),
            )
        };
        let has_layer = layers
            .iter()
            .any(|l| l.layer_name_as_c_str() == Ok(VALIDATION_LAYER));
        if desc.validation && !has_layer {
            return Err(GpuError::NoValidationLayer.into());
        }
        let is_debug_utils = |e: &vk::ExtensionProperties| {
            e.extension_name_as_c_str() == Ok(ash::ext::debug_utils::NAME)
        };
        let mut has_debug_utils = exts.iter().any(is_debug_utils);
        if desc.validation && !has_debug_utils {
            // The validation layer itself provides VK_EXT_debug_utils.
            // SAFETY: enumeration of a present layer's extensions.
            let layer_exts =
                unsafe { entry.enumerate_instance_extension_properties(Some(VALIDATION_LAYER)) }
                    .map_err(vkerr("vkEnumerateInstanceExtensionProperties"))?;
            has_debug_utils = layer_exts.iter().any(is_debug_utils);
            if !has_debug_utils {
                return Err(GpuError::Invalid(
                    "validation requested but VK_EXT_debug_utils is unavailable, so validation \
                     messages could not be counted"
                        .to_owned(),
                )
                .into());
            }
        }
        if inst_version < vk::API_VERSION_1_2 {
            return Err(GpuError::Invalid(format!(
                "the Vulkan loader supports only API {}.{}; tessera needs 1.2 or newer",
                vk::api_version_major(inst_version),
                vk::api_version_minor(inst_version)
            ))
            .into());
        }
        let mut has_validation_features = false;
        if desc.validation && desc.sync_validation {
            // SAFETY: enumeration of a present layer's extensions.
            let layer_exts =
                unsafe { entry.enumerate_instance_extension_properties(Some(VALIDATION_LAYER)) }
                    .map_err(vkerr("vkEnumerateInstanceExtensionProperties"))?;
            has_validation_features = layer_exts
                .iter()
                .any(|e| e.extension_name_as_c_str() == Ok(ash::ext::validation_features::NAME));
        }
        let api = inst_version.min(vk::API_VERSION_1_3);

        let app = vk::ApplicationInfo::default()
            .application_name(c"tessera")
            .engine_name(c"tessera")
            .api_version(api);
        let layer_names: Vec<*const std::ffi::c_char> = if desc.validation {
            vec![VALIDATION_LAYER.as_ptr()]
        } else {
            Vec::new()
        };
        let mut ext_names: Vec<*const std::ffi::c_char> = Vec::new();
        if has_debug_utils {
            ext_names.push(ash::ext::debug_utils::NAME.as_ptr());
        }
        if has_validation_features {
            ext_names.push(ash::ext::validation_features::NAME.as_ptr());
        }
        let enables = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
        let mut validation_features =
            vk::ValidationFeaturesEXT::default().enabled_validation_features(&enables);
        let mut messenger_info = debug::messenger_info(&log);
        let mut ici = vk::InstanceCreateInfo::default()
            .application_info(&app)
            .enabled_layer_names(&layer_names)
            .enabled_extension_names(&ext_names);
        if desc.validation && has_debug_utils {
            ici = ici.push_next(&mut messenger_info);
        }
        if has_validation_features {
            ici = ici.push_next(&mut validation_features);
        }
        // SAFETY: create info is valid; `log` outlives the instance (owned by Shared).
        let instance = match unsafe { entry.create_instance(&ici, None) } {
            Ok(i) => i,
            // The loader found no driver at all.
            Err(vk::Result::ERROR_INCOMPATIBLE_DRIVER) => {
                return Err(GpuError::NoSuitableDevice {
                    devices: Vec::new(),
                }
                .into())
            }
            Err(e) => return Err(GpuError::vk("vkCreateInstance")(e)),
        };

        let debug_instance =
            has_debug_utils.then(|| ash::ext::debug_utils::Instance::new(&entry, &instance));
        let mut messenger = vk::DebugUtilsMessengerEXT::null();
        if desc.validation {
            if let Some(di) = &debug_instance {
                let info = debug::messenger_info(&log);
                // SAFETY: valid create info pointing at the boxed log.
                match unsafe { di.create_debug_utils_messenger(&info, None) } {
                    Ok(m) => messenger = m,
                    Err(e) => {
                        // SAFETY: nothing else was created from the instance.
                        unsafe { instance.destroy_instance(None) };
                        return Err(GpuError::vk("vkCreateDebugUtilsMessengerEXT")(e));
                    }
                }
            }
        }

        // From here on, failures must tear down what exists.
        let cleanup = |instance: &ash::Instance| unsafe {
            if let Some(di) = &debug_instance {
                if messenger != vk::DebugUtilsMessengerEXT::null() {
                    di.destroy_debug_utils_messenger(messenger, None);
                }
            }
            instance.destroy_instance(None);
        };

        let result = Self::open_device(&instance, desc);
        let (candidate, device) = match result {
            Ok(x) => x,
            Err(e) => {
                cleanup(&instance);
                return Err(e);
            }
        };
        let info = candidate.info.clone();
        // SAFETY: the device was created with one queue of this family.
        let queue = unsafe { device.get_device_queue(info.queue_family, 0) };
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(info.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: valid device.
        let command_pool = match unsafe { device.create_command_pool(&pool_info, None) } {
            Ok(p) => p,
            Err(e) => {
                unsafe { device.destroy_device(None) };
                cleanup(&instance);
                return Err(GpuError::vk("vkCreateCommandPool")(e));
            }
        };
        let allocator = match Allocator::new(&AllocatorCreateDesc {
            instance: instance.clone(),
            device: device.clone(),
            physical_device: candidate.handle,
            debug_settings: AllocatorDebugSettings::default(),
            buffer_device_address: false,
            allocation_sizes: AllocationSizes::default(),
        }) {
            Ok(a) => a,
            Err(e) => {
                unsafe {
                    device.destroy_command_pool(command_pool, None);
                    device.destroy_device(None);
                }
                cleanup(&instance);
                return Err(GpuError::Allocation(e.to_string()).into());
            }
        };
        let debug_device =
            has_debug_utils.then(|| ash::ext::debug_utils::Device::new(&instance, &device));

        let shared = Shared {
            _entry: entry,
            instance,
            debug_instance,
            messenger,
            log,
            physical: candidate.handle,
            device,
            debug_device,
            owns_device: true,
            queue: Mutex::new(queue),
            command_pool: Mutex::new(command_pool),
            pending: Mutex::new(Vec::new()),
            leaked: AtomicU64::new(0),
            gave_up: AtomicBool::new(false),
            allocator: ManuallyDrop::new(Arc::new(Mutex::new(allocator))),
            pipelines: Mutex::new(PipelineCache::default()),
            added_shaders: Mutex::new(Vec::new()),
            info,
            timeout_ms: desc.timeout_ms.max(1),
            validation: desc.validation,
        };
        shared.set_name(queue, "tessera graphics queue");
        shared.set_name(command_pool, "tessera one-shot command pool");
        Ok(Context {
            shared: Arc::new(shared),
        })
    }

    fn open_device(
        instance: &ash::Instance,
        desc: &ContextDesc,
    ) -> Result<(device::Candidate, ash::Device)> {
        // SAFETY: valid instance.
        let pds = match unsafe { instance.enumerate_physical_devices() } {
            Ok(p) => p,
            // Some loaders report "no driver" here instead of at instance creation.
            Err(vk::Result::ERROR_INITIALIZATION_FAILED) => Vec::new(),
            Err(e) => return Err(GpuError::vk("vkEnumeratePhysicalDevices")(e)),
        };
        let candidates: Vec<_> = pds
            .iter()
            .map(|pd| device::describe(instance, *pd))
            .collect();
        let env = std::env::var("TESSERA_DEVICE").ok();
        let wanted = desc.device.clone().or(env);
        let idx = device::select(&candidates, wanted.as_deref(), &desc.required)?;
        let cand = candidates[idx].clone();
        let f = cand.info.features;
        let features = vk::PhysicalDeviceFeatures::default()
            .tessellation_shader(f.tessellation_shader)
            .fill_mode_non_solid(f.fill_mode_non_solid)
            .pipeline_statistics_query(f.pipeline_statistics_query)
            .vertex_pipeline_stores_and_atomics(f.vertex_pipeline_stores_and_atomics)
            .geometry_shader(f.geometry_shader)
            .shader_float64(f.shader_float64);
        let mut f13 =
            vk::PhysicalDeviceVulkan13Features::default().dynamic_rendering(f.dynamic_rendering);
        let prio = [1.0f32];
        let queues = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(cand.info.queue_family)
            .queue_priorities(&prio)];
        let mut dci = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queues)
            .enabled_features(&features);
        if f.dynamic_rendering {
            dci = dci.push_next(&mut f13);
        }
        // SAFETY: valid create info for this physical device.
        let device = unsafe { instance.create_device(cand.handle, &dci, None) }
            .map_err(vkerr("vkCreateDevice"))?;
        Ok((cand, device))
    }

    /// The `ash` device (for recording commands).
    pub fn device(&self) -> &ash::Device {
        &self.shared.device
    }

    /// The `ash` instance.
    pub fn instance(&self) -> &ash::Instance {
        &self.shared.instance
    }

    /// The physical device in use.
    pub fn physical_device(&self) -> vk::PhysicalDevice {
        self.shared.physical
    }

    /// Size in bytes of the device's largest memory heap (what a frame's allocations must fit).
    pub fn largest_heap_bytes(&self) -> u64 {
        // SAFETY: the physical device belongs to this instance.
        let props = unsafe {
            self.shared
                .instance
                .get_physical_device_memory_properties(self.shared.physical)
        };
        props.memory_heaps[..props.memory_heap_count as usize]
            .iter()
            .map(|h| h.size)
            .max()
            .unwrap_or(0)
    }

    /// Name, features, limits and queue family of the selected device.
    pub fn info(&self) -> &DeviceInfo {
        &self.shared.info
    }

    /// Whether validation is on.
    pub fn validation_enabled(&self) -> bool {
        self.shared.validation
    }

    /// Fails with a typed error naming every feature of `features` the device lacks.
    pub fn require(&self, features: &[Feature]) -> Result<()> {
        let missing = self.shared.info.features.missing(features);
        if missing.is_empty() {
            return Ok(());
        }
        Err(GpuError::MissingFeatures {
            name: self.shared.info.name.clone(),
            missing,
            devices: Vec::new(),
        }
        .into())
    }

    fn log(&self) -> ValidationLog {
        self.shared
            .log
            .lock()
            .map(|l| l.clone())
            .unwrap_or_default()
    }

    /// Number of validation errors reported so far.
    pub fn validation_errors(&self) -> usize {
        self.shared.log.lock().map(|l| l.errors).unwrap_or(0)
    }

    /// Number of validation warnings reported so far.
    pub fn validation_warnings(&self) -> usize {
        self.shared.log.lock().map(|l| l.warnings).unwrap_or(0)
    }

    /// The validation messages kept so far (errors and warnings).
    pub fn validation_messages(&self) -> Vec<String> {
        self.log().messages
    }

    /// Names a Vulkan object for debuggers / validation messages (no-op without debug utils).
    pub fn set_name<H: vk::Handle>(&self, handle: H, name: &str) {
        self.shared.set_name(handle, name);
    }

    /// Number of objects (buffers, images, pools, ...) whose drop left them undestroyed because
    /// a submission had timed out and its work had still not finished within the timeout when
    /// they were dropped (their memory stays allocated rather than be freed under the GPU; it
    /// is released with the device). 0 unless a submission timed out.
    pub fn leaked_objects(&self) -> u64 {
        self.shared.leaked.load(Ordering::Relaxed)
    }

    /// Waits until the device is idle.
    pub fn wait_idle(&self) -> Result<()> {
        // SAFETY: valid device; queue access is serialised by holding the queue lock.
        let _q = self.shared.queue.lock().unwrap_or_else(|p| p.into_inner());
        unsafe { self.shared.device.device_wait_idle() }.map_err(vkerr("vkDeviceWaitIdle"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::{Buffer, MemoryLocation};

    #[test]
    fn drop_decision_after_a_failed_wait() {
        assert!(may_destroy_after(Ok(())));
        assert!(may_destroy_after(Err(vk::Result::ERROR_DEVICE_LOST)));
        assert!(!may_destroy_after(Err(vk::Result::TIMEOUT)));
    }

    /// A submission that timed out and never finishes (an unsignalled fence in the pending
    /// list, the state `submit_once` leaves after a timeout): dropping a buffer waits one
    /// timeout, logs and leaves it alive instead of destroying it under the GPU or hanging;
    /// once the work is gone, drops destroy again.
    #[test]
    fn dropping_after_a_timeout_leaks_instead_of_hanging() {
        let desc = ContextDesc {
            timeout_ms: 20,
            ..ContextDesc::default()
        };
        let Ok(ctx) = Context::new(&desc) else {
            log::warn!("no Vulkan device; skipped");
            return;
        };
        let dev = ctx.device();
        // SAFETY: valid device; the fence is destroyed below.
        let fence = unsafe { dev.create_fence(&vk::FenceCreateInfo::default(), None) }.unwrap();
        ctx.shared
            .pending
            .lock()
            .unwrap()
            .push((fence, vk::CommandBuffer::null()));
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
        for _ in 0..3 {
            drop(Buffer::new(&ctx, 64, usage, MemoryLocation::CpuToGpu, "t").unwrap());
        }
        assert_eq!(ctx.leaked_objects(), 3);
        ctx.shared.pending.lock().unwrap().clear();
        // SAFETY: no submission uses the fence.
        unsafe { dev.destroy_fence(fence, None) };
        drop(Buffer::new(&ctx, 64, usage, MemoryLocation::CpuToGpu, "t").unwrap());
        assert_eq!(ctx.leaked_objects(), 3);
        assert_eq!(
            ctx.validation_errors(),
            0,
            "{:?}",
            ctx.validation_messages()
        );
    }
}
