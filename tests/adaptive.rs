//! Feature-adaptive refinement and its patch census (`subdiv::adaptive`), pure CPU: the
//! invariants of Köbler 2013 §3.3-3.4 on every loadable OpenSubdiv shape, and the census against
//! OpenSubdiv 3.5's `Far` patch table (Gregory-basis end caps, single-crease patches off).
//!
//! Measured totals (ours = OpenSubdiv's at every isolation):
//!
//! | isolation | 1 | 2 | 3 | 4 | 5 | 6 |
//! |---|---|---|---|---|---|---|
//! | `catmark_car` | 4,539 | 11,307 | 21,843 | 39,915 | 73,059 | 136,347 (1,240 end caps) |
//! | `catmark_cube_creases1` | 24 | 96 | 300 | 768 | 1,764 | 1,836 |
//!
//! With single-crease patches (`AdaptiveOptions::single_crease`, OpenSubdiv's
//! `useSingleCreasePatch`), `catmark_car` totals also equal OpenSubdiv's: 3,975 / 7,719 / 11,463
//! / 15,207 / 18,951 / 22,695 at isolation 1-6 (a constant 3,744 per level past level 1).

mod common;

use std::collections::HashMap;

use common::meshes::{mesh, osd, osd_names, try_osd};
use tessera::subdiv::adaptive::{
    AdaptiveOptions, AdaptiveRefinement, ChildOf, PatchCensus, PatchType,
};
use tessera::subdiv::tables::RefinementTables;
use tessera::subdiv::Level;
use tessera::topology::Topology;
use tessera::ControlMesh;

fn refine(m: &ControlMesh, isolation: u32) -> (AdaptiveRefinement, PatchCensus) {
    refine_with(m, AdaptiveOptions::new(isolation))
}

fn refine_with(m: &ControlMesh, options: AdaptiveOptions) -> (AdaptiveRefinement, PatchCensus) {
    let r = AdaptiveRefinement::with_options(&Level::from_mesh(m).unwrap(), options).unwrap();
    let c = PatchCensus::new(&r);
    (r, c)
}

/// Single-crease patches on.
fn single(isolation: u32) -> AdaptiveOptions {
    AdaptiveOptions {
        single_crease: true,
        ..AdaptiveOptions::new(isolation)
    }
}

/// Every loadable shape of the corpus with its name.
fn corpus() -> Vec<(String, ControlMesh)> {
    osd_names()
        .into_iter()
        .filter_map(|n| try_osd(&n).ok().map(|m| (n, m)))
        .collect()
}

/// The face of `t` with corners `c` in this cyclic order, if any.
fn find_face(t: &Topology, c: [u32; 4]) -> Option<u32> {
    t.vertex_faces(c[0]).iter().copied().find(|&f| {
        let fv = t.face_vertices(f);
        fv.len() == 4 && (0..4).any(|s| (0..4).all(|k| fv[(s + k) % 4] == c[k]))
    })
}

/// Every B-spline patch's real control vertices form a 4x4 grid of faces of its level, with
/// its face in the middle and valence-4 interior corners.
fn check_grids(name: &str, r: &AdaptiveRefinement, c: &PatchCensus) {
    for p in &c.patches {
        let Some(b) = p.bspline else { continue };
        let lev = &r.levels[p.level as usize];
        let t = lev.topology();
        let local = |k: usize| b.cvs[k] - lev.first_vertex;
        let m = b.boundary_mask;
        let real_col = |i: usize| !(i == 0 && m & 8 != 0 || i == 3 && m & 2 != 0);
        let real_row = |j: usize| !(j == 0 && m & 1 != 0 || j == 3 && m & 4 != 0);
        for j in 0..3 {
            for i in 0..3 {
                if !(real_col(i) && real_col(i + 1) && real_row(j) && real_row(j + 1)) {
                    continue;
                }
                let corners = [4 * j + i, 4 * j + i + 1, 4 * j + i + 5, 4 * j + i + 4].map(local);
                let f = find_face(t, corners).unwrap_or_else(|| {
                    panic!(
                        "{name}: level {} patch {:?}: cell ({i},{j}) is not a face",
                        p.level, b
                    )
                });
                if (i, j) == (1, 1) {
                    assert_eq!(f, p.face, "{name}");
                }
            }
        }
        for (k, slot) in [5usize, 6, 10, 9].into_iter().enumerate() {
            let v = local(slot);
            let prev = (k + 3) % 4;
            if m & (1 << k) == 0 && m & (1 << prev) == 0 {
                let sharp = t.vertex_edges(v).iter().any(|&e| t.edge_sharpness(e) > 0.0);
                if !sharp {
                    assert_eq!(t.valence(v), 4, "{name}: corner {k} of {:?}", b);
                    assert!(!t.is_boundary_vertex(v), "{name}");
                }
            }
        }
    }
}

