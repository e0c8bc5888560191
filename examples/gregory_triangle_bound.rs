//! What any rule for the triangular Gregory patch's free control points can achieve: per triangle
//! face, the control points a rule would choose are least-squares fitted to the exact limit
//! surface (`LimitEvaluator`), and every Gregory face is written as samples in the capture format
//! (`f u v x y z nx ny nz`) for `tools/osd_eval/metro.py`, beside the construction itself.
//!
//! ```sh
//! cargo run --release --example gregory_triangle_bound -- MESH.obj OUTDIR [paper|optimal]
//! tessera limit MESH.obj --grid 32 --out exact.txt
//! python3 tools/osd_eval/metro.py exact.txt OUTDIR/fit_shared.txt DIAGONAL
//! ```
//!
//! Six fits (files `OUTDIR/NAME.txt`; `construction.txt` is the construction itself, with the
//! tangents of the third argument, `optimal` by default, or a number: `GregoryTangents::Scaled`),
//! all keeping the corner points (the exact limit points, shared by every face at the vertex):
//! - `fit_faces`: the edge curves stay the construction's (shared with the neighbours, what
//!   bitwise watertightness fixes); the six face points of each triangle are fitted;
//! - `fit_edges`: the six edge points are fitted too, per patch (edge curves no longer shared:
//!   not a watertight surface, the loosest bound);
//! - `fit_shared`: one global fit of every triangle's face points and of the edge points of every
//!   edge between two Gregory triangles, each shared by both faces (watertight; edges next to
//!   other faces keep the construction's curves): the bound on any rule for edge-tangent lengths,
//!   directions and interior points, G1 or not;
//! - `fit_shared_normals`: the same with both derivatives' normal components in the objective
//!   (weight `NORMAL_WEIGHT`), trading distance for normals;
//! - `fit_shared_plane`: `fit_shared_normals` with every fitted edge point in the exact tangent
//!   plane at its corner (as every Gregory rule keeps it, so that the corner normal is exact);
//! - `fit_shared_length`: `fit_shared_normals` with every fitted edge point on the
//!   construction's edge tangent, its length free per directed edge (rules for tangent lengths
//!   and interior points only).
//!
//! The fit is geometric, not parametric (a Gregory triangle is not parameterised like the three
//! quads Catmull-Clark makes of a triangle): samples at barycentric `(i/G, j/G)`, each paired with
//! the closest exact point of the current patch (`gregory::accuracy::closest_exact`), and the
//! squared normal distance plus `EPS²` times the squared tangential offset minimised; repeated
//! (ICP) until the pairs settle. Quads keep the construction; regular faces are written from the
//! exact surface (the GPU draws them exactly). Each file is sampled on the lattice of uniform
//! level 16 (quads `(i/16, j/16)`, triangles barycentric `(i/16, j/16)`).

use glam::DVec3;
use std::fmt::Write as _;
use tessera::mesh::ObjOptions;
use tessera::patch::gregory::accuracy::{closest_exact, nearby_exact_samples};
use tessera::patch::gregory::{
    check_face, gregory_faces, gregory_patch, gregory_vertices_with, GregoryPatch, GregoryTangents,
    GregoryTriangle,
};
use tessera::subdiv::eval::LimitEvaluator;
use tessera::topology::Topology;
use tessera::ControlMesh;

/// Samples per triangle side of the fit.
const FIT_GRID: usize = 12;
/// Weight of the tangential offset against the normal distance.
const EPS: f64 = 0.1;
/// Weight of the derivatives' normal components in `fit_shared_normals` (a derivative is about
/// one face side long, so this weighs an angle error like a distance of a quarter side).
const NORMAL_WEIGHT: f64 = 0.25;
/// ICP rounds.
const ROUNDS: usize = 8;
/// Output lattice (uniform level 16).
const OUT_GRID: usize = 16;

/// The control points a fit may move: `(kind, corner)` of the 15, kinds
/// `[p, e_plus, e_minus, f_plus, f_minus]` (every one but the corner points).
fn free_slots() -> Vec<(usize, usize)> {
    [1, 2, 3, 4]
        .iter()
        .flat_map(|&k| (0..3).map(move |i| (k, i)))
        .collect()
}

