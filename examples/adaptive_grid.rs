//! The CPU feature-adaptive surface (`AdaptiveSurface`: the patches `--scheme adaptive` draws,
//! end caps included) sampled at chosen points, in `tessera limit`'s `f u v x y z nx ny nz`
//! lines (`f:k` for sub-face k of a non-quad) with two appended columns, the patch type and
//! level, so `tools/osd_eval/compare.py` measures it against the exact limit beside
//! OpenSubdiv's patches at the same points (`osd_eval MESH L - < points`), at any isolation.
//! The points: `grid:N`, the grid of `tessera limit --grid N`; `endcaps:K`, a K x K grid of each
//! end cap's own (s, t) (the GPU capture at `--tess N` draws a level-L end cap with only
//! N / 2^L segments, too few from L = 3). With `exact` the same points are written with
//! `LimitEvaluator`'s position and normal instead (the type columns stay the patch's).
//!
//! ```sh
//! cargo run --release --example adaptive_grid -- MESH.obj ISOLATION grid:N|endcaps:K [single-crease] [smooth] [exact] > a.txt
//! ```
//! `single-crease`: stop at single-crease patches; `smooth`: OpenSubdiv's smooth end caps
//! (`EndCapSharpness::Smooth`) instead of the default crease end caps.

use std::io::Write;

use tessera::mesh::ObjOptions;
use tessera::patch::adaptive::AdaptiveSurface;
use tessera::subdiv::adaptive::{AdaptiveOptions, AdaptiveRefinement, EndCapSharpness, PatchType};
use tessera::subdiv::eval::LimitEvaluator;
use tessera::subdiv::Level;
use tessera::ControlMesh;

/// Where to sample.
enum Points {
    /// `tessera limit --grid N`'s points of every face with a limit surface.
    Grid(usize),
    /// A K x K grid of each end cap's own (s, t), corners included.
    EndCaps(usize),
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage =
        "usage: adaptive_grid MESH.obj ISOLATION grid:N|endcaps:K [single-crease] [smooth] [exact]";
    let (Some(spec), Some(iso), Some(points)) = (args.first(), args.get(1), args.get(2)) else {
        return Err(usage.into());
    };
    let points = match points.split_once(':') {
        Some(("grid", n)) => Points::Grid(n.parse()?),
        Some(("endcaps", k)) => Points::EndCaps(n_at_least(k.parse()?, 2)?),
        _ => return Err(usage.into()),
    };
    let flag = |name: &str| args.iter().skip(3).any(|a| a == name);
    let options = AdaptiveOptions {
        single_crease: flag("single-crease"),
        end_cap_sharpness: if flag("smooth") {
            EndCapSharpness::Smooth
        } else {
            EndCapSharpness::Crease
        },
        ..AdaptiveOptions::new(iso.parse()?)
    };
    let mesh = ControlMesh::from_obj_file(spec, &ObjOptions::default())?;
    let base = Level::from_mesh(&mesh)?;
    let refinement = AdaptiveRefinement::with_options(&base, options)?;
    let surface = AdaptiveSurface::new(&refinement, mesh.positions())?;
    let exact = flag("exact")
        .then(|| LimitEvaluator::new(&mesh))
        .transpose()?;
    let topo = base.topology();
    // (base face, sub-face, u, v) of every point.
    let mut at: Vec<(u32, Option<u32>, f64, f64)> = Vec::new();
    match points {
        Points::Grid(n) => {
            let n = n_at_least(n, 1)?;
            for f in (0..topo.face_count() as u32).filter(|&f| topo.has_limit_surface(f)) {
                let size = topo.face_size(f) as u32;
                let subs: Vec<Option<u32>> = match size {
                    4 => vec![None],
                    _ => (0..size).map(Some).collect(),
                };
                for sub in subs {
                    for j in 0..=n {
                        for i in 0..=n {
                            at.push((f, sub, i as f64 / n as f64, j as f64 / n as f64));
                        }
                    }
                }
            }
        }
        Points::EndCaps(k) => {
            let end_caps = surface
                .patches
                .iter()
                .filter(|p| p.kind == PatchType::EndCap);
            for p in end_caps {
                let d = &p.domain;
                for j in 0..k {
                    for i in 0..k {
                        let (s, t) = (i as f64 / (k - 1) as f64, j as f64 / (k - 1) as f64);
                        let x = d.origin + s * d.u + t * d.v;
                        at.push((d.base_face, d.sub_face, x.x, x.y));
                    }
                }
            }
        }
    }
    let out = std::io::stdout();
    let mut w = std::io::BufWriter::new(out.lock());
    for (f, sub, u, v) in at {
        let Some((i, s, t)) = surface.locate(f, sub, u, v) else {
            continue;
        };
        let (p, n) = match &exact {
            Some(ev) => {
                let e = ev.eval(f as usize, sub.unwrap_or(0) as usize, u, v)?;
                (e.position, e.normal)
            }
            // The normal the GPU draws (shared on promoted creases, `AdaptiveSurface::normal`).
            None => {
                let (p, n) = surface.eval_with_normal(i, s, t);
                (p.position, n)
            }
        };
        let patch = &surface.patches[i];
        let face = match sub {
            None => format!("{f}"),
            Some(k) => format!("{f}:{k}"),
        };
        writeln!(
            w,
            "{face} {u:?} {v:?} {:?} {:?} {:?} {:?} {:?} {:?} {} {}",
            p.x,
            p.y,
            p.z,
            n.x,
            n.y,
            n.z,
            patch.kind.name(),
            patch.level
        )?;
    }
    Ok(())
}

/// `n` if it is at least `min`.
fn n_at_least(n: usize, min: usize) -> Result<usize, String> {
    (n >= min)
        .then_some(n)
        .ok_or_else(|| format!("{n}: must be at least {min}"))
}
