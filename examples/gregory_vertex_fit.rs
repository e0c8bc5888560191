//! Edge-tangent factors fitted per vertex on one mesh (issue 10, part 1): what a factor per
//! vertex and crease sector, fitted once on the rest pose and then frozen, can do for the
//! level-0 Gregory patches. Every control point stays a fixed linear combination of the
//! control points (a factor is a constant per vertex, like a crease sharpness), so such a
//! rule would keep the stencils, the GPU construction and animation.
//!
//! The fit is `tessera::patch::gregory::vertex_fit` (what `--gregory-tangents fitted` runs at
//! plan build, crease sectors only); with `smooth` it also fits, per smooth vertex of valence
//! other than 4, the factor `s` on its edge tangents (`e_j = p + s 2/3 λ q_j`), which no
//! scheme carries. Prints the RMS normal distance per round (of the faces at free vertices)
//! and the fitted factors beside the construction's, and writes
//! `OUTDIR/construction.txt` and `OUTDIR/fitted.txt` (regular faces from the exact surface,
//! Gregory faces sampled on the level-16 lattice) for `tools/osd_eval/metro.py`:
//!
//! ```sh
//! cargo run --release --example gregory_vertex_fit -- MESH.obj OUTDIR [smooth] [rest=REST.obj]
//! tessera limit MESH.obj --grid 32 --out exact.txt
//! python3 tools/osd_eval/metro.py exact.txt OUTDIR/fitted.txt DIAGONAL
//! ```
//!
//! With `rest=REST.obj` (the same topology in another pose) the factors are fitted on `REST`
//! and applied, frozen, to `MESH`: what an animated mesh whose factors were fitted once on its
//! rest pose would draw.

use glam::DVec3;
use std::fmt::Write as _;
use tessera::mesh::ObjOptions;
use tessera::patch::gregory::vertex_fit::{with_offsets, VertexFit};
use tessera::patch::gregory::{check_face_level0, gregory_faces, gregory_patch};
use tessera::patch::regular::RegularPatch;
use tessera::subdiv::eval::LimitEvaluator;
use tessera::topology::Topology;
use tessera::ControlMesh;

/// Output lattice (uniform level 16).
const OUT_GRID: usize = 16;

fn write_line(out: &mut String, key: u32, u: f64, v: f64, p: DVec3, n: DVec3) {
    let _ = writeln!(
        out,
        "{key} {u} {v} {} {} {} {} {} {}",
        p.x, p.y, p.z, n.x, n.y, n.z
    );
}

fn lattice() -> Vec<(f64, f64)> {
    let g = OUT_GRID as f64;
    (0..=OUT_GRID)
        .flat_map(|j| (0..=OUT_GRID).map(move |i| (i as f64 / g, j as f64 / g)))
        .collect()
}

/// One mesh with its topology and exact surface.
struct Setup {
    mesh: ControlMesh,
    topo: Topology,
    ev: LimitEvaluator,
}

impl Setup {
    fn new(path: &str) -> tessera::Result<Setup> {
        let mesh = ControlMesh::from_obj_file(path, &ObjOptions::default())?;
        let topo = Topology::new(&mesh)?;
        let ev = LimitEvaluator::new(&mesh)?;
        Ok(Setup { mesh, topo, ev })
    }

    fn fit(&self, smooth: bool) -> VertexFit<'_> {
        VertexFit::new(&self.topo, self.mesh.positions(), smooth)
    }

    /// Writes every level-0 Gregory face of `fit` with factor offsets `x` (CPU evaluation)
    /// and the regular faces (exact).
    fn write(&self, fit: &VertexFit, path: &std::path::Path, x: &[f64]) -> tessera::Result<()> {
        let (topo, uv) = (&self.topo, lattice());
        let verts = with_offsets(&fit.base, &fit.factors, x);
        let faces: Vec<u32> = gregory_faces(topo)
            .into_iter()
            .filter(|&f| check_face_level0(topo, f).is_ok())
            .collect();
        let mut out = String::new();
        for f in 0..topo.face_count() as u32 {
            if faces.contains(&f) {
                let patch = gregory_patch(topo, &verts, f)
                    .map_err(|e| tessera::Error::Invalid(e.to_string()))?;
                let tri = patch.corner_count() == 3;
                for &(u, v) in uv.iter().filter(|(u, v)| !tri || u + v <= 1.0 + 1e-12) {
                    let s = patch.eval(u, v);
                    write_line(&mut out, f, u, v, s.position, s.normal());
                }
            } else if topo.face_size(f) == 4 && RegularPatch::gather(topo, f).is_some() {
                for (&(u, v), s) in uv.iter().zip(self.ev.eval_points(f as usize, 0, &uv)?) {
                    write_line(&mut out, f, u, v, s.position, s.normal);
                }
            }
        }
        std::fs::write(path, out).map_err(|e| tessera::Error::Invalid(e.to_string()))
    }
}

fn main() -> tessera::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let (path, dir) = (&args[1], std::path::PathBuf::from(&args[2]));
    let smooth = args.iter().any(|a| a == "smooth");
    let rest = args.iter().find_map(|a| a.strip_prefix("rest="));
    std::fs::create_dir_all(&dir).map_err(|e| tessera::Error::Invalid(e.to_string()))?;
    let pose = Setup::new(path)?;
    let pose_fit = pose.fit(smooth);
    let diagonal = pose.mesh.bbox_diagonal();
    let (x, rms) = match rest {
        Some(rest) => {
            let rest = Setup::new(rest)?;
            let rest_fit = rest.fit(smooth);
            if rest.topo.vertex_count() != pose.topo.vertex_count()
                || rest_fit.factors.len() != pose_fit.factors.len()
            {
                return Err(tessera::Error::Invalid(
                    "the rest mesh's topology differs from the pose's".into(),
                ));
            }
            println!("fit on the rest pose:");
            let (x, rms) = rest_fit.fit(&rest.ev)?;
            (
                x,
                rms.iter().map(|r| r / rest.mesh.bbox_diagonal()).collect(),
            )
        }
        None => {
            let (x, rms) = pose_fit.fit(&pose.ev)?;
            (x, rms.iter().map(|r| r / diagonal).collect::<Vec<_>>())
        }
    };
    for (round, r) in rms.iter().enumerate() {
        println!("round {round}: RMS normal distance / diagonal {r:.4e} (faces at free vertices)");
    }
    for (u, dx) in pose_fit.factors.iter().zip(&x) {
        println!(
            "vertex {} ({}): construction {:.4}, fitted {:.4}",
            u.vertex,
            u.label,
            u.start,
            u.start + dx
        );
    }
    pose.write(
        &pose_fit,
        &dir.join("construction.txt"),
        &vec![0.0; x.len()],
    )?;
    pose.write(&pose_fit, &dir.join("fitted.txt"), &x)?;
    println!("diagonal {diagonal}");
    Ok(())
}
