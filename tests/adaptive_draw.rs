//! The GPU draw tables of the feature-adaptive scheme (`patch::adaptive::draw`), pure CPU,
//! against independent computations: slot rows against the exact limit (`LimitEvaluator`),
//! end-cap rows against `AdaptiveSurface`'s Gregory patches, coarse-edge records against both
//! the coarse and the finer B-spline patches' own evaluation, and the layout invariants.

mod common;

use std::collections::{BTreeMap, HashMap};
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};

use common::meshes::osd;
use glam::{DVec2, DVec3};
use rayon::prelude::*;
use tessera::patch::adaptive::records::CoarseEdge;
use tessera::patch::adaptive::{AdaptiveDrawTables, AdaptiveSurface, PatchShape};
use tessera::patch::edge_grid::PATCH_EDGES;
use tessera::subdiv::adaptive::AdaptiveRefinement;
use tessera::subdiv::bspline::{bspline, bspline_deriv};
use tessera::subdiv::eval::LimitEvaluator;
use tessera::subdiv::Level;
use tessera::ControlMesh;

const MESHES: [&str; 9] = [
    "catmark_cube",
    "catmark_inf_crease1",
    "catmark_single_crease",
    "catmark_car",
    "catmark_bishop",
    "catmark_pole64",
    "catmark_nonquads",
    "catmark_cube_creases1",
    "catmark_edgecorner",
];

const NONE: u32 = u32::MAX;
/// Domain corners in face order.
const CORNERS: [(f64, f64); 4] = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];

struct Case {
    name: &'static str,
    iso: u32,
    mesh: ControlMesh,
    refinement: AdaptiveRefinement,
    surface: AdaptiveSurface,
    tables: AdaptiveDrawTables,
}

fn case(name: &'static str, mesh: &ControlMesh, iso: u32) -> Case {
    let refinement = AdaptiveRefinement::new(&Level::from_mesh(mesh).unwrap(), iso).unwrap();
    let surface = AdaptiveSurface::new(&refinement, mesh.positions())
        .unwrap_or_else(|e| panic!("{name} iso {iso}: {e}"));
    let tables =
        AdaptiveDrawTables::new(&refinement).unwrap_or_else(|e| panic!("{name} iso {iso}: {e}"));
    Case {
        name,
        iso,
        mesh: mesh.clone(),
        refinement,
        surface,
        tables,
    }
}

fn for_each_case(f: impl Fn(&Case) + Sync) {
    MESHES.par_iter().for_each(|&name| {
        let m = osd(name);
        (1..=4)
            .into_par_iter()
            .for_each(|iso| f(&case(name, &m, iso)));
    });
}

impl Case {
    /// Global ids of patch `i`'s corners in face order.
    fn corner_ids(&self, i: usize) -> Vec<u32> {
        let p = &self.surface.patches[i];
        let lev = &self.refinement.levels[p.level as usize];
        lev.topology()
            .face_vertices(p.face)
            .iter()
            .map(|&v| lev.global(v))
            .collect()
    }

    fn slot(&self, g: u32) -> u32 {
        self.tables
            .slot_of(g)
            .unwrap_or_else(|| panic!("{}: vertex {g} has no slot", self.name))
    }

    /// Whether global vertex `g` of patch `i`'s level touches a semi-sharp tag there.
    fn residual_semi_sharp(&self, i: usize, g: u32) -> bool {
        let p = &self.surface.patches[i];
        let lev = &self.refinement.levels[p.level as usize];
        let t = lev.topology();
        let v = g - lev.first_vertex;
        let semi = |s: f32| s > 0.0 && s < 10.0;
        semi(t.vertex_sharpness(v)) || t.vertex_edges(v).iter().any(|&e| semi(t.edge_sharpness(e)))
    }

    fn label(&self) -> String {
        format!("{} iso {}", self.name, self.iso)
    }
}

/// A patch corner: its slot, the frame of its normal (the slot, or the sector frame of its
/// sector) and base-face `(u, v)`.
type Occurrence = (u32, u32, (f64, f64));

