//! What any rule for the Gregory patches' free control points can achieve: per fitted face
//! (every triangle; with `all` every Gregory face, quads too), the control points a rule would
//! choose are least-squares fitted to the exact limit surface (`LimitEvaluator`), and every
//! Gregory face is written as samples in the capture format (`f u v x y z nx ny nz`) for
//! `tools/osd_eval/metro.py`, beside the construction itself.
//!
//! ```sh
//! cargo run --release --example gregory_bound -- MESH.obj OUTDIR [paper|optimal|S] [all]
//! tessera limit MESH.obj --grid 32 --out exact.txt
//! python3 tools/osd_eval/metro.py exact.txt OUTDIR/fit_shared.txt DIAGONAL
//! ```
//!
//! Seven fits (files `OUTDIR/NAME.txt`; `construction.txt` is the construction itself, with the
//! tangents of the third argument, `optimal` by default, or a number: `GregoryTangents::Scaled`),
//! all keeping the corner points (the exact limit points, shared by every face at the vertex):
//! - `fit_faces`: the edge curves stay the construction's (shared with the neighbours, what
//!   bitwise watertightness fixes); the face points of each fitted face are fitted;
//! - `fit_edges`: its edge points are fitted too, per patch (edge curves no longer shared:
//!   not a watertight surface, the loosest bound);
//! - `fit_shared`: one global fit of every fitted face's face points and of the edge points of
//!   every smooth edge whose faces are fitted or on the CPU path, each shared by both faces
//!   (watertight; edges next to other patches keep the construction's curves, boundary and
//!   infinitely sharp edges their exact crease curves): the bound on any rule for edge-tangent
//!   lengths, directions and interior points, G1 or not;
//! - `fit_shared_normals`: the same with both derivatives' normal components in the objective
//!   (weight `NORMAL_WEIGHT`), trading distance for normals;
//! - `fit_shared_plane`: `fit_shared_normals` with every fitted edge point in the exact tangent
//!   plane at its corner (as every Gregory rule keeps it, so that the corner normal is exact);
//! - `fit_shared_length`: `fit_shared_normals` with every fitted edge point on the
//!   construction's edge tangent, its length free per directed edge (rules for tangent lengths
//!   and interior points only);
//! - `fit_shared_sector`: `fit_shared_normals` with one length per vertex or crease sector
//!   (`EdgeFreedom::Sector`: rules that keep condition (1), with any interior points).
//!
//! The fit is geometric, not parametric (a Gregory triangle is not parameterised like the three
//! quads Catmull-Clark makes of a triangle): samples at barycentric `(i/G, j/G)`, each paired with
//! the closest exact point of the current patch (`gregory::accuracy::closest_exact`), and the
//! squared normal distance plus `EPS²` times the squared tangential offset minimised; repeated
//! (ICP) until the pairs settle; quads are fitted the same way at `(i/G, j/G)`, their
//! derivatives also pulled towards the exact ones at equal `(u, v)` (`DERIVATIVE_EPS`). Quads keep the
//! construction unless `all`; regular faces are written from the exact surface (the GPU draws
//! them exactly). Each file is sampled on the lattice of uniform level 16 (quads
//! `(i/16, j/16)`, triangles barycentric `(i/16, j/16)`).

use glam::DVec3;
use std::fmt::Write as _;
use tessera::mesh::ObjOptions;
use tessera::patch::gregory::accuracy::{closest_exact, nearby_exact_samples, Located};
use tessera::patch::gregory::{
    check_face, gregory_faces, gregory_patch, gregory_vertices_with, sectors, GregoryPatch,
    GregoryTangents, GregoryVertex, VertexKind,
};
use tessera::subdiv::eval::LimitEvaluator;
use tessera::topology::{is_sharp_edge, Topology};
use tessera::ControlMesh;

/// Samples per face side of the fit.
const FIT_GRID: usize = 12;
/// Weight of the tangential offset against the normal distance.
const EPS: f64 = 0.1;
/// Weight of the derivatives' normal components in `fit_shared_normals` (a derivative is about
/// one face side long, so this weighs an angle error like a distance of a quarter side).
const NORMAL_WEIGHT: f64 = 0.25;
/// Weight of a quad's derivatives against the exact ones at equal `(u, v)` (keeps the fit from
/// folding a patch along a fixed edge, which the normal rows cannot see).
const DERIVATIVE_EPS: f64 = 0.01;
/// ICP rounds.
const ROUNDS: usize = 8;
/// Output lattice (uniform level 16).
const OUT_GRID: usize = 16;

