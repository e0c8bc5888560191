//! Typed GPU errors.

use std::fmt;

use ash::vk;
use thiserror::Error;

/// What one physical device offers, as reported when no device is suitable.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DeviceReport {
    /// `deviceName` from the driver.
    pub name: String,
    /// Device type (integrated, discrete, CPU, ...).
    pub kind: String,
    /// Vulkan API version as `major.minor.patch`.
    pub api_version: String,
    /// Required features or limits this device lacks (empty if it is usable).
    pub missing: Vec<String>,
}

impl fmt::Display for DeviceReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "\"{}\" ({}, Vulkan {})",
            self.name, self.kind, self.api_version
        )?;
        if self.missing.is_empty() {
            write!(f, ": usable")
        } else {
            write!(f, ": missing {}", self.missing.join(", "))
        }
    }
}

fn list(devices: &[DeviceReport]) -> String {
    if devices.is_empty() {
        return " none found (is a Vulkan driver installed? Without a GPU, Mesa lavapipe: \
                Debian package mesa-vulkan-drivers)"
            .to_owned();
    }
    devices.iter().map(|d| format!("\n  - {d}")).collect()
}

/// Every failure of the Vulkan layer.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum GpuError {
    /// The Vulkan loader (libvulkan) could not be loaded.
    #[error("cannot load the Vulkan loader: {0}")]
    Loader(String),
    /// A Vulkan call failed.
    #[error("Vulkan call {call} failed: {result:?}")]
    Vk {
        /// The Vulkan entry point (or our operation) that failed.
        call: &'static str,
        /// The result code.
        result: vk::Result,
    },
    /// No device has every feature tessera needs.
    #[error("no Vulkan device with the required features; devices:{}", list(.devices))]
    NoSuitableDevice {
        /// Every device found, with what it lacks.
        devices: Vec<DeviceReport>,
    },
    /// `TESSERA_DEVICE` named no device.
    #[error("TESSERA_DEVICE=\"{wanted}\" matches no Vulkan device; devices:{}", list(.devices))]
    DeviceNotFound {
        /// The requested substring.
        wanted: String,
        /// Every device found.
        devices: Vec<DeviceReport>,
    },
    /// The device chosen with `TESSERA_DEVICE` lacks required features.
    #[error("device \"{name}\" lacks required features: {}; devices:{}", .missing.join(", "), list(.devices))]
    MissingFeatures {
        /// Device name.
        name: String,
        /// Names of the missing features.
        missing: Vec<String>,
        /// Every device found.
        devices: Vec<DeviceReport>,
    },
    /// The validation layer was requested but is not installed.
    #[error("validation requested but VK_LAYER_KHRONOS_validation is not installed (Debian: vulkan-validationlayers)")]
    NoValidationLayer,
    /// A request exceeds a device limit.
    #[error("device limit exceeded: {0}")]
    Limit(String),
    /// Waiting for the GPU timed out.
    #[error("GPU work did not finish within {0} ms (timeout)")]
    Timeout(u64),
    /// Memory allocation failed.
    #[error("GPU memory allocation failed: {0}")]
    Allocation(String),
    /// A shader name is neither embedded in the binary nor added to the context.
    #[error("unknown shader \"{name}\"; known shaders: {available}")]
    UnknownShader {
        /// The requested name.
        name: String,
        /// Comma-separated list of the known names (embedded, then added).
        available: String,
    },
    /// Invalid use of the GPU API (bad sizes, mismatched descriptions).
    #[error("invalid GPU request: {0}")]
    Invalid(String),
    /// Image encoding / file output failed.
    #[error("image output failed: {0}")]
    Output(String),
}

impl GpuError {
    /// Wraps a failed Vulkan call.
    pub fn vk(call: &'static str) -> impl FnOnce(vk::Result) -> crate::Error {
        move |result| crate::Error::Gpu(GpuError::Vk { call, result })
    }
}

/// Shorthand for `Err(GpuError::Invalid(..).into())`.
pub(crate) fn invalid<T>(msg: impl Into<String>) -> crate::Result<T> {
    Err(GpuError::Invalid(msg.into()).into())
}