/// (a) Every slot row applied to the refined positions is the exact limit position (and, where
/// the normal is shared, normal) at every patch corner with that slot; an exact patch's corner
/// with a sector frame (a point split by sharp edges) takes that frame's normal, the exact one
/// of its face.
#[test]
fn slot_rows_are_the_exact_limit_frames() {
    let sector_corners = AtomicUsize::new(0);
    for_each_case(|c| {
        let ev = LimitEvaluator::new(&c.mesh).unwrap();
        let diag = c.mesh.bbox_diagonal();
        let rows = &c.tables.rows;
        let pos = &c.tables.with_vertex_points(&c.surface.positions);
        // Occurrences grouped by (base face, sub-face): (slot, (u, v)).
        let mut groups: BTreeMap<(u32, u32), Vec<Occurrence>> = BTreeMap::new();
        let mut skipped = 0;
        for (i, p) in c.surface.patches.iter().enumerate() {
            for (k, g) in c.corner_ids(i).into_iter().enumerate() {
                let s = c.slot(g);
                if c.residual_semi_sharp(i, g) {
                    skipped += 1;
                    continue;
                }
                let d = p.domain;
                let uv = d.origin + CORNERS[k].0 * d.u + CORNERS[k].1 * d.v;
                let frame = match c.tables.sector_corners[i][k] {
                    NONE => s,
                    // An end cap's sector frame is its sector's Gregory corner plane (frames
                    // from end caps exist only in sectors without an exact patch), not the
                    // face's exact normal where that differs per face (three-face corner
                    // sectors): its position is still checked, with the slot.
                    _ if matches!(p.shape, PatchShape::Gregory(_)) => s,
                    f => {
                        sector_corners.fetch_add(1, Relaxed);
                        f
                    }
                };
                groups
                    .entry((d.base_face, d.sub_face.unwrap_or(0)))
                    .or_default()
                    .push((s, frame, (uv.x, uv.y)));
            }
        }
        let mut checked = 0;
        for ((f, sub), occ) in &groups {
            let uv: Vec<(f64, f64)> = occ.iter().map(|o| o.2).collect();
            let exact = ev.eval_points(*f as usize, *sub as usize, &uv).unwrap();
            for (&(s, frame, _), x) in occ.iter().zip(exact) {
                let r = 3 * s as usize;
                let p = rows.apply(r, pos);
                let err = p.distance(x.position) / diag;
                assert!(
                    err <= 1e-9,
                    "{}: slot {s} position off by {err:e}",
                    c.label()
                );
                if c.tables.shared_normal[frame as usize] {
                    let rf = 3 * frame as usize;
                    let n = rows
                        .apply(rf + 1, pos)
                        .cross(rows.apply(rf + 2, pos))
                        .normalize();
                    let angle = n.angle_between(x.normal);
                    assert!(
                        angle <= 1e-7,
                        "{}: slot {s} (frame {frame}) normal off by {angle:e}",
                        c.label()
                    );
                }
                // The f32 weights the GPU reads.
                let p32 = rows.apply_f32(r, pos);
                assert!(p32.distance(x.position) / diag <= 1e-6, "{}", c.label());
                checked += 1;
            }
        }
        assert!(checked > 0, "{}", c.label());
        if skipped > 0 {
            eprintln!(
                "{}: {skipped} corners with residual semi-sharp tags not exact",
                c.label()
            );
        }
    });
    let sectors = sector_corners.into_inner();
    eprintln!("{sectors} patch corners read a sector frame");
    assert!(sectors > 0, "no sector frame was checked");
}

