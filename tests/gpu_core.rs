//! Vulkan core tests: run on the real device (lavapipe here) with validation on, and fail on
//! any validation error. Without a usable device they fail unless TESSERA_ALLOW_NO_GPU=1.

mod common;

use std::collections::BTreeSet;

use common::capture::CaptureBuffer;
use common::gpu::{assert_validation_clean, context, context_with, no_gpu_allowed};
use tessera::gpu::*;
use tessera::Error;

/// sRGB encoding (IEC 61966-2-1) of a linear value, as an 8-bit code.
fn srgb_byte(linear: f32) -> u8 {
    let c = f64::from(linear).clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as u8
}

fn close(a: u8, b: u8) -> bool {
    a.abs_diff(b) <= 1
}

fn out_dir() -> std::path::PathBuf {
    common::out_dir("gpu_core")
}

fn clear_and_read(ctx: &Context, samples: u32, clear: [f32; 4]) -> image::RgbaImage {
    let rt = RenderTarget::new(ctx, 37, 21, samples).expect("render target");
    ctx.submit_once(|dev, cmd| {
        rt.begin(dev, cmd, clear);
        rt.end(dev, cmd);
        Ok(())
    })
    .expect("submit");
    let img = rt.read_rgba(ctx).expect("readback");
    let path = out_dir().join(format!("clear_{samples}x.png"));
    rt.write_png(ctx, &path).expect("png");
    let back = image::open(&path).expect("reopen png").to_rgba8();
    assert_eq!(back, img, "PNG round trip changed pixels");
    img
}

#[test]
fn clear_colour_reads_back_as_srgb() {
    let Some(ctx) = context() else { return };
    // 0.002 lies in the linear segment of the sRGB curve, the others in the power segment.
    let clear = [0.002, 0.214, 0.8, 0.5];
    let want = [
        srgb_byte(clear[0]),
        srgb_byte(clear[1]),
        srgb_byte(clear[2]),
        (clear[3] * 255.0f32).round() as u8, // alpha is stored linearly
    ];
    let mut sample_counts = vec![1];
    if ctx.info().limits.supports_samples(4) {
        sample_counts.push(4);
    }
    for s in sample_counts {
        let img = clear_and_read(&ctx, s, clear);
        assert_eq!(img.dimensions(), (37, 21));
        for (x, y, p) in img.enumerate_pixels() {
            assert!(
                p.0.iter().zip(&want).all(|(a, b)| close(*a, *b)),
                "{s}x: pixel ({x},{y}) = {:?} expected {want:?}",
                p.0
            );
        }
    }
    assert_validation_clean(&ctx);
}

const STAGES: vk::ShaderStageFlags = vk::ShaderStageFlags::from_raw(
    vk::ShaderStageFlags::VERTEX.as_raw()
        | vk::ShaderStageFlags::TESSELLATION_CONTROL.as_raw()
        | vk::ShaderStageFlags::TESSELLATION_EVALUATION.as_raw()
        | vk::ShaderStageFlags::FRAGMENT.as_raw(),
);

fn quad_desc(fragment: &str, polygon_mode: vk::PolygonMode) -> GraphicsPipelineDesc {
    GraphicsPipelineDesc {
        label: "core test quad".into(),
        vertex: "core_test.vert".into(),
        tess_control: Some("core_test_quad.tesc".into()),
        tess_eval: Some("core_test_quad.tese".into()),
        fragment: fragment.into(),
        vertex_bindings: vec![VertexBinding {
            binding: 0,
            stride: 12,
            per_instance: false,
        }],
        vertex_attributes: vec![VertexAttribute {
            location: 0,
            binding: 0,
            format: vk::Format::R32G32B32_SFLOAT,
            offset: 0,
        }],
        topology: vk::PrimitiveTopology::PATCH_LIST,
        patch_control_points: 4,
        polygon_mode,
        set_layouts: vec![vec![DescriptorBinding {
            binding: 0,
            kind: DescriptorKind::StorageBuffer,
            stages: vk::ShaderStageFlags::TESSELLATION_EVALUATION,
        }]],
        push_constants: Some(PushConstants {
            stages: STAGES,
            size: 32,
        }),
        ..GraphicsPipelineDesc::default()
    }
}

/// Floats of a core test shader's capture record: (u, v, TES primitive id, TCS primitive id,
/// position, TCS mean of the inputs' x).
const RECORD_FLOATS: usize = 8;