/// Each base face with a limit surface is tiled exactly once by its patches' domains (per
/// sub-face for non-quads), on a grid at the finest level.
fn check_tiling(name: &str, r: &AdaptiveRefinement, c: &PatchCensus) {
    let depth = r.levels.len() as u32 - 1;
    let n = 1usize << depth;
    let base = r.levels[0].topology();
    let mut cells: HashMap<(u32, u32), Vec<u8>> = HashMap::new();
    for p in &c.patches {
        let d = r.levels[p.level as usize].domains[p.face as usize];
        let key = (d.base_face, d.sub_face.unwrap_or(u32::MAX));
        let lo = d
            .origin
            .min(d.origin + d.u)
            .min(d.origin + d.v)
            .min(d.origin + d.u + d.v);
        let size = (d.u.length() * n as f64).round() as usize;
        // A non-quad's level-1 children are its whole sub-faces.
        let depth_in_domain = p.level - d.sub_face.is_some() as u32;
        assert_eq!(size, n >> depth_in_domain, "{name}: patch domain size");
        let (i0, j0) = ((lo.x * n as f64) as usize, (lo.y * n as f64) as usize);
        let grid = cells.entry(key).or_insert_with(|| vec![0; n * n]);
        for j in j0..j0 + size {
            for i in i0..i0 + size {
                grid[j * n + i] += 1;
            }
        }
    }
    for f in 0..base.face_count() as u32 {
        if !base.has_limit_surface(f) {
            continue;
        }
        let subs: Vec<u32> = if base.face_size(f) == 4 || depth == 0 {
            vec![u32::MAX]
        } else {
            (0..base.face_size(f) as u32).collect()
        };
        for s in subs {
            let grid = cells
                .get(&(f, s))
                .unwrap_or_else(|| panic!("{name}: base face {f} sub {s} has no patch"));
            assert!(
                grid.iter().all(|&x| x == 1),
                "{name}: base face {f} sub {s} not tiled exactly once"
            );
        }
    }
}

/// Patches meeting across an edge differ by at most one level: a patch's finer neighbour's
/// children along the edge are not refined again, and a coarser neighbour (a ring face) is a
/// child of a face drawn one level up.
fn check_level_steps(name: &str, r: &AdaptiveRefinement, c: &PatchCensus) {
    // Level-l face -> its children at level l + 1.
    let children: Vec<HashMap<u32, Vec<u32>>> = r.levels[..r.levels.len() - 1]
        .iter()
        .zip(&r.levels[1..])
        .map(|(lev, next)| {
            let mut m: HashMap<u32, Vec<u32>> = HashMap::new();
            for cf in 0..next.level.face_count() as u32 {
                m.entry(lev.child_face_parent(cf).0).or_default().push(cf);
            }
            m
        })
        .collect();
    for p in &c.patches {
        let l = p.level as usize;
        let lev = &r.levels[l];
        let t = lev.topology();
        for k in 0..t.face_size(p.face) {
            let Some(g) = t.adjacent_face(p.face, k) else {
                continue;
            };
            let gi = g as usize;
            if !t.has_limit_surface(g) {
                continue; // holes draw nothing
            }
            if lev.refined[gi] {
                assert_ne!(p.transition & (1 << k), 0, "{name}: transition bit");
                let next = &r.levels[l + 1];
                let [a, b] = t.edge_vertices(t.face_edges(p.face)[k]);
                for &cf in &children[l][&g] {
                    let (_, corner) = lev.child_face_parent(cf);
                    let v = t.face_vertices(g)[corner];
                    if v == a || v == b {
                        assert!(
                            !next.refined[cf as usize],
                            "{name}: level {l} patch next to level {}",
                            l + 2
                        );
                    }
                }
            } else if !lev.own[gi] {
                let (parent, _) = r.levels[l - 1].child_face_parent(g);
                assert!(
                    r.levels[l - 1].own[parent as usize],
                    "{name}: level {l} patch next to level < {}",
                    l - 1
                );
            } else {
                assert_eq!(p.transition & (1 << k), 0, "{name}");
            }
        }
    }
}

