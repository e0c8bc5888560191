//! The Vulkan context of the GPU tests: the Khronos validation layer on, a loud failure without
//! a device unless `TESSERA_ALLOW_NO_GPU=1`, and the validation-clean assertion.

use tessera::gpu::{Context, ContextDesc};

/// Whether a missing Vulkan device skips GPU tests instead of failing them
/// (`TESSERA_ALLOW_NO_GPU=1`).
pub fn no_gpu_allowed() -> bool {
    std::env::var("TESSERA_ALLOW_NO_GPU").as_deref() == Ok("1")
}

/// A validation-enabled context, or `None` when there is no usable device and
/// `TESSERA_ALLOW_NO_GPU=1` (without it, any failure panics loudly).
pub fn context() -> Option<Context> {
    context_with(ContextDesc::default())
}

/// [`context`] with other settings; validation is always on.
pub fn context_with(desc: ContextDesc) -> Option<Context> {
    let desc = ContextDesc {
        validation: true,
        ..desc
    };
    match Context::new(&desc) {
        Ok(c) => Some(c),
        Err(e) if no_gpu_allowed() => {
            eprintln!("skipping: no usable Vulkan device ({e}); TESSERA_ALLOW_NO_GPU=1");
            None
        }
        Err(e) => panic!(
            "no usable Vulkan device with tessellation: {e}\n(set TESSERA_ALLOW_NO_GPU=1 to skip GPU \
             tests)"
        ),
    }
}

/// Fails the test unless validation is on and the layer reported no error.
pub fn assert_validation_clean(ctx: &Context) {
    assert!(ctx.validation_enabled(), "validation is off");
    assert_eq!(
        ctx.validation_errors(),
        0,
        "validation errors:\n{}",
        ctx.validation_messages().join("\n")
    );
}