/// A core test pipeline with its TES capture buffer bound as set 0, binding 0.
struct QuadPipeline {
    pipe: Pipeline,
    capture: CaptureBuffer,
    _pool: DescriptorPool,
    set: vk::DescriptorSet,
}

impl QuadPipeline {
    /// The pipeline of `desc` for `rt`, capturing up to `capacity` records.
    fn new(ctx: &Context, desc: &GraphicsPipelineDesc, rt: &RenderTarget, capacity: u32) -> Self {
        let pipe = ctx.graphics_pipeline(desc, rt).expect("pipeline");
        let capture = CaptureBuffer::new(ctx, capacity, RECORD_FLOATS, "tes capture");
        let pool = DescriptorPool::new(ctx, 1, 1, 0).expect("pool");
        let set = pool.allocate(pipe.set_layouts[0]).expect("set");
        ctx.write_buffer_descriptors(
            set,
            &[BufferBinding {
                binding: 0,
                kind: DescriptorKind::StorageBuffer,
                buffer: capture.buffer(),
            }],
        );
        QuadPipeline {
            pipe,
            capture,
            _pool: pool,
            set,
        }
    }

    /// Records binding the pipeline, the capture set and `vertices` into `cmd`.
    fn bind(&self, dev: &ash::Device, cmd: vk::CommandBuffer, vertices: &Buffer) {
        // SAFETY: `cmd` is recording inside a render pass of the target the pipeline was made
        // for; every handle lives until the submission completes.
        unsafe {
            dev.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipe.raw);
            dev.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::GRAPHICS,
                self.pipe.layout,
                0,
                &[self.set],
                &[],
            );
            dev.cmd_bind_vertex_buffers(cmd, 0, &[vertices.raw()], &[0]);
        }
    }

    /// Records the push constants: colour, tessellation level, first patch.
    fn push(
        &self,
        dev: &ash::Device,
        cmd: vk::CommandBuffer,
        colour: [f32; 4],
        level: f32,
        first: u32,
    ) {
        let push: [f32; 8] = [
            colour[0],
            colour[1],
            colour[2],
            colour[3],
            level,
            first as f32,
            0.0,
            0.0,
        ];
        // SAFETY: as in `bind`; the range matches the layout's push constants.
        unsafe { dev.cmd_push_constants(cmd, self.pipe.layout, STAGES, 0, as_bytes(&push)) };
    }

    /// The TES invocations counted and the records that fit.
    fn records(&self) -> (u32, Vec<[f32; RECORD_FLOATS]>) {
        let (count, words) = self.capture.read();
        let records = words
            .chunks(RECORD_FLOATS)
            .map(|r| std::array::from_fn(|i| f32::from_bits(r[i])))
            .collect();
        (count, records)
    }
}

struct QuadRun {
    image: image::RgbaImage,
    stats: PipelineStats,
    uvs: Vec<[f32; 2]>,
    written: u32,
    gpu_ms: f64,
}

/// Draws one bilinear quad patch covering clip space [-half, half]^2 at tessellation `level`
/// into a 64x64 target with `samples` samples per pixel.
fn draw_quad(
    ctx: &Context,
    desc: &GraphicsPipelineDesc,
    level: f32,
    colour: [f32; 4],
    samples: u32,
    half: f32,
) -> QuadRun {
    let size = 64;
    let rt = RenderTarget::new(ctx, size, size, samples).expect("render target");
    let quad = QuadPipeline::new(ctx, desc, &rt, 256);
    let again = ctx.graphics_pipeline(desc, &rt).expect("cached pipeline");
    assert_eq!(
        quad.pipe, again,
        "pipeline cache returned a different pipeline"
    );

    let corners: [[f32; 3]; 4] = [
        [-half, -half, 0.25],
        [half, -half, 0.25],
        [half, half, 0.25],
        [-half, half, 0.25],
    ];
    let vbuf = ctx
        .upload_buffer(
            &corners,
            vk::BufferUsageFlags::VERTEX_BUFFER,
            "quad vertices",
        )
        .expect("vertex buffer");
    let stats = StatsQuery::new(ctx).expect("stats query");
    let mut timer = GpuTimer::new(ctx, 1).expect("timer");
    ctx.submit_once(|dev, cmd| {
        stats.reset(cmd);
        timer.reset(cmd);
        let t = timer.begin(cmd, "quad")?;
        rt.begin(dev, cmd, [0.0, 0.0, 0.0, 1.0]);
        quad.bind(dev, cmd, &vbuf);
        quad.push(dev, cmd, colour, level, 0);
        stats.begin(cmd);
        // SAFETY: recording inside the render pass; all handles are valid for the submission.
        unsafe { dev.cmd_draw(cmd, 4, 1, 0, 0) };
        stats.end(cmd);
        rt.end(dev, cmd);
        timer.end(cmd, t)?;
        tessera::gpu::tes_writes_to_host(dev, cmd);
        Ok(())
    })
    .expect("draw");
    let (written, records) = quad.records();
    let uvs = records.iter().map(|c| [c[0], c[1]]).collect();
    let timings = timer.results().expect("timings");
    assert_eq!(timings.len(), 1);
    QuadRun {
        image: rt.read_rgba(ctx).expect("readback"),
        stats: stats.results().expect("stats"),
        uvs,
        written,
        gpu_ms: timings[0].1,
    }
}

