//! `tessera error`: accuracy of a patch scheme against the exact Catmull-Clark limit surface.

use std::sync::OnceLock;

use clap::builder::PossibleValue;
use clap::{Args, ValueEnum};

use super::render::AdaptiveArgs;
use tessera::mesh::ObjOptions;
use tessera::patch::gregory::accuracy::{
    measure_tangents, AccuracyOptions, AccuracyReport, FaceHeat,
};
use tessera::render::accuracy::{measure_gpu_with, TypeAccuracy};
use tessera::render::Scheme;

/// What `tessera error` measures: the CPU Gregory construction, or a GPU scheme's TES output
/// (every `--scheme` of the other subcommands, same names).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorScheme {
    /// Gregory patches built and evaluated on the CPU (the reference construction).
    GregoryCpu,
    /// The TES output of the real pipeline with this scheme at level `--grid`.
    Gpu(Scheme),
}

impl ValueEnum for ErrorScheme {
    fn value_variants<'a>() -> &'a [Self] {
        static ALL: OnceLock<Vec<ErrorScheme>> = OnceLock::new();
        ALL.get_or_init(|| {
            std::iter::once(ErrorScheme::GregoryCpu)
                .chain(
                    Scheme::value_variants()
                        .iter()
                        .map(|&s| ErrorScheme::Gpu(s)),
                )
                .collect()
        })
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        match self {
            ErrorScheme::GregoryCpu => Some(
                PossibleValue::new("gregory-cpu")
                    .help("Gregory patches built and evaluated on the CPU (the reference)"),
            ),
            ErrorScheme::Gpu(s) => s.to_possible_value(),
        }
    }
}

/// Arguments of `tessera error`.
#[derive(Args)]
pub struct ErrorArgs {
    /// Control mesh: an OBJ file with OpenSubdiv tags, or `embedded:NAME`.
    pub mesh: String,
    /// Patch scheme to measure.
    #[arg(long, value_enum, default_value = "gregory-cpu")]
    pub scheme: ErrorScheme,
    /// Samples per face: an (N+1) x (N+1) grid on quads, the barycentric grid on triangles.
    /// GPU schemes: the uniform tessellation level (the adaptive scheme scales it down per
    /// patch level, so every base face gets about the same density).
    #[arg(long, default_value_t = 8)]
    pub grid: usize,
    /// `--isolation`, `--single-crease` (the adaptive scheme's planning).
    #[command(flatten)]
    pub adaptive: AdaptiveArgs,
    /// Also sample regular faces (drawn as exact B-splines, so their error is ~0).
    #[arg(long)]
    pub include_regular: bool,
    /// The file's faces are wound clockwise seen from outside: reverse them.
    #[arg(long)]
    pub left_handed: bool,
    /// Also write an error map (as the paper's Fig. 11): Gregory faces coloured from blue (exact)
    /// to red (`--heatmap-scale` or more), regular faces blue, faces without a Gregory patch grey.
    /// The map shows the CPU construction, which the GPU variants reproduce to < 1e-6.
    #[arg(long)]
    pub heatmap: Option<std::path::PathBuf>,
    /// Distance shown as full red, as a fraction of the bbox diagonal (default: the largest error).
    #[arg(long)]
    pub heatmap_scale: Option<f64>,
    /// Error-map image size WxH.
    #[arg(long, default_value = "800x600")]
    pub size: String,
    /// World axis pointing up on screen in the error map: `z` or `y`.
    #[arg(long, default_value = "z")]
    pub up: String,
}

/// Samples per face side of the error map.
fn heatmap_grid(args: &ErrorArgs) -> usize {
    args.grid.max(2)
}

/// Renders the error map of `mesh` to `path`.
///
/// `samples`: the CPU construction's samples when the report already measured exactly the map's
/// faces on the map's grid (so they are not measured twice).
fn write_heatmap(
    mesh: &tessera::ControlMesh,
    args: &ErrorArgs,
    path: &std::path::Path,
    samples: Option<&[FaceHeat]>,
) -> tessera::Result<()> {
    use tessera::render::{heatmap, render_to_image, ColorBy, OffscreenDesc, RenderDesc, UpAxis};
    let (width, height) = super::render::parse_size(&args.size)?;
    if let Some(s) = args.heatmap_scale {
        if !(s.is_finite() && s > 0.0) {
            return Err(tessera::Error::Invalid(format!(
                "--heatmap-scale {s}: must be a positive fraction of the bbox diagonal"
            )));
        }
    }
    let scale = args.heatmap_scale.map(|s| s * mesh.bbox_diagonal());
    let heat = match samples {
        Some(samples) => heatmap::heat_surface_from_samples(mesh, samples, 8, scale)?,
        None => heatmap::heat_surface(mesh, heatmap_grid(args), 8, scale)?,
    };
    let ctx = super::render::context(false)?;
    let mut render = RenderDesc {
        color_by: ColorBy::Error,
        ..RenderDesc::default()
    };
    render.tess.level = 8.0;
    let desc = OffscreenDesc {
        width,
        height,
        samples: 4,
        up: UpAxis::parse(&args.up)?,
        ..OffscreenDesc::default()
    };
    let out = render_to_image(&ctx, &heat.surface, &render, &desc, false)?;
    super::render::check_validation(&ctx)?;
    super::image_out::save(&out.image, path)?;
    eprintln!(
        "error map written to {} (full red = {:.3e} of the bbox diagonal; largest error {:.3e})",
        path.display(),
        heat.scale / mesh.bbox_diagonal(),
        heat.max_distance / mesh.bbox_diagonal()
    );
    Ok(())
}