/// Every kept vertex of every level equals the same vertex of the uniform refinement (1e-12
/// relative to the bounding box).
fn check_positions(name: &str, m: &ControlMesh, r: &AdaptiveRefinement) {
    let all = r.refine_positions(m.positions());
    let scale = m
        .positions()
        .iter()
        .fold(1.0f64, |s, p| s.max(p.abs().max_element()));
    let mut uniform = Level::from_mesh(m).unwrap();
    let mut upos = m.positions().to_vec();
    let mut vmap: Vec<u32> = (0..uniform.vertex_count() as u32).collect();
    let mut fmap: Vec<u32> = (0..uniform.face_count() as u32).collect();
    for (l, lev) in r.levels.iter().enumerate() {
        for (v, &u) in vmap.iter().enumerate() {
            let d = (all[lev.first_vertex as usize + v] - upos[u as usize]).length();
            assert!(
                d <= 1e-12 * scale,
                "{name}: level {l} vertex {v} off by {d}"
            );
        }
        if lev.refinement.is_none() {
            break;
        }
        let next = &r.levels[l + 1];
        let ut = uniform.topology();
        let (nf, ne) = (ut.face_count() as u32, ut.edge_count() as u32);
        let nvm = (0..next.level.vertex_count() as u32)
            .map(|v| match lev.child_of(v) {
                ChildOf::Face(f) => fmap[f as usize],
                ChildOf::Edge(e) => {
                    let [a, b] = lev.topology().edge_vertices(e);
                    nf + ut.find_edge(vmap[a as usize], vmap[b as usize]).unwrap()
                }
                ChildOf::Vertex(u) => nf + ne + vmap[u as usize],
            })
            .collect();
        let nfm = (0..next.level.face_count() as u32)
            .map(|c| {
                let (f, k) = lev.child_face_parent(c);
                ut.face_offsets()[fmap[f as usize] as usize] + k as u32
            })
            .collect();
        let (child, matrix) = uniform.refine();
        upos = matrix.apply_vec(&upos);
        uniform = child;
        vmap = nvm;
        fmap = nfm;
    }
}

fn check_all(name: &str, m: &ControlMesh, isolation: u32) {
    check_all_with(name, m, AdaptiveOptions::new(isolation));
}

fn check_all_with(name: &str, m: &ControlMesh, options: AdaptiveOptions) {
    let (r, c) = refine_with(m, options);
    check_grids(name, &r, &c);
    check_tiling(name, &r, &c);
    check_level_steps(name, &r, &c);
    check_positions(name, m, &r);
}

#[test]
fn invariants_on_the_corpus() {
    for (name, m) in corpus() {
        for isolation in [0, 1, 2] {
            check_all(&name, &m, isolation);
        }
    }
}

#[test]
fn invariants_at_higher_isolation() {
    for name in [
        "catmark_cube_creases1",
        "catmark_nonquads",
        "catmark_pyramid_creases1",
        "catmark_hole_test2",
        "catmark_chaikin1",
        "catmark_edgenone",
        "catmark_inf_crease0",
        "embedded:mixed",
        "embedded:creased",
    ] {
        check_all(name, &mesh(name), 4);
    }
    check_all("catmark_car", &osd("catmark_car"), 3);
}