#[test]
fn tessellated_quad_has_the_spec_domain_points() {
    let Some(ctx) = context() else { return };
    let level = 4u32;
    let colour = [0.2, 0.6, 1.0, 1.0];
    let run = draw_quad(
        &ctx,
        &quad_desc("core_test.frag", vk::PolygonMode::FILL),
        level as f32,
        colour,
        1,
        0.5,
    );

    // Quad domain, equal spacing, all levels n: the vertices are the (n+1)^2 grid points
    // (i/n, j/n) (Vulkan spec, "Quad Tessellation").
    let expected: BTreeSet<(u32, u32)> = (0..=level)
        .flat_map(|i| (0..=level).map(move |j| (i, j)))
        .collect();
    let got: BTreeSet<(u32, u32)> = run
        .uvs
        .iter()
        .map(|uv| {
            let (u, v) = (uv[0] * level as f32, uv[1] * level as f32);
            assert!(
                (u - u.round()).abs() < 1e-5 && (v - v.round()).abs() < 1e-5,
                "domain point {uv:?} is not on the 1/{level} grid"
            );
            (u.round() as u32, v.round() as u32)
        })
        .collect();
    assert_eq!(got, expected, "TES domain points");
    // The spec allows more than one TES invocation per vertex but never fewer.
    let unique = (level + 1) * (level + 1);
    assert!(run.written >= unique, "{} TES invocations", run.written);
    assert_eq!(run.stats.tes_invocations, u64::from(run.written));
    assert_eq!(run.stats.tcs_patches, 1);
    assert_eq!(run.stats.input_primitives, 1);
    // Any triangulation of a convex polygon's n points with b on the boundary has 2n - b - 2
    // triangles (Euler); here n = 25, b = 16 -> 32. All are inside the view volume.
    let (n, b) = (u64::from(unique), u64::from(4 * level));
    assert_eq!(run.stats.clipping_invocations, 2 * n - b - 2);
    assert!(run.gpu_ms > 0.0 && run.gpu_ms.is_finite(), "{}", run.gpu_ms);
    eprintln!(
        "level {level}: {:?}, {} TES writes, GPU {:.3} ms",
        run.stats, run.written, run.gpu_ms
    );

    // Pixels: quad covers pixels 16..48 of a 64x64 target; outside stays the clear colour.
    let inside = run.image.get_pixel(32, 20).0;
    let want = [
        srgb_byte(colour[0]),
        srgb_byte(colour[1]),
        srgb_byte(colour[2]),
        255,
    ];
    for c in 0..4 {
        assert!(
            close(inside[c], want[c]),
            "inside pixel {inside:?} want {want:?}"
        );
    }
    assert_eq!(run.image.get_pixel(2, 2).0, [0, 0, 0, 255]);
    assert_eq!(run.image.get_pixel(60, 33).0, [0, 0, 0, 255]);
    // Coverage: 32x32 pixel centres inside the quad.
    let covered = run.image.pixels().filter(|p| p.0 != [0, 0, 0, 255]).count();
    assert_eq!(covered, 32 * 32);
    run.image
        .save(out_dir().join("quad_level4.png"))
        .expect("save png");
    assert_validation_clean(&ctx);
}

