//! `tessera render`: draws a control mesh offscreen through the tessellation pipeline to a PNG.

use std::path::PathBuf;

use clap::Args;
use tessera::gpu::{Context, ContextDesc};
use tessera::mesh::ObjOptions;
use tessera::patch::gregory::GregoryTangents;
use tessera::render::displace::DisplacementMap;
use tessera::render::{
    render_to_image, CameraSpec, ColorBy, FrameReport, OffscreenDesc, RenderDesc, Scheme, Spacing,
    SurfaceData, TessMode, TessSettings, UpAxis,
};
use tessera::subdiv::adaptive::EndCapSharpness;
use tessera::{ControlMesh, Error, Result};

/// Arguments of `tessera render`.
///
/// Regular faces (also next to boundaries and infinitely sharp creases) are bicubic B-spline
/// patches tessellated and evaluated on the GPU; irregular triangles and quads whose vertices are
/// interior and smooth are Gregory patches built and evaluated on the GPU (`--scheme`). Every
/// other face with a limit surface (polygons, faces at boundary/crease/dart vertices, rings or
/// valences over a scheme's limits) is drawn from the CPU reference: exact limit points on a grid
/// matching the tessellation level, as triangles. Holes are not drawn.
#[derive(Args)]
pub struct RenderArgs {
    /// Control mesh: an OBJ file (OpenSubdiv tags) or `embedded:NAME`; default: the embedded
    /// default mesh.
    pub mesh: Option<String>,
    /// Output PNG.
    #[arg(long, default_value = "out.png")]
    pub out: PathBuf,
    /// Image size WxH in pixels.
    #[arg(long, default_value = "800x600")]
    pub size: String,
    /// `auto` (frame the bounding box) or `az,el,dist` (degrees, degrees, model units).
    #[arg(long, default_value = "auto")]
    pub camera: String,
    /// World axis pointing up on screen: `z` (OpenSubdiv shapes, embedded meshes) or `y`.
    #[arg(long, default_value = "z")]
    pub up: String,
    /// Uniform tessellation level (clamped to the device's maxTessellationGenerationLevel); also
    /// the grid density of the CPU-evaluated faces.
    #[arg(long, default_value_t = 8.0)]
    pub tess: f32,
    /// `uniform`, `adaptive` (screen-space, from the shared edges' end-point limit positions) or
    /// `distance` (camera distance: `--tess` at `--tess-distance`, ∝ 1 / distance).
    #[arg(long, default_value = "uniform", value_parser = ["uniform", "adaptive", "distance"])]
    pub tess_mode: String,
    /// Adaptive mode: target length of a tessellated segment in pixels.
    #[arg(long, default_value_t = 8.0)]
    pub pixels_per_edge: f32,
    /// Distance mode: the camera distance at which an edge gets `--tess` (default: the surface's
    /// bounding-box diagonal).
    #[arg(long)]
    pub tess_distance: Option<f32>,
    /// Tessellation spacing.
    #[arg(long, default_value = "equal", value_parser = ["equal", "fractional-odd", "fractional-even"])]
    pub spacing: String,
    /// Uniform levels above this draw each patch as 2x2, 4x4, ... sub-patches (lavapipe's cost
    /// per domain point jumps above ~24); 0 disables.
    #[arg(long, default_value_t = 16.0)]
    pub max_patch_level: f32,
    /// GPU scheme for the faces that are not regular B-spline patches: `gregory-stencil`
    /// (default: one Gregory patch per triangle/quad, control points as precomputed one-ring
    /// stencils in the TCS, paper §4.3), `gregory-vs` (two-stage: per-vertex data in the vertex
    /// shader, face points in the TCS, §4.1-4.2) or `bspline-only`. Both Gregory schemes draw
    /// regular quads with one semi-sharp crease line as exact single-crease patches (Nießner et
    /// al. 2012). Faces a scheme cannot take (polygons, other semi-sharp creases, darts, too
    /// large rings or valences) are drawn from the exact CPU reference, with a message.
    #[arg(long, value_enum, default_value_t = Scheme::default())]
    pub scheme: Scheme,
    /// `--isolation`, `--single-crease` (the adaptive scheme's planning).
    #[command(flatten)]
    pub adaptive: AdaptiveArgs,
    /// `--displacement`, `--displacement-scale`.
    #[command(flatten)]
    pub displace: DisplacementArgs,
    /// `--cull`, `--no-cull`.
    #[command(flatten)]
    pub cull: CullArgs,
    /// Draw triangle edges only.
    #[arg(long)]
    pub wireframe: bool,
    /// Animation: render this many frames of a twist about the up axis (one period), updating
    /// only the control positions, and write them to `--out` as a contact sheet.
    #[arg(long, default_value_t = 0)]
    pub animate: u32,
    /// `patch-type`: regular gold, irregular purple, triangles green (adaptive: regular gold,
    /// boundary orange, crease red, end caps purple, single-crease teal, transition blue);
    /// `level`: adaptive patches by refinement level (0 blue, 1 cyan, 2 green, 3 yellow, 4 orange,
    /// 5 red, 6 magenta, 7 violet, 8 white); `none`: one material.
    #[arg(long, default_value = "none", value_parser = ["patch-type", "level", "none"])]
    pub color_by: String,
    /// MSAA samples (1, 2, 4, 8; must be supported by the device).
    #[arg(long, default_value_t = 1)]
    pub msaa: u32,
    /// Print GPU time per pass (timestamp queries) and pipeline statistics.
    #[arg(long)]
    pub timings: bool,
    /// Enable the Khronos validation layer (always on in debug builds); errors fail the run.
    #[arg(long)]
    pub validation: bool,
    /// The file's faces are wound clockwise.
    #[arg(long)]
    pub left_handed: bool,
    /// Input size limits.
    #[command(flatten)]
    pub limits: super::limits::InputLimits,
}