/// The same invariants with single-crease patches: in particular neighbouring patch levels
/// still differ by at most one (Köbler 2013 §3.7), and every single-crease patch is a face of
/// its level that `single_crease_line` takes, none of them an end cap.
#[test]
fn invariants_with_single_crease_patches() {
    let mut seen = 0;
    for (name, m) in corpus() {
        for isolation in [0, 1, 2, 3] {
            check_all_with(&name, &m, single(isolation));
            let (r, c) = refine_with(&m, single(isolation));
            for p in c
                .patches
                .iter()
                .filter(|p| p.kind == PatchType::SingleCrease)
            {
                let lev = &r.levels[p.level as usize];
                let line =
                    tessera::subdiv::single_crease::single_crease_line(lev.topology(), p.face)
                        .unwrap_or_else(|| panic!("{name}: not a single-crease face"));
                let crease = p.crease.unwrap();
                assert_eq!(crease.cvs, line.cvs.map(|v| lev.global(v)), "{name}");
                assert_eq!(crease.cvs, p.bspline.unwrap().cvs, "{name}");
                seen += 1;
            }
        }
    }
    assert!(seen > 1000, "{seen} single-crease patches");
    for name in [
        "catmark_cube_creases1",
        "catmark_single_crease",
        "embedded:creased",
    ] {
        check_all_with(name, &mesh(name), single(5));
    }
    check_all_with("catmark_car", &osd("catmark_car"), single(4));
}

/// `catmark_car` with single-crease patches: no more patches than OpenSubdiv's
/// `useSingleCreasePatch` (measured: equal at every isolation), end caps and single-crease
/// patches at each level, and without the option no single-crease patch at all.
#[test]
fn single_crease_census_within_opensubdiv() {
    let m = osd("catmark_car");
    let osd_totals = [3_975, 7_719, 11_463, 15_207, 18_951, 22_695];
    for (i, &limit) in osd_totals.iter().enumerate() {
        let isolation = i as u32 + 1;
        let (_, c) = refine_with(&m, single(isolation));
        assert!(
            c.total() <= limit,
            "catmark_car isolation {isolation} single-crease: {} > {limit}",
            c.total()
        );
        assert!(c.count(PatchType::SingleCrease) > 0);
        let (_, plain) = refine(&m, isolation);
        assert_eq!(plain.count(PatchType::SingleCrease), 0);
    }
}

#[test]
fn census_within_opensubdiv() {
    let figures = [
        (
            "catmark_car",
            [4_539, 11_307, 21_843, 39_915, 73_059, 136_347],
        ),
        ("catmark_cube_creases1", [24, 96, 300, 768, 1_764, 1_836]),
    ];
    for (name, osd_totals) in figures {
        let m = osd(name);
        for (i, &limit) in osd_totals.iter().enumerate() {
            let (_, c) = refine(&m, i as u32 + 1);
            assert!(
                c.total() <= limit,
                "{name} isolation {}: {} > {limit}",
                i + 1,
                c.total()
            );
        }
    }
    let (_, c) = refine(&osd("catmark_car"), 6);
    assert!(c.count(PatchType::EndCap) <= 1_240);
}

#[test]
fn regular_meshes_stop_early_and_bad_isolation_is_an_error() {
    let m = osd("catmark_torus");
    let (r, c) = refine(&m, 5);
    assert_eq!(r.levels.len(), 1);
    assert_eq!(c.total(), m.face_count());
    assert!(AdaptiveRefinement::new(&Level::from_mesh(&m).unwrap(), 9).is_err());
}

