//! `tessera compare`: every scheme on one mesh in one table (Markdown, or CSV) and one contact
//! sheet of error maps on a shared colour scale ([`tessera::render::compare`]).

use clap::Args;
use image::RgbaImage;
use tessera::render::compare::{
    compare_scheme, error_map, exact_reference, CompareDesc, SchemeComparison,
};
use tessera::render::{render_to_image, ColorBy, OffscreenDesc, RenderDesc, Scheme, UpAxis};
use tessera::subdiv::eval::GridSample;
use tessera::{Error, Result};

use super::render::{
    check_validation, clamp_level, context, load, parse_size, plan_options, AdaptiveArgs,
};

/// Arguments of `tessera compare`.
#[derive(Args)]
pub struct CompareArgs {
    /// Control mesh: an OBJ file or `embedded:NAME`; default: the embedded default mesh.
    pub mesh: Option<String>,
    /// Uniform tessellation level of the measured capture and of the timed frames.
    #[arg(long, default_value_t = 8.0)]
    pub tess: f32,
    /// Comma-separated schemes to run (default: every scheme).
    #[arg(long, value_delimiter = ',', value_enum)]
    pub schemes: Vec<Scheme>,
    /// Timed frames per scheme (after one warm-up frame); the table has the median.
    #[arg(long, default_value_t = 5)]
    pub frames: u32,
    /// `--isolation`, `--single-crease` (the adaptive scheme's planning).
    #[command(flatten)]
    pub adaptive: AdaptiveArgs,
    /// Print CSV instead of a Markdown table.
    #[arg(long)]
    pub csv: bool,
    /// Write a contact sheet of error maps (PNG or JPEG): one panel per scheme (its name in the
    /// top-left corner), in table order, left to right then top to bottom, the exact limit
    /// coloured by the scheme's distance from blue (exact) to red (`--scale` or more).
    #[arg(long)]
    pub sheet: Option<std::path::PathBuf>,
    /// Distance shown as full red in every panel, as a fraction of the bbox diagonal (default:
    /// the 99th percentile of every scheme's measured distances together, so that one outlier
    /// does not turn every panel blue).
    #[arg(long)]
    pub scale: Option<f64>,
    /// Size WxH of the timed frames and of each contact-sheet panel.
    #[arg(long, default_value = "400x300")]
    pub size: String,
    /// World axis pointing up on screen in the contact sheet: `z` or `y`.
    #[arg(long, default_value = "z")]
    pub up: String,
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

/// A scheme's result: measured, or why it could not draw the mesh.
type Outcome = (Scheme, Result<SchemeComparison>);

/// Runs the subcommand.
pub fn run(args: CompareArgs) -> Result<()> {
    let (width, height) = parse_size(&args.size)?;
    if let Some(path) = &args.sheet {
        super::image_out::check_out(path)?;
    }
    if let Some(s) = args.scale {
        if !(s.is_finite() && s > 0.0) {
            return Err(Error::Invalid(format!(
                "--scale {s}: must be a positive fraction of the bbox diagonal"
            )));
        }
    }
    let up = UpAxis::parse(&args.up)?;
    let mesh = load(args.mesh.as_deref(), args.left_handed)?;
    super::limits::check_mesh(&mesh, &args.limits)?;
    super::limits::check_gpu_range(&mesh)?;
    let ctx = context(args.validation)?;
    let desc = CompareDesc {
        tess: clamp_level(&ctx, args.tess)?,
        frames: args.frames,
        width,
        height,
        plan: plan_options(&ctx, &args.adaptive),
    };
    let schemes = if args.schemes.is_empty() {
        Scheme::ALL.to_vec()
    } else {
        args.schemes.clone()
    };
    let exact = exact_reference(&mesh, &desc)?;
    let outcomes: Vec<Outcome> = schemes
        .iter()
        .map(|&s| {
            log::info!("compare: {s}");
            (s, compare_scheme(&ctx, &mesh, &exact, s, &desc))
        })
        .collect();
    let diagonal = mesh.bbox_diagonal();
    if args.csv {
        print!("{}", csv(&outcomes, diagonal));
    } else {
        println!(
            "mesh {} (bbox diagonal {diagonal:.4e}), tess {}, device {}",
            args.mesh.as_deref().unwrap_or("(embedded default)"),
            desc.tess,
            ctx.info().name
        );
        println!();
        print!("{}", markdown(&outcomes));
    }
    if let Some(path) = &args.sheet {
        let scale = args
            .scale
            .map(|s| s * diagonal)
            .unwrap_or_else(|| percentile_distance(&outcomes, 0.99));
        let grid = desc.tess.round().max(2.0) as usize;
        let map = MapGrid {
            grid,
            exact: exact.ev.eval_all_grids(grid)?,
        };
        let panels = outcomes
            .iter()
            .filter_map(|(_, r)| r.as_ref().ok())
            .map(|c| {
                let mut img = panel(&ctx, &mesh, &map, c, &desc, scale, up)?;
                let white = image::Rgba([235, 235, 235, 255]);
                super::glyphs::draw_text(&mut img, 8, 8, c.row.scheme.name(), 2, white);
                Ok(img)
            })
            .collect::<Result<Vec<_>>>()?;
        super::image_out::save(&contact_sheet(&panels, width, height), path)?;
        let names: Vec<&str> = (outcomes.iter())
            .filter(|(_, r)| r.is_ok())
            .map(|(s, _)| s.name())
            .collect();
        eprintln!(
            "contact sheet written to {} (panels: {}; full red = {:.3e} of the bbox diagonal)",
            path.display(),
            names.join(", "),
            scale / diagonal
        );
    }
    check_validation(&ctx)
}

/// The `q` quantile of the distances of every measured point of every scheme (model units).
fn percentile_distance(outcomes: &[Outcome], q: f64) -> f64 {
    let mut d: Vec<f64> = (outcomes.iter())
        .filter_map(|(_, r)| r.as_ref().ok())
        .flat_map(|c| c.points.iter().map(|m| m.distance))
        .collect();
    d.sort_by(f64::total_cmp);
    let k = ((d.len() as f64 - 1.0) * q).round().max(0.0) as usize;
    d.get(k).copied().unwrap_or(0.0)
}

/// The exact limit on the error maps' grid, evaluated once for every panel.
struct MapGrid {
    grid: usize,
    exact: Vec<Option<Vec<GridSample>>>,
}

/// The error map of one scheme, rendered.
fn panel(
    ctx: &tessera::gpu::Context,
    mesh: &tessera::ControlMesh,
    map: &MapGrid,
    c: &SchemeComparison,
    desc: &CompareDesc,
    scale: f64,
    up: UpAxis,
) -> Result<RgbaImage> {
    let heat = error_map(mesh, &map.exact, map.grid, &c.points, scale)?;
    let render = RenderDesc {
        color_by: ColorBy::Error,
        ..RenderDesc::default()
    };
    let off = OffscreenDesc {
        width: desc.width,
        height: desc.height,
        samples: 4,
        up,
        ..OffscreenDesc::default()
    };
    Ok(render_to_image(ctx, &heat.surface, &render, &off, false)?.image)
}

/// Panels in a near-square grid (2 x 2 for four schemes), empty cells in the background colour.
fn contact_sheet(panels: &[RgbaImage], width: u32, height: u32) -> RgbaImage {
    let n = panels.len().max(1) as u32;
    let columns = (1..=n).find(|c| c * c >= n).unwrap_or(1);
    let rows = n.div_ceil(columns);
    let background = panels
        .first()
        .map_or(image::Rgba([0, 0, 0, 255]), |p| *p.get_pixel(0, 0));
    let mut sheet = RgbaImage::from_pixel(width * columns, height * rows, background);
    for (k, p) in panels.iter().enumerate() {
        let (x, y) = ((k as u32 % columns) * width, (k as u32 / columns) * height);
        image::imageops::replace(&mut sheet, p, i64::from(x), i64::from(y));
    }
    sheet
}

/// The Markdown table.
fn markdown(outcomes: &[Outcome]) -> String {
    let mut s = String::from(
        "| scheme | control points per patch | patches | CPU faces | distance / diag (RMS / max) \
         | normal rad (RMS / max) | GPU ms/frame (compute) | GPU KiB | watertight | normal jump rad: \
         drawn / patches (limit) | continuity |\n|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for (scheme, r) in outcomes {
        match r {
            Ok(c) => {
                let r = &c.row;
                let pair = |a: f64, b: f64| match r.samples {
                    0 => "—".to_string(),
                    _ => format!("{:.2e} / {:.2e}", a + 0.0, b + 0.0),
                };
                s += &format!(
                    "| {} | {} | {} | {} | {} | {} | {:.2} ({:.2}) | {:.0} | {} | {} | {} |\n",
                    scheme,
                    scheme.control_points(),
                    r.patches,
                    r.cpu_faces,
                    pair(r.rms_distance, r.max_distance),
                    pair(r.rms_normal, r.max_normal),
                    r.frame_ms + 0.0,
                    r.compute_ms + 0.0,
                    r.memory_bytes as f64 / 1024.0,
                    watertight(c),
                    normal_jump(c),
                    scheme.continuity(),
                )
            }
            Err(e) => s += &format!("| {scheme} | cannot draw this mesh: {e} |||||||||\n"),
        }
    }
    s + "\nDistances and normals over every point the GPU patches emit at `--tess` (CPU faces are \
         exact and not sampled); the adaptive scheme tessellates a level-l patch at tess / 2^l \
         (at least 1), so at high isolation its end caps are sampled near their corners only: \
         raise `--tess` to see their interior. Normal jump: the largest angle between the drawn \
         normals of coincident seam points where the exact limit is smooth; then between the two \
         patches' geometric normals 1e-4 inside each side of every smooth edge two GPU quads \
         share (their CPU constructions, central differences of positions), with the exact \
         limit's angle at the same points in parentheses.\n"
}

/// The watertight column: `yes` / `no (N of M pairs, gap G)`, noting CPU faces are not checked.
fn watertight(c: &SchemeComparison) -> String {
    let r = &c.row;
    let verdict = if r.seams.watertight() {
        format!("yes ({} pairs)", r.seams.pairs)
    } else {
        format!(
            "no ({} of {} pairs, gap {:.1e})",
            r.seams.cracked, r.seams.pairs, r.seams.max_gap
        )
    };
    if r.cpu_faces > 0 {
        format!("{verdict}; CPU faces not checked")
    } else {
        verdict
    }
}

/// The normal-jump column: drawn normals over smooth seam pairs, then the patches' own normals
/// just inside shared smooth edges (the limit's in parentheses).
fn normal_jump(c: &SchemeComparison) -> String {
    let drawn = match c.row.seams.smooth_pairs {
        0 => "—".to_string(),
        _ => format!("{:.1e}", c.row.seams.max_normal_jump),
    };
    let g = &c.row.continuity;
    match g.samples {
        0 => format!("{drawn} / —"),
        _ => format!("{drawn} / {:.1e} ({:.1e})", g.max_jump, g.max_exact_jump),
    }
}

/// The CSV table: one header line, raw numbers (distances as fractions of `diagonal`).
fn csv(outcomes: &[Outcome], diagonal: f64) -> String {
    let mut s = String::from(
        "scheme,patches,cpu_faces,samples,rms_distance,max_distance,rms_normal,max_normal,\
         frame_ms,compute_ms,memory_bytes,seam_pairs,cracked_pairs,max_gap,smooth_pairs,\
         max_normal_jump,error,g1_edges,g1_max_jump,g1_rms_jump,g1_exact_max_jump\n",
    );
    for (scheme, r) in outcomes {
        match r {
            Ok(c) => {
                let r = &c.row;
                s += &format!(
                    "{},{},{},{},{:e},{:e},{:e},{:e},{},{},{},{},{},{:e},{},{:e},,{},{:e},{:e},{:e}\n",
                    scheme,
                    r.patches,
                    r.cpu_faces,
                    r.samples,
                    r.rms_distance,
                    r.max_distance,
                    r.rms_normal,
                    r.max_normal,
                    r.frame_ms,
                    r.compute_ms,
                    r.memory_bytes,
                    r.seams.pairs,
                    r.seams.cracked,
                    r.seams.max_gap / diagonal,
                    r.seams.smooth_pairs,
                    r.seams.max_normal_jump,
                    r.continuity.edges,
                    r.continuity.max_jump,
                    r.continuity.rms_jump,
                    r.continuity.max_exact_jump,
                )
            }
            Err(e) => {
                s += &format!(
                    "{scheme},,,,,,,,,,,,,,,,\"{}\",,,,\n",
                    e.to_string().replace('"', "'")
                )
            }
        }
    }
    s
}
