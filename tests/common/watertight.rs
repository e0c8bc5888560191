//! Bitwise watertightness: the points two patches emit on their shared edge must be the same
//! bits on both sides. Where a captured point lies on its face's boundary, the bits compared,
//! and the shared-edge check.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::fmt::Debug;

use glam::DVec3;
use tessera::mesh::ControlMesh;
use tessera::mesh::INFINITE_SHARPNESS;
use tessera::render::{CaptureRecord, SurfaceData};
use tessera::topology::{is_sharp_edge, sector_count, sector_faces, Topology};

/// Where a domain point lies on a face with `n` corners: a quad's (u, v), or a triangle's
/// barycentric weights (u, v) of corners 1 and 2.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Boundary {
    /// Inside the face.
    Interior,
    /// At corner `k`.
    Corner(usize),
    /// On the edge between corners `from` and `to` (adjacent), at parameter `t` from `from`.
    Edge { from: usize, to: usize, t: f32 },
}

impl Boundary {
    /// The edges (pairs of adjacent corners) the point lies on: two at a corner.
    pub fn edges(self, n: usize) -> Vec<(usize, usize)> {
        match self {
            Boundary::Interior => Vec::new(),
            Boundary::Corner(k) => vec![((k + n - 1) % n, k), (k, (k + 1) % n)],
            Boundary::Edge { from, to, .. } => vec![(from, to)],
        }
    }
}

/// Classifies domain point (u, v) of a quad (`n == 4`) or triangle (`n == 3`); a triangle's
/// third weight counts as zero within 1e-6.
pub fn boundary(n: usize, u: f32, v: f32) -> Boundary {
    if n == 4 {
        let (ue, ve) = (u == 0.0 || u == 1.0, v == 0.0 || v == 1.0);
        if ue && ve {
            return Boundary::Corner(match (u == 0.0, v == 0.0) {
                (true, true) => 0,
                (false, true) => 1,
                (false, false) => 2,
                (true, false) => 3,
            });
        }
        if v == 0.0 {
            Boundary::Edge {
                from: 0,
                to: 1,
                t: u,
            }
        } else if u == 1.0 {
            Boundary::Edge {
                from: 1,
                to: 2,
                t: v,
            }
        } else if v == 1.0 {
            Boundary::Edge {
                from: 3,
                to: 2,
                t: u,
            }
        } else if u == 0.0 {
            Boundary::Edge {
                from: 0,
                to: 3,
                t: v,
            }
        } else {
            Boundary::Interior
        }
    } else {
        let w0_zero = (1.0 - f64::from(u) - f64::from(v)).abs() < 1e-6;
        let zeros = usize::from(u == 0.0) + usize::from(v == 0.0) + usize::from(w0_zero);
        if zeros >= 2 {
            return Boundary::Corner(if u == 0.0 && v == 0.0 {
                0
            } else if u != 0.0 {
                1
            } else {
                2
            });
        }
        if v == 0.0 {
            Boundary::Edge {
                from: 0,
                to: 1,
                t: u,
            }
        } else if w0_zero {
            Boundary::Edge {
                from: 1,
                to: 2,
                t: v,
            }
        } else if u == 0.0 {
            Boundary::Edge {
                from: 2,
                to: 0,
                t: 1.0 - v,
            }
        } else {
            Boundary::Interior
        }
    }
}

/// Where point `(u, v)` of sub-face `k` of a face with `n` corners lies on the face's boundary
/// (sub-face `k`: `(0, 0)` at corner `k`, `v = 0` the first half of edge `k -> k+1`, `u = 0` the
/// half of edge `k-1 -> k` at corner `k`, as `tessera limit` names the points of n-gons).
pub fn sub_face_boundary(n: usize, k: usize, u: f32, v: f32) -> Boundary {
    match (u == 0.0, v == 0.0) {
        (true, true) => Boundary::Corner(k),
        (false, true) => Boundary::Edge {
            from: k,
            to: (k + 1) % n,
            t: 0.5 * u,
        },
        (true, false) => Boundary::Edge {
            from: k,
            to: (k + n - 1) % n,
            t: 0.5 * v,
        },
        (false, false) => Boundary::Interior,
    }
}