#[test]
fn info_prints_the_census() {
    let path = common::meshes::osd_path("catmark_cube_creases1");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_tessera"))
        .args(["info", path.to_str().unwrap(), "--isolation", "3"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.lines().any(|l| l == "patches total=300"), "{text}");
    assert!(text.contains("patches level 3: total="), "{text}");
    let (r, _) = refine(&osd("catmark_cube_creases1"), 3);
    let bytes = RefinementTables::adaptive(&r).unwrap().gpu_tables().bytes();
    let vertices = format!("refined vertices={}", r.vertex_count());
    assert!(text.lines().any(|l| l == vertices), "{text}");
    assert!(
        text.lines().any(|l| l == format!("table bytes={bytes}")),
        "{text}"
    );
}

/// Patch totals against a mesh-wide crease sharpness (`ControlMesh::set_crease_sharpness`) at
/// isolation 8, so that no sharpness 1-7 is capped by the isolation level: with single-crease
/// patches each unit of sharpness adds the same number of patches (only the crease ends are
/// refined deeper), without them the increment doubles (the whole crease line is refined one
/// level deeper). Measured on `catmark_single_crease`, s = 1..7: with 194, 302, ..., 842 (+108
/// each); without 296, 728, 1,592, ..., 27,512 (+432, +864, ...).
#[test]
fn patch_count_is_linear_in_sharpness_with_single_crease_patches() {
    let base = osd("catmark_single_crease");
    let totals = |single_crease: bool| -> Vec<usize> {
        (1..=7)
            .map(|s| {
                let mut m = base.clone();
                assert!(m.set_crease_sharpness(s as f32).unwrap() > 0);
                let options = AdaptiveOptions {
                    single_crease,
                    ..AdaptiveOptions::new(8)
                };
                refine_with(&m, options).1.total()
            })
            .collect()
    };
    let steps = |t: Vec<usize>| -> Vec<usize> { t.windows(2).map(|w| w[1] - w[0]).collect() };
    let linear = steps(totals(true));
    assert!(
        linear.iter().all(|&d| d == linear[0] && d > 0),
        "{linear:?}"
    );
    let exponential = steps(totals(false));
    assert!(
        exponential.windows(2).all(|w| w[1] == 2 * w[0]),
        "{exponential:?}"
    );
}

#[test]
fn crease_sharpness_override_sets_every_sharp_tag() {
    let mut m = osd("catmark_single_crease");
    let before: Vec<f32> = m.creases().iter().map(|c| c.sharpness).collect();
    assert!(before
        .iter()
        .any(|&s| s >= tessera::mesh::INFINITE_SHARPNESS));
    m.set_crease_sharpness(2.5).unwrap();
    for (c, &s) in m.creases().iter().zip(&before) {
        assert_eq!(c.sharpness, if s > 0.0 { 2.5 } else { 0.0 });
    }
    assert!(m.set_crease_sharpness(-1.0).is_err());
    assert!(m.set_crease_sharpness(f32::NAN).is_err());
}

#[test]
fn info_prints_single_crease_counts() {
    let path = common::meshes::osd_path("catmark_car");
    let run = |extra: &[&str]| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_tessera"))
            .args(["info", path.to_str().unwrap(), "--isolation", "2"])
            .args(extra)
            .output()
            .unwrap();
        assert!(out.status.success());
        String::from_utf8(out.stdout).unwrap()
    };
    let text = run(&["--single-crease"]);
    assert!(text.lines().any(|l| l == "patches total=7719"), "{text}");
    let levels = text
        .lines()
        .filter(|l| l.starts_with("patches level") && l.contains(" single-crease="))
        .count();
    assert_eq!(levels, 3, "{text}");
    assert!(!run(&[]).contains("single-crease="));
    let text = run(&["--single-crease", "--crease-sharpness", "1"]);
    assert!(
        text.contains("creases: 314 (by sharpness: 1: 314)"),
        "{text}"
    );
}

/// Each adaptive step, made from its level in place (`subdiv::ring_step`), is the refinement of
/// the sub-level its faces make (`AdaptiveLevel::uniform_step`: `Level::extract_increasing`
/// then `Level::refine_kept`, the path it replaced) up to numbering and ring starts: the same
/// quads corner for corner, the vertex and edge maps they induce one-to-one, and through them
/// the same edges (ends, faces, sharpness bit for bit, cut flags), vertices (sharpness,
/// completeness) and one-rings (faces and edges), each ring a valid one (`check_fans`), on every
/// loadable corpus shape at isolation 4, with and without single-crease patches.
#[test]
fn steps_in_place_equal_sub_level_refinements() {
    for (name, m) in corpus() {
        for options in [AdaptiveOptions::new(4), single(4)] {
            let (r, _) = refine_with(&m, options);
            for (l, pair) in r.levels.windows(2).enumerate() {
                let step = pair[0].uniform_step(&pair[1]).unwrap().unwrap();
                let at = format!("{name} level {}", l + 1);
                same_level_up_to_numbering(&pair[1].level, &step.child, &at);
            }
        }
    }
}