#[test]
fn variant_and_wireframe_pipelines_draw_cleanly() {
    let Some(ctx) = context() else { return };
    let colour = [0.25, 0.5, 0.75, 1.0];
    let inv = draw_quad(
        &ctx,
        &quad_desc("core_test_invert.frag", vk::PolygonMode::FILL),
        3.0,
        colour,
        1,
        0.5,
    );
    let p = inv.image.get_pixel(32, 32).0;
    let want = [srgb_byte(0.75), srgb_byte(0.5), srgb_byte(0.25), 255];
    for c in 0..4 {
        assert!(
            close(p[c], want[c]),
            "inverted variant pixel {p:?} want {want:?}"
        );
    }
    if ctx.info().features.fill_mode_non_solid {
        let wire = draw_quad(
            &ctx,
            &quad_desc("core_test.frag", vk::PolygonMode::LINE),
            4.0,
            colour,
            1,
            0.5,
        );
        let lit = wire
            .image
            .pixels()
            .filter(|p| p.0 != [0, 0, 0, 255])
            .count();
        // Lines cover far fewer pixels than the filled 32x32 quad, but some.
        assert!(lit > 32 && lit < 32 * 32, "wireframe covered {lit} pixels");
        wire.image
            .save(out_dir().join("quad_wire.png"))
            .expect("save png");
    }
    assert_validation_clean(&ctx);
}

#[test]
fn limits_are_enforced_with_typed_errors() {
    let Some(ctx) = context() else { return };
    let lim = ctx.info().limits;
    assert!(lim.max_tessellation_patch_size >= 32, "spec minimum is 32");
    assert!(
        lim.max_tessellation_generation_level >= 64,
        "spec minimum is 64"
    );
    match RenderTarget::new(&ctx, 8, 8, 3) {
        Err(Error::Gpu(GpuError::Limit(m))) => assert!(m.contains('3'), "{m}"),
        other => panic!("3 samples must be rejected, got {other:?}"),
    }
    let rt = RenderTarget::new(&ctx, 8, 8, 1).expect("target");
    let mut desc = quad_desc("core_test.frag", vk::PolygonMode::FILL);
    desc.patch_control_points = lim.max_tessellation_patch_size + 1;
    match ctx.graphics_pipeline(&desc, &rt) {
        Err(Error::Gpu(GpuError::Limit(m))) => {
            assert!(m.contains("maxTessellationPatchSize"), "{m}")
        }
        other => panic!("oversized patch must be rejected, got {other:?}"),
    }
    desc.patch_control_points = 4;
    desc.fragment = "no_such_shader.frag".into();
    match ctx.graphics_pipeline(&desc, &rt) {
        Err(Error::Gpu(GpuError::UnknownShader { available, .. })) => {
            assert!(available.contains("core_test.frag"), "{available}")
        }
        other => panic!("unknown shader must be rejected, got {other:?}"),
    }
    assert_validation_clean(&ctx);
}

#[test]
fn unknown_device_name_lists_devices() {
    let desc = ContextDesc {
        validation: true,
        device: Some("no-such-device-zz9".into()),
        ..ContextDesc::default()
    };
    match Context::new(&desc) {
        Err(Error::Gpu(GpuError::DeviceNotFound { wanted, devices })) => {
            assert_eq!(wanted, "no-such-device-zz9");
            let msg = Error::Gpu(GpuError::DeviceNotFound {
                wanted: wanted.clone(),
                devices: devices.clone(),
            })
            .to_string();
            for d in &devices {
                assert!(msg.contains(&d.name), "{msg}");
            }
            if !no_gpu_allowed() {
                assert!(!devices.is_empty(), "no Vulkan device at all");
                assert!(devices.iter().any(|d| d.missing.is_empty()), "{msg}");
            }
        }
        Err(Error::Gpu(GpuError::Loader(m))) if no_gpu_allowed() => eprintln!("skipping: {m}"),
        other => panic!("expected DeviceNotFound, got {other:?}"),
    }
}

#[test]
fn missing_feature_error_names_the_feature() {
    // Asks the selected device for every optional feature: the error must name exactly the
    // absent ones (lavapipe has all, so there `require` must succeed; the failing path on
    // synthetic device lists is unit-tested in src/gpu/device.rs).
    let Some(ctx) = context() else { return };
    let all = [
        Feature::TessellationShader,
        Feature::FillModeNonSolid,
        Feature::PipelineStatisticsQuery,
        Feature::VertexPipelineStoresAndAtomics,
        Feature::Timestamps,
        Feature::ShaderFloat64,
    ];
    let absent: Vec<&str> = all
        .iter()
        .filter(|f| !ctx.info().features.has(**f))
        .map(|f| f.name())
        .collect();
    match ctx.require(&all) {
        Ok(()) => assert!(absent.is_empty()),
        Err(Error::Gpu(GpuError::MissingFeatures { missing, name, .. })) => {
            assert_eq!(name, ctx.info().name);
            assert_eq!(missing, absent);
        }
        Err(e) => panic!("unexpected error {e}"),
    }
    assert_validation_clean(&ctx);
}

