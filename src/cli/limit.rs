//! `tessera limit`: the exact limit surface sampled on a grid per face.

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::PathBuf;

use clap::Args;
use rayon::prelude::*;
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

/// Runs the subcommand.
pub fn run(args: LimitArgs) -> tessera::Result<()> {
    if args.grid == 0 {
        return Err(Error::Invalid("--grid must be at least 1".into()));
    }
    let options = ObjOptions {
        left_handed: args.left_handed,
    };
    let mesh = tessera::assets::load_mesh(&args.mesh, &options)?;
    let ev = LimitEvaluator::new(&mesh)?;
    let lines: Vec<String> = (0..ev.face_count())
        .into_par_iter()
        .map(|f| -> tessera::Result<String> {
            let mut s = String::new();
            if !ev.has_limit_surface(f) {
                return Ok(s);
            }
            let quad = mesh.face_size(f) == 4;
            for g in ev.eval_grid(f, args.grid)? {
                format_line(&mut s, f, quad, &g);
            }
            Ok(s)
        })
        .collect::<tessera::Result<_>>()?;
    let io_err = |path: &str, e: std::io::Error| Error::Io {
        path: path.to_string(),
        message: e.to_string(),
    };
    match &args.out {
        Some(path) => {
            let name = path.display().to_string();
            let file = std::fs::File::create(path).map_err(|e| io_err(&name, e))?;
            let mut w = std::io::BufWriter::new(file);
            for l in &lines {
                w.write_all(l.as_bytes()).map_err(|e| io_err(&name, e))?;
            }
            w.flush().map_err(|e| io_err(&name, e))?;
        }
        None => {
            let stdout = std::io::stdout();
            let mut w = std::io::BufWriter::new(stdout.lock());
            for l in &lines {
                w.write_all(l.as_bytes())
                    .map_err(|e| io_err("<stdout>", e))?;
            }
            w.flush().map_err(|e| io_err("<stdout>", e))?;
        }
    }
    Ok(())
}