/// Parses `WxH`.
pub fn parse_size(s: &str) -> Result<(u32, u32)> {
    let bad = || Error::Invalid(format!("size `{s}`: expected WxH, e.g. 800x600"));
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let w: u32 = w.trim().parse().map_err(|_| bad())?;
    let h: u32 = h.trim().parse().map_err(|_| bad())?;
    if w == 0 || h == 0 || w > 16384 || h > 16384 {
        return Err(Error::Invalid(format!(
            "size `{s}`: width and height must be in 1..=16384"
        )));
    }
    Ok((w, h))
}

/// Loads the mesh named on the command line, or the embedded default mesh.
pub fn load(mesh: Option<&str>, left_handed: bool) -> Result<ControlMesh> {
    match mesh {
        Some(spec) => tessera::assets::load_mesh(
            spec,
            &ObjOptions {
                left_handed,
                ..ObjOptions::default()
            },
        ),
        None => Ok(tessera::assets::default_mesh()),
    }
}

/// Creates the Vulkan context (validation on in debug builds or when asked).
pub fn context(validation: bool) -> Result<Context> {
    Context::new(&ContextDesc {
        validation: validation || cfg!(debug_assertions),
        ..ContextDesc::default()
    })
}

/// Fails if the validation layer reported errors (each was logged as it came).
pub fn check_validation(ctx: &Context) -> Result<()> {
    let n = ctx.validation_errors();
    if n == 0 {
        return Ok(());
    }
    Err(Error::Invalid(format!(
        "the Vulkan validation layer reported {n} error(s)"
    )))
}

/// Checks a requested level and says when the device limit will clamp it (the one clamp is
/// [`TessSettings::resolve`], which the renderer applies; the CPU path's grid uses the same
/// value).
pub fn clamp_level(ctx: &Context, level: f32) -> Result<f32> {
    if !level.is_finite() || level < 1.0 {
        return Err(Error::Invalid(format!(
            "--tess {level}: the tessellation level must be at least 1"
        )));
    }
    let max = ctx.info().limits.max_tessellation_generation_level as f32;
    let clamped = TessSettings {
        level,
        ..TessSettings::default()
    }
    .resolve(max, &[])
    .level;
    if clamped != level {
        log::warn!("--tess {level} clamped to the device limit {max}");
    }
    Ok(clamped)
}

/// `--max-patch-level`: 0 (or less) disables splitting.
pub fn max_patch_level(arg: f32) -> f32 {
    if arg > 0.0 {
        arg
    } else {
        f32::INFINITY
    }
}