#[test]
fn buffers_round_trip_through_staging() {
    let Some(ctx) = context() else { return };
    let data: Vec<f32> = (0..1000).map(|i| i as f32 * 0.5 - 7.0).collect();
    let buf = ctx
        .upload_buffer(
            &data,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC,
            "round trip",
        )
        .expect("upload");
    assert!(!buf.is_host_visible() || buf.location() == MemoryLocation::GpuOnly);
    let back: Vec<f32> = ctx.read_buffer(&buf).expect("readback");
    assert_eq!(back, data);
    assert!(Buffer::new(
        &ctx,
        0,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::GpuOnly,
        "empty"
    )
    .is_err());
    assert_validation_clean(&ctx);
}

#[test]
fn messenger_counts_validation_errors() {
    let Some(ctx) = context() else { return };
    assert_eq!(ctx.validation_errors(), 0);
    // A buffer with no usage bits violates VUID-VkBufferCreateInfo-usage-requiredbitmask.
    let ci = vk::BufferCreateInfo::default()
        .size(16)
        .usage(vk::BufferUsageFlags::empty())
        .sharing_mode(vk::SharingMode::EXCLUSIVE);
    // SAFETY: deliberately invalid create info; the object (if any) is destroyed at once.
    unsafe {
        if let Ok(b) = ctx.device().create_buffer(&ci, None) {
            ctx.device().destroy_buffer(b, None);
        }
    }
    assert!(
        ctx.validation_errors() >= 1,
        "the messenger missed an invalid call"
    );
    let msgs = ctx.validation_messages();
    assert!(
        msgs.iter()
            .any(|m| m.starts_with("ERROR") && m.contains("usage")),
        "{msgs:?}"
    );
}

#[test]
fn handles_are_send_and_sync() {
    fn check<T: Send + Sync>() {}
    check::<Context>();
    check::<Buffer>();
    check::<Image>();
    check::<RenderTarget>();
    check::<DescriptorPool>();
    check::<GpuTimer>();
    check::<StatsQuery>();
}

#[test]
fn readback_before_rendering_is_an_error() {
    let Some(ctx) = context() else { return };
    let rt = RenderTarget::new(&ctx, 4, 4, 1).expect("target");
    assert!(matches!(
        rt.read_rgba(&ctx),
        Err(Error::Gpu(GpuError::Invalid(_)))
    ));
    assert_validation_clean(&ctx);
}

#[test]
fn synchronization_validation_reports_hazards() {
    let Some(ctx) = context() else { return };
    let buf = Buffer::new(
        &ctx,
        256,
        vk::BufferUsageFlags::TRANSFER_DST | vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::GpuOnly,
        "hazard",
    )
    .expect("buffer");
    // Two transfer writes to the same range without a barrier: a write-after-write hazard.
    ctx.submit_once(|dev, cmd| {
        // SAFETY: valid buffer; the missing barrier is deliberate.
        unsafe {
            dev.cmd_fill_buffer(cmd, buf.raw(), 0, 256, 1);
            dev.cmd_fill_buffer(cmd, buf.raw(), 0, 256, 2);
        }
        Ok(())
    })
    .expect("submit");
    let msgs = ctx.validation_messages();
    assert!(
        msgs.iter()
            .any(|m| m.contains("SYNC-HAZARD-WRITE-AFTER-WRITE")),
        "sync validation missed the hazard: {msgs:?}"
    );
}

#[test]
fn long_work_times_out_with_an_error_instead_of_hanging() {
    let Some(ctx) = context_with(ContextDesc {
        timeout_ms: 1,
        ..ContextDesc::default()
    }) else {
        return;
    };
    let rt = RenderTarget::new(&ctx, 64, 64, 1).expect("target");
    // Capacity 0: the capture only counts.
    let quad = QuadPipeline::new(
        &ctx,
        &quad_desc("core_test.frag", vk::PolygonMode::FILL),
        &rt,
        0,
    );
    let corners: [[f32; 3]; 4] = [
        [-1.0, -1.0, 0.5],
        [1.0, -1.0, 0.5],
        [1.0, 1.0, 0.5],
        [-1.0, 1.0, 0.5],
    ];
    let vbuf = Buffer::from_slice(&ctx, &corners, vk::BufferUsageFlags::VERTEX_BUFFER, "quad")
        .expect("vertices");
    let level = ctx.info().limits.max_tessellation_generation_level as f32;
    let instances = 400u32;
    let result = ctx.submit_once(|dev, cmd| {
        rt.begin(dev, cmd, [0.0; 4]);
        quad.bind(dev, cmd, &vbuf);
        quad.push(dev, cmd, [1.0; 4], level, 0);
        // SAFETY: valid handles; the work is deliberately heavy.
        unsafe { dev.cmd_draw(cmd, 4, instances, 0, 0) };
        rt.end(dev, cmd);
        Ok(())
    });
    match result {
        Err(Error::Gpu(GpuError::Timeout(1))) => {}
        other => panic!("expected a 1 ms timeout, got {other:?}"),
    }
    ctx.wait_idle().expect("wait idle");
    // The work completed after the timeout: (level+1)^2 domain points per instance at least.
    let (count, _) = quad.records();
    let per = (level as u32 + 1) * (level as u32 + 1);
    assert!(count >= per * instances, "{} < {}", count, per * instances);
    // The next submission reclaims the timed-out command buffer and works normally.
    ctx.submit_once(|_, _| Ok(())).expect("empty submit");
    assert_validation_clean(&ctx);
}

