//! `tessera bench`: GPU time per frame of the tessellation pipeline at several levels: each
//! pass's compute pre-pass (the adaptive scheme's refinement and derived points), the patch
//! draws, the CPU-evaluated triangles; and the surface's GPU buffer memory.

use clap::Args;
use tessera::render::bench::median;
use tessera::render::static_draw::StaticDraw;
use tessera::render::{
    CameraSpec, MemoryReport, OffscreenDesc, OffscreenSession, RenderDesc, Scheme, TessSettings,
    CPU_PATH_LABEL,
};
use tessera::{Error, Result};

use super::render::{
    check_validation, clamp_level, context, load, max_patch_level, parse_size, report_fallback,
    surface_for, AdaptiveArgs,
};

/// Arguments of `tessera bench`.
#[derive(Args)]
pub struct BenchArgs {
    /// Control mesh: an OBJ file or `embedded:NAME`; default: the embedded default mesh.
    pub mesh: Option<String>,
    /// Comma-separated uniform tessellation levels.
    #[arg(long, default_value = "2,4,8,16,32,64")]
    pub tess: String,
    /// Timed frames per level (after one warm-up frame).
    #[arg(long, default_value_t = 10)]
    pub frames: u32,
    /// Uniform levels above this draw each patch as sub-patches; 0 disables (see `render`).
    #[arg(long, default_value_t = 16.0)]
    pub max_patch_level: f32,
    /// GPU scheme for non-regular faces (see `tessera render --help`).
    #[arg(long, value_enum, default_value_t = Scheme::default())]
    pub scheme: Scheme,
    /// `--isolation`, `--single-crease` (the adaptive scheme's planning).
    #[command(flatten)]
    pub adaptive: AdaptiveArgs,
    /// Animate: before every timed frame, twist the control positions (as `render --animate`)
    /// and hand them to the renderer (`update_positions`: vertex limit frames and CPU-path faces
    /// recomputed on the CPU, every GPU patch rebuilt on the GPU); adds the CPU milliseconds of
    /// that update as a column.
    #[arg(long)]
    pub animate: bool,
    /// Instead of whole frames: the Gregory faces alone with both GPU variants, on the exact CPU
    /// path, and the regular pass alone, each timed in frames of its own (paper Table 1).
    #[arg(long)]
    pub variants: bool,
    /// The paper's Fig. 2 (Nießner, Loop, Greiner 2012): set every crease tag of sharpness > 0 to
    /// each of these comma-separated values in turn and time `--scheme adaptive` at the first
    /// `--tess` level with and without single-crease patches; prints frame ms and the GPU memory
    /// of the patch data per configuration.
    #[arg(long, value_name = "S1,S2,...")]
    pub crease_sharpness: Option<String>,
    /// With --crease-sharpness: write the sweep as a PNG plot (frame ms and patch-data MB over
    /// the sharpness; teal with single-crease patches, orange without).
    #[arg(long, requires = "crease_sharpness")]
    pub plot: Option<std::path::PathBuf>,
    /// Also time the static draw of the same triangles at each level (`render::static_draw`):
    /// the triangles one frame drew (captured by a pass-through geometry stage, with the
    /// CPU-path triangles), drawn from a static vertex + index buffer by the plain
    /// vertex/fragment pipeline, same camera, target, frames and median; adds the triangles of
    /// the tessellated frame (clipping-stage primitives), the static triangles, the static ms
    /// and the ratio frame / static. Needs `geometryShader`.
    #[arg(long = "static")]
    pub static_draw: bool,
    /// Also time each draw group of the patch passes alone at each level (a frame of its own
    /// per group, `OffscreenSession::group_frame`; e.g. the adaptive scheme's B-spline,
    /// transition, single-crease and end-cap draws): one line per group with its median GPU ms
    /// (with the frame's compute pre-pass), patches, TES invocations and triangles.
    #[arg(long)]
    pub per_draw: bool,
    /// Image size WxH.
    #[arg(long, default_value = "800x600")]
    pub size: String,
    /// `auto` (frame the bounding box) or `az,el,dist` (degrees, degrees, model units).
    #[arg(long, default_value = "auto")]
    pub camera: String,
    /// `--cull`, `--no-cull` (frustum culling of patches; see `render`).
    #[command(flatten)]
    pub cull: super::render::CullArgs,
    /// Enable the Khronos validation layer (always on in debug builds).
    #[arg(long)]
    pub validation: bool,
    /// The file's faces are wound clockwise.
    #[arg(long)]
    pub left_handed: bool,
    /// Input size limits.
    #[command(flatten)]
    pub limits: super::limits::InputLimits,
}