/// The planning flags (adaptive scheme, Gregory construction), shared by `render`, `sample`,
/// `bench`, `error` and `compare`.
#[derive(Args, Debug, Clone, Copy)]
pub struct AdaptiveArgs {
    /// Isolation level of `--scheme adaptive` (0-8): faces are refined around features until
    /// they are regular or this level is reached (Köbler 2013 §3.3).
    #[arg(long, default_value_t = tessera::render::PlanOptions::DEFAULT_ISOLATION,
          value_parser = clap::value_parser!(u32).range(0..=8))]
    pub isolation: u32,
    /// `--scheme adaptive`: draw regular quads whose only feature is one semi-sharp crease line
    /// as single-crease patches instead of refining them (Nießner, Loop, Greiner 2012; OpenSubdiv's
    /// `useSingleCreasePatch`): `true` (default) or `false`.
    #[arg(long, default_value_t = tessera::render::PlanOptions::DEFAULT_SINGLE_CREASE,
          action = clap::ArgAction::Set, value_name = "BOOL")]
    pub single_crease: bool,
    /// Edge-tangent lengths of the Gregory construction (`gregory-vs`, `gregory-stencil` and the
    /// adaptive end caps): `optimal` (fitted to the exact limit: the paper's tangents scaled per
    /// valence at all-quad vertices, tangents and transversal vectors scaled per ring at vertices
    /// with triangles, cross-boundary tangents scaled per sector size at boundary and crease
    /// vertices; `patch::gregory::tangents`), `paper` (the paper's 2/3 λ q, Loop et al. 2009
    /// §3.3), `bands` (`optimal` with the 2-ring fit at crease sectors on a band), `fitted`
    /// (`optimal` with each free crease sector's factor fitted to the exact limit on the mesh
    /// as loaded, the rest pose, and frozen: `--animate` keeps them; `patch::gregory::vertex_fit`), `end-caps`
    /// (`optimal` with the adaptive end caps' own factors, at every Gregory patch) or `scaled:S`
    /// (the paper's tangents times S at every valence but 4; for experiments).
    #[arg(long, default_value_t = GregoryTangents::default(),
          value_name = "paper|optimal|bands|fitted|end-caps|scaled:S",
          value_parser = |s: &str| s.parse::<GregoryTangents>())]
    pub gregory_tangents: GregoryTangents,
    /// `--scheme adaptive`: how end caps treat semi-sharpness left at the isolation level:
    /// `crease` (default: residual sharpness >= 1 infinitely sharp, below smooth) or `smooth`
    /// (all of it smooth, as OpenSubdiv's end caps).
    #[arg(long, default_value_t = EndCapSharpness::default(), value_name = "crease|smooth",
          value_parser = |s: &str| s.parse::<EndCapSharpness>())]
    pub end_cap_sharpness: EndCapSharpness,
    /// `--scheme adaptive`: near crease vertices that are not regular, end caps draw the exact
    /// limit normals of a 2^-3 lattice of each end cap (`true`, default; their normal error then
    /// falls with the isolation level) or their own normals (`false`: 6.5 % less preprocessing
    /// on catmark_car at isolation 2, 132.1 against 141.3 M instructions per build).
    #[arg(long, default_value_t = tessera::render::PlanOptions::DEFAULT_LATTICE_NORMALS,
          action = clap::ArgAction::Set, value_name = "BOOL")]
    pub lattice_normals: bool,
    /// `--scheme pm`: crease scalar `a` in [0, 1] of every untagged edge (Myles, Ni, Peters 2008
    /// eq. 14): 2/3 (default) is the smooth surface, 0 the control polyhedron, 4/5 rounder;
    /// tagged edges of sharpness `s` get `a · 2^-s` (0 when infinitely sharp).
    #[arg(long, value_name = "A", value_parser = parse_crease_scalar)]
    pub pm_crease_scalar: Option<f64>,
}

/// A crease scalar in [0, 1].
fn parse_crease_scalar(s: &str) -> std::result::Result<f64, String> {
    let a: f64 = s.parse().map_err(|_| format!("`{s}` is not a number"))?;
    if (0.0..=1.0).contains(&a) {
        Ok(a)
    } else {
        Err(format!("crease scalar {s} is outside [0, 1]"))
    }
}

impl AdaptiveArgs {
    /// The `--gregory-tangents` setting.
    pub fn tangents(&self) -> GregoryTangents {
        self.gregory_tangents
    }
}

