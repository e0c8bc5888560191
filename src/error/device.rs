//! Errors of the Vulkan layer ([`crate::gpu`]) in types this crate owns, so that
//! [`crate::Error`], which the CPU layers return, carries no Vulkan type and the error module
//! depends on nothing above it. The `gpu` layer converts `ash::vk::Result` into
//! [`VkResultCode`] and re-exports these types as `tessera::gpu::{GpuError, DeviceReport}`.

use std::fmt;

use thiserror::Error;

/// A `VkResult` code as the driver returned it, with the name Vulkan gives it (as `ash` prints
/// it: `ERROR_DEVICE_LOST`, or the number for codes `ash` does not know). Built by the `gpu`
/// layer from `ash::vk::Result`; both `Display` and `Debug` print the name.
#[derive(Clone, PartialEq, Eq, Hash)]
pub struct VkResultCode {
    code: i32,
    name: String,
}

impl VkResultCode {
    /// A code and its name.
    pub fn new(code: i32, name: impl Into<String>) -> VkResultCode {
        VkResultCode {
            code,
            name: name.into(),
        }
    }

    /// The raw `VkResult` value.
    pub fn code(&self) -> i32 {
        self.code
    }

    /// The code's name, e.g. `ERROR_DEVICE_LOST`.
    pub fn name(&self) -> &str {
        &self.name
    }
}

impl fmt::Display for VkResultCode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.name)
    }
}

impl fmt::Debug for VkResultCode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.name)
    }
}

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
    #[error("Vulkan call {call} failed: {result}")]
    Vk {
        /// The Vulkan entry point (or our operation) that failed.
        call: &'static str,
        /// The result code.
        result: VkResultCode,
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