/// (b) End-cap rows are the `AdaptiveSurface` Gregory control points; the extra rows are the
/// neighbouring end cap's edge and face points, bitwise shared with it.
#[test]
fn end_cap_rows_are_the_gregory_control_points() {
    let shared = AtomicUsize::new(0);
    for_each_case(|c| {
        let diag = c.mesh.bbox_diagonal();
        let rows = &c.tables.rows;
        let pos = &c.tables.with_vertex_points(&c.surface.positions);
        let by_face: HashMap<(u32, u32), usize> = c
            .surface
            .patches
            .iter()
            .enumerate()
            .map(|(i, p)| ((p.level, p.face), i))
            .collect();
        let caps: HashMap<usize, u32> = c
            .tables
            .end_caps
            .iter()
            .map(|e| (e.record as usize, e.first_row))
            .collect();
        let near = |a: DVec3, b: DVec3| a.distance(b) <= 1e-9 * diag;
        let terms = |r: u32| {
            let (a, b) = (
                rows.offsets[r as usize] as usize,
                rows.offsets[r as usize + 1] as usize,
            );
            (
                rows.ids[a..b].to_vec(),
                rows.weights_f64[a..b]
                    .iter()
                    .map(|&w| (w as f32).to_bits())
                    .collect::<Vec<_>>(),
            )
        };
        for (&i, &first) in &caps {
            let PatchShape::Gregory(g) = &c.surface.patches[i].shape else {
                panic!("{}: record {i} is no end cap", c.label());
            };
            let points: Vec<DVec3> = g.points().into_iter().flatten().copied().collect();
            for (q, &x) in points.iter().enumerate() {
                assert!(
                    near(rows.apply(first as usize + q, pos), x),
                    "{}: cap {i} row {q}",
                    c.label()
                );
            }
            let n = g.corner_count();
            let p = &c.surface.patches[i];
            let t = c.refinement.levels[p.level as usize].topology();
            let fv = t.face_vertices(p.face);
            for k in 0..n {
                let (x, y) = (fv[k], fv[(k + 1) % n]);
                let Some(h) = t.adjacent_face(p.face, k) else {
                    continue;
                };
                let Some(&j) = by_face.get(&(p.level, h)) else {
                    continue;
                };
                let (Some(&other), PatchShape::Gregory(o)) =
                    (caps.get(&j), &c.surface.patches[j].shape)
                else {
                    continue;
                };
                let d = t.face_vertices(h);
                let m = d.len();
                let k2 = (0..m).find(|&i| d[i] == y && d[(i + 1) % m] == x).unwrap();
                let k2n = (k2 + 1) % m;
                let [_, ep, em, fp, fm] = o.points();
                let extra = [
                    (5 * n + 2 * k, ep[k2n]),
                    (5 * n + 2 * k + 1, em[k2]),
                    (7 * n + 2 * k, fm[k2n]),
                    (7 * n + 2 * k + 1, fp[k2]),
                ];
                for (r, want) in extra {
                    assert!(
                        near(rows.apply(first as usize + r, pos), want),
                        "{}: cap {i} extra row {r}",
                        c.label()
                    );
                }
                shared.fetch_add(1, Relaxed);
                // Shared corner points: the same terms, bitwise.
                assert_eq!(
                    terms(first + k as u32),
                    terms(other + k2n as u32),
                    "{}",
                    c.label()
                );
                assert_eq!(
                    terms(first + ((k + 1) % n) as u32),
                    terms(other + k2 as u32),
                    "{}",
                    c.label()
                );
            }
        }
    });
    assert!(
        shared.into_inner() > 1000,
        "too few shared end-cap edges checked"
    );
}

/// The canonical edge curve of a coarse record at `t` (from the lo end): position and, for
/// smooth edges, the normal from the cross direction (`grid_edge_rows` of watertight.glsl).
fn record_curve(e: &CoarseEdge, pos: &[DVec3], t: f64) -> (DVec3, Option<DVec3>) {
    let row = |r: usize| {
        let mut x: [DVec3; 4] = std::array::from_fn(|k| pos[e.rows[4 * r + k] as usize]);
        if e.flags & 2 != 0 {
            x[0] = 2.0 * x[1] - x[2];
        }
        if e.flags & 4 != 0 {
            x[3] = 2.0 * x[2] - x[1];
        }
        x
    };
    let (l, m, r) = (row(0), row(1), row(2));
    let sharp = e.flags & 1 != 0;
    let c: [DVec3; 4] = std::array::from_fn(|i| {
        if sharp {
            m[i]
        } else {
            (l[i] + r[i] + 4.0 * m[i]) / 6.0
        }
    });
    let (n, dn) = (bspline(t), bspline_deriv(t));
    let p = (0..4).map(|i| n[i] * c[i]).sum();
    let tangent: DVec3 = (0..4).map(|i| dn[i] * c[i]).sum();
    let cross: DVec3 = (0..4).map(|i| n[i] * (l[i] - r[i])).sum();
    (p, (!sharp).then(|| tangent.cross(cross).normalize()))
}

/// Patch `i`'s edge `k` (B-spline numbering for B-spline patches, face order for end caps) as
/// its two end corners (face-order corner indices).
fn edge_corners(c: &Case, i: usize, k: usize) -> (usize, usize) {
    match c.surface.patches[i].shape {
        PatchShape::BSpline(_) | PatchShape::SingleCrease(_) => PATCH_EDGES[k],
        PatchShape::Gregory(ref g) => (k, (k + 1) % g.corner_count()),
    }
}