/// Patch culling, shared by `render` and `bench`.
#[derive(Args, Debug, Clone, Copy)]
pub struct CullArgs {
    /// Cull patches outside the view frustum in the control stages (the default): zero
    /// tessellation levels where the patch's control hull, grown by the displacement scale, lies
    /// outside one frustum plane. The image is the same; fewer TES invocations.
    #[arg(long, overrides_with = "no_cull")]
    pub cull: bool,
    /// Tessellate every patch, in view or not.
    #[arg(long, overrides_with = "cull")]
    pub no_cull: bool,
}

impl CullArgs {
    /// Whether patches are culled (`--cull` unless `--no-cull` came last).
    pub fn enabled(&self) -> bool {
        !self.no_cull
    }
}

/// Displacement along the normal, shared by `render` and `sample`.
#[derive(Args, Debug, Clone)]
pub struct DisplacementArgs {
    /// `procedural`: move the surface along its normal by S * d(p) with
    /// d(p) = (sin(5x + 1) + sin(5y + 2) + sin(5z + 3)) / 3 of the undisplaced limit position
    /// (world units; continuous across faces, watertight where the normal is). FILE.png: a
    /// displacement map sampled at the mesh's texture coordinates (OBJ `vt`, required), moving
    /// by S * (value - 0.5) with value its first channel (grey or red, 8 or 16 bit) in [0, 1]:
    /// mid-grey stays, white moves S/2 outwards, black S/2 inwards; linear filtering, repeat
    /// addressing, the image's top row at t = 0; watertight where faces share their `vt`; the
    /// shading normal is not tilted by the map. `none`: the limit surface.
    #[arg(long, default_value = "none", value_name = "none|procedural|FILE.png")]
    pub displacement: String,
    /// The scale S of `--displacement` (world units).
    #[arg(long, default_value_t = 0.05, allow_negative_numbers = true)]
    pub displacement_scale: f32,
}

impl DisplacementArgs {
    /// The renderer's displacement; a non-finite scale is refused. A map file is read and
    /// given to `surface` (an error names the file, or the missing texture coordinates).
    pub fn displacement(
        &self,
        surface: &mut tessera::render::SurfaceData,
    ) -> Result<tessera::render::Displacement> {
        if !self.displacement_scale.is_finite() {
            return Err(Error::Invalid(format!(
                "--displacement-scale {} is not a finite number",
                self.displacement_scale
            )));
        }
        Ok(match self.displacement.as_str() {
            "procedural" => tessera::render::Displacement::Procedural {
                scale: self.displacement_scale,
            },
            "none" => tessera::render::Displacement::None,
            path => {
                let map = DisplacementMap::load(std::path::Path::new(path))?;
                surface.set_displacement_map(map)?;
                tessera::render::Displacement::Map {
                    scale: self.displacement_scale,
                }
            }
        })
    }
}

/// Planning options on `ctx`'s device with `--isolation`, `--single-crease`,
/// `--gregory-tangents` and `--end-cap-sharpness`.
pub fn plan_options(ctx: &Context, args: &AdaptiveArgs) -> tessera::render::PlanOptions {
    tessera::render::PlanOptions::new(tessera::render::SchemeLimits::from_context(ctx))
        .with_isolation(args.isolation)
        .with_single_crease(args.single_crease)
        .with_gregory_tangents(args.tangents())
        .with_end_cap_sharpness(args.end_cap_sharpness)
        .with_lattice_normals(args.lattice_normals)
        .with_pm_crease_scalar(args.pm_crease_scalar)
}

/// The surface of `mesh` for the `--scheme` named `scheme` on `ctx`'s device.
pub fn surface_for(
    ctx: &Context,
    mesh: &ControlMesh,
    level: f32,
    scheme: Scheme,
    args: &AdaptiveArgs,
) -> Result<SurfaceData> {
    tessera::render::surface_for_scheme_with(
        mesh,
        level.ceil() as u32,
        scheme,
        &plan_options(ctx, args),
    )
}

/// Says how many faces each pass draws and how many stay on the CPU path.
pub fn report_fallback(surface: &SurfaceData) {
    if !surface.fallback_faces.is_empty() {
        let parts: Vec<String> = surface
            .parts
            .iter()
            .map(|p| format!("{} by {}", p.faces().len(), p.pass_name()))
            .collect();
        log::warn!(
            "{} face(s) drawn from the CPU reference (no GPU patch for them); on the GPU: {}",
            surface.fallback_faces.len(),
            if parts.is_empty() {
                "none".to_string()
            } else {
                parts.join(", ")
            }
        );
        // The last pass's reasons: what no pass could take.
        if let Some(last) = surface.refusals.last().map(|r| r.pass) {
            for r in surface.refusals.iter().filter(|r| r.pass == last).take(3) {
                log::info!("  {r}");
            }
        }
    }
}