/// `a` and `b` are one level numbered apart (see `steps_in_place_equal_sub_level_refinements`),
/// their faces in the same order.
fn same_level_up_to_numbering(a: &Level, b: &Level, at: &str) {
    let (ta, tb) = (a.topology(), b.topology());
    assert_eq!(ta.face_count(), tb.face_count(), "{at}");
    assert_eq!(ta.vertex_count(), tb.vertex_count(), "{at}");
    assert_eq!(ta.edge_count(), tb.edge_count(), "{at}");
    // The vertex and edge maps the corners induce, each checked one-to-one.
    let one_to_one = |pairs: &mut dyn Iterator<Item = (u32, u32)>, n: usize, what: &str| {
        let (mut to, mut from) = (vec![u32::MAX; n], vec![u32::MAX; n]);
        for (x, y) in pairs {
            assert!(
                to[x as usize] == u32::MAX || to[x as usize] == y,
                "{at}: {what} {x}"
            );
            assert!(
                from[y as usize] == u32::MAX || from[y as usize] == x,
                "{at}: {what} {x}"
            );
            to[x as usize] = y;
            from[y as usize] = x;
        }
        assert!(!to.contains(&u32::MAX), "{at}: a {what} is on no face");
        to
    };
    let faces = 0..ta.face_count() as u32;
    let vmap = one_to_one(
        &mut faces.clone().flat_map(|f| {
            let (x, y) = (ta.face_vertices(f), tb.face_vertices(f));
            assert_eq!(x.len(), y.len(), "{at} face {f}");
            x.iter().copied().zip(y.iter().copied()).collect::<Vec<_>>()
        }),
        ta.vertex_count(),
        "vertex",
    );
    let emap = one_to_one(
        &mut faces.clone().flat_map(|f| {
            let (x, y) = (ta.face_edges(f), tb.face_edges(f));
            x.iter().copied().zip(y.iter().copied()).collect::<Vec<_>>()
        }),
        ta.edge_count(),
        "edge",
    );
    for f in faces {
        assert_eq!(ta.is_hole(f), tb.is_hole(f), "{at} face {f}");
        assert_eq!(
            ta.has_limit_surface(f),
            tb.has_limit_surface(f),
            "{at} face {f}"
        );
    }
    for e in 0..ta.edge_count() as u32 {
        let g = emap[e as usize];
        let at = format!("{at} edge {e}");
        assert_eq!(
            ta.edge_vertices(e).map(|v| vmap[v as usize]),
            tb.edge_vertices(g),
            "{at}"
        );
        assert_eq!(ta.edge_faces(e), tb.edge_faces(g), "{at}");
        assert_eq!(ta.edge_face_locals(e), tb.edge_face_locals(g), "{at}");
        assert_eq!(
            ta.edge_sharpness(e).to_bits(),
            tb.edge_sharpness(g).to_bits(),
            "{at}"
        );
        assert_eq!(a.is_cut_edge(e), b.is_cut_edge(g), "{at}");
    }
    for v in 0..ta.vertex_count() as u32 {
        let w = vmap[v as usize];
        let at = format!("{at} vertex {v}");
        assert_eq!(
            ta.vertex_sharpness(v).to_bits(),
            tb.vertex_sharpness(w).to_bits(),
            "{at}"
        );
        assert_eq!(a.is_complete_vertex(v), b.is_complete_vertex(w), "{at}");
        let ring = |t: &Topology, v: u32| {
            let mut x: Vec<(u32, u16)> = t
                .vertex_faces(v)
                .iter()
                .copied()
                .zip(t.vertex_face_locals(v).iter().copied())
                .collect();
            x.sort_unstable();
            x
        };
        assert_eq!(ring(ta, v), ring(tb, w), "{at}");
        let mut ea: Vec<u32> = ta
            .vertex_edges(v)
            .iter()
            .map(|&e| emap[e as usize])
            .collect();
        let mut eb = tb.vertex_edges(w).to_vec();
        ea.sort_unstable();
        eb.sort_unstable();
        assert_eq!(ea, eb, "{at}");
        check_fans(ta, v, &at);
    }
}