/// Where a captured point lies on its face's boundary: in its sub-face when it names one (faces
/// other than quads drawn per sub-face), else in the face's own domain ([`boundary`]).
pub fn record_boundary(n: usize, r: &CaptureRecord) -> Boundary {
    match r.sub_face {
        Some(k) if n != 4 => sub_face_boundary(n, k as usize, r.u, r.v),
        _ => boundary(n, r.u, r.v),
    }
}

/// Bit patterns of a record's position.
pub fn position_bits(r: &CaptureRecord) -> [u32; 3] {
    r.position.map(f32::to_bits)
}

/// Bit patterns of a record's position and normal.
pub fn point_bits(r: &CaptureRecord) -> [u32; 6] {
    let [p0, p1, p2] = position_bits(r);
    let [n0, n1, n2] = r.normal.map(f32::to_bits);
    [p0, p1, p2, n0, n1, n2]
}

/// The distinct bit patterns `B` each face emitted on each mesh edge.
pub struct EdgePoints<B> {
    edges: HashMap<(u32, u32), BTreeMap<u32, BTreeSet<B>>>,
}

/// What [`EdgePoints::assert_equal_sides`] compared.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Compared {
    /// Edges whose two sides were compared.
    pub edges: usize,
    /// Points found bitwise equal on both sides.
    pub points: usize,
}

impl<B: Ord + Debug> EdgePoints<B> {
    /// No points yet.
    pub fn new() -> Self {
        EdgePoints {
            edges: HashMap::new(),
        }
    }

    /// Face `face` emitted `bits` on the edge between vertices `a` and `b`.
    pub fn add(&mut self, a: u32, b: u32, face: u32, bits: B) {
        self.edges
            .entry((a.min(b), a.max(b)))
            .or_default()
            .entry(face)
            .or_default()
            .insert(bits);
    }

    /// For every edge for which `sides(edge, faces that emitted points on it)` names two faces:
    /// the first emitted points, and both emitted the same set of bit patterns.
    pub fn assert_equal_sides(
        &self,
        what: &str,
        sides: impl Fn((u32, u32), &[u32]) -> Option<[u32; 2]>,
    ) -> Compared {
        let empty = BTreeSet::new();
        let mut compared = Compared {
            edges: 0,
            points: 0,
        };
        for (&(a, b), by_face) in &self.edges {
            let emitting: Vec<u32> = by_face.keys().copied().collect();
            let Some([f0, f1]) = sides((a, b), &emitting) else {
                continue;
            };
            let (s0, s1) = (
                by_face.get(&f0).unwrap_or(&empty),
                by_face.get(&f1).unwrap_or(&empty),
            );
            assert!(!s0.is_empty(), "{what}: edge {a}-{b}: no points captured");
            assert!(
                s0 == s1,
                "{what}: edge {a}-{b} (faces {f0} / {f1}): {} and {} points, not bitwise equal",
                s0.len(),
                s1.len()
            );
            compared.edges += 1;
            compared.points += s0.len();
        }
        compared
    }
}

/// The B-spline patches of `surface` against each other: on every edge two patches emitted
/// points on, both emitted the same position bits. Returns the number of such edges.
pub fn assert_regular_watertight(
    what: &str,
    surface: &SurfaceData,
    records: &[CaptureRecord],
) -> usize {
    let corners: HashMap<u32, [u32; 4]> = surface
        .regular_patches()
        .iter()
        .map(|p| (p.face, p.corners()))
        .collect();
    let mut points = EdgePoints::new();
    for r in records {
        let c = corners[&r.face];
        for (i, j) in boundary(4, r.u, r.v).edges(4) {
            points.add(c[i], c[j], r.face, position_bits(r));
        }
    }
    let both = |_, faces: &[u32]| <[u32; 2]>::try_from(faces).ok();
    points.assert_equal_sides(what, both).edges
}

