//! `tessera sample`: captures every TES invocation of the real pipeline.

use std::fmt::Write as _;
use std::path::PathBuf;

use clap::Args;
use tessera::render::{
    capture_capacity_for, plan_for_scheme_with, render_to_image, resolve_tess, CaptureRecord,
    OffscreenDesc, RenderDesc, Scheme, TessSettings,
};
use tessera::{Error, Result};

use super::render::{
    check_validation, clamp_level, context, load, plan_options, AdaptiveArgs, DisplacementArgs,
};

/// Arguments of `tessera sample`.
///
/// Renders the mesh at uniform level N and writes, from an SSBO the TES fills, one line per TES
/// invocation: `f u v x y z nx ny nz` (base face, the face's (u, v), limit position and normal;
/// numbers as the shortest text reading back as the same f32, like `tessera limit`), sorted by
/// face, v, u. Faces drawn from the CPU reference are not in the file (counted on stderr).
/// Gregory patches (`--scheme gregory-*`): quads in the face's (u, v); a triangle's line holds
/// (u, v) = the barycentric weights of its corners 1 and 2 (corner 0 has weight 1 - u - v),
/// not Catmull-Clark's three-quad parameterisation of the triangle.
/// `--scheme adaptive`: quads in the face's (u, v), other faces `f:k u v …` in sub-face k (as
/// `tessera limit`), and two more columns: the patch type (regular, boundary, crease, gregory-quad
/// for end caps, single-crease, transition) and its refinement level. Meshes with texture
/// coordinates (OBJ `vt`): two last columns `s t`, the face-varying coordinate at the point
/// (bilinear over quads and sub-faces, barycentric over triangles drawn whole).
#[derive(Args)]
pub struct SampleArgs {
    /// Control mesh: an OBJ file or `embedded:NAME`.
    pub mesh: String,
    /// Uniform tessellation level.
    #[arg(long, default_value_t = 4.0)]
    pub tess: f32,
    /// Output file.
    #[arg(long)]
    pub out: PathBuf,
    /// GPU scheme for non-regular faces (see `tessera render --help`).
    #[arg(long, value_enum, default_value_t = Scheme::default())]
    pub scheme: Scheme,
    /// `--isolation`, `--single-crease` (the adaptive scheme's planning).
    #[command(flatten)]
    pub adaptive: AdaptiveArgs,
    /// `--displacement`, `--displacement-scale`: the captured points are displaced.
    #[command(flatten)]
    pub displace: DisplacementArgs,
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
pub fn run(args: SampleArgs) -> Result<()> {
    let mesh = load(Some(&args.mesh), args.left_handed)?;
    super::limits::check_mesh(&mesh, &args.limits)?;
    super::limits::check_gpu_range(&mesh)?;
    let ctx = context(args.validation)?;
    let level = clamp_level(&ctx, args.tess)?;
    // Only the GPU patches are captured; the other faces are counted, not evaluated.
    let mut surface =
        plan_for_scheme_with(&mesh, args.scheme, &plan_options(&ctx, &args.adaptive))?;
    log::info!(
        "{} face(s) captured from the GPU, {} drawn another way (CPU fallback, not in the file), \
         {} without limit surface",
        surface.parts.iter().map(|p| p.faces().len()).sum::<usize>(),
        surface.fallback_faces.len(),
        surface.skipped_faces
    );
    super::limits::check_drawable(&surface)?;
    if surface.patch_count() == 0 {
        return Err(Error::NothingToDraw(format!(
            "{}: no face is drawn by a GPU patch with --scheme {}, so no TES invocation would \
             be captured",
            args.mesh,
            args.scheme.name()
        )));
    }
    surface.fallback_faces.clear();
    let displacement = args.displace.displacement(&mut surface)?;
    let tess = TessSettings {
        level,
        ..TessSettings::default()
    };
    let render = RenderDesc {
        tess,
        capture_capacity: Some(capture_capacity_for(
            surface.patch_count(),
            &resolve_tess(&ctx, &surface, &tess),
        )),
        displacement,
        ..RenderDesc::default()
    };
    let desc = OffscreenDesc {
        width: 64,
        height: 64,
        ..OffscreenDesc::default()
    };
    super::limits::check_gpu_memory(
        &ctx,
        super::limits::estimate_gpu_bytes(
            &surface,
            desc.width,
            desc.height,
            desc.samples,
            u64::from(render.capture_capacity.unwrap_or(0)),
        ),
        "this capture",
    )?;
    // Opened before rendering: a path that cannot be written fails before the GPU work.
    let (mut w, name) = super::stream::open_output(Some(&args.out))?;
    let out = render_to_image(&ctx, &surface, &render, &desc, false)?;
    let texcoords = surface.texcoords.is_some();
    let mut recs = out.capture.unwrap_or_default();
    recs.sort_by(|a, b| {
        (a.face, a.sub_face, a.v, a.u)
            .partial_cmp(&(b.face, b.sub_face, b.v, b.u))
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    // Streamed: one block of lines in memory at a time, not the whole file.
    let mut progress = super::stream::Progress::new(
        "records",
        recs.len() as u64,
        !log::log_enabled!(log::Level::Info),
    );
    super::stream::write_ordered(
        recs.chunks(4096),
        |c| c.len() as u64,
        |c, text| {
            for r in *c {
                write_record(text, r, texcoords);
            }
            Ok(())
        },
        &mut w,
        &name,
        &mut progress,
    )?;
    eprintln!("{} TES invocations written", recs.len());
    check_validation(&ctx)
}

/// One capture line: `f u v x y z nx ny nz` (`f:k` for sub-face k), then the patch type and level
/// where the scheme tags them.
fn write_record(text: &mut String, r: &CaptureRecord, texcoords: bool) {
    let [x, y, z] = r.position;
    let [nx, ny, nz] = r.normal;
    let _ = match r.sub_face {
        Some(k) => write!(text, "{}:{k}", r.face),
        None => write!(text, "{}", r.face),
    };
    let _ = write!(
        text,
        " {:?} {:?} {:?} {:?} {:?} {:?} {:?} {:?}",
        r.u, r.v, x, y, z, nx, ny, nz
    );
    if let Some(p) = r.patch {
        let _ = write!(
            text,
            " {} {}",
            tessera::render::schemes::adaptive::kind_name(p.kind),
            p.level
        );
    }
    if texcoords {
        let _ = write!(text, " {:?} {:?}", r.texcoord[0], r.texcoord[1]);
    }
    text.push('\n');
}
