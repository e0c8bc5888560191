//! Refinement checks against independent values: hand-computed B-spline masks, crease rules,
//! counting identities and the OpenSubdiv regression meshes.

mod common;

use common::meshes::{corpus_options, osd, osd_names, osd_path};
use glam::DVec3;
use tessera::mesh::{
    BoundaryInterpolation, ControlMeshDesc, Crease, CreaseMethod, ObjOptions, INFINITE_SHARPNESS,
};
use tessera::subdiv::Level;
use tessera::topology::Topology;
use tessera::ControlMesh;

/// An `n x n` grid of quads over [0,n]^2 with a bumpy height `h(i, j)` (deterministic, no
/// symmetry), counter-clockwise seen from +z. Vertex (i, j) has index `j * (n + 1) + i`.
fn grid(n: u32) -> ControlMeshDesc {
    let mut d = ControlMeshDesc::default();
    for j in 0..=n {
        for i in 0..=n {
            let h = ((i * 7 + j * 13) % 5) as f64 * 0.3 + (i as f64 * 0.37).sin();
            d.positions.push(DVec3::new(i as f64, j as f64, h));
        }
    }
    let id = |i: u32, j: u32| j * (n + 1) + i;
    for j in 0..n {
        for i in 0..n {
            d.face_sizes.push(4);
            d.face_vertices
                .extend([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    d
}

fn level_of(d: ControlMeshDesc) -> (Level, Vec<DVec3>) {
    let mesh = ControlMesh::new(d).unwrap();
    (Level::from_mesh(&mesh).unwrap(), mesh.positions().to_vec())
}

fn close(a: DVec3, b: DVec3, tol: f64) -> bool {
    (a - b).abs().max_element() <= tol
}

#[test]
fn regular_grid_reproduces_dyadic_bspline_masks() {
    let n = 6;
    let d = grid(n);
    let p = d.positions.clone();
    let (level, _) = level_of(d);
    let t = level.topology();
    let q = level.refine_positions(&p);
    let at = |i: i32, j: i32| p[(j * (n as i32 + 1) + i) as usize];
    // Tensor products of the cubic B-spline masks (1, 6, 1) / 8 and (1, 1) / 2.
    let w3 = [1.0, 6.0, 1.0];
    for j in 1..n as i32 {
        for i in 1..n as i32 {
            let v = (j * (n as i32 + 1) + i) as u32;
            let mut expect = DVec3::ZERO;
            for b in -1..=1 {
                for a in -1..=1 {
                    expect +=
                        at(i + a, j + b) * (w3[(a + 1) as usize] * w3[(b + 1) as usize] / 64.0);
                }
            }
            assert!(close(
                q[level.child_vertex_point(v) as usize],
                expect,
                1e-14
            ));
            // Edge (i, j)-(i+1, j), away from the boundary rows.
            if i + 1 < n as i32 {
                let e = t.find_edge(v, v + 1).unwrap();
                let mut expect = DVec3::ZERO;
                for b in -1..=1 {
                    expect += (at(i, j + b) + at(i + 1, j + b)) * (w3[(b + 1) as usize] / 16.0);
                }
                assert!(close(q[level.child_edge_point(e) as usize], expect, 1e-14));
            }
        }
    }
    for f in 0..t.face_count() as u32 {
        let c = t
            .face_vertices(f)
            .iter()
            .map(|&v| p[v as usize])
            .sum::<DVec3>()
            / 4.0;
        assert!(close(q[f as usize], c, 1e-15));
    }
}

/// The one-ring invariants of every vertex, checked against the face arrays: face `i` of the
/// ring holds ring edge `i` as the edge leaving the vertex and ring edge `i + 1` as the edge
/// entering it, consecutive faces share the edge between them, boundary rings start and end
/// at boundary edges; every edge is oriented as in its first face.
fn check_rings(t: &Topology) {
    for v in 0..t.vertex_count() as u32 {
        let faces = t.vertex_faces(v);
        let locals = t.vertex_face_locals(v);
        let edges = t.vertex_edges(v);
        let boundary = t.is_boundary_vertex(v);
        if faces.is_empty() {
            // An unreferenced vertex.
            assert!(edges.is_empty());
            continue;
        }
        assert_eq!(edges.len(), faces.len() + boundary as usize, "vertex {v}");
        for (i, (&f, &l)) in faces.iter().zip(locals).enumerate() {
            let fv = t.face_vertices(f);
            let fe = t.face_edges(f);
            let n = fv.len();
            assert_eq!(fv[l as usize], v);
            assert_eq!(edges[i], fe[l as usize], "vertex {v} face {i}");
            let next = edges[(i + 1) % edges.len()];
            assert_eq!(next, fe[(l as usize + n - 1) % n], "vertex {v} face {i}");
            if i + 1 < faces.len() || !boundary {
                let g = faces[(i + 1) % faces.len()];
                assert!(t.edge_faces(next).contains(&f) && t.edge_faces(next).contains(&g));
            }
        }
        if boundary && !edges.is_empty() {
            assert!(t.is_boundary_edge(edges[0]));
            assert!(t.is_boundary_edge(*edges.last().unwrap()));
        }
    }
    for e in 0..t.edge_count() as u32 {
        let [a, b] = t.edge_vertices(e);
        for (&f, &l) in t.edge_faces(e).iter().zip(t.edge_face_locals(e)) {
            let fv = t.face_vertices(f);
            let l = l as usize;
            assert_eq!(t.face_edges(f)[l], e);
            let (x, y) = (fv[l], fv[(l + 1) % fv.len()]);
            assert!((x, y) == (a, b) || (x, y) == (b, a));
        }
        let f = t.edge_faces(e)[0];
        let l = t.edge_face_locals(e)[0] as usize;
        let fv = t.face_vertices(f);
        assert_eq!((fv[l], fv[(l + 1) % fv.len()]), (a, b));
    }
}

#[test]
fn cube_refines_with_consistent_counts() {
    let text = std::fs::read_to_string(osd_path("catmark_cube")).unwrap();
    let mesh = ControlMesh::from_obj_str(&text, "cube", &ObjOptions::default()).unwrap();
    let mut level = Level::from_mesh(&mesh).unwrap();
    for _ in 0..3 {
        let t = level.topology();
        let (v, e, f) = (t.vertex_count(), t.edge_count(), t.face_count());
        let child = level.refine_topology();
        let c = child.topology();
        assert_eq!(c.face_count(), t.corner_count());
        assert_eq!(c.vertex_count(), v + e + f);
        assert_eq!(
            c.vertex_count() as i64 - c.edge_count() as i64 + c.face_count() as i64,
            2
        );
        level = child;
    }
    let _ = (
        Topology::new(&mesh),
        INFINITE_SHARPNESS,
        Crease {
            v0: 0,
            v1: 1,
            sharpness: 0.0,
        },
    );
    let _ = (BoundaryInterpolation::None, CreaseMethod::Chaikin);
}

/// The OpenSubdiv regression meshes that are not manifold (SOURCE.md lists their
/// non-manifold edges / vertices); the validator refuses them.
const NON_MANIFOLD: &[&str] = &[
    "catmark_fan",
    "catmark_gregory_test4",
    "catmark_nonman_bareverts",
    "catmark_nonman_edge100",
    "catmark_nonman_edges",
    "catmark_nonman_quadpole360",
    "catmark_nonman_quadpole64",
    "catmark_nonman_quadpole8",
    "catmark_nonman_verts",
    "catmark_val2_nonman",
];

fn osd_meshes() -> Vec<(String, ControlMesh)> {
    let mut out = Vec::new();
    for name in osd_names() {
        match ControlMesh::from_obj_file(osd_path(&name), &corpus_options(&name)) {
            Ok(m) => out.push((name, m)),
            Err(e) => {
                eprintln!("refused {name}: {e}");
                assert!(NON_MANIFOLD.contains(&name.as_str()), "{name}: {e}")
            }
        }
    }
    out
}

#[test]
fn every_manifold_osd_mesh_refines_three_levels() {
    let meshes = osd_meshes();
    assert!(meshes.len() >= 70, "only {} meshes loaded", meshes.len());
    for (name, mesh) in &meshes {
        let mut level = Level::from_mesh(mesh).unwrap_or_else(|e| panic!("{name}: {e}"));
        check_rings(level.topology());
        let mut pos = mesh.positions().to_vec();
        let t0 = level.topology();
        let euler = t0.vertex_count() as i64 - t0.edge_count() as i64 + t0.face_count() as i64;
        for _ in 0..3 {
            let (child, m) = level.refine();
            let (t, c) = (level.topology(), child.topology());
            assert_eq!(c.face_count(), t.corner_count(), "{name}");
            assert_eq!(
                c.vertex_count(),
                t.vertex_count() + t.edge_count() + t.face_count()
            );
            let e = c.vertex_count() as i64 - c.edge_count() as i64 + c.face_count() as i64;
            assert_eq!(e, euler, "{name}: Euler characteristic changed");
            check_rings(c);
            pos = m.apply_vec(&pos);
            assert_eq!(pos.len(), c.vertex_count());
            assert!(pos.iter().all(|p| p.is_finite()), "{name}");
            // Every refinement row is an affine combination.
            for r in 0..m.rows() {
                let s: f64 = m.row(r).1.iter().sum();
                assert!((s - 1.0).abs() < 1e-12, "{name}: row {r} sums to {s}");
            }
            level = child;
        }
    }
}

#[test]
fn closed_osd_meshes_have_the_euler_characteristic_of_their_genus() {
    // cube and pyramid are spheres (2), the torus has genus 1 (0).
    for (name, chi) in [
        ("catmark_cube", 2),
        ("catmark_pyramid", 2),
        ("catmark_torus", 0),
    ] {
        let mesh = osd(name);
        let t = Topology::new(&mesh).unwrap();
        assert!((0..t.edge_count() as u32).all(|e| !t.is_boundary_edge(e)));
        let e = t.vertex_count() as i64 + t.face_count() as i64 - chi;
        assert_eq!(t.edge_count() as i64, e, "{name}");
    }
}

/// The grid of [`grid`] with the whole row `j = 3` tagged with per-edge sharpness `s(i)`.
fn creased_grid(n: u32, s: impl Fn(u32) -> f32, method: CreaseMethod) -> ControlMeshDesc {
    let mut d = grid(n);
    let id = |i: u32, j: u32| j * (n + 1) + i;
    for i in 0..n {
        d.creases.push(Crease {
            v0: id(i, 3),
            v1: id(i + 1, 3),
            sharpness: s(i),
        });
    }
    d.options.crease_method = method;
    d
}

#[test]
fn infinitely_sharp_crease_follows_the_crease_rules() {
    let n = 6;
    let d = creased_grid(n, |_| INFINITE_SHARPNESS, CreaseMethod::Normal);
    let p = d.positions.clone();
    let (level, _) = level_of(d);
    let t = level.topology();
    let q = level.refine_positions(&p);
    let id = |i: u32| 3 * (n + 1) + i;
    for i in 1..n {
        let expect = p[id(i - 1) as usize] * 0.125
            + p[id(i) as usize] * 0.75
            + p[id(i + 1) as usize] * 0.125;
        assert!(close(
            q[level.child_vertex_point(id(i)) as usize],
            expect,
            1e-15
        ));
    }
    for i in 0..n {
        let e = t.find_edge(id(i), id(i + 1)).unwrap();
        let mid = (p[id(i) as usize] + p[id(i + 1) as usize]) * 0.5;
        assert!(close(q[level.child_edge_point(e) as usize], mid, 1e-15));
    }
    // The crease ends on the boundary have three sharp edges: corners.
    for v in [id(0), id(n)] {
        assert_eq!(q[level.child_vertex_point(v) as usize], p[v as usize]);
    }
}

#[test]
fn sharpness_zero_equals_smooth() {
    let smooth = grid(6);
    let p = smooth.positions.clone();
    let (ls, _) = level_of(smooth);
    let (lz, _) = level_of(creased_grid(6, |_| 0.0, CreaseMethod::Normal));
    let (a, b) = (ls.refine_positions(&p), lz.refine_positions(&p));
    assert_eq!(a, b);
}

#[test]
fn sharpness_one_is_sharp_once_then_smooth() {
    let n = 6;
    let p = grid(n).positions;
    let (l1, _) = level_of(creased_grid(n, |_| 1.0, CreaseMethod::Normal));
    let (linf, _) = level_of(creased_grid(
        n,
        |_| INFINITE_SHARPNESS,
        CreaseMethod::Normal,
    ));
    let (ls, _) = level_of(grid(n));
    let (c1, m1) = l1.refine();
    let q1 = m1.apply_vec(&p);
    let qinf = linf.refine_positions(&p);
    for (a, b) in q1.iter().zip(&qinf) {
        assert!(close(*a, *b, 1e-15));
    }
    // After one step no sharpness is left: the second step is the smooth rule.
    assert!(c1
        .topology()
        .edge_sharpnesses()
        .iter()
        .zip(0..)
        .all(|(&s, e)| { s == 0.0 || c1.topology().is_boundary_edge(e) }));
    let smooth_child = ls.refine_topology();
    let r1 = c1.refine_positions(&q1);
    let rs = smooth_child.refine_positions(&q1);
    for (a, b) in r1.iter().zip(&rs) {
        assert!(close(*a, *b, 1e-15));
    }
}

#[test]
fn fractional_sharpness_blends_sharp_and_smooth() {
    let n = 6;
    let p = grid(n).positions;
    let (lh, _) = level_of(creased_grid(n, |_| 0.5, CreaseMethod::Normal));
    let (linf, _) = level_of(creased_grid(
        n,
        |_| INFINITE_SHARPNESS,
        CreaseMethod::Normal,
    ));
    let (ls, _) = level_of(grid(n));
    let qh = lh.refine_positions(&p);
    let qi = linf.refine_positions(&p);
    let qs = ls.refine_positions(&p);
    let t = lh.topology();
    let on_crease_row = |v: u32| v / (n + 1) == 3;
    let mut blended = 0;
    let mut differ = 0;
    for e in 0..t.edge_count() as u32 {
        let [a, b] = t.edge_vertices(e);
        let r = lh.child_edge_point(e) as usize;
        if on_crease_row(a) && on_crease_row(b) {
            assert!(close(qh[r], (qi[r] + qs[r]) * 0.5, 1e-14));
            blended += 1;
        } else {
            assert!(close(qh[r], qs[r], 1e-15));
        }
    }
    for v in 0..t.vertex_count() as u32 {
        let r = lh.child_vertex_point(v) as usize;
        if on_crease_row(v) {
            assert!(close(qh[r], (qi[r] + qs[r]) * 0.5, 1e-14), "vertex {v}");
            differ += !close(qi[r], qs[r], 1e-6) as usize;
            blended += 1;
        } else {
            assert!(close(qh[r], qs[r], 1e-15));
        }
    }
    assert_eq!(blended, 6 + 7);
    assert!(differ >= 5, "the test needs sharp != smooth on the crease");
}

/// Sharpness of the child half of parent edge `a-b` that ends at `a`.
fn child_half_sharpness(level: &Level, child: &Level, a: u32, b: u32) -> f32 {
    let e = level.topology().find_edge(a, b).unwrap();
    let ce = child
        .topology()
        .find_edge(level.child_vertex_point(a), level.child_edge_point(e))
        .unwrap();
    child.topology().edge_sharpness(ce)
}

#[test]
fn chaikin_differs_from_normal_only_where_neighbouring_sharpness_differs() {
    let n = 6;
    let id = |i: u32| 3 * (n + 1) + i;
    let sharp = |i: u32| if i < 3 { 1.0 } else { 2.0 };
    let (ln, _) = level_of(creased_grid(n, sharp, CreaseMethod::Normal));
    let (lc, _) = level_of(creased_grid(n, sharp, CreaseMethod::Chaikin));
    let (cn, cc) = (ln.refine_topology(), lc.refine_topology());
    // At the junction vertex (3,3): edges of sharpness 1 (left) and 2 (right).
    // Chaikin: 0.75 * 1 + 0.25 * 2 - 1 = 0.25 and 0.75 * 2 + 0.25 * 1 - 1 = 0.75.
    assert_eq!(child_half_sharpness(&lc, &cc, id(3), id(2)), 0.25);
    assert_eq!(child_half_sharpness(&lc, &cc, id(3), id(4)), 0.75);
    assert_eq!(child_half_sharpness(&ln, &cn, id(3), id(2)), 0.0);
    assert_eq!(child_half_sharpness(&ln, &cn, id(3), id(4)), 1.0);
    // At (4,3) both neighbours have sharpness 2: 0.75 * 2 + 0.25 * 2 - 1 = 1 as with Normal.
    assert_eq!(child_half_sharpness(&lc, &cc, id(4), id(3)), 1.0);
    assert_eq!(child_half_sharpness(&lc, &cc, id(4), id(5)), 1.0);
    // Uniform sharpness along the crease: both methods give identical surfaces.
    let p = grid(n).positions;
    let mut pos = [p.clone(), p.clone()];
    let mut levels = [
        level_of(creased_grid(n, |_| 2.0, CreaseMethod::Normal)).0,
        level_of(creased_grid(n, |_| 2.0, CreaseMethod::Chaikin)).0,
    ];
    for _ in 0..3 {
        for k in 0..2 {
            let (c, m) = levels[k].refine();
            pos[k] = m.apply_vec(&pos[k]);
            levels[k] = c;
        }
        assert_eq!(pos[0], pos[1]);
    }
    // Different sharpness: the second level differs.
    let (q0, q1) = (
        cn.refine_positions(&ln.refine_positions(&p)),
        cc.refine_positions(&lc.refine_positions(&p)),
    );
    assert!(q0.iter().zip(&q1).any(|(a, b)| !close(*a, *b, 1e-9)));
}

#[test]
fn boundary_corner_rules() {
    let n = 4;
    let p = grid(n).positions;
    let corner = 0u32;
    let (a, b) = (1usize, (n + 1) as usize);
    // EdgeAndCorner: a valence-2 boundary vertex is a corner; EdgeOnly: the crease rule.
    let (lc, _) = level_of(grid(n));
    assert_eq!(
        lc.refine_positions(&p)[lc.child_vertex_point(corner) as usize],
        p[0]
    );
    let mut d = grid(n);
    d.options.boundary = BoundaryInterpolation::EdgeOnly;
    let (le, _) = level_of(d);
    let q = le.refine_positions(&p)[le.child_vertex_point(corner) as usize];
    assert!(close(q, p[0] * 0.75 + (p[a] + p[b]) * 0.125, 1e-15));
    // Boundary::None refines like EdgeOnly but faces at the boundary have no limit surface.
    let mut d = grid(n);
    d.options.boundary = BoundaryInterpolation::None;
    let (ln, _) = level_of(d);
    assert_eq!(le.refine_positions(&p), ln.refine_positions(&p));
    assert!(!ln.has_limit_surface(0) && ln.has_limit_surface(5));
    // Descendants inherit it: the child of face 0 at its corner 2 = (1,1) does not touch the
    // boundary but still has no limit surface (OpenSubdiv makes these faces holes).
    let c = ln.refine_topology();
    let inner_child = ln.child_faces(0).start + 2;
    let cv = c.topology().face_vertices(inner_child);
    assert!(cv.iter().all(|&v| !c.topology().is_boundary_vertex(v)));
    assert!(!c.has_limit_surface(inner_child));
    assert!(ln.child_faces(5).all(|f| c.has_limit_surface(f)));
    let (sub, _) = c.extract(&[inner_child, ln.child_faces(5).start]);
    assert!(!sub.has_limit_surface(0) && sub.has_limit_surface(1));
}

#[test]
fn children_of_holes_are_holes() {
    let mut d = grid(4);
    d.holes.push(5);
    let (l, _) = level_of(d);
    let c = l.refine_topology().refine_topology();
    let holes = (0..c.face_count() as u32)
        .filter(|&f| c.topology().is_hole(f))
        .count();
    assert_eq!(holes, 16);
    let first = l.child_faces(5).start * 4;
    assert!((first..first + 16).all(|f| c.topology().is_hole(f)));
}

/// Extracts the faces within `rings` vertex-rings of face `seed`, refines the extraction and
/// the whole mesh three times, and checks that they agree (position, sharpness, limit-surface
/// flags) on every vertex the extraction reports complete. Returns how many were checked.
fn check_extraction(mesh: &ControlMesh, seed: u32, rings: usize) -> usize {
    let whole = Level::from_mesh(mesh).unwrap();
    let t = whole.topology();
    let mut faces: Vec<u32> = vec![seed];
    let mut verts: Vec<u32> = t.face_vertices(seed).to_vec();
    for _ in 0..rings {
        for &v in &verts {
            faces.extend_from_slice(t.vertex_faces(v));
        }
        faces.sort_unstable();
        faces.dedup();
        verts = faces
            .iter()
            .flat_map(|&f| t.face_vertices(f).to_vec())
            .collect();
    }
    let (sub, map) = whole.extract(&faces);
    let sp: Vec<DVec3> = map.iter().map(|&v| mesh.positions()[v as usize]).collect();
    let (mut wl, mut wp, mut sl, mut spos) = (whole, mesh.positions().to_vec(), sub, sp);
    // Track which whole-mesh vertex / face each extracted one is, through the refinements.
    let mut vmap = map;
    let mut fmap: Vec<u32> = faces.clone();
    let mut checked = 0;
    for _ in 0..3 {
        let (wc, wm) = wl.refine();
        let (sc, sm) = sl.refine();
        let (wt, st) = (wl.topology(), sl.topology());
        let mut cv = vec![0u32; sc.vertex_count()];
        let mut cf = Vec::new();
        for f in 0..st.face_count() as u32 {
            let wf = fmap[f as usize];
            assert_eq!(sl.has_limit_surface(f), wl.has_limit_surface(wf));
            cv[sl.child_face_point(f) as usize] = wl.child_face_point(wf);
            let n = st.face_size(f);
            let wk = wt
                .face_vertices(wf)
                .iter()
                .position(|&v| v == vmap[st.face_vertices(f)[0] as usize])
                .unwrap();
            for k in 0..n {
                cf.push(wl.child_faces(wf).start + ((wk + k) % n) as u32);
            }
        }
        for e in 0..st.edge_count() as u32 {
            let [a, b] = st.edge_vertices(e);
            let we = wt.find_edge(vmap[a as usize], vmap[b as usize]).unwrap();
            cv[sl.child_edge_point(e) as usize] = wl.child_edge_point(we);
        }
        for v in 0..st.vertex_count() as u32 {
            cv[sl.child_vertex_point(v) as usize] = wl.child_vertex_point(vmap[v as usize]);
        }
        wp = wm.apply_vec(&wp);
        spos = sm.apply_vec(&spos);
        let (ct, wct) = (sc.topology(), wc.topology());
        for v in 0..sc.vertex_count() as u32 {
            if sc.is_complete_vertex(v) {
                let w = cv[v as usize];
                assert!(close(spos[v as usize], wp[w as usize], 1e-12), "vertex {v}");
                assert_eq!(ct.vertex_sharpness(v), wct.vertex_sharpness(w));
                assert_eq!(ct.vertex_faces(v).len(), wct.vertex_faces(w).len());
                for &e in ct.vertex_edges(v) {
                    let o = ct.other_vertex(e, v);
                    let we = wct.find_edge(w, cv[o as usize]).unwrap();
                    assert_eq!(ct.edge_sharpness(e), wct.edge_sharpness(we));
                }
                checked += 1;
            }
        }
        (wl, sl, vmap, fmap) = (wc, sc, cv, cf);
    }
    checked
}

#[test]
fn extraction_refines_like_the_whole_mesh_where_complete() {
    let mesh = osd("catmark_chaikin1");
    let checked = check_extraction(&mesh, 3, 2);
    assert!(checked > 100, "only {checked} complete vertices");
}

#[test]
fn extractions_of_every_osd_mesh_agree_with_the_whole() {
    let mut total = 0;
    for (name, mesh) in osd_meshes() {
        let nf = mesh.face_count() as u32;
        for seed in [0, nf / 2, nf - 1] {
            for rings in [1, 2] {
                let r = std::panic::catch_unwind(|| check_extraction(&mesh, seed, rings));
                match r {
                    Ok(n) => total += n,
                    Err(_) => panic!("{name}: seed face {seed}, {rings} rings"),
                }
            }
        }
    }
    assert!(total > 10_000, "only {total} complete vertices checked");
}

#[test]
fn stencil_tables_match_direct_refinement() {
    use tessera::subdiv::StencilTable;
    for name in [
        "catmark_car",
        "catmark_chaikin1",
        "catmark_nonquads",
        "catmark_edgenone",
        "catmark_cubes_semisharp",
        "catmark_hole_test3",
    ] {
        let mesh = osd(name);
        let mut level = Level::from_mesh(&mesh).unwrap();
        let mut pos = mesh.positions().to_vec();
        for depth in 0..=3u32 {
            let table = StencilTable::refined(&mesh, depth).unwrap();
            assert_eq!(table.len(), pos.len(), "{name} level {depth}");
            assert_eq!(table.base_count(), mesh.vertex_count());
            let got = table.apply_vec(mesh.positions());
            for (a, b) in got.iter().zip(&pos) {
                assert!(close(*a, *b, 1e-12), "{name} level {depth}: {a} vs {b}");
            }
            for r in 0..table.len() {
                let (idx, w) = table.stencil(r);
                assert!(idx.windows(2).all(|x| x[0] < x[1]) && w.iter().all(|&x| x != 0.0));
            }
            let (child, m) = level.refine();
            pos = m.apply_vec(&pos);
            level = child;
        }
    }
}

#[test]
fn refined_level_round_trips_through_a_control_mesh() {
    let mesh = osd("catmark_car");
    let level = Level::from_mesh(&mesh).unwrap();
    let (child, m) = level.refine();
    let pos = m.apply_vec(mesh.positions());
    let again = Level::from_mesh(&ControlMesh::new(child.to_mesh_desc(pos)).unwrap()).unwrap();
    let (a, b) = (child.topology(), again.topology());
    assert_eq!(a.edge_count(), b.edge_count());
    for e in 0..a.edge_count() as u32 {
        let [u, v] = a.edge_vertices(e);
        let f = b.find_edge(u, v).unwrap();
        assert_eq!(a.edge_sharpness(e), b.edge_sharpness(f));
    }
    assert_eq!(a.vertex_sharpnesses(), b.vertex_sharpnesses());
}

#[test]
fn triangles_use_the_general_valence_rules() {
    // A regular tetrahedron centred at the origin, outward counter-clockwise triangles.
    let d = ControlMeshDesc {
        positions: vec![
            DVec3::new(1.0, 1.0, 1.0),
            DVec3::new(1.0, -1.0, -1.0),
            DVec3::new(-1.0, 1.0, -1.0),
            DVec3::new(-1.0, -1.0, 1.0),
        ],
        face_sizes: vec![3; 4],
        face_vertices: vec![0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2],
        ..Default::default()
    };
    let p = d.positions.clone();
    let (level, _) = level_of(d);
    let t = level.topology();
    assert_eq!(t.edge_count(), 6);
    let q = level.refine_positions(&p);
    // With the vertices summing to zero, the valence-3 smooth rule
    // (1/3) v + (1/9) sum(neighbours) + (1/9) sum(face centroids) gives 7/27 v, and the edge
    // rule (a + b + c0 + c1) / 4 gives (a + b) / 3.
    for v in 0..4u32 {
        let got = q[level.child_vertex_point(v) as usize];
        assert!(
            close(got, p[v as usize] * (7.0 / 27.0), 1e-15),
            "vertex {v}"
        );
    }
    for e in 0..6u32 {
        let [a, b] = t.edge_vertices(e);
        let got = q[level.child_edge_point(e) as usize];
        assert!(
            close(got, (p[a as usize] + p[b as usize]) / 3.0, 1e-15),
            "edge {e}"
        );
    }
    // Every child face is a quad (vertex point, edge point, face point, edge point).
    let c = level.refine_topology();
    assert_eq!(c.face_count(), 12);
    for f in 0..12u32 {
        let fv = c.topology().face_vertices(f);
        let parent = f / 3;
        let k = (f % 3) as usize;
        let pv = t.face_vertices(parent);
        let pe = t.face_edges(parent);
        assert_eq!(fv[0], level.child_vertex_point(pv[k]));
        assert_eq!(fv[1], level.child_edge_point(pe[k]));
        assert_eq!(fv[2], level.child_face_point(parent));
        assert_eq!(fv[3], level.child_edge_point(pe[(k + 2) % 3]));
    }
}

#[test]
fn extraction_with_a_bow_tie_vertex_refines_without_error() {
    // Faces (0,0) and (1,1) of a 2x2 grid touch only at the centre vertex 4.
    let d = grid(2);
    let p = d.positions.clone();
    let (level, _) = level_of(d);
    let (sub, map) = level.extract(&[0, 3]);
    assert_eq!(map.len(), 7);
    let centre = map.iter().position(|&v| v == 4).unwrap() as u32;
    let t = sub.topology();
    assert_eq!(t.vertex_faces(centre).len(), 2);
    assert_eq!(t.vertex_edges(centre).len(), 4);
    assert!(!sub.is_complete_vertex(centre));
    // Face 0 keeps its boundary corner 0, which is complete (its whole ring is present).
    assert!(sub.is_complete_vertex(0));
    assert_eq!(
        (0..t.edge_count() as u32)
            .filter(|&e| sub.is_cut_edge(e))
            .count(),
        4
    );
    let mut pos: Vec<DVec3> = map.iter().map(|&v| p[v as usize]).collect();
    let mut l = sub;
    for _ in 0..2 {
        let (c, m) = l.refine();
        pos = m.apply_vec(&pos);
        assert!(pos.iter().all(|x| x.is_finite()));
        l = c;
    }
    assert_eq!(l.face_count(), 32);
}

#[test]
fn dart_ends_use_the_smooth_vertex_rule() {
    // One infinitely sharp interior edge (2,2)-(3,2): both ends have a single sharp edge.
    let n = 5;
    let mut d = grid(n);
    let (a, b) = (2 * (n + 1) + 2, 2 * (n + 1) + 3);
    d.creases.push(Crease {
        v0: a,
        v1: b,
        sharpness: INFINITE_SHARPNESS,
    });
    let p = d.positions.clone();
    let (ld, _) = level_of(d);
    let (ls, _) = level_of(grid(n));
    let (qd, qs) = (ld.refine_positions(&p), ls.refine_positions(&p));
    for v in [a, b] {
        let r = ld.child_vertex_point(v) as usize;
        assert_eq!(qd[r], qs[r]);
    }
    let e = ld.topology().find_edge(a, b).unwrap();
    let mid = (p[a as usize] + p[b as usize]) * 0.5;
    assert!(close(qd[ld.child_edge_point(e) as usize], mid, 1e-15));
}

#[test]
fn stencil_tables_take_appended_rows() {
    use tessera::subdiv::{SparseMatrix, StencilTable};
    let mesh = osd("catmark_nonquads");
    let mut table = StencilTable::refined(&mesh, 1).unwrap();
    let n = table.len();
    // A row over the level-1 vertices: the mean of child vertices 0 and 5.
    let mut extra = SparseMatrix::new(n);
    extra.push_row(&[(0, 0.5), (5, 0.5)]);
    table.append_composed(&extra);
    table.push(&[(3, 1.0)]);
    assert_eq!(table.len(), n + 2);
    let level1 = table.apply_vec(mesh.positions());
    assert!(close(level1[n], (level1[0] + level1[5]) * 0.5, 1e-14));
    assert_eq!(level1[n + 1], mesh.positions()[3]);
}

/// The face-vertex-only last level of a uniform refinement equals the faces of the full one.
#[test]
fn face_vertices_only_last_level_matches_full_refinement() {
    for name in ["catmark_nonquads", "catmark_car", "catmark_hole_test2"] {
        let mesh = osd(name);
        let base = Level::from_mesh(&mesh).unwrap();
        let mut full = base.clone();
        for depth in 1..=3 {
            full = full.refine_topology();
            let expected: Vec<u32> = (0..full.face_count() as u32)
                .flat_map(|f| full.topology().face_vertices(f).to_vec())
                .collect();
            assert_eq!(
                base.uniform_face_vertices(depth),
                expected,
                "{name} depth {depth}"
            );
        }
    }
}

/// Every other child face in a scattered pattern (deterministic), or all of them.
fn scattered_corners(level: &Level, salt: u32) -> Vec<u32> {
    let n = level.topology().corner_count() as u32;
    (0..n)
        .filter(|&h| salt == 0 || (h.wrapping_mul(2_654_435_761) ^ salt) >> 13 & 3 != 0)
        .collect()
}

/// `Level::refine_kept` (the child faces of a sparse refinement step built from the parent by
/// index arithmetic) is bit for bit `refine_topology().try_extract(keep)`: topology and
/// numbering, edge sharpness (Normal and Chaikin decay), vertex sharpness, holes, no-limit
/// faces, cut edges and incomplete vertices, and the vertex map. On every manifold corpus mesh,
/// its whole first level and its first refinement, an extraction of a few rings (cut edges,
/// incomplete vertices), each with all corners and with scattered ones (non-manifold fans).
/// Fails on the pre-change path's output whenever the new one differs in any field; checked by
/// mutation: numbering the two halves of a parent edge in their fixed order instead of by their
/// first kept quad fails it (bishop, level 0).
#[test]
fn refine_kept_equals_refine_then_extract() {
    let mut compared = 0;
    for (name, mesh) in &osd_meshes() {
        let l0 = Level::from_mesh(mesh).unwrap();
        let l1 = l0.refine_topology();
        let t = l0.topology();
        let seed = t.face_count() as u32 / 2;
        let mut faces: Vec<u32> = t
            .face_vertices(seed)
            .iter()
            .flat_map(|&v| t.vertex_faces(v).to_vec())
            .collect();
        faces.sort_unstable();
        faces.dedup();
        let (sub, _) = l0.extract(&faces);
        let sub1 = sub.refine_topology();
        for (which, level) in [
            ("level 0", &l0),
            ("level 1", &l1),
            ("ring", &sub),
            ("ring 1", &sub1),
        ] {
            for salt in [0, 0x5bd1_e995] {
                let keep = scattered_corners(level, salt);
                if keep.is_empty() {
                    continue;
                }
                let want = format!("{:?}", level.refine_topology().try_extract(&keep));
                let got = format!("{:?}", level.refine_kept(&keep));
                assert!(
                    want == got,
                    "{name} {which} salt {salt:#x}: refine_kept differs"
                );
                compared += 1;
            }
        }
    }
    assert!(compared >= 8 * 70, "only {compared} comparisons");
}

/// `Level::extract_increasing` (an extraction's edges taken from the level's) is bit for bit
/// `try_extract` (edges bucketed anew by `topology::build`): connectivity and numbering,
/// sharpness, holes, cut edges, incomplete vertices, vertex map. On every manifold corpus mesh,
/// its first two levels and an extraction (cut edges, incomplete vertices), each with all faces
/// and scattered ones. Checked by mutation: ordering a vertex's edges by their last extracted
/// corner instead of their first fails it (bishop, level 0).
#[test]
fn extract_increasing_equals_try_extract() {
    let mut compared = 0;
    for (name, mesh) in &osd_meshes() {
        let l0 = Level::from_mesh(mesh).unwrap();
        let l1 = l0.refine_topology();
        let (sub, _) = l0.extract(&scattered_faces(&l0, 0x2545_f491));
        for (which, level) in [("level 0", &l0), ("level 1", &l1), ("extraction", &sub)] {
            for salt in [0, 0x5bd1_e995] {
                let faces = scattered_faces(level, salt);
                if faces.is_empty() {
                    continue;
                }
                let want = format!("{:?}", level.try_extract(&faces));
                let got = format!("{:?}", level.extract_increasing(&faces));
                assert!(
                    want == got,
                    "{name} {which} salt {salt:#x}: extract_increasing differs"
                );
                compared += 1;
            }
        }
    }
    assert!(compared >= 6 * 70, "only {compared} comparisons");
}

/// Faces of `level` in a scattered pattern (deterministic), or all of them.
fn scattered_faces(level: &Level, salt: u32) -> Vec<u32> {
    let n = level.face_count() as u32;
    (0..n)
        .filter(|&f| salt == 0 || (f.wrapping_mul(2_654_435_761) ^ salt) >> 11 & 3 != 0)
        .collect()
}