/// Pairs of records closer than 1e-6 of `m`'s diagonal, whatever the patches' types and levels;
/// asserts that each pair's positions are bitwise equal.
pub fn coincident_pairs(m: &ControlMesh, records: &[CaptureRecord]) -> Vec<(usize, usize)> {
    // Bitwise-unequal copies of one point differ by a few ulp (~1e-7 of the diagonal); distinct
    // domain points of fractional spacing can come within ~5e-6.
    let eps = 1e-6 * m.bbox_diagonal();
    let cell = |p: [f32; 3]| p.map(|c| (f64::from(c) / eps).floor() as i64);
    let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for (i, r) in records.iter().enumerate() {
        grid.entry(cell(r.position)).or_default().push(i);
    }
    let mut pairs = Vec::new();
    for (i, r) in records.iter().enumerate() {
        let c = cell(r.position);
        let p = DVec3::from(r.position.map(f64::from));
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let Some(list) = grid.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) else {
                        continue;
                    };
                    for &j in list.iter().filter(|&&j| j > i) {
                        let q = &records[j];
                        if (DVec3::from(q.position.map(f64::from)) - p).length() > eps {
                            continue;
                        }
                        let same_pos = r.position.map(f32::to_bits) == q.position.map(f32::to_bits);
                        assert!(same_pos, "positions differ: {r:?} vs {q:?}");
                        pairs.push((i, j));
                    }
                }
            }
        }
    }
    pairs
}

/// Points patches emit at the same place are the same bits, whatever the patches' types and
/// levels: every pair of records closer than 1e-6 of `m`'s diagonal has bitwise-equal positions,
/// and normals bitwise equal or more than 0.01 rad apart (a crease). Returns the number of
/// coincident pairs.
pub fn assert_coincident_points_equal(m: &ControlMesh, records: &[CaptureRecord]) -> usize {
    assert_pair_normals(records, &coincident_pairs(m, records), |_, _| None)
}

/// [`assert_coincident_points_equal`] where the topology tells the sides of every sharp feature
/// apart: two points on the same side (the same base face, across a smooth base edge, or in
/// one sector of a base vertex split by sharp edges) must have bitwise-equal normals however
/// close the two sides' normals are; points of different sides may differ by any angle.
pub fn assert_coincident_points_equal_by_side(m: &ControlMesh, records: &[CaptureRecord]) -> usize {
    let topo = Topology::new(m).unwrap();
    let pairs = coincident_pairs(m, records);
    assert_pair_normals(records, &pairs, |r, q| {
        Some(side(&topo, r)? == side(&topo, q)?)
    })
}

/// [`assert_coincident_points_equal_by_side`] for `--scheme adaptive` at `isolation` (default
/// options). The end caps' creases ([`EndCapCreases`], residual semi-sharpness) count as smooth:
/// the exact limit is smooth across them and both sides draw one shared normal there
/// (`patch::adaptive::promoted`). Returns the number of coincident pairs and how many of them
/// lie on an end-cap crease.
pub fn assert_adaptive_points_equal_by_side(
    m: &ControlMesh,
    isolation: u32,
    records: &[CaptureRecord],
) -> (usize, usize) {
    let creases = EndCapCreases::new(m, isolation);
    let topo = Topology::new(m).unwrap();
    let pairs = coincident_pairs(m, records);
    let on_crease = pairs
        .iter()
        .filter(|&&(i, _)| creases.on_crease(&records[i]))
        .count();
    let n = assert_pair_normals(records, &pairs, |r, q| {
        Some(side(&topo, r)? == side(&topo, q)?)
    });
    (n, on_crease)
}

/// The edges end caps treat as infinitely sharp while the base mesh does not (residual
/// semi-sharpness, `AdaptiveRefinement::end_cap_topology`), from the same refinement the GPU
/// draws: edges of the end caps' level that are infinitely sharp in the end-cap topology, not in
/// the level's own, with an end cap on both sides (beside a single-crease patch the end cap
/// reads that patch's edge record, normals included), as spans along their base edges.
pub struct EndCapCreases {
    /// The base topology with every base edge holding a span made infinitely sharp (sectors at
    /// base vertices).
    pub topo: Topology,
    /// Per base edge: spans along it, parameter from its smaller vertex id.
    spans: HashMap<u32, Vec<(f64, f64)>>,
    /// How many spans there are.
    pub count: usize,
}

