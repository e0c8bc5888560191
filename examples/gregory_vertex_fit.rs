//! Edge-tangent factors fitted per vertex on one mesh (issue 10, part 1): what a factor per
//! vertex and crease sector, fitted once on the rest pose and then frozen, can do for the
//! level-0 Gregory patches. Every control point stays a fixed linear combination of the
//! control points (a factor is a constant per vertex, like a crease sharpness), so such a
//! rule would keep the stencils, the GPU construction and animation.
//!
//! The unknowns, starting from `GregoryTangents::Optimal`:
//! - per crease sector that the construction gives a free length (`GregoryTangents::Scaled`
//!   scales it: three or more faces, or two faces on a band), the factor `s` on its
//!   cross-boundary tangent `s T/3` (`GregoryVertex::sectored`); the two sectors of a crease
//!   vertex get one factor each;
//! - with `smooth`, per smooth vertex of valence other than 4, the factor `s` on its edge
//!   tangents (`e_j = p + s 2/3 λ q_j`).
//!
//! Sectors of two faces off a band and valence-4 vertices keep the construction's lengths: a
//! face beside them may be a regular B-spline patch, whose edge curve they must stay.
//!
//! Every control point is affine in every factor, so the normal distance of the Gregory faces'
//! samples (12 × 12 per face) to their closest exact points (`gregory::accuracy::closest_exact`,
//! re-paired each round: ICP) is affine in the factors and each round is one linear
//! least-squares solve for all of them at once (no coordinate descent needed). Prints the RMS
//! normal distance per round and the fitted factors beside the construction's, and writes
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
use tessera::patch::gregory::accuracy::{closest_exact, nearby_exact_samples};
use tessera::patch::gregory::tangent_fit::solve_normal_equations;
use tessera::patch::gregory::tangents_tri_fit::face_samples;
use tessera::patch::gregory::{
    check_face_level0, gregory_faces, gregory_patch, gregory_vertices_with, sectors, vertex_ring,
    GregoryPatch, GregoryTangents, GregoryVertex, VertexKind,
};
use tessera::patch::regular::RegularPatch;
use tessera::subdiv::eval::LimitEvaluator;
use tessera::topology::Topology;
use tessera::ControlMesh;

/// ICP rounds.
const ROUNDS: usize = 6;
/// Output lattice (uniform level 16).
const OUT_GRID: usize = 16;

/// One free factor: the edge points it moves (`(vertex, edge, direction per unit of factor)`)
/// and the construction's value.
struct Unknown {
    vertex: u32,
    label: String,
    start: f64,
    moves: Vec<(usize, DVec3)>,
}

type Vertices = Vec<Option<GregoryVertex<DVec3>>>;

/// The free factors of the mesh (module docs).
fn unknowns(topo: &Topology, positions: &[DVec3], base: &Vertices, smooth: bool) -> Vec<Unknown> {
    let one = gregory_vertices_with(topo, positions, GregoryTangents::Scaled(1.0));
    let two = gregory_vertices_with(topo, positions, GregoryTangents::Scaled(2.0));
    let mut out = Vec::new();
    for v in 0..topo.vertex_count() {
        let (Some(g), Some(g1), Some(g2)) = (&base[v], &one[v], &two[v]) else {
            continue;
        };
        match g.kind {
            VertexKind::Crease => {
                let ring = vertex_ring(topo, positions, v as u32);
                for sec in sectors(&ring.sharp, g.n) {
                    let ne = ring.m.len();
                    let moves: Vec<(usize, DVec3)> = (1..sec.faces)
                        .map(|i| (sec.start + i) % ne)
                        .map(|j| (j, g2.e[j] - g1.e[j]))
                        .filter(|(_, d)| d.length_squared() > 0.0)
                        .collect();
                    let Some(&(j, d)) = moves.first() else {
                        continue;
                    };
                    let start = 1.0 + (g.e[j] - g1.e[j]).dot(d) / d.length_squared();
                    out.push(Unknown {
                        vertex: v as u32,
                        label: format!("crease sector of {} faces", sec.faces),
                        start,
                        moves,
                    });
                }
            }
            VertexKind::Smooth if smooth && g.n != 4 => {
                let start =
                    g1.e.iter()
                        .zip(&g.e)
                        .map(|(a, b)| (*b - g.p).length() / (*a - g.p).length())
                        .next()
                        .unwrap_or(1.0);
                out.push(Unknown {
                    vertex: v as u32,
                    label: format!("smooth valence {}", g.n),
                    start,
                    moves: g1
                        .e
                        .iter()
                        .enumerate()
                        .map(|(j, e)| (j, *e - g.p))
                        .collect(),
                });
            }
            _ => {}
        }
    }
    out
}

/// The vertices with factor offsets `x` (from the construction's) applied.
fn with_offsets(base: &Vertices, unknowns: &[Unknown], x: &[f64]) -> Vertices {
    let mut verts = base.clone();
    for (u, &dx) in unknowns.iter().zip(x) {
        let g = verts[u.vertex as usize].as_mut().expect("a Gregory vertex");
        for &(j, d) in &u.moves {
            g.e[j] += dx * d;
        }
    }
    verts
}

fn patches(topo: &Topology, verts: &Vertices, faces: &[u32]) -> Vec<GregoryPatch> {
    faces
        .iter()
        .map(|&f| gregory_patch(topo, verts, f).expect("a Gregory face"))
        .collect()
}

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

/// One mesh with its Gregory construction, faces, free factors and exact surface.
struct Setup {
    mesh: ControlMesh,
    topo: Topology,
    ev: LimitEvaluator,
    base: Vertices,
    faces: Vec<u32>,
    unknowns: Vec<Unknown>,
}

