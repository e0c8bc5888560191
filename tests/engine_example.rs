//! `examples/engine.rs` run as a test: tessera inside an application that owns the instance,
//! device, queue, allocator, render pass (or dynamic rendering), frames in flight and a pipeline
//! of its own. The last frame against a golden, in both rendering modes and with 1-3 frames in
//! flight (which must not change a pixel); the caller's device checked up front; tessera leaves
//! what it does not own alive. Validation on throughout.

mod common;
#[allow(dead_code)]
#[path = "../examples/engine.rs"]
mod engine;

use ash::vk;
use common::golden::check_golden;
use engine::{run, EngineOptions, Gpu};
use tessera::gpu::{Context, DrawTarget, LayoutSlots, PassKind, TargetFormat};
use tessera::render::{
    plan_for_scheme, EngineDesc, RenderDesc, Scheme, SchemeLimits, SurfaceRenderer,
};

/// The example's run, or `None` without a device and `TESSERA_ALLOW_NO_GPU=1`.
fn run_clean(opts: &EngineOptions) -> Option<image::RgbaImage> {
    let r = match run(opts) {
        Ok(r) => r,
        Err(e) if common::gpu::no_gpu_allowed() => {
            eprintln!("skipping: {e}");
            return None;
        }
        Err(e) => panic!("engine example failed: {e}"),
    };
    assert_eq!(
        r.validation_errors,
        0,
        "validation messages:\n{}",
        r.validation_messages.join("\n")
    );
    assert!(r.patches > 0);
    Some(r.image)
}

#[test]
fn engine_example_matches_golden_in_both_rendering_modes() {
    let opts = EngineOptions::default();
    let Some(pass) = run_clean(&opts) else { return };
    check_golden("engine_example", &pass);
    let dynamic = run_clean(&EngineOptions {
        dynamic_rendering: true,
        ..opts.clone()
    })
    .expect("device present");
    assert!(
        pass == dynamic,
        "dynamic rendering draws other pixels than the render pass"
    );
}

#[test]
fn frames_in_flight_do_not_change_the_frames() {
    // One frame in flight waits for every frame before the next: the reference. With two and
    // three, frame N+1 is prepared while N may run; each reads only its own slot's positions.
    let opts = |n| EngineOptions {
        frames: 7,
        frames_in_flight: n,
        ..EngineOptions::default()
    };
    let Some(one) = run_clean(&opts(1)) else {
        return;
    };
    for n in [2, 3] {
        let img = run_clean(&opts(n)).expect("device present");
        assert!(img == one, "{n} frames in flight change the last frame");
    }
}

fn gpu(features: vk::PhysicalDeviceFeatures, dynamic: bool) -> Option<Gpu> {
    match Gpu::new(true, dynamic, features) {
        Ok(g) => Some(g),
        Err(e) if common::gpu::no_gpu_allowed() => {
            eprintln!("skipping: {e}");
            None
        }
        Err(e) => panic!("no device: {e}"),
    }
}

#[test]
fn caller_device_is_checked_up_front() {
    let Some(g) = gpu(vk::PhysicalDeviceFeatures::default(), false) else {
        return;
    };
    let e = Context::from_raw(&g.raw_desc(false)).unwrap_err();
    assert!(
        e.to_string().contains("tessellationShader"),
        "error does not name the missing feature: {e}"
    );
}

#[test]
fn features_a_renderer_needs_are_named() {
    let tess = vk::PhysicalDeviceFeatures::default().tessellation_shader(true);
    let Some(g) = gpu(tess, false) else { return };
    let ctx = Context::from_raw(&g.raw_desc(false)).unwrap();
    let mesh = tessera::assets::EmbeddedMesh::Mixed.load().unwrap();
    let surface = plan_for_scheme(
        &mesh,
        Scheme::BsplineOnly,
        &SchemeLimits::from_context(&ctx),
    )
    .unwrap();
    let format = TargetFormat {
        color: vk::Format::R8G8B8A8_SRGB,
        depth: vk::Format::D32_SFLOAT,
        samples: 1,
    };
    let dynamic = EngineDesc {
        target: DrawTarget {
            format,
            pass: PassKind::Dynamic,
            slots: LayoutSlots::default(),
        },
        frames_in_flight: 2,
    };
    let e = SurfaceRenderer::for_engine(&ctx, &surface, &RenderDesc::default(), &dynamic)
        .err()
        .expect("dynamic rendering was not enabled");
    assert!(e.to_string().contains("dynamicRendering"), "{e}");
    let wire = RenderDesc {
        wireframe: true,
        ..RenderDesc::default()
    };
    let e = SurfaceRenderer::new(&ctx, &surface, &wire, format)
        .err()
        .expect("fillModeNonSolid was not enabled");
    assert!(e.to_string().contains("fillModeNonSolid"), "{e}");
    let capture = RenderDesc {
        capture_capacity: Some(16),
        ..RenderDesc::default()
    };
    let e = SurfaceRenderer::new(&ctx, &surface, &capture, format)
        .err()
        .expect("vertexPipelineStoresAndAtomics was not enabled");
    assert!(
        e.to_string().contains("vertexPipelineStoresAndAtomics"),
        "{e}"
    );
    let too_many = EngineDesc {
        frames_in_flight: 9,
        ..dynamic
    };
    assert!(
        SurfaceRenderer::for_engine(&ctx, &surface, &RenderDesc::default(), &too_many).is_err()
    );
    assert_eq!(
        ctx.validation_errors(),
        0,
        "{:?}",
        ctx.validation_messages()
    );
}

#[test]
fn tessera_leaves_the_callers_objects_alive() {
    let tess = vk::PhysicalDeviceFeatures::default().tessellation_shader(true);
    let Some(g) = gpu(tess, false) else { return };
    let ctx = Context::from_raw(&g.raw_desc(false)).unwrap();
    assert!(!ctx.owns_device());
    // A tessera buffer from the caller's allocator, then the context dropped.
    let b = tessera::gpu::Buffer::new(
        &ctx,
        256,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        tessera::gpu::MemoryLocation::CpuToGpu,
        "tessera buffer",
    )
    .unwrap();
    drop(b);
    drop(ctx);
    // The device, queue and allocator still work for the caller.
    let buffer = g
        .buffer(
            1024,
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            gpu_allocator::MemoryLocation::CpuToGpu,
        )
        .unwrap();
    // SAFETY: the caller's live device.
    unsafe { g.device().device_wait_idle() }.unwrap();
    g.free_buffer(buffer).unwrap();
    // Gpu's drop destroys the device and instance: a second destruction by tessera would
    // have crashed here.
}