impl EndCapCreases {
    /// The end caps' creases of `m` at `isolation` with the GPU scheme's default options.
    pub fn new(m: &ControlMesh, isolation: u32) -> EndCapCreases {
        use tessera::subdiv::adaptive::{
            AdaptiveOptions, AdaptiveRefinement, PatchCensus, PatchType,
        };
        let base = Topology::new(m).unwrap();
        let options = AdaptiveOptions {
            single_crease: tessera::render::PlanOptions::DEFAULT_SINGLE_CREASE,
            ..AdaptiveOptions::new(isolation)
        };
        let r = AdaptiveRefinement::with_options(
            &tessera::subdiv::Level::from_topology(base.clone()),
            options,
        )
        .unwrap();
        let census = PatchCensus::new(&r);
        let mut caps = std::collections::HashSet::new();
        for p in census
            .patches
            .iter()
            .filter(|p| p.kind == PatchType::EndCap)
        {
            caps.insert((p.level, p.face));
        }
        let mut spans: HashMap<u32, Vec<(f64, f64)>> = HashMap::new();
        let mut count = 0;
        for (l, lev) in r.levels.iter().enumerate() {
            let t = lev.topology();
            let tc = r.end_cap_topology(l);
            for e in 0..t.edge_count() as u32 {
                let faces = t.edge_faces(e);
                let crease = tc.edge_sharpness(e) >= INFINITE_SHARPNESS
                    && t.edge_sharpness(e) < INFINITE_SHARPNESS
                    && faces.len() == 2
                    && faces.iter().all(|&f| caps.contains(&(l as u32, f)));
                if !crease {
                    continue;
                }
                let f = faces[0];
                let k = t.face_edges(f).iter().position(|&x| x == e).unwrap();
                let d = lev.domains[f as usize];
                let corner = |c: usize| {
                    let (a, b) = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)][c % 4];
                    d.origin + a * d.u + b * d.v
                };
                let (p, q) = (corner(k), corner(k + 1));
                let ends =
                    [p, q].map(|x| base_edge_points(&base, d.base_face, d.sub_face, x.x, x.y));
                let (be, s0, s1) = ends[0]
                    .iter()
                    .find_map(|&(e0, s0)| {
                        ends[1]
                            .iter()
                            .find(|&&(e1, _)| e1 == e0)
                            .map(|&(_, s1)| (e0, s0, s1))
                    })
                    .expect("an end-cap crease lies on a base edge");
                spans.entry(be).or_default().push((s0.min(s1), s0.max(s1)));
                count += 1;
            }
        }
        let creases: Vec<tessera::mesh::Crease> = spans
            .keys()
            .map(|&e| {
                let [v0, v1] = base.edge_vertices(e);
                tessera::mesh::Crease {
                    v0,
                    v1,
                    sharpness: INFINITE_SHARPNESS,
                }
            })
            .collect();
        EndCapCreases {
            topo: base.with_creases(&creases).unwrap(),
            spans,
            count,
        }
    }

    /// Whether captured point `r` lies on an end-cap crease away from base vertices: inside a
    /// span, or where two spans meet (an end of a single span is a dart, one normal).
    pub fn on_crease(&self, r: &CaptureRecord) -> bool {
        let (u, v) = (f64::from(r.u), f64::from(r.v));
        let on = base_edge_points(&self.topo, r.face, r.sub_face, u, v);
        if on.len() != 1 {
            return false;
        }
        let (e, s) = on[0];
        let Some(spans) = self.spans.get(&e) else {
            return false;
        };
        const EPS: f64 = 1e-6;
        let inside = spans.iter().any(|&(a, b)| s > a + EPS && s < b - EPS);
        let ends = spans
            .iter()
            .filter(|&&(a, b)| (s - a).abs() <= EPS || (s - b).abs() <= EPS)
            .count();
        inside || ends >= 2
    }
}