/// Compares the record's curve over `[t0, t1]` of its parameter with patch `i`'s own
/// evaluation along its edge from corner `a` to corner `b`. Returns whether normals were
/// compared.
fn compare_edge(c: &Case, e: &CoarseEdge, i: usize, (a, b): (usize, usize), (t0, t1): (f64, f64)) {
    let diag = c.mesh.bbox_diagonal();
    let (pa, pb) = (DVec2::from(CORNERS[a]), DVec2::from(CORNERS[b]));
    for j in 0..=8 {
        let t = j as f64 / 8.0;
        let st = pa + t * (pb - pa);
        let own = c.surface.eval_patch(i, st.x, st.y);
        let (p, n) = record_curve(e, &c.surface.positions, t0 + t * (t1 - t0));
        let err = p.distance(own.position) / diag;
        assert!(
            err <= 1e-9,
            "{}: patch {i} edge {a}->{b} t {t}: {err:e}",
            c.label()
        );
        if let Some(n) = n {
            let angle = n.angle_between(own.du.cross(own.dv).normalize());
            assert!(angle <= 1e-7, "{}: patch {i} normal {angle:e}", c.label());
        }
    }
}

/// (c) Every coarse-edge record's curve equals the coarse patch's own edge and, mapped to the
/// halves, each finer B-spline patch's own edge (position, and normal on smooth edges).
#[test]
fn coarse_edges_match_both_levels() {
    let phantoms = AtomicUsize::new(0);
    let fine = AtomicUsize::new(0);
    for_each_case(|c| {
        let t = &c.tables;
        let mut fine_refs = vec![0; t.coarse_edges.len()];
        let key: HashMap<(u32, u32, u32), usize> = t
            .coarse_edges
            .iter()
            .enumerate()
            .map(|(r, e)| ((e.lo_slot, e.hi_slot, e.mid_slot), r))
            .collect();
        for (i, rec) in t.records.iter().enumerate() {
            let ids = c.corner_ids(i);
            for k in 0..4 {
                let (a, b) = edge_corners(c, i, k);
                let (sa, sb) = (c.slot(ids[a]), c.slot(ids[b]));
                if rec.transition & (1 << k) != 0 {
                    let r = key[&(sa.min(sb), sa.max(sb), rec.mid_slots[k])];
                    let (a, b) = if sa < sb { (a, b) } else { (b, a) };
                    compare_edge(c, &t.coarse_edges[r], i, (a, b), (0.0, 1.0));
                }
                if rec.coarse[k] == NONE {
                    continue;
                }
                let r = rec.coarse[k] as usize;
                fine_refs[r] += 1;
                let e = &t.coarse_edges[r];
                if e.flags & 6 != 0 {
                    phantoms.fetch_add(1, Relaxed);
                }
                let ((a, b), half) = match (sa, sb) {
                    (x, y) if x == e.lo_slot && y == e.mid_slot => ((a, b), (0.0, 0.5)),
                    (x, y) if y == e.lo_slot && x == e.mid_slot => ((b, a), (0.0, 0.5)),
                    (x, y) if x == e.mid_slot && y == e.hi_slot => ((a, b), (0.5, 1.0)),
                    (x, y) if y == e.mid_slot && x == e.hi_slot => ((b, a), (0.5, 1.0)),
                    _ => panic!("{}: patch {i} edge {k} is no half of record {r}", c.label()),
                };
                if matches!(c.surface.patches[i].shape, PatchShape::BSpline(_)) {
                    compare_edge(c, e, i, (a, b), half);
                    fine.fetch_add(1, Relaxed);
                }
            }
        }
        assert!(fine_refs.iter().all(|&n| n == 2), "{}", c.label());
    });
    assert!(
        phantoms.into_inner() > 0,
        "no record with phantom ends checked"
    );
    assert!(fine.into_inner() > 1000, "too few finer halves checked");
}