fn slot(t: &mut GregoryTriangle, (k, i): (usize, usize)) -> &mut DVec3 {
    match k {
        0 => &mut t.p[i],
        1 => &mut t.e_plus[i],
        2 => &mut t.e_minus[i],
        3 => &mut t.f_plus[i],
        _ => &mut t.f_minus[i],
    }
}

/// The basis function of each slot at barycentric `(s, t)` (the patch is linear in its control
/// points once the face-point blends are fixed by the parameter), and those of the two (§4.4)
/// derivatives: `[b, b_s, b_t]`.
fn basis_d(slots: &[(usize, usize)], s: f64, t: f64) -> Vec<[f64; 3]> {
    slots
        .iter()
        .map(|&sl| {
            let mut unit = GregoryTriangle {
                p: [DVec3::ZERO; 3],
                e_plus: [DVec3::ZERO; 3],
                e_minus: [DVec3::ZERO; 3],
                f_plus: [DVec3::ZERO; 3],
                f_minus: [DVec3::ZERO; 3],
            };
            *slot(&mut unit, sl) = DVec3::X;
            let x = unit.eval(s, t);
            [x.position.x, x.du.x, x.dv.x]
        })
        .collect()
}

/// Solves the symmetric positive definite `a x = b` (Cholesky, `n × n` row-major).
fn solve(mut a: Vec<f64>, mut b: Vec<f64>, n: usize) -> Vec<f64> {
    for j in 0..n {
        let mut d = a[j * n + j];
        for k in 0..j {
            d -= a[j * n + k] * a[j * n + k];
        }
        let d = d.max(1e-300).sqrt();
        a[j * n + j] = d;
        for i in j + 1..n {
            let mut x = a[i * n + j];
            for k in 0..j {
                x -= a[i * n + k] * a[j * n + k];
            }
            a[i * n + j] = x / d;
        }
    }
    for i in 0..n {
        for k in 0..i {
            b[i] -= a[i * n + k] * b[k];
        }
        b[i] /= a[i * n + i];
    }
    for i in (0..n).rev() {
        for k in i + 1..n {
            b[i] -= a[k * n + i] * b[k];
        }
        b[i] /= a[i * n + i];
    }
    b
}

fn tri_params(g: usize) -> Vec<(f64, f64)> {
    (0..=g)
        .flat_map(|j| (0..=g - j).map(move |i| (i as f64 / g as f64, j as f64 / g as f64)))
        .collect()
}

/// Which edge points a fit moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Edges {
    /// None: the construction's edge curves.
    Fixed,
    /// Each patch its own (not watertight).
    PerPatch,
    /// Those of edges between two triangles, shared by both.
    Shared(EdgeFreedom),
}

/// How the shared fit may move an edge point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum EdgeFreedom {
    /// Anywhere.
    Free,
    /// In the exact tangent plane at its corner.
    Plane,
    /// Along the construction's edge tangent (its length per directed edge).
    Length,
}

