//! The Vulkan side of the GPU errors: [`GpuError`] and [`DeviceReport`] are defined in
//! [`crate::error`] (so the CPU layers' error type carries no Vulkan type); this module turns
//! `vk::Result` into them.

use ash::vk;

pub use crate::error::{DeviceReport, GpuError, VkResultCode};

impl From<vk::Result> for VkResultCode {
    fn from(r: vk::Result) -> VkResultCode {
        VkResultCode::new(r.as_raw(), format!("{r:?}"))
    }
}

impl GpuError {
    /// Wraps a failed Vulkan call.
    pub fn vk(call: &'static str) -> impl FnOnce(vk::Result) -> crate::Error {
        move |result| {
            crate::Error::Gpu(GpuError::Vk {
                call,
                result: result.into(),
            })
        }
    }
}

/// Shorthand for `Err(GpuError::Invalid(..).into())`.
pub(crate) fn invalid<T>(msg: impl Into<String>) -> crate::Result<T> {
    Err(GpuError::Invalid(msg.into()).into())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn result_codes_print_as_ash_does() {
        for r in [
            vk::Result::ERROR_DEVICE_LOST,
            vk::Result::ERROR_OUT_OF_POOL_MEMORY,
            vk::Result::TIMEOUT,
            vk::Result::from_raw(-12345),
        ] {
            let code = VkResultCode::from(r);
            assert_eq!(code.code(), r.as_raw());
            assert_eq!(code.to_string(), format!("{r:?}"));
            assert_eq!(format!("{code:?}"), format!("{r:?}"));
        }
        let e = GpuError::vk("vkQueueSubmit")(vk::Result::ERROR_DEVICE_LOST);
        assert_eq!(
            e.to_string(),
            "Vulkan call vkQueueSubmit failed: ERROR_DEVICE_LOST"
        );
    }
}
