//! A TES capture buffer per frame slot: with two frames in flight, frame N+1 (the other slot,
//! other control positions) is recorded and submitted while frame N may still run, and each
//! frame's capture, read after waiting for that frame's fence only, holds exactly the records a
//! one-slot renderer captures for the same positions (compared as sorted bit patterns: the
//! record order follows the GPU's atomic counter). Under validation.

mod common;

use common::capture::{scheme_surface, surface_capacity, uniform};
use common::gpu::{assert_validation_clean, context};
use common::meshes::mesh;
use glam::{DVec3, Mat4, Vec3};
use tessera::gpu::{tes_writes_to_host, vk, Context, RenderTarget};
use tessera::render::{
    CaptureRecord, EngineDesc, FrameUniforms, RenderDesc, Scheme, SurfaceRenderer,
};

/// Fixed uniforms: capture turns culling off, so the camera does not change what is captured.
fn uniforms() -> FrameUniforms {
    FrameUniforms {
        view_proj: Mat4::from_scale(Vec3::splat(0.3)),
        eye: Vec3::new(0.0, 0.0, 5.0),
        viewport: [32.0, 32.0],
        light_dir: Vec3::Z,
        color_by: Default::default(),
    }
}

/// Every record as its bits, sorted: the capture as a set.
fn bits(records: &[CaptureRecord]) -> Vec<Vec<u32>> {
    let mut v: Vec<Vec<u32>> = records
        .iter()
        .map(|r| {
            let mut w = vec![r.face, r.u.to_bits(), r.v.to_bits()];
            w.extend(r.position.map(f32::to_bits));
            w.extend(r.normal.map(f32::to_bits));
            w.push(r.sub_face.unwrap_or(u32::MAX));
            w.extend(r.texcoord.map(f32::to_bits));
            w
        })
        .collect();
    v.sort();
    v
}

/// A command pool with one command buffer and fence per frame, submitted without waiting.
struct Frames {
    ctx: Context,
    pool: vk::CommandPool,
    fences: Vec<vk::Fence>,
}

impl Frames {
    fn new(ctx: &Context) -> Frames {
        let info = vk::CommandPoolCreateInfo::default().queue_family_index(ctx.info().queue_family);
        // SAFETY: valid device; destroyed in Drop after the device is idle.
        let pool = unsafe { ctx.device().create_command_pool(&info, None) }.unwrap();
        Frames {
            ctx: ctx.clone(),
            pool,
            fences: Vec::new(),
        }
    }