/// Prints per-pass GPU times and the patch pass's pipeline statistics.
pub fn print_report(r: &FrameReport) {
    println!("GPU time per pass:");
    for (label, ms) in &r.passes {
        println!("  {label:<28} {ms:9.3} ms");
    }
    let s = &r.patch_stats;
    println!("pipeline statistics (patch pass):");
    println!("  TCS patches                  {}", s.tcs_patches);
    println!("  TES invocations              {}", s.tes_invocations);
    println!("  clipping invocations         {}", s.clipping_invocations);
    println!("  clipping primitives          {}", s.clipping_primitives);
    println!("  fragment invocations         {}", s.fragment_invocations);
}

/// Runs the subcommand.
pub fn run(args: RenderArgs) -> Result<()> {
    let (width, height) = parse_size(&args.size)?;
    super::image_out::check_out(&args.out)?;
    let camera = CameraSpec::parse(&args.camera)?;
    let mesh = load(args.mesh.as_deref(), args.left_handed)?;
    super::limits::check_mesh(&mesh, &args.limits)?;
    super::limits::check_gpu_range(&mesh)?;
    let ctx = context(args.validation)?;
    if !ctx.info().limits.supports_samples(args.msaa) {
        return Err(Error::Invalid(format!(
            "--msaa {}: the device supports {:?}",
            args.msaa,
            ctx.info().limits.supported_sample_counts()
        )));
    }
    let level = clamp_level(&ctx, args.tess)?;
    let tess = TessSettings {
        level,
        mode: match args.tess_mode.as_str() {
            "adaptive" => TessMode::Adaptive,
            "distance" => TessMode::Distance,
            _ => TessMode::Uniform,
        },
        pixels_per_edge: args.pixels_per_edge,
        distance: args.tess_distance.unwrap_or(0.0),
        spacing: Spacing::parse(&args.spacing)?,
        max_patch_level: max_patch_level(args.max_patch_level),
    };
    if !(tess.pixels_per_edge.is_finite() && tess.pixels_per_edge > 0.0) {
        return Err(Error::Invalid("--pixels-per-edge must be positive".into()));
    }
    if let Some(d) = args.tess_distance {
        if !(d.is_finite() && d > 0.0) {
            return Err(Error::Invalid(format!(
                "--tess-distance {d}: must be a positive distance"
            )));
        }
    }
    let mut surface = surface_for(&ctx, &mesh, level, args.scheme, &args.adaptive)?;
    let displacement = args.displace.displacement(&mut surface)?;
    super::limits::check_drawable(&surface)?;
    super::limits::check_gpu_memory(
        &ctx,
        super::limits::estimate_gpu_bytes(&surface, width, height, args.msaa, 0),
        "this render",
    )?;
    report_fallback(&surface);
    let render = RenderDesc {
        tess,
        wireframe: args.wireframe,
        color_by: match args.color_by.as_str() {
            "patch-type" => ColorBy::PatchType,
            "level" => ColorBy::Level,
            _ => ColorBy::None,
        },
        displacement,
        cull_patches: args.cull.enabled(),
        ..RenderDesc::default()
    };
    let desc = OffscreenDesc {
        width,
        height,
        samples: args.msaa,
        camera,
        up: UpAxis::parse(&args.up)?,
        ..OffscreenDesc::default()
    };
    if args.animate > 0 {
        super::animate::run(
            &ctx,
            &mesh,
            &surface,
            level.ceil() as u32,
            &render,
            &desc,
            args.animate,
            &args.out,
            args.timings,
        )?;
        return check_validation(&ctx);
    }
    let out = render_to_image(&ctx, &surface, &render, &desc, args.timings)?;
    super::image_out::save(&out.image, &args.out)?;
    if let Some(r) = &out.report {
        print_report(r);
    }
    check_validation(&ctx)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes() {
        assert_eq!(parse_size("800x600").unwrap(), (800, 600));
        assert!(parse_size("800").is_err());
        assert!(parse_size("0x10").is_err());
        assert!(parse_size("axb").is_err());
    }
}