/// ICP fit of every triangle's face points (private) and of the edge points `edges` names (with
/// `Edges::Shared` those of every edge between two Gregory triangles, shared by both faces, so the
/// surface stays watertight; edge points on edges next to other faces keep the construction's).
fn fit(
    topo: &Topology,
    ev: &LimitEvaluator,
    candidates: &[Vec<tessera::patch::gregory::accuracy::Located>],
    faces: &[u32],
    start: &[GregoryTriangle],
    normal_weight: f64,
    edges: Edges,
) -> tessera::Result<Vec<GregoryTriangle>> {
    let tri_edge = |a: u32, b: u32| {
        topo.find_edge(a, b).is_some_and(|e| {
            topo.edge_faces(e)
                .iter()
                .all(|g| faces.contains(g) && topo.face_size(*g) == 3)
        })
    };
    let mut ids: std::collections::HashMap<(u32, u32, u32), usize> = Default::default();
    let mut next = 0usize;
    let mut id = |key: (u32, u32, u32)| -> usize {
        *ids.entry(key).or_insert_with(|| {
            next += 1;
            next - 1
        })
    };
    // Per face, per slot of `free_slots()`: the unknown or None (fixed).
    let all = free_slots();
    let index: Vec<Vec<Option<usize>>> = faces
        .iter()
        .map(|&f| {
            let fv = topo.face_vertices(f);
            all.iter()
                .map(|&(k, i)| match k {
                    1 | 2 => {
                        let other = if k == 1 {
                            fv[(i + 1) % 3]
                        } else {
                            fv[(i + 2) % 3]
                        };
                        match edges {
                            Edges::Fixed => None,
                            Edges::PerPatch => Some(id((f, k as u32, i as u32))),
                            Edges::Shared(_) => {
                                tri_edge(fv[i], other).then(|| id((fv[i], other, u32::MAX)))
                            }
                        }
                    }
                    _ => Some(id((f, k as u32, i as u32))),
                })
                .collect()
        })
        .collect();
    // Each unknown point is `origin + Σ u_k axis_k`: free in space, or an edge point in the
    // exact tangent plane at its corner (what keeps the corner normal exact), or on the
    // construction's edge tangent (its length free).
    let mut frames: Vec<(DVec3, Vec<DVec3>)> =
        vec![(DVec3::ZERO, vec![DVec3::X, DVec3::Y, DVec3::Z]); next];
    if let Edges::Shared(freedom @ (EdgeFreedom::Plane | EdgeFreedom::Length)) = edges {
        for (t, &f) in faces.iter().enumerate() {
            for (i, &(k, c)) in all.iter().enumerate() {
                if let (1 | 2, Some(g)) = (k, index[t][i]) {
                    let p = start[t].p[c];
                    frames[g] = if freedom == EdgeFreedom::Plane {
                        let nrm = ev.eval(f as usize, c, 0.0, 0.0)?.normal;
                        let t1 = nrm.any_orthonormal_vector();
                        (p, vec![t1, nrm.cross(t1)])
                    } else {
                        let mut tri = start[t];
                        (p, vec![*slot(&mut tri, all[i]) - p])
                    };
                }
            }
        }
    }
    let mut offset = Vec::with_capacity(next);
    let mut n = 0;
    for (_, axes) in &frames {
        offset.push(n);
        n += axes.len();
    }
    let params = tri_params(FIT_GRID);
    let bases: Vec<Vec<[f64; 3]>> = params.iter().map(|&(s, t)| basis_d(&all, s, t)).collect();
    let mut cur = start.to_vec();
    for _ in 0..ROUNDS {
        let mut a = vec![0.0; n * n];
        let mut b = vec![0.0; n];
        for (t, &f) in faces.iter().enumerate() {
            for (k, &(s, u)) in params.iter().enumerate() {
                let here = cur[t].eval(s, u);
                let g = here.position;
                let close = closest_exact(ev, g, &candidates[t], f)?;
                let (l, nrm) = (close.sample.position, close.sample.normal);
                let bs = &bases[k];
                // The free part of the position and of both derivatives.
                let mut x = [DVec3::ZERO; 3];
                let mut tri = cur[t];
                for (i, &sl) in all.iter().enumerate() {
                    if index[t][i].is_some() {
                        for (d, xd) in x.iter_mut().enumerate() {
                            *xd += bs[i][d] * *slot(&mut tri, sl);
                        }
                    }
                }
                let target = l - (g - x[0]);
                // Rows `(derivative, direction, rhs)`: the normal distance, EPS times each
                // coordinate, and (with `normal_weight`) both derivatives' normal components
                // (zero when the patch normal is the exact one).
                let mut rows: Vec<(usize, DVec3, f64)> = vec![(0, nrm, nrm.dot(target))];
                for e in [DVec3::X, DVec3::Y, DVec3::Z] {
                    rows.push((0, EPS * e, EPS * e.dot(target)));
                }
                if normal_weight > 0.0 {
                    let w = normal_weight;
                    rows.push((1, w * nrm, -w * nrm.dot(here.du - x[1])));
                    rows.push((2, w * nrm, -w * nrm.dot(here.dv - x[2])));
                }
                for (d, dir, mut rhs) in rows {
                    let mut coef: Vec<(usize, f64)> = Vec::new();
                    for (i, gi) in index[t].iter().enumerate() {
                        let Some(gi) = *gi else { continue };
                        let (origin, axes) = &frames[gi];
                        rhs -= bs[i][d] * dir.dot(*origin);
                        for (q, axis) in axes.iter().enumerate() {
                            let w = bs[i][d] * dir.dot(*axis);
                            if w != 0.0 {
                                coef.push((offset[gi] + q, w));
                            }
                        }
                    }
                    for &(p, wp) in &coef {
                        b[p] += wp * rhs;
                        for &(q, wq) in &coef {
                            a[p * n + q] += wp * wq;
                        }
                    }
                }
            }
        }
        for i in 0..n {
            a[i * n + i] += 1e-12;
        }
        let x = solve(a, b, n);
        for (t, tri) in cur.iter_mut().enumerate() {
            for (i, &sl) in all.iter().enumerate() {
                if let Some(g) = index[t][i] {
                    let (origin, axes) = &frames[g];
                    *slot(tri, sl) = axes
                        .iter()
                        .enumerate()
                        .fold(*origin, |acc, (q, axis)| acc + x[offset[g] + q] * *axis);
                }
            }
        }
    }
    Ok(cur)
}