/// The base edges point `(u, v)` of `face` (sub-face `sub` of a non-quad) lies on, each with
/// the point's parameter along it from its smaller vertex id: none inside, two at a corner.
fn base_edge_points(
    topo: &Topology,
    face: u32,
    sub: Option<u32>,
    u: f64,
    v: f64,
) -> Vec<(u32, f64)> {
    let fv = topo.face_vertices(face);
    let n = fv.len();
    // (face edge k, parameter from corner k).
    let mut on: Vec<(usize, f64)> = Vec::new();
    match sub {
        None if n == 4 => {
            if v == 0.0 {
                on.push((0, u));
            }
            if u == 1.0 {
                on.push((1, v));
            }
            if v == 1.0 {
                on.push((2, 1.0 - u));
            }
            if u == 0.0 {
                on.push((3, 1.0 - v));
            }
        }
        Some(k) => {
            let k = k as usize;
            if v == 0.0 {
                on.push((k, u / 2.0));
            }
            if u == 0.0 {
                on.push(((k + n - 1) % n, 1.0 - v / 2.0));
            }
        }
        None => {}
    }
    on.into_iter()
        .map(|(k, s)| {
            let (a, b) = (fv[k], fv[(k + 1) % n]);
            let e = topo.face_edges(face)[k];
            (e, if a < b { s } else { 1.0 - s })
        })
        .collect()
}

/// The side of the sharp features captured point `r` lies on: its base face inside the face or on
/// a sharp base edge, the smaller face beside a smooth base edge, the smallest face of its sector
/// at a base vertex (its own face at a cone); `None` where the record does not tell (a
/// triangle's barycentric domain).
fn side(topo: &Topology, r: &CaptureRecord) -> Option<u32> {
    let f = r.face;
    let fv = topo.face_vertices(f);
    let n = fv.len();
    let edge = |k: usize| topo.face_edges(f)[k % n];
    let across = |e: u32| {
        if is_sharp_edge(topo, e) {
            f
        } else {
            topo.edge_faces(e).iter().copied().min().unwrap_or(f)
        }
    };
    // A cone (corner tag, fewer than two sharp edges) has a normal per face.
    let cone = |v: u32| topo.vertex_sharpness(v) >= INFINITE_SHARPNESS && sector_count(topo, v) < 2;
    let sector = |v: u32| match cone(v) {
        true => f,
        false => sector_faces(topo, v, f).into_iter().min().unwrap_or(f),
    };
    let (u, v) = (r.u, r.v);
    match r.sub_face {
        // Sub-face k: corner k at (0, 0), half of edge k along v = 0, of edge k - 1 along u = 0.
        Some(k) => {
            let k = k as usize;
            Some(match (u == 0.0, v == 0.0) {
                (true, true) => sector(fv[k]),
                (false, true) => across(edge(k)),
                (true, false) => across(edge(k + n - 1)),
                (false, false) => f,
            })
        }
        None if n == 4 => Some(match boundary(4, u, v) {
            Boundary::Interior => f,
            Boundary::Corner(k) => sector(fv[k]),
            // Face edge k joins corners k and k + 1.
            Boundary::Edge { from, to, .. } => {
                across(edge(if (from + 1) % 4 == to { from } else { to }))
            }
        }),
        None => None,
    }
}

/// Asserts bitwise-equal normals for each coincident pair `(i, j)` of `records` where
/// `same_side(r, q)` says `Some(true)`; with `None` the normals must be bitwise equal or more than
/// 0.01 rad apart (a crease). Returns the number of pairs.
fn assert_pair_normals(
    records: &[CaptureRecord],
    pairs: &[(usize, usize)],
    same_side: impl Fn(&CaptureRecord, &CaptureRecord) -> Option<bool>,
) -> usize {
    for &(i, j) in pairs {
        let (r, q) = (&records[i], &records[j]);
        let (a, b) = (
            DVec3::from(r.normal.map(f64::from)),
            DVec3::from(q.normal.map(f64::from)),
        );
        let same_n = r.normal.map(f32::to_bits) == q.normal.map(f32::to_bits);
        let may_differ = same_side(r, q).map_or(a.angle_between(b) > 0.01, |s| !s);
        assert!(
            same_n || may_differ,
            "normals differ by {:.2e} rad: {r:?} vs {q:?}",
            a.angle_between(b)
        );
    }
    pairs.len()
}

/// The TES capture of one 64 x 64 frame of `surface`.
fn capture_64(
    ctx: &tessera::gpu::Context,
    surface: &SurfaceData,
    render: &tessera::render::RenderDesc,
) -> Vec<CaptureRecord> {
    let off = super::capture::offscreen(64, 64);
    super::capture::capture(ctx, surface, render, &off, false).records
}