#[test]
fn msaa_resolves_partial_coverage() {
    let Some(ctx) = context() else { return };
    if !ctx.info().limits.supports_samples(4) {
        eprintln!("device has no 4x MSAA; only the single-sample path is checked");
    }
    let white = [1.0, 1.0, 1.0, 1.0];
    let desc = quad_desc("core_test.frag", vk::PolygonMode::FILL);
    // Edges at clip +-0.51: x = 15.68 and 48.32 pixels, so columns 15 and 48 are partly covered
    // but their centres (15.5, 48.5) are outside the quad.
    let single = draw_quad(&ctx, &desc, 2.0, white, 1, 0.51);
    for y in 20..44 {
        assert_eq!(single.image.get_pixel(15, y).0, [0, 0, 0, 255]);
        assert_eq!(single.image.get_pixel(48, y).0, [0, 0, 0, 255]);
        assert_eq!(single.image.get_pixel(16, y).0, [255, 255, 255, 255]);
    }
    if ctx.info().limits.supports_samples(4) {
        let multi = draw_quad(&ctx, &desc, 2.0, white, 4, 0.51);
        let partial = |x: u32| {
            (20..44)
                .filter(|y| {
                    let v = multi.image.get_pixel(x, *y).0[0];
                    v > 0 && v < 255
                })
                .count()
        };
        // The resolve averages covered and uncovered samples on both partly covered columns.
        assert!(
            partial(15) > 0 && partial(48) > 0,
            "no partial coverage resolved"
        );
        assert_eq!(multi.image.get_pixel(32, 32).0, [255, 255, 255, 255]);
        assert_eq!(multi.image.get_pixel(2, 2).0, [0, 0, 0, 255]);
        assert_eq!(multi.stats.tcs_patches, 1);
        multi
            .image
            .save(out_dir().join("quad_msaa4.png"))
            .expect("save png");
    }
    assert_validation_clean(&ctx);
}

#[test]
fn device_info_is_reported() {
    let Some(ctx) = context() else { return };
    let line = ctx.info().to_string();
    eprintln!("{line}");
    assert!(line.contains(&ctx.info().name));
    let lim = ctx.info().limits;
    assert!(
        lim.max_tess_control_per_vertex_output_components >= 64,
        "spec minimum"
    );
    assert!(
        lim.max_tess_control_per_patch_output_components >= 120,
        "spec minimum"
    );
    assert!(
        lim.max_tess_evaluation_input_components >= 64,
        "spec minimum"
    );
    assert!(lim.supports_samples(1));
    if ctx.info().features.timestamps {
        assert!(lim.timestamp_period_ns > 0.0 && lim.timestamp_valid_bits >= 36);
    }
    assert_validation_clean(&ctx);
}

/// Child half of `no_driver_gives_a_typed_error`: runs only in the re-executed test binary.
#[test]
fn no_driver_child() {
    if std::env::var("TESSERA_D1_NO_DRIVER_CHILD").is_err() {
        return;
    }
    match Context::new(&ContextDesc {
        validation: false,
        ..ContextDesc::default()
    }) {
        Err(Error::Gpu(GpuError::NoSuitableDevice { devices })) => {
            assert!(devices.is_empty(), "{devices:?}");
            let msg = GpuError::NoSuitableDevice { devices }.to_string();
            assert!(msg.contains("mesa-vulkan-drivers"), "{msg}");
            println!("CHILD-OK: {msg}");
        }
        Err(Error::Gpu(GpuError::Loader(m))) => println!("CHILD-OK (no loader): {m}"),
        other => panic!("expected NoSuitableDevice without drivers, got {other:?}"),
    }
}