/// The fitted edge-tangent lengths of `fit_shared_length` relative to the construction's,
/// `(e_fit − p)·(e − p) / |e − p|²`, grouped by the faces at the corner (the valence of an
/// interior vertex) and the triangles among them: `faces triangles count mean min max`.
fn print_lengths(
    topo: &Topology,
    faces: &[u32],
    start: &[GregoryTriangle],
    fitted: &[GregoryTriangle],
) {
    let mut groups: std::collections::BTreeMap<(usize, usize), Vec<f64>> = Default::default();
    for (t, &f) in faces.iter().enumerate() {
        for c in 0..3 {
            let v = topo.face_vertices(f)[c];
            let ring = topo.vertex_faces(v);
            let tris = ring.iter().filter(|&&g| topo.face_size(g) == 3).count();
            let p = start[t].p[c];
            for (e0, e1) in [
                (start[t].e_plus[c], fitted[t].e_plus[c]),
                (start[t].e_minus[c], fitted[t].e_minus[c]),
            ] {
                if e0 != e1 {
                    let d = e0 - p;
                    groups
                        .entry((ring.len(), tris))
                        .or_default()
                        .push((e1 - p).dot(d) / d.length_squared());
                }
            }
        }
    }
    println!("fitted edge length / construction's: faces triangles count mean min max");
    for ((n, k), a) in groups {
        let mean = a.iter().sum::<f64>() / a.len() as f64;
        let (lo, hi) = a
            .iter()
            .fold((f64::MAX, f64::MIN), |(l, h), &x| (l.min(x), h.max(x)));
        println!("{n} {k} {} {mean:.3} {lo:.3} {hi:.3}", a.len());
    }
}

fn write(dir: &std::path::Path, name: &str, text: &str) -> tessera::Result<()> {
    std::fs::write(dir.join(format!("{name}.txt")), text)
        .map_err(|e| tessera::Error::Invalid(e.to_string()))
}

fn write_line(out: &mut String, key: &str, u: f64, v: f64, p: DVec3, n: DVec3) {
    let _ = writeln!(
        out,
        "{key} {u} {v} {} {} {} {} {} {}",
        p.x, p.y, p.z, n.x, n.y, n.z
    );
}