/// Displacement keeps the surface watertight: `surface` captured with `render(0.0)` and
/// `render(scale)` has the same number of bitwise-equal coincident pairs
/// ([`assert_coincident_points_equal`]), more than 0 (a point moved differently on the two
/// sides would leave the coincident set unnoticed otherwise). Returns the count.
pub fn assert_displacement_keeps_seams(
    ctx: &tessera::gpu::Context,
    m: &ControlMesh,
    surface: &SurfaceData,
    render: impl Fn(f32) -> tessera::render::RenderDesc,
    scale: f32,
    what: &str,
) -> usize {
    let pairs = |s| assert_coincident_points_equal(m, &capture_64(ctx, surface, &render(s)));
    let (plain, moved) = (pairs(0.0), pairs(scale));
    eprintln!("{what}: {moved} coincident pairs bitwise equal");
    assert!(moved > 0, "{what}: no shared point compared");
    assert_eq!(moved, plain, "{what}: shared points split apart");
    moved
}

/// Map displacement keeps the surface watertight: `surface` captured with `render(0.0)` and
/// `render(scale)` has the same number of coincident pairs, each bitwise equal in position
/// ([`coincident_pairs`]), more than 0. The map's tilted normals of the two sides agree only
/// to a tolerance (each side's own tangents and texture-coordinate Jacobian): returns the
/// count and the largest angle (rad) between the displaced normals of a pair whose
/// undisplaced normals are bitwise equal (smooth there).
pub fn map_displacement_seams(
    ctx: &tessera::gpu::Context,
    m: &ControlMesh,
    surface: &SurfaceData,
    render: impl Fn(f32) -> tessera::render::RenderDesc,
    scale: f32,
    what: &str,
) -> (usize, f64) {
    let run = |s| capture_64(ctx, surface, &render(s));
    let key = |r: &CaptureRecord| (r.face, r.sub_face, r.u.to_bits(), r.v.to_bits());
    let plain = run(0.0);
    let plain_normal: HashMap<_, _> = plain.iter().map(|r| (key(r), r.normal)).collect();
    let moved = run(scale);
    let (before, pairs) = (
        coincident_pairs(m, &plain).len(),
        coincident_pairs(m, &moved),
    );
    let mut worst = 0.0f64;
    for &(i, j) in &pairs {
        let (r, q) = (&moved[i], &moved[j]);
        let smooth = match (plain_normal.get(&key(r)), plain_normal.get(&key(q))) {
            (Some(a), Some(b)) => a.map(f32::to_bits) == b.map(f32::to_bits),
            _ => false,
        };
        if smooth {
            let (a, b) = (
                DVec3::from(r.normal.map(f64::from)),
                DVec3::from(q.normal.map(f64::from)),
            );
            worst = worst.max(a.angle_between(b));
        }
    }
    eprintln!(
        "{what}: {} coincident pairs bitwise equal in position, displaced normals of smooth \
         pairs within {worst:.2e} rad",
        pairs.len()
    );
    assert!(!pairs.is_empty(), "{what}: no shared point compared");
    assert_eq!(pairs.len(), before, "{what}: shared points split apart");
    (pairs.len(), worst)
}

/// Inside a base face: every domain point two or more patches emitted (same face, sub-face and
/// (u, v) bits) has the same position bits from each, however far apart a crack would put
/// them (the pair test of [`coincident_pairs`] sees only points closer than 1e-6 of the
/// diagonal). Returns how many such points were compared.
pub fn assert_equal_at_shared_domain_points(records: &[CaptureRecord]) -> usize {
    type Key = (u32, Option<u32>, u32, u32);
    let mut at: HashMap<Key, &CaptureRecord> = HashMap::new();
    let mut shared = std::collections::HashSet::new();
    for r in records {
        let key = (r.face, r.sub_face, r.u.to_bits(), r.v.to_bits());
        match at.get(&key) {
            None => {
                at.insert(key, r);
            }
            Some(q) => {
                assert!(
                    position_bits(q) == position_bits(r),
                    "face {} sub-face {:?} ({}, {}): {:?} and {:?} ({:?} / {:?})",
                    r.face,
                    r.sub_face,
                    r.u,
                    r.v,
                    q.position,
                    r.position,
                    q.patch,
                    r.patch
                );
                shared.insert(key);
            }
        }
    }
    shared.len()
}