impl Setup {
    fn new(path: &str, smooth: bool) -> tessera::Result<Setup> {
        let mesh = ControlMesh::from_obj_file(path, &ObjOptions::default())?;
        let topo = Topology::new(&mesh)?;
        let ev = LimitEvaluator::new(&mesh)?;
        let base = gregory_vertices_with(&topo, mesh.positions(), GregoryTangents::Optimal);
        let faces: Vec<u32> = gregory_faces(&topo)
            .into_iter()
            .filter(|&f| check_face_level0(&topo, f).is_ok())
            .collect();
        let unknowns = unknowns(&topo, mesh.positions(), &base, smooth);
        Ok(Setup {
            mesh,
            topo,
            ev,
            base,
            faces,
            unknowns,
        })
    }

    /// The factor offsets from the construction's, fitted by ICP (module docs).
    fn fit(&self) -> tessera::Result<Vec<f64>> {
        let (topo, faces) = (&self.topo, &self.faces);
        let dense = self.ev.eval_all_grids(24)?;
        let cands: Vec<_> = faces
            .iter()
            .map(|&f| nearby_exact_samples(topo, &dense, f))
            .collect();
        let n = self.unknowns.len();
        let mut index = vec![None; topo.face_count()];
        for (i, &f) in faces.iter().enumerate() {
            index[f as usize] = Some(i);
        }
        // Per face, the unknowns that move it: those at its corners (an edge point enters
        // the patches of the faces at its vertex only, face points through eq. 6 included).
        let mut touching: Vec<Vec<usize>> = vec![Vec::new(); faces.len()];
        for (k, u) in self.unknowns.iter().enumerate() {
            for &f in topo.vertex_faces(u.vertex) {
                if let Some(i) = index[f as usize] {
                    touching[i].push(k);
                }
            }
        }
        let mut x = vec![0.0; n];
        for round in 0..=ROUNDS {
            let mut current = with_offsets(&self.base, &self.unknowns, &x);
            let now = patches(topo, &current, faces);
            // Per face, the patch with each touching unknown moved by 1 (the others at `x`), in
            // the order of `touching`.
            let mut moved: Vec<Vec<GregoryPatch>> = vec![Vec::new(); faces.len()];
            for u in &self.unknowns {
                let slot = &mut current[u.vertex as usize];
                let saved = slot.clone();
                let g = slot.as_mut().expect("a Gregory vertex");
                for &(j, d) in &u.moves {
                    g.e[j] += d;
                }
                for &f in topo.vertex_faces(u.vertex) {
                    if let Some(i) = index[f as usize] {
                        let patch = gregory_patch(topo, &current, f).expect("a Gregory face");
                        moved[i].push(patch);
                    }
                }
                current[u.vertex as usize] = saved;
            }
            let mut a = vec![vec![0.0; n]; n];
            let mut b = vec![0.0; n];
            let (mut e2, mut w) = (0.0, 0.0);
            for (i, &f) in faces.iter().enumerate() {
                for (u, v) in face_samples(topo.face_size(f) == 3) {
                    let p = now[i].eval(u, v).position;
                    let l = closest_exact(&self.ev, p, &cands[i], f)?;
                    let normal = l.sample.normal;
                    let d0 = (p - l.sample.position).dot(normal);
                    let g: Vec<f64> = moved[i]
                        .iter()
                        .map(|q| (q.eval(u, v).position - p).dot(normal))
                        .collect();
                    for (r, &kr) in touching[i].iter().enumerate() {
                        b[kr] -= d0 * g[r];
                        for (c, &kc) in touching[i].iter().enumerate() {
                            a[kr][kc] += g[r] * g[c];
                        }
                    }
                    e2 += d0 * d0;
                    w += 1.0;
                }
            }
            println!(
                "round {round}: RMS normal distance / diagonal {:.4e}",
                (e2 / w).sqrt() / self.mesh.bbox_diagonal()
            );
            if round < ROUNDS && n > 0 {
                for (xi, s) in x.iter_mut().zip(solve_normal_equations(a, b)) {
                    *xi += s;
                }
            }
        }
        Ok(x)
    }

    /// Writes the Gregory faces with factor offsets `x` and the regular faces (exact).
    fn write(&self, path: &std::path::Path, x: &[f64]) -> tessera::Result<()> {
        let (topo, uv) = (&self.topo, lattice());
        let verts = with_offsets(&self.base, &self.unknowns, x);
        let mut out = String::new();
        for f in 0..topo.face_count() as u32 {
            if self.faces.contains(&f) {
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
    let pose = Setup::new(path, smooth)?;
    let x = match rest {
        Some(rest) => {
            let rest = Setup::new(rest, smooth)?;
            if rest.topo.vertex_count() != pose.topo.vertex_count()
                || rest.unknowns.len() != pose.unknowns.len()
            {
                return Err(tessera::Error::Invalid(
                    "the rest mesh's topology differs from the pose's".into(),
                ));
            }
            println!("fit on the rest pose:");
            rest.fit()?
        }
        None => pose.fit()?,
    };
    for (u, dx) in pose.unknowns.iter().zip(&x) {
        println!(
            "vertex {} ({}): construction {:.4}, fitted {:.4}",
            u.vertex,
            u.label,
            u.start,
            u.start + dx
        );
    }
    pose.write(&dir.join("construction.txt"), &vec![0.0; x.len()])?;
    pose.write(&dir.join("fitted.txt"), &x)?;
    println!("diagonal {}", pose.mesh.bbox_diagonal());
    Ok(())
}