/// The printed report. `not_sampled` describes the faces left out: by default (the CPU Gregory
/// construction) those without a Gregory patch; a GPU scheme passes its own CPU-path count and
/// first refusal.
pub fn format_report(
    mesh: &str,
    scheme: &str,
    r: &AccuracyReport,
    not_sampled: Option<&str>,
) -> String {
    let without = format!(
        "without Gregory patch {}{}",
        r.unsupported,
        r.first_unsupported
            .map(|e| format!(" (first: {e})"))
            .unwrap_or_default()
    );
    format!(
        "mesh {mesh}\nscheme {scheme}\nfaces sampled {} ({} triangles), regular {}, {}\n\
         samples {}\nbbox diagonal {:.6e}\n\
         distance / diagonal: rms {:.3e} max {:.3e}\n\
         equal (u,v) on quads and sub-faces / diagonal: rms {:.3e} max {:.3e}\n\
         normal angle (rad): rms {:.3e} max {:.3e}\n",
        r.faces,
        r.triangles,
        r.regular,
        not_sampled.unwrap_or(&without),
        r.samples,
        r.diagonal,
        r.rms_distance,
        r.max_distance,
        r.rms_uv,
        r.max_uv,
        r.rms_normal,
        r.max_normal
    )
}

/// The per-patch-type lines of a tagged GPU capture (adaptive scheme); empty for none.
pub fn format_types(types: &[TypeAccuracy]) -> String {
    if types.is_empty() {
        return String::new();
    }
    let mut out = format!(
        "by patch type (distance / diagonal; normal angle rad):\n{:<14} {:>6} {:>9} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}\n",
        "type", "levels", "samples", "rms dist", "max dist", "rms (u,v)", "max (u,v)", "rms nrm", "max nrm"
    );
    for t in types {
        out += &format!(
            "{:<14} {:>6} {:>9} {:>10.3e} {:>10.3e} {:>10.3e} {:>10.3e} {:>10.3e} {:>10.3e}\n",
            t.kind,
            format!("{}-{}", t.levels.0, t.levels.1),
            t.samples,
            t.rms_distance,
            t.max_distance,
            t.rms_uv,
            t.max_uv,
            t.rms_normal,
            t.max_normal
        );
    }
    out
}

/// Runs the subcommand.
pub fn run(args: ErrorArgs) -> tessera::Result<()> {
    if args.grid == 0 {
        return Err(tessera::Error::Invalid("--grid must be at least 1".into()));
    }
    let options = ObjOptions {
        left_handed: args.left_handed,
        ..ObjOptions::default()
    };
    let mesh = tessera::assets::load_mesh(&args.mesh, &options)?;
    // The map shows the Gregory faces on a grid of at least 2; the CPU report's samples are
    // reused when they are exactly those.
    let reuse = args.heatmap.is_some() && !args.include_regular && heatmap_grid(&args) == args.grid;
    let mut samples = None;
    let mut types = Vec::new();
    let mut cpu_path = None;
    let report = match args.scheme {
        ErrorScheme::GregoryCpu => {
            let options = AccuracyOptions {
                grid: args.grid,
                include_regular: args.include_regular,
            };
            let (report, heat) =
                measure_tangents(&mesh, &options, args.adaptive.tangents(), reuse)?;
            if reuse {
                samples = Some(heat);
            }
            report
        }
        ErrorScheme::Gpu(scheme) => {
            let ctx = super::render::context(false)?;
            let opts = super::render::plan_options(&ctx, &args.adaptive);
            let r = measure_gpu_with(&ctx, &mesh, scheme, args.grid, &opts)?;
            super::render::check_validation(&ctx)?;
            types = r.by_type;
            cpu_path = Some(format!(
                "on the exact CPU path {}{}",
                r.cpu_faces,
                r.first_refusal
                    .map(|e| format!(" (first: {e})"))
                    .unwrap_or_default()
            ));
            r.report
        }
    };
    let name = match args.scheme {
        ErrorScheme::GregoryCpu => "gregory-cpu",
        ErrorScheme::Gpu(s) => s.name(),
    };
    let name = match args.scheme {
        ErrorScheme::Gpu(Scheme::Adaptive) => {
            format!("{name} (isolation {})", args.adaptive.isolation)
        }
        _ => name.to_string(),
    };
    print!(
        "{}",
        format_report(&args.mesh, &name, &report, cpu_path.as_deref())
    );
    print!("{}", format_types(&types));
    if let Some(path) = &args.heatmap {
        write_heatmap(&mesh, &args, path, samples.as_deref())?;
    }
    Ok(())
}
