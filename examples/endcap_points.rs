//! The 20 Gregory points of tessera's end caps (`AdaptiveSurface`, the construction the GPU
//! draws) at chosen points, beside OpenSubdiv's for the same end caps
//! (`osd_eval MESH L - patch-points`, `tools/osd_eval/README.md`): reads `f u v` / `f:k u v`
//! lines (the first three columns of `adaptive_grid`'s output) from standard input and writes,
//! per point inside a quad end cap, a `# f:k u v level L face F` line then one
//! `corner P|Ep|Em|Fp|Fm x y z` line per point (corner `i` is the level-L face's vertex `i`, as
//! OpenSubdiv's Gregory basis; `Ep` / `Fp` towards / next to the edge `i -> i + 1`).
//!
//! ```sh
//! echo "956:0 0.01171875 0.0234375" > p.txt
//! cargo run --release --example endcap_points -- catmark_bishop.obj 6 < p.txt > t.txt
//! osd_eval catmark_bishop.obj 6 - patch-points < p.txt > o.txt
//! ```

use std::io::{BufRead, Write};

use tessera::mesh::ObjOptions;
use tessera::patch::adaptive::{AdaptiveSurface, PatchShape};
use tessera::patch::gregory::GregoryPatch;
use tessera::subdiv::adaptive::{AdaptiveOptions, AdaptiveRefinement};
use tessera::subdiv::Level;
use tessera::ControlMesh;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(spec), Some(iso)) = (args.first(), args.get(1)) else {
        return Err("usage: endcap_points MESH.obj ISOLATION < points".into());
    };
    let mesh = ControlMesh::from_obj_file(spec, &ObjOptions::default())?;
    let base = Level::from_mesh(&mesh)?;
    let refinement = AdaptiveRefinement::with_options(&base, AdaptiveOptions::new(iso.parse()?))?;
    let surface = AdaptiveSurface::new(&refinement, mesh.positions())?;
    let out = std::io::stdout();
    let mut w = std::io::BufWriter::new(out.lock());
    for line in std::io::stdin().lock().lines() {
        let line = line?;
        let cols: Vec<&str> = line.split_whitespace().collect();
        let [face, u, v, ..] = cols[..] else {
            continue;
        };
        let (f, sub) = match face.split_once(':') {
            Some((f, k)) => (f.parse()?, Some(k.parse()?)),
            None => (face.parse()?, None),
        };
        let Some((i, _, _)) = surface.locate(f, sub, u.parse()?, v.parse()?) else {
            continue;
        };
        let patch = &surface.patches[i];
        let PatchShape::Gregory(g) = &patch.shape else {
            continue;
        };
        let GregoryPatch::Quad(q) = &**g else {
            continue;
        };
        let level = patch.level;
        writeln!(w, "# {face} {u} {v} level {level} face {}", patch.face)?;
        for c in 0..4 {
            let named = [
                ("P", q.p[c]),
                ("Ep", q.e_plus[c]),
                ("Em", q.e_minus[c]),
                ("Fp", q.f_plus[c]),
                ("Fm", q.f_minus[c]),
            ];
            for (name, x) in named {
                writeln!(w, "{c} {name} {:?} {:?} {:?}", x.x, x.y, x.z)?;
            }
        }
    }
    Ok(())
}