/// (d) Layout invariants: byte sizes, every corner has a slot and one point has one slot, the
/// transition fans tile the domain, shared edges get one canonical direction.
#[test]
fn layout_invariants() {
    for_each_case(|c| {
        let t = &c.tables;
        assert_eq!(t.patch_record_bytes().len(), 144 * c.surface.patches.len());
        assert_eq!(t.regular_info_bytes().len(), 32 * t.regular.len());
        assert_eq!(t.regular_index_bytes().len(), 64 * t.regular.len());
        assert_eq!(t.transition_info_bytes().len(), 32 * t.transition.len());
        assert_eq!(t.triangle_bytes().len(), 16 * t.triangles.len());
        assert_eq!(t.triangle_index_bytes().len(), 64 * t.triangles.len());
        assert_eq!(t.end_cap_info_bytes().len(), 32 * t.end_caps.len());
        assert_eq!(t.end_cap_grid_bytes().len(), 192 * t.end_caps.len());
        assert_eq!(t.coarse_edge_bytes().len(), 64 * t.coarse_edges.len());
        assert_eq!(t.end_cap_first_row as usize, 3 * t.frame_count());
        assert_eq!(
            t.vertex_first_row as usize,
            3 * t.frame_count() + 36 * t.end_caps.len()
        );
        // Only vertex points some row reads; the first stage reads refined points only, the
        // rest any.
        let n = t.refined_points as usize;
        let mut read = vec![false; t.vertex_point_count()];
        for r in 0..t.vertex_first_row as usize {
            for (v, _) in t.rows.row(r) {
                if v as usize >= n {
                    read[v as usize - n] = true;
                }
            }
        }
        assert!(
            read.iter().all(|&r| r),
            "{}: unread vertex point",
            c.label()
        );
        for r in 0..t.rows.len() {
            let bound = if r < t.vertex_first_row as usize {
                n + t.vertex_point_count()
            } else {
                n
            };
            assert!(
                t.rows.row(r).all(|(v, _)| (v as usize) < bound),
                "{}",
                c.label()
            );
        }
        assert_eq!(
            t.regular.len() + t.transition.len() + t.end_caps.len(),
            c.surface.patches.len()
        );
        // One slot per point: corners at the same base-face parameter share a slot, and every
        // slot is somebody's corner.
        let mut at: HashMap<(u32, u32, i64, i64), u32> = HashMap::new();
        let mut used = vec![false; t.slot_count()];
        for (i, p) in c.surface.patches.iter().enumerate() {
            for (k, g) in c.corner_ids(i).into_iter().enumerate() {
                let s = c.slot(g);
                used[s as usize] = true;
                let d = p.domain;
                let uv = d.origin + CORNERS[k].0 * d.u + CORNERS[k].1 * d.v;
                let q = |x: f64| (x * 1e9).round() as i64;
                let key = (d.base_face, d.sub_face.unwrap_or(0), q(uv.x), q(uv.y));
                assert_eq!(
                    *at.entry(key).or_insert(s),
                    s,
                    "{}: two slots at one point",
                    c.label()
                );
            }
        }
        assert!(used.iter().all(|&u| u), "{}", c.label());
        // Fans: triangles per transition patch cover the unit square once, same orientation.
        let mut area = vec![0.0; t.transition.len()];
        for tri in &t.triangles {
            let mask = t.records[t.transition[tri.patch as usize].record as usize].transition;
            let e = tri.edge as usize;
            assert_eq!(tri.half == 0, mask & (1 << e) == 0, "{}", c.label());
            let (s, u) = PATCH_EDGES[e];
            let (a, b) = (DVec2::from(CORNERS[s]), DVec2::from(CORNERS[u]));
            let m = 0.5 * (a + b);
            let (p, q) = [(a, b), (a, m), (m, b)][tri.half as usize];
            let centre = DVec2::splat(0.5);
            area[tri.patch as usize] += 0.5 * (p - centre).perp_dot(q - centre).abs();
        }
        assert!(
            area.iter().all(|&a| (a - 1.0).abs() < 1e-12),
            "{}",
            c.label()
        );
        // Canonical directions: the start of every B-spline edge from the flags is its smaller
        // slot, whichever patch holds the edge.
        let mut dir: HashMap<(u32, u32), u32> = HashMap::new();
        for d in t.regular.iter().chain(&t.transition) {
            for (e, &(s, u)) in PATCH_EDGES.iter().enumerate() {
                let (a, b) = (d.corners[s], d.corners[u]);
                let start = if d.flags & (1 << (4 + e)) != 0 { b } else { a };
                assert_eq!(start, a.min(b), "{}", c.label());
                assert_eq!(*dir.entry((a.min(b), a.max(b))).or_insert(start), start);
            }
        }
    });
}

/// The car and the bishop (residual semi-sharp edges below isolation 6) and the 360-valent pole
/// (rings beyond any fixed patch size) build with every end cap.
#[test]
fn residual_semi_sharp_and_huge_rings_build() {
    for name in ["catmark_car", "catmark_bishop", "catmark_pole360"] {
        let m = osd(name);
        for iso in 1..=4 {
            let c = case(name, &m, iso);
            let caps = c
                .surface
                .patches
                .iter()
                .filter(|p| matches!(p.shape, PatchShape::Gregory(_)))
                .count();
            assert_eq!(caps, c.tables.end_caps.len(), "{}", c.label());
            assert!(c.tables.memory_bytes() > 0);
        }
    }
}