/// Vertex `v`'s ring is fans one after the other, each its faces counter-clockwise with the edge
/// leaving `v` in its first face, then the edge entering `v` in each face (the next face's
/// leaving one), ending on an edge with one face; or a single closed fan, the last face's
/// entering edge the first one's leaving edge.
fn check_fans(t: &Topology, v: u32, at: &str) {
    let (faces, locals, edges) = (
        t.vertex_faces(v),
        t.vertex_face_locals(v),
        t.vertex_edges(v),
    );
    let leaving = |j: usize| t.face_edges(faces[j])[usize::from(locals[j])];
    let entering = |j: usize| {
        let fe = t.face_edges(faces[j]);
        fe[(usize::from(locals[j]) + fe.len() - 1) % fe.len()]
    };
    for (j, (&f, &k)) in faces.iter().zip(locals).enumerate() {
        assert_eq!(t.face_vertices(f)[usize::from(k)], v, "{at} face {j}");
    }
    if edges.len() == faces.len() {
        for (j, &e) in edges.iter().enumerate() {
            assert_eq!(e, leaving(j), "{at} face {j}");
            assert_eq!(entering(j), leaving((j + 1) % faces.len()), "{at} face {j}");
        }
        return;
    }
    let mut c = 0;
    let mut j = 0;
    while j < faces.len() {
        assert_eq!(edges[c], leaving(j), "{at} face {j}");
        assert_eq!(
            t.edge_faces(edges[c]).len(),
            1,
            "{at}: a fan starts on a one-face edge"
        );
        loop {
            c += 1;
            assert_eq!(edges[c], entering(j), "{at} face {j}");
            j += 1;
            if j == faces.len() || leaving(j) != edges[c] {
                break;
            }
        }
        assert_eq!(
            t.edge_faces(edges[c]).len(),
            1,
            "{at}: a fan ends on a one-face edge"
        );
        c += 1;
    }
    assert_eq!(c, edges.len(), "{at}");
}

/// `AdaptiveLevel::child_of` (a per-vertex array made with the step) names the component the
/// step's refined sub-level says: its face, its vertex, or the level's edge joining the
/// sub-level edge's two ends (`find_edge`, the lookup the array replaced), on every loadable
/// corpus shape at isolation 3, with and without single-crease patches.
#[test]
fn child_of_is_the_sub_levels_component() {
    for (name, m) in corpus() {
        for options in [AdaptiveOptions::new(3), single(3)] {
            let (r, _) = refine_with(&m, options);
            for (l, pair) in r.levels.windows(2).enumerate() {
                let lev = &pair[0];
                let Some(step) = lev.uniform_step(&pair[1]) else {
                    break;
                };
                let step = step.unwrap();
                let sub = step.parent.topology();
                let (nf, ne) = (sub.face_count() as u32, sub.edge_count() as u32);
                for (v, &p) in step.child_points.iter().enumerate() {
                    let want = if p < nf {
                        ChildOf::Face(step.parent_faces[p as usize])
                    } else if p < nf + ne {
                        let [a, b] = sub.edge_vertices(p - nf);
                        let [a, b] = [a, b].map(|x| step.parent_vertices[x as usize]);
                        ChildOf::Edge(lev.topology().find_edge(a, b).unwrap())
                    } else {
                        ChildOf::Vertex(step.parent_vertices[(p - nf - ne) as usize])
                    };
                    assert_eq!(lev.child_of(v as u32), want, "{name} level {l} vertex {v}");
                }
            }
        }
    }
}