/// The control points a fit may move: `(kind, corner)` of a patch with `corners` corners, kinds
/// `[p, e_plus, e_minus, f_plus, f_minus]` (every one but the corner points).
fn free_slots(corners: usize) -> Vec<(usize, usize)> {
    [1, 2, 3, 4]
        .iter()
        .flat_map(|&k| (0..corners).map(move |i| (k, i)))
        .collect()
}

fn slot(patch: &mut GregoryPatch, (k, i): (usize, usize)) -> &mut DVec3 {
    let [p, e_plus, e_minus, f_plus, f_minus] = match patch {
        GregoryPatch::Quad(q) => [
            &mut q.p[..],
            &mut q.e_plus[..],
            &mut q.e_minus[..],
            &mut q.f_plus[..],
            &mut q.f_minus[..],
        ],
        GregoryPatch::Triangle(t) => [
            &mut t.p[..],
            &mut t.e_plus[..],
            &mut t.e_minus[..],
            &mut t.f_plus[..],
            &mut t.f_minus[..],
        ],
    };
    match k {
        0 => &mut p[i],
        1 => &mut e_plus[i],
        2 => &mut e_minus[i],
        3 => &mut f_plus[i],
        _ => &mut f_minus[i],
    }
}

/// The basis function of each slot of a patch shaped like `shape` at `(s, t)` (the patch is
/// linear in its control points once the face-point blends are fixed by the parameter), and
/// those of the two (§4.4) derivatives: `[b, b_s, b_t]`.
fn basis_d(shape: &GregoryPatch, slots: &[(usize, usize)], s: f64, t: f64) -> Vec<[f64; 3]> {
    slots
        .iter()
        .map(|&sl| {
            let mut unit = *shape;
            for k in free_slots(shape.corner_count()) {
                *slot(&mut unit, k) = DVec3::ZERO;
            }
            for i in 0..shape.corner_count() {
                *slot(&mut unit, (0, i)) = DVec3::ZERO;
            }
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

/// The parameters of a patch with `corners` corners on a lattice of `g` steps: quads
/// `(i/g, j/g)`, triangles barycentric `(i/g, j/g)` with `i + j <= g`.
fn params(corners: usize, g: usize) -> Vec<(f64, f64)> {
    (0..=g)
        .flat_map(|j| {
            let row = if corners == 3 { g - j } else { g };
            (0..=row).map(move |i| (i as f64 / g as f64, j as f64 / g as f64))
        })
        .collect()
}

/// The parameter of corner `c` of a patch with `corners` corners.
fn corner_uv(corners: usize, c: usize) -> (f64, f64) {
    match (corners, c) {
        (3, _) => (0.0, 0.0),
        (_, 0) => (0.0, 0.0),
        (_, 1) => (1.0, 0.0),
        (_, 2) => (1.0, 1.0),
        _ => (0.0, 1.0),
    }
}

/// Which edge points a fit moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Edges {
    /// None: the construction's edge curves.
    Fixed,
    /// Each patch its own (not watertight).
    PerPatch,
    /// Those of smooth edges between two fitted faces, shared by both.
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
    /// One length per vertex (smooth) or crease sector, as a rule keeping condition (1) sets
    /// it: `p + s (e − p)` at a smooth vertex, `p + cos(iπ/k)(e_s − p) + s sin(iπ/k) T/3` in a
    /// crease sector (`GregoryVertex::sectored`, `s` on the construction's `s(k) T`); corner
    /// sectors keep the construction's (condition (1) fixes them).
    Sector,
}

/// Under [`EdgeFreedom::Sector`], the unknown, origin and axis of the edge point at `v` on the
/// edge towards `other` (the point is `origin + x axis`, the construction's at `x = 1`), or
/// `None` where it is fixed.
fn sector_frame(
    topo: &Topology,
    verts: &[Option<GregoryVertex>],
    v: u32,
    other: u32,
) -> Option<((u32, u32, u32), DVec3, DVec3)> {
    let gv = verts[v as usize].as_ref()?;
    let ring = topo.vertex_edges(v);
    let e = topo.find_edge(v, other)?;
    let j = ring.iter().position(|&x| x == e)?;
    let (p, ej) = (gv.p, gv.e[j]);
    match gv.kind {
        VertexKind::Crease => {
            let ne = ring.len();
            let sharp: Vec<bool> = ring.iter().map(|&x| is_sharp_edge(topo, x)).collect();
            let sec = sectors(&sharp, gv.n)
                .into_iter()
                .find(|s| (1..s.faces).any(|i| (s.start + i) % ne == j))?;
            let i = (j + ne - sec.start) % ne;
            let cs = (i as f64 * std::f64::consts::PI / sec.faces as f64).cos();
            let origin = p + cs * (gv.e[sec.start] - p);
            Some(((v, sec.start as u32, u32::MAX - 1), origin, ej - origin))
        }
        VertexKind::Corner => None,
        _ => Some(((v, u32::MAX - 1, u32::MAX - 1), p, ej - p)),
    }
}

/// The mesh and the faces a fit sees.
struct Setup<'a> {
    topo: &'a Topology,
    ev: &'a LimitEvaluator,
    /// Faces drawn as patches (regular and Gregory), whose edge curves a neighbour shares.
    drawn: &'a [u32],
    /// The construction's per-vertex data (for [`EdgeFreedom::Sector`]).
    verts: &'a [Option<GregoryVertex>],
    /// Per fitted face, the exact samples near it (`nearby_exact_samples`).
    candidates: &'a [Vec<Located>],
}

/// ICP fit of every face's face points (private) and of the edge points `edges` names (with
/// `Edges::Shared` those of every smooth edge whose faces are fitted or drawn on the CPU path,
/// shared by both, so the surface stays watertight; edge points on other edges keep the
/// construction's). Quads also pull their derivatives towards the exact ones at equal `(u, v)`
/// with weight `DERIVATIVE_EPS` (the normal rows only see tilts, not folds).
fn fit(
    setup: &Setup,
    faces: &[u32],
    start: &[GregoryPatch],
    normal_weight: f64,
    edges: Edges,
) -> tessera::Result<Vec<GregoryPatch>> {
    let Setup {
        topo,
        ev,
        drawn,
        verts,
        candidates,
    } = *setup;
    let shared_edge = |a: u32, b: u32| {
        topo.find_edge(a, b).is_some_and(|e| {
            !is_sharp_edge(topo, e)
                && topo
                    .edge_faces(e)
                    .iter()
                    .all(|g| faces.contains(g) || !drawn.contains(g))
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
    // Per face, per slot of `free_slots`: the unknown or None (fixed); under `Sector` with its
    // own origin and axis.
    let slots: Vec<Vec<(usize, usize)>> =
        start.iter().map(|p| free_slots(p.corner_count())).collect();
    let mut sector_axes: std::collections::HashMap<(usize, usize), (DVec3, DVec3)> =
        Default::default();
    let index: Vec<Vec<Option<usize>>> = faces
        .iter()
        .zip(&slots)
        .enumerate()
        .map(|(t, (&f, all))| {
            let fv = topo.face_vertices(f);
            let n = fv.len();
            all.iter()
                .enumerate()
                .map(|(slot_index, &(k, i))| match k {
                    1 | 2 => {
                        let other = if k == 1 {
                            fv[(i + 1) % n]
                        } else {
                            fv[(i + n - 1) % n]
                        };
                        match edges {
                            Edges::Fixed => None,
                            Edges::PerPatch => Some(id((f, k as u32, i as u32))),
                            Edges::Shared(EdgeFreedom::Sector) => {
                                let (key, origin, axis) = shared_edge(fv[i], other)
                                    .then(|| sector_frame(topo, verts, fv[i], other))??;
                                sector_axes.insert((t, slot_index), (origin, axis));
                                Some(id(key))
                            }
                            Edges::Shared(_) => {
                                shared_edge(fv[i], other).then(|| id((fv[i], other, u32::MAX)))
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
    for (&(t, i), &(origin, axis)) in &sector_axes {
        frames[index[t][i].unwrap()] = (origin, vec![axis]);
    }
    if let Edges::Shared(freedom @ (EdgeFreedom::Plane | EdgeFreedom::Length)) = edges {
        for (t, &f) in faces.iter().enumerate() {
            let corners = start[t].corner_count();
            for (i, &(k, c)) in slots[t].iter().enumerate() {
                if let (1 | 2, Some(g)) = (k, index[t][i]) {
                    let mut patch = start[t];
                    let p = *slot(&mut patch, (0, c));
                    frames[g] = if freedom == EdgeFreedom::Plane {
                        let (sub, (u, v)) = if corners == 3 {
                            (c, (0.0, 0.0))
                        } else {
                            (0, corner_uv(corners, c))
                        };
                        let nrm = ev.eval(f as usize, sub, u, v)?.normal;
                        let t1 = nrm.any_orthonormal_vector();
                        (p, vec![t1, nrm.cross(t1)])
                    } else {
                        (p, vec![*slot(&mut patch, (k, c)) - p])
                    };
                }
            }
        }
    }
    // The frame of slot `i` of face `t` with unknown `g`.
    let frame = |t: usize, i: usize, g: usize| match sector_axes.get(&(t, i)) {
        Some(&(origin, axis)) => (origin, vec![axis]),
        None => frames[g].clone(),
    };
    let mut offset = Vec::with_capacity(next);
    let mut n = 0;
    for (_, axes) in &frames {
        offset.push(n);
        n += axes.len();
    }
    let bases: Vec<Vec<Vec<[f64; 3]>>> = [3, 4]
        .iter()
        .map(|&c| {
            let shape = start.iter().find(|p| p.corner_count() == c);
            params(c, FIT_GRID)
                .iter()
                .map(|&(s, t)| shape.map_or(Vec::new(), |p| basis_d(p, &free_slots(c), s, t)))
                .collect()
        })
        .collect();
    // Exact derivatives of quads at the fit's parameters.
    let exact: Vec<Vec<(DVec3, DVec3)>> = faces
        .iter()
        .zip(start)
        .map(|(&f, p)| match p {
            GregoryPatch::Quad(_) => Ok(ev
                .eval_points(f as usize, 0, &params(4, FIT_GRID))?
                .iter()
                .map(|x| (x.du, x.dv))
                .collect()),
            GregoryPatch::Triangle(_) => Ok(Vec::new()),
        })
        .collect::<tessera::Result<_>>()?;
    let mut cur = start.to_vec();
    for _ in 0..ROUNDS {
        let mut a = vec![0.0; n * n];
        let mut b = vec![0.0; n];
        for (t, &f) in faces.iter().enumerate() {
            let corners = cur[t].corner_count();
            let all = &slots[t];
            for (k, &(s, u)) in params(corners, FIT_GRID).iter().enumerate() {
                let here = cur[t].eval(s, u);
                let g = here.position;
                let close = closest_exact(ev, g, &candidates[t], f)?;
                let (l, nrm) = (close.sample.position, close.sample.normal);
                let bs = &bases[corners - 3][k];
                // The free part of the position and of both derivatives.
                let mut x = [DVec3::ZERO; 3];
                let mut patch = cur[t];
                for (i, &sl) in all.iter().enumerate() {
                    if index[t][i].is_some() {
                        for (d, xd) in x.iter_mut().enumerate() {
                            *xd += bs[i][d] * *slot(&mut patch, sl);
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
                if let Some(&(du, dv)) = exact[t].get(k) {
                    let w = DERIVATIVE_EPS;
                    for e in [DVec3::X, DVec3::Y, DVec3::Z] {
                        rows.push((1, w * e, w * e.dot(du - (here.du - x[1]))));
                        rows.push((2, w * e, w * e.dot(dv - (here.dv - x[2]))));
                    }
                }
                for (d, dir, mut rhs) in rows {
                    let mut coef: Vec<(usize, f64)> = Vec::new();
                    for (i, gi) in index[t].iter().enumerate() {
                        let Some(gi) = *gi else { continue };
                        let (origin, axes) = frame(t, i, gi);
                        rhs -= bs[i][d] * dir.dot(origin);
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
        for (t, patch) in cur.iter_mut().enumerate() {
            for (i, &sl) in slots[t].iter().enumerate() {
                if let Some(g) = index[t][i] {
                    let (origin, axes) = frame(t, i, g);
                    *slot(patch, sl) = axes
                        .iter()
                        .enumerate()
                        .fold(origin, |acc, (q, axis)| acc + x[offset[g] + q] * *axis);
                }
            }
        }
    }
    Ok(cur)
}

/// The fitted edge-tangent lengths of `fit_shared_length` relative to the construction's,
/// `(e_fit − p)·(e − p) / |e − p|²`, grouped by the faces at the corner (the valence of an
/// interior vertex), the triangles among them and the sharp edges at the corner (0 at a smooth
/// vertex, 2 at a boundary or crease vertex): `faces triangles sharp count mean min max`.
fn print_lengths(topo: &Topology, faces: &[u32], start: &[GregoryPatch], fitted: &[GregoryPatch]) {
    type Key = (usize, usize, usize);
    let mut groups: std::collections::BTreeMap<Key, Vec<f64>> = Default::default();
    for (t, &f) in faces.iter().enumerate() {
        for c in 0..start[t].corner_count() {
            let v = topo.face_vertices(f)[c];
            let ring = topo.vertex_faces(v);
            let tris = ring.iter().filter(|&&g| topo.face_size(g) == 3).count();
            let sharp = topo
                .vertex_edges(v)
                .iter()
                .filter(|&&e| is_sharp_edge(topo, e))
                .count();
            let (mut a, mut b) = (start[t], fitted[t]);
            let p = *slot(&mut a, (0, c));
            for k in [1, 2] {
                let (e0, e1) = (*slot(&mut a, (k, c)), *slot(&mut b, (k, c)));
                if e0 != e1 {
                    let d = e0 - p;
                    groups
                        .entry((ring.len(), tris, sharp))
                        .or_default()
                        .push((e1 - p).dot(d) / d.length_squared());
                }
            }
        }
    }
    println!("fitted edge length / construction's: faces triangles sharp count mean min max");
    for ((n, k, sharp), a) in groups {
        let mean = a.iter().sum::<f64>() / a.len() as f64;
        let (lo, hi) = a
            .iter()
            .fold((f64::MAX, f64::MIN), |(l, h), &x| (l.min(x), h.max(x)));
        println!("{n} {k} {sharp} {} {mean:.3} {lo:.3} {hi:.3}", a.len());
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

/// Appends a patch sampled on the output lattice.
fn write_patch(out: &mut String, f: u32, patch: &GregoryPatch) {
    let key = f.to_string();
    for (u, v) in params(patch.corner_count(), OUT_GRID) {
        let x = patch.eval(u, v);
        write_line(out, &key, u, v, x.position, x.normal());
    }
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
    let quads_too = args.get(4).is_some_and(|a| a == "all");
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
    let drawn: Vec<u32> = (0..topo.face_count() as u32)
        .filter(|&f| {
            gregory.contains(&f)
                || (topo.face_size(f) == 4
                    && tessera::patch::regular::RegularPatch::gather(&topo, f).is_some())
        })
        .collect();
    let mut files = [String::new(), String::new(), String::new()];
    let mut shared = String::new();
    let (mut fit_faces, mut fit_start, mut fit_cands) = (Vec::new(), Vec::new(), Vec::new());
    let quad_uv = params(4, OUT_GRID);
    for f in 0..topo.face_count() as u32 {
        if !gregory.contains(&f) {
            // Regular faces (drawn exactly); CPU-path faces are in no file.
            if drawn.contains(&f) {
                let key = f.to_string();
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
        if matches!(patch, GregoryPatch::Quad(_)) && !quads_too {
            for file in files.iter_mut().chain([&mut shared]) {
                write_patch(file, f, &patch);
            }
            continue;
        }
        let candidates = nearby_exact_samples(&topo, &dense, f);
        let one = Setup {
            topo: &topo,
            ev: &ev,
            drawn: &drawn,
            verts: &verts,
            candidates: std::slice::from_ref(&candidates),
        };
        let fa = fit(&one, &[f], &[patch], 0.0, Edges::Fixed)?[0];
        let fb = fit(&one, &[f], &[patch], 0.0, Edges::PerPatch)?[0];
        fit_faces.push(f);
        fit_start.push(patch);
        fit_cands.push(candidates);
        for (file, p) in files.iter_mut().zip([patch, fa, fb]) {
            write_patch(file, f, &p);
        }
    }
    let runs: Vec<(String, f64, EdgeFreedom)> = vec![
        ("fit_shared".into(), 0.0, EdgeFreedom::Free),
        (
            "fit_shared_normals".into(),
            NORMAL_WEIGHT,
            EdgeFreedom::Free,
        ),
        ("fit_shared_plane".into(), NORMAL_WEIGHT, EdgeFreedom::Plane),
        (
            "fit_shared_length".into(),
            NORMAL_WEIGHT,
            EdgeFreedom::Length,
        ),
        (
            "fit_shared_sector".into(),
            NORMAL_WEIGHT,
            EdgeFreedom::Sector,
        ),
    ];
    for (name, weight, freedom) in runs {
        let mut out = shared.clone();
        let setup = Setup {
            topo: &topo,
            ev: &ev,
            drawn: &drawn,
            verts: &verts,
            candidates: &fit_cands,
        };
        let fitted = fit(
            &setup,
            &fit_faces,
            &fit_start,
            weight,
            Edges::Shared(freedom),
        )?;
        for (&f, patch) in fit_faces.iter().zip(&fitted) {
            write_patch(&mut out, f, patch);
        }
        write(&dir, &name, &out)?;
        if matches!(freedom, EdgeFreedom::Length | EdgeFreedom::Sector) {
            println!("{name}:");
            print_lengths(&topo, &fit_faces, &fit_start, &fitted);
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