/// Runs the subcommand.
pub fn run(args: BenchArgs) -> Result<()> {
    let (width, height) = parse_size(&args.size)?;
    let camera = CameraSpec::parse(&args.camera)?;
    if args.frames == 0 {
        return Err(Error::Invalid("--frames must be at least 1".into()));
    }
    let levels: Vec<f32> = args
        .tess
        .split(',')
        .map(|t| {
            t.trim()
                .parse::<f32>()
                .map_err(|_| Error::Invalid(format!("--tess: `{t}` is not a number")))
        })
        .collect::<Result<_>>()?;
    let mesh = load(args.mesh.as_deref(), args.left_handed)?;
    super::limits::check_mesh(&mesh, &args.limits)?;
    super::limits::check_gpu_range(&mesh)?;
    let ctx = context(args.validation)?;
    println!("device: {}", ctx.info().name);
    if let Some(list) = &args.crease_sharpness {
        let sharpness: Vec<f32> = list
            .split(',')
            .map(|t| {
                t.trim().parse::<f32>().map_err(|_| {
                    Error::Invalid(format!("--crease-sharpness: `{t}` is not a number"))
                })
            })
            .collect::<Result<_>>()?;
        let sweep = super::bench_creases::Sweep {
            sharpness: &sharpness,
            level: clamp_level(&ctx, levels[0])?,
            isolation: args.adaptive.isolation,
            frames: args.frames,
            size: (width, height),
        };
        let rows = super::bench_creases::run(&ctx, &mesh, &sweep)?;
        if let Some(path) = &args.plot {
            super::bench_creases::plot(&rows, path)?;
        }
        return check_validation(&ctx);
    }
    if args.variants {
        let levels: Vec<f32> = levels
            .iter()
            .map(|&l| clamp_level(&ctx, l))
            .collect::<Result<_>>()?;
        let max = max_patch_level(args.max_patch_level);
        let size = (width, height);
        super::bench_gregory::run_variants(&ctx, &mesh, &levels, args.frames, size, max)?;
        return check_validation(&ctx);
    }
    println!(
        "{:>6} {:>9} {:>12} {:>14} {:>14} {:>14} {:>14}{}{}",
        "level",
        "patches",
        "TES invoc.",
        "compute ms",
        "patch ms (med)",
        "cpu-tri ms",
        "frame ms (med)",
        if args.animate {
            format!(" {:>15}", "update ms (cpu)")
        } else {
            String::new()
        },
        if args.static_draw {
            format!(
                " {:>10} {:>11} {:>15} {:>14}",
                "frame tris", "static tris", "static ms (med)", "frame / static"
            )
        } else {
            String::new()
        }
    );
    let mut moving = mesh.clone();
    let rest = mesh.positions().to_vec();
    for &req in &levels {
        let level = clamp_level(&ctx, req)?;
        let surface = surface_for(&ctx, &mesh, level, args.scheme, &args.adaptive)?;
        if req == levels[0] {
            report_fallback(&surface);
        }
        let render = RenderDesc {
            tess: TessSettings {
                level,
                max_patch_level: max_patch_level(args.max_patch_level),
                ..TessSettings::default()
            },
            cull_patches: args.cull.enabled(),
            ..RenderDesc::default()
        };
        let desc = OffscreenDesc {
            width,
            height,
            camera,
            ..OffscreenDesc::default()
        };
        let mut session = OffscreenSession::new(&ctx, &surface, &render, &desc, true)?;
        if req == levels[0] {
            print_memory(&session.renderer().memory_bytes());
        }
        session.frame()?;
        let (mut compute, mut patch, mut cpu, mut total) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let mut tes = 0;
        let mut triangles = 0;
        let mut update = Vec::new();
        for k in 0..args.frames {
            if args.animate {
                let t0 = std::time::Instant::now();
                let moved = tessera::render::animate::twist(
                    &rest,
                    desc.up.vector(),
                    1.5,
                    f64::from(k) / f64::from(args.frames),
                );
                moving.set_positions(&moved)?;
                let fallback = if surface.fallback_faces.is_empty() {
                    None
                } else {
                    Some(tessera::render::cpu_faces(
                        &moving,
                        &surface.fallback_faces,
                        level.ceil() as u32,
                    )?)
                };
                session
                    .renderer_mut()
                    .update_positions(&moved, fallback.as_ref())?;
                update.push(t0.elapsed().as_secs_f64() * 1e3);
            }
            let r = session
                .frame()?
                .ok_or_else(|| Error::Invalid("bench: no timings returned".into()))?;
            let k = r.compute_ms();
            let p = r.patch_ms();
            let c = r.ms(CPU_PATH_LABEL);
            compute.push(k);
            patch.push(p);
            cpu.push(c);
            total.push(k + p + c);
            tes = r.patch_stats.tes_invocations;
            triangles =
                r.patch_stats.clipping_invocations as usize + surface.fallback.indices.len() / 3;
        }
        let frame_ms = median(&mut total);
        let groups = if args.per_draw {
            draw_group_lines(&mut session, args.frames)?
        } else {
            Vec::new()
        };
        let static_columns = if args.static_draw {
            drop(session);
            let fixed = StaticDraw::capture(&ctx, &surface, &render, &desc)?;
            let ms = fixed.time(&ctx, &desc, args.frames)?;
            format!(
                " {:>10} {:>11} {:>15.3} {:>14.2}",
                triangles,
                fixed.triangles(),
                ms,
                frame_ms / ms
            )
        } else {
            String::new()
        };
        println!(
            "{:>6} {:>9} {:>12} {:>14.3} {:>14.3} {:>14.3} {:>14.3}{}{}",
            level,
            surface.patch_count(),
            tes,
            median(&mut compute),
            median(&mut patch),
            median(&mut cpu),
            frame_ms,
            if args.animate {
                format!(" {:>15.3}", median(&mut update))
            } else {
                String::new()
            },
            static_columns
        );
        for line in groups {
            println!("{line}");
        }
    }
    check_validation(&ctx)
}

