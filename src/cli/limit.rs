//! `tessera limit`: the exact limit surface sampled on a grid per face.

use std::fmt::Write as _;
use std::path::PathBuf;

use clap::Args;
use tessera::mesh::ObjOptions;
use tessera::subdiv::eval::{GridSample, LimitEvaluator};
use tessera::Error;

/// Arguments of `tessera limit`.
#[derive(Args)]
pub struct LimitArgs {
    /// Control mesh: an OBJ file with OpenSubdiv tags, or `embedded:NAME`
    /// (mixed, open, creased).
    pub mesh: String,
    /// Grid resolution N: samples at u = i/N, v = j/N, i, j in 0..=N, per quad or quad sub-face.
    #[arg(long, default_value_t = 4)]
    pub grid: usize,
    /// Output file (default: standard output).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// The file's faces are wound clockwise.
    #[arg(long)]
    pub left_handed: bool,
    /// Input size limits.
    #[command(flatten)]
    pub limits: super::limits::InputLimits,
}

/// Formats one sample line: `f u v x y z nx ny nz` (or `f:k ...` for sub-face `k` of a
/// non-quad), every number as the shortest text that reads back as the same `f32`.
fn format_line(buf: &mut String, face: usize, quad: bool, g: &GridSample) {
    let p = g.sample.position.as_vec3();
    let n = g.sample.normal.as_vec3();
    if quad {
        let _ = write!(buf, "{face}");
    } else {
        let _ = write!(buf, "{face}:{}", g.sub);
    }
    let _ = writeln!(
        buf,
        " {:?} {:?} {:?} {:?} {:?} {:?} {:?} {:?}",
        g.u as f32, g.v as f32, p.x, p.y, p.z, n.x, n.y, n.z
    );
}

/// One unit of streamed work: rows `rows` of the grid on sub-face `sub` of `face`.
struct Unit {
    face: usize,
    sub: usize,
    rows: std::ops::Range<usize>,
}

/// Grid points evaluated together in one unit (whole rows; at least one row).
const UNIT_POINTS: usize = 4096;

/// Runs the subcommand. The samples are evaluated block by block and streamed to the output,
/// so memory stays bounded whatever `--grid` is.
pub fn run(args: LimitArgs) -> tessera::Result<()> {
    if args.grid == 0 {
        return Err(Error::Invalid("--grid must be at least 1".into()));
    }
    let n = args.grid;
    let options = ObjOptions {
        left_handed: args.left_handed,
        ..ObjOptions::default()
    };
    let mesh = tessera::assets::load_mesh(&args.mesh, &options)?;
    super::limits::check_mesh(&mesh, &args.limits)?;
    let ev = LimitEvaluator::new(&mesh)?;
    let faces = (0..ev.face_count()).filter(|&f| ev.has_limit_surface(f));
    let row = (n as u64) + 1;
    let total: u64 = faces
        .clone()
        .map(|f| ev.sub_face_count(f) as u64 * row * row)
        .sum();
    if total == 0 {
        return Err(Error::NothingToDraw(format!(
            "{}: no face has a limit surface (every face is a hole or touches an \
             uninterpolated boundary)",
            args.mesh
        )));
    }
    let rows_per_unit = (UNIT_POINTS / (n + 1)).max(1);
    let units = faces.flat_map(|f| {
        (0..ev.sub_face_count(f)).flat_map(move |sub| {
            (0..=n).step_by(rows_per_unit).map(move |j0| Unit {
                face: f,
                sub,
                rows: j0..(j0 + rows_per_unit).min(n + 1),
            })
        })
    });
    let (mut w, name) = super::stream::open_output(args.out.as_deref())?;
    let mut progress =
        super::stream::Progress::new("samples", total, !log::log_enabled!(log::Level::Info));
    super::stream::write_ordered(
        units,
        |u| u.rows.len() as u64 * row,
        |u, s| {
            let uv: Vec<(f64, f64)> = u
                .rows
                .clone()
                .flat_map(|j| (0..=n).map(move |i| (i as f64 / n as f64, j as f64 / n as f64)))
                .collect();
            let quad = mesh.face_size(u.face) == 4;
            for (&(uu, vv), sample) in uv.iter().zip(ev.eval_points(u.face, u.sub, &uv)?) {
                let g = GridSample {
                    sub: u.sub,
                    u: uu,
                    v: vv,
                    sample,
                };
                format_line(s, u.face, quad, &g);
            }
            Ok(())
        },
        &mut w,
        &name,
        &mut progress,
    )
}