#[test]
fn no_driver_gives_a_typed_error() {
    // The loader reads VK_ICD_FILENAMES / VK_DRIVER_FILES at instance creation; a child process
    // keeps the other tests unaffected.
    let out = std::process::Command::new(std::env::current_exe().expect("test binary"))
        .args([
            "--exact",
            "no_driver_child",
            "--nocapture",
            "--test-threads",
            "1",
        ])
        .env("TESSERA_D1_NO_DRIVER_CHILD", "1")
        .env("VK_ICD_FILENAMES", "/nonexistent/tessera-no-driver.json")
        .env("VK_DRIVER_FILES", "/nonexistent/tessera-no-driver.json")
        .output()
        .expect("run child");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success() && stdout.contains("CHILD-OK"),
        "child failed:\n{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Corners of patch `k` of the many-patch test: a 0.1-wide square on a 16-column grid.
fn patch_corners(k: u32) -> [[f32; 3]; 4] {
    let x0 = -1.0 + 0.125 * (k % 16) as f32;
    let y0 = -1.0 + 0.125 * (k / 16) as f32;
    let d = 0.1 + 0.001 * (k % 7) as f32;
    [
        [x0, y0, 0.5],
        [x0 + d, y0, 0.5],
        [x0 + d, y0 + d, 0.5],
        [x0, y0 + d, 0.5],
    ]
}

/// Control points of patch `k` with `points` = 4 (corners), or >= 16: a 4x4 row-major grid
/// followed by `points - 16` extra points (repeating the grid from its start).
fn patch_points(k: u32, points: u32) -> Vec<[f32; 3]> {
    let c = patch_corners(k);
    if points == 4 {
        return c.to_vec();
    }
    let d = c[1][0] - c[0][0];
    (0..points)
        .map(|i| {
            let g = i % 16;
            let (x, y) = ((g % 4) as f32 / 3.0, (g / 4) as f32 / 3.0);
            [c[0][0] + d * x, c[0][1] + d * y, 0.5]
        })
        .collect()
}

/// What the many-patch draw captured.
struct ManyReport {
    /// TES positions not on their own patch: (patch, u, v, error).
    wrong_position: Vec<(u32, f32, f32, f32)>,
    /// Records whose TES gl_PrimitiveID differs from the TCS's: (tes, tcs).
    tcs_id_mismatch: Vec<(u32, u32)>,
    /// Records whose TCS mean-of-inputs is not its patch's: (patch, got, want).
    tcs_mean_mismatch: Vec<(u32, f32, f32)>,
    /// Distinct (patch, u, v) domain points.
    distinct: usize,
}

/// Draws `patches` patches of `points` control points each, in one draw call or (`chunked`) in
/// draws of `max_patches_per_draw` patches, and checks every TES record against its own patch.
fn many_patches(
    ctx: &Context,
    patches: u32,
    points: u32,
    indexed: bool,
    chunked: bool,
) -> ManyReport {
    let level = 2u32;
    let rt = RenderTarget::new(ctx, 64, 64, 1).expect("target");
    let mut desc = quad_desc("core_test.frag", vk::PolygonMode::FILL);
    if points >= 16 {
        desc.tess_control = Some(format!("core_test_quad{points}.tesc"));
        desc.tess_eval = Some("core_test_quad16.tese".into());
        desc.patch_control_points = points;
    }
    let quad = QuadPipeline::new(ctx, &desc, &rt, patches * (level + 1) * (level + 1) * 2);
    let verts: Vec<[f32; 3]> = (0..patches).flat_map(|k| patch_points(k, points)).collect();
    let vbuf = ctx
        .upload_buffer(&verts, vk::BufferUsageFlags::VERTEX_BUFFER, "patches")
        .expect("vertices");
    let indices: Vec<u32> = (0..points * patches).collect();
    let ibuf = ctx
        .upload_buffer(
            &indices,
            vk::BufferUsageFlags::INDEX_BUFFER,
            "patch indices",
        )
        .expect("indices");
    let draws: Vec<(u32, u32)> = if chunked {
        patch_draw_chunks(patches, points, indexed).collect()
    } else {
        vec![(0, patches)]
    };
    ctx.submit_once(|dev, cmd| {
        rt.begin(dev, cmd, [0.0, 0.0, 0.0, 1.0]);
        quad.bind(dev, cmd, &vbuf);
        // SAFETY: valid handles, recording inside the render pass.
        unsafe { dev.cmd_bind_index_buffer(cmd, ibuf.raw(), 0, vk::IndexType::UINT32) };
        for &(first, count) in &draws {
            quad.push(dev, cmd, [1.0; 4], level as f32, first);
            // SAFETY: as above; the draw stays within the uploaded vertices and indices.
            unsafe {
                if indexed {
                    dev.cmd_draw_indexed(cmd, points * count, 1, points * first, 0, 0);
                } else {
                    dev.cmd_draw(cmd, points * count, 1, points * first, 0);
                }
            }
        }
        rt.end(dev, cmd);
        tessera::gpu::tes_writes_to_host(dev, cmd);
        Ok(())
    })
    .expect("draw");
    let (_, records) = quad.records();
    let n = records.len();
    assert!(
        n >= (patches * (level + 1) * (level + 1)) as usize,
        "{n} records"
    );
    let mut wrong = Vec::new();
    let mut seen = BTreeSet::new();
    let mut tcs_mismatch = Vec::new();
    let mut mean_mismatch = Vec::new();
    for r in &records {
        let (u, v, prim) = (r[0], r[1], r[2] as u32);
        assert!(prim < patches, "gl_PrimitiveID {prim}");
        if r[3] != r[2] {
            tcs_mismatch.push((prim, r[3] as u32));
        }
        let pts = patch_points(prim, points);
        let mean_x = pts.iter().map(|p| p[0]).sum::<f32>() / pts.len() as f32;
        if (r[7] - mean_x).abs() > 1e-5 {
            mean_mismatch.push((prim, r[7], mean_x));
        }
        let c = patch_corners(prim);
        // Bilinear interpolation of the patch's own corners (same formula as the TES).
        let want: Vec<f32> = (0..3)
            .map(|i| {
                let a = c[0][i] + (c[1][i] - c[0][i]) * u;
                let b = c[3][i] + (c[2][i] - c[3][i]) * u;
                a + (b - a) * v
            })
            .collect();
        let err = (0..3)
            .map(|i| (r[4 + i] - want[i]).abs())
            .fold(0.0f32, f32::max);
        if err > 1e-5 {
            wrong.push((prim, u, v, err));
        }
        seen.insert((
            prim,
            (u * level as f32).round() as u32,
            (v * level as f32).round() as u32,
        ));
    }
    ManyReport {
        wrong_position: wrong,
        tcs_id_mismatch: tcs_mismatch,
        tcs_mean_mismatch: mean_mismatch,
        distinct: seen.len(),
    }
}

fn check_many(patches: u32, points: u32, indexed: bool, chunked: bool) {
    let Some(ctx) = context() else { return };
    let r = many_patches(&ctx, patches, points, indexed, chunked);
    let bad: BTreeSet<u32> = r
        .wrong_position
        .iter()
        .map(|w| w.0)
        .chain(r.tcs_mean_mismatch.iter().map(|w| w.0))
        .chain(r.tcs_id_mismatch.iter().map(|w| w.0))
        .collect();
    assert!(
        r.wrong_position.is_empty() && r.tcs_id_mismatch.is_empty() && r.tcs_mean_mismatch.is_empty(),
        "{patches} {points}-point patches (indexed {indexed}, chunked {chunked}): {} wrong positions (first {:?}), {} TCS/TES \
         primitive-id mismatches (first {:?}), {} wrong TCS input means (first {:?}); {} patches \
         affected, first {:?}",
        r.wrong_position.len(),
        r.wrong_position.first(),
        r.tcs_id_mismatch.len(),
        r.tcs_id_mismatch.first(),
        r.tcs_mean_mismatch.len(),
        r.tcs_mean_mismatch.first(),
        bad.len(),
        bad.iter().take(10).collect::<Vec<_>>()
    );
    assert_eq!(
        r.distinct,
        (patches * 9) as usize,
        "distinct domain points (level 2)"
    );
    assert_validation_clean(&ctx);
}

#[test]
fn many_patches_keep_their_own_control_points() {
    // 200 four-point patches: 800 vertices, within both draw-size rules (src/gpu/draw.rs).
    check_many(200, 4, false, false);
    check_many(200, 4, true, false);
}

#[test]
fn chunked_patch_draws_are_correct() {
    // Large patch lists split with `patch_draw_chunks` evaluate every patch from its own
    // control points (one draw of this size is wrong on Mesa 22.3 lavapipe; see draw.rs).
    for points in [4, 16, 20] {
        for indexed in [false, true] {
            check_many(1100, points, indexed, true);
        }
    }
}