/// One line per draw group of `session`'s patch passes: median GPU ms of `frames` frames of
/// the group alone (after a warm-up frame), its patches, TES invocations and triangles.
fn draw_group_lines(session: &mut OffscreenSession, frames: u32) -> Result<Vec<String>> {
    let mut lines = Vec::new();
    for (pass, group, label) in session.draw_groups() {
        session.group_frame(pass, group)?;
        let mut ms = Vec::new();
        let mut stats = tessera::gpu::PipelineStats::default();
        for _ in 0..frames {
            let r = session
                .group_frame(pass, group)?
                .ok_or_else(|| Error::Invalid("bench: no timings returned".into()))?;
            ms.push(r.compute_ms() + r.patch_ms());
            stats = r.patch_stats;
        }
        lines.push(format!(
            "  draw {label}: {:.3} ms (med), {} TCS patches, {} TES invocations, {} triangles",
            median(&mut ms),
            stats.tcs_patches,
            stats.tes_invocations,
            stats.clipping_invocations
        ));
    }
    Ok(lines)
}

/// Prints the GPU buffer memory of a renderer, one line.
fn print_memory(m: &MemoryReport) {
    let kb = |b: u64| b as f64 / 1024.0;
    let passes: Vec<String> = m
        .passes
        .iter()
        .map(|(l, b)| format!("{l} {:.1}", kb(*b)))
        .collect();
    println!(
        "GPU memory KiB: total {:.1} = shared {:.1} + passes {:.1} ({}) + cpu-path {:.1}",
        kb(m.total()),
        kb(m.shared),
        kb(m.passes_total()),
        passes.join(", "),
        kb(m.cpu_path)
    );
}