fn main() -> tessera::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let (path, dir) = (&args[1], std::path::PathBuf::from(&args[2]));
    let tangents: GregoryTangents = args
        .get(3)
        .map(|s| match s.parse::<f64>() {
            Ok(x) => GregoryTangents::Scaled(x),
            Err(_) => s.parse().unwrap(),
        })
        .unwrap_or(GregoryTangents::Optimal);
    std::fs::create_dir_all(&dir).map_err(|e| tessera::Error::Invalid(e.to_string()))?;
    let mesh = if let Some(name) = path.strip_prefix("embedded:") {
        tessera::assets::EmbeddedMesh::from_name(name)
            .ok_or_else(|| tessera::Error::Invalid(format!("no embedded mesh {name}")))?
            .load()?
    } else {
        ControlMesh::from_obj_file(path, &ObjOptions::default())?
    };
    let topo = Topology::new(&mesh)?;
    let ev = LimitEvaluator::new(&mesh)?;
    let verts = gregory_vertices_with(&topo, mesh.positions(), tangents);
    let dense = ev.eval_all_grids(2 * FIT_GRID)?;
    let gregory: Vec<u32> = gregory_faces(&topo)
        .into_iter()
        .filter(|&f| check_face(&topo, f).is_ok())
        .collect();
    let mut files = [String::new(), String::new(), String::new()];
    let mut shared = String::new();
    let (mut tri_faces, mut tri_start, mut tri_cands) = (Vec::new(), Vec::new(), Vec::new());
    let quad_uv: Vec<(f64, f64)> = (0..=OUT_GRID)
        .flat_map(|j| (0..=OUT_GRID).map(move |i| (i as f64, j as f64)))
        .map(|(i, j)| (i / OUT_GRID as f64, j / OUT_GRID as f64))
        .collect();
    for f in 0..topo.face_count() as u32 {
        let key = f.to_string();
        if !gregory.contains(&f) {
            // Regular faces (drawn exactly); CPU-path faces are in no file.
            if topo.face_size(f) == 4
                && tessera::patch::regular::RegularPatch::gather(&topo, f).is_some()
            {
                let s = ev.eval_points(f as usize, 0, &quad_uv)?;
                for file in files.iter_mut().chain([&mut shared]) {
                    for (&(u, v), x) in quad_uv.iter().zip(&s) {
                        write_line(file, &key, u, v, x.position, x.normal);
                    }
                }
            }
            continue;
        }
        let patch =
            gregory_patch(&topo, &verts, f).map_err(|e| tessera::Error::Invalid(e.to_string()))?;
        match patch {
            GregoryPatch::Quad(q) => {
                for file in files.iter_mut().chain([&mut shared]) {
                    for &(u, v) in &quad_uv {
                        let x = q.eval(u, v);
                        write_line(file, &key, u, v, x.position, x.normal());
                    }
                }
            }
            GregoryPatch::Triangle(t) => {
                let candidates = nearby_exact_samples(&topo, &dense, f);
                let one = std::slice::from_ref(&candidates);
                let fa = fit(&topo, &ev, one, &[f], &[t], 0.0, Edges::Fixed)?[0];
                let fb = fit(&topo, &ev, one, &[f], &[t], 0.0, Edges::PerPatch)?[0];
                tri_faces.push(f);
                tri_start.push(t);
                tri_cands.push(candidates);
                for (file, tri) in files.iter_mut().zip([t, fa, fb]) {
                    for (u, v) in tri_params(OUT_GRID) {
                        let x = tri.eval(u, v);
                        write_line(file, &key, u, v, x.position, x.normal());
                    }
                }
            }
        }
    }
    let names = [
        "fit_shared",
        "fit_shared_normals",
        "fit_shared_plane",
        "fit_shared_length",
    ];
    let runs = [
        (0.0, EdgeFreedom::Free),
        (NORMAL_WEIGHT, EdgeFreedom::Free),
        (NORMAL_WEIGHT, EdgeFreedom::Plane),
        (NORMAL_WEIGHT, EdgeFreedom::Length),
    ];
    for (name, (weight, freedom)) in names.iter().zip(runs) {
        let mut out = shared.clone();
        let fitted = fit(
            &topo,
            &ev,
            &tri_cands,
            &tri_faces,
            &tri_start,
            weight,
            Edges::Shared(freedom),
        )?;
        for (&f, tri) in tri_faces.iter().zip(&fitted) {
            for (u, v) in tri_params(OUT_GRID) {
                let x = tri.eval(u, v);
                write_line(&mut out, &f.to_string(), u, v, x.position, x.normal());
            }
        }
        write(&dir, name, &out)?;
        if freedom == EdgeFreedom::Length {
            print_lengths(&topo, &tri_faces, &tri_start, &fitted);
        }
    }
    for (name, text) in ["construction", "fit_faces", "fit_edges"]
        .iter()
        .zip(&files)
    {
        write(&dir, name, text)?;
    }
    println!("diagonal {}", mesh.bbox_diagonal());
    Ok(())
}