    /// Records the renderer's current frame into `target` and submits it; returns its fence.
    fn submit(&mut self, renderer: &SurfaceRenderer, target: &RenderTarget) -> vk::Fence {
        let dev = self.ctx.device();
        let ai = vk::CommandBufferAllocateInfo::default()
            .command_pool(self.pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: the pool is ours and used from this thread only.
        unsafe {
            let cmd = dev.allocate_command_buffers(&ai).unwrap()[0];
            dev.begin_command_buffer(cmd, &vk::CommandBufferBeginInfo::default())
                .unwrap();
            renderer.record_compute(cmd);
            target.begin(dev, cmd, [0.0, 0.0, 0.0, 1.0]);
            renderer.record(cmd);
            target.end(dev, cmd);
            tes_writes_to_host(dev, cmd);
            dev.end_command_buffer(cmd).unwrap();
            let fence = dev
                .create_fence(&vk::FenceCreateInfo::default(), None)
                .unwrap();
            let cmds = [cmd];
            let submit = vk::SubmitInfo::default().command_buffers(&cmds);
            dev.queue_submit(self.ctx.queue(), &[submit], fence)
                .unwrap();
            self.fences.push(fence);
            fence
        }
    }

    fn wait(&self, fence: vk::Fence) {
        // SAFETY: a fence of this device.
        unsafe {
            self.ctx
                .device()
                .wait_for_fences(&[fence], true, 120_000_000_000)
                .unwrap()
        };
    }
}

impl Drop for Frames {
    fn drop(&mut self) {
        let _ = self.ctx.wait_idle();
        // SAFETY: the device is idle; the pool's command buffers go with it.
        unsafe {
            for &f in &self.fences {
                self.ctx.device().destroy_fence(f, None);
            }
            self.ctx.device().destroy_command_pool(self.pool, None);
        }
    }
}

#[test]
fn frames_in_flight_capture_into_their_own_slots() {
    let Some(ctx) = context() else { return };
    let m = mesh("embedded:mixed");
    let surface = scheme_surface(&ctx, &m, 5, Scheme::GregoryStencil);
    let render = RenderDesc {
        tess: uniform(5.0),
        capture_capacity: Some(surface_capacity(&surface, &uniform(5.0))),
        ..RenderDesc::default()
    };
    let first = surface.positions.clone();
    let second: Vec<DVec3> = first
        .iter()
        .enumerate()
        .map(|(i, p)| *p * 1.1 + DVec3::new(0.05, -0.02 * (i % 3) as f64, 0.01))
        .collect();
    let targets = [
        RenderTarget::new(&ctx, 32, 32, 1).unwrap(),
        RenderTarget::new(&ctx, 32, 32, 1).unwrap(),
    ];
    let engine = |n| EngineDesc {
        target: targets[0].format().into(),
        frames_in_flight: n,
    };
    let mut frames = Frames::new(&ctx);

    // Reference: one slot, every frame waited for before the next is prepared.
    let mut single = SurfaceRenderer::for_engine(&ctx, &surface, &render, &engine(1)).unwrap();
    let mut reference = Vec::new();
    for positions in [&first, &second] {
        single.update_positions(positions, None).unwrap();
        single.set_frame(&uniforms()).unwrap();
        let fence = frames.submit(&single, &targets[0]);
        frames.wait(fence);
        reference.push(bits(&single.read_capture().unwrap()));
    }
    assert_ne!(reference[0], reference[1], "the two frames differ");
    assert!(reference[0].len() > 100, "{} records", reference[0].len());

    // Two slots: frame 1 is prepared and submitted before frame 0 is waited for.
    let mut double = SurfaceRenderer::for_engine(&ctx, &surface, &render, &engine(2)).unwrap();
    double.set_frame(&uniforms()).unwrap();
    let slot_a = double.frame_slot();
    let fence_a = frames.submit(&double, &targets[0]);
    double.update_positions(&second, None).unwrap();
    double.set_frame(&uniforms()).unwrap();
    let slot_b = double.frame_slot();
    assert_ne!(slot_a, slot_b);
    let fence_b = frames.submit(&double, &targets[1]);
    frames.wait(fence_b);
    let b = bits(&double.read_capture_slot(slot_b).unwrap());
    frames.wait(fence_a);
    let a = bits(&double.read_capture_slot(slot_a).unwrap());
    eprintln!(
        "slot {slot_a}: {} records, slot {slot_b}: {} records",
        a.len(),
        b.len()
    );
    assert!(
        a == reference[0],
        "frame 0's capture (slot {slot_a}) is not its own"
    );
    assert!(
        b == reference[1],
        "frame 1's capture (slot {slot_b}) is not its own"
    );
    assert_eq!(bits(&double.read_capture().unwrap()), b, "current slot");
    assert!(double.read_capture_slot(2).is_err(), "no third slot");
    // Capture memory: one full buffer per slot with capture on, none per slot without.
    let plain = RenderDesc {
        capture_capacity: None,
        ..render
    };
    let shared = |desc: &RenderDesc, n| {
        SurfaceRenderer::for_engine(&ctx, &surface, desc, &engine(n))
            .unwrap()
            .memory_bytes()
            .shared
    };
    let (one, two) = (
        shared(&render, 1) - shared(&plain, 1),
        shared(&render, 2) - shared(&plain, 2),
    );
    eprintln!("capture bytes: one slot {one}, two slots {two}");
    assert!(
        two >= 2 * one && one > 100 * 52,
        "one slot {one}, two slots {two}"
    );
    drop(frames);
    assert_validation_clean(&ctx);
}
