//! Conformance of `--scheme qas` (Boubekeur, Schlick 2007): quadratic position and normal patches
//! through one Catmull-Clark step's limit points. The patches interpolate those limit points
//! exactly (to f32), approximate the rest of the limit (figures reported, bounded by what was
//! measured), shade with normals closer to the limit's than their own geometric normals, equal
//! their CPU construction, are bitwise watertight, animate as a rebuild, and refuse n-gons with a
//! typed reason (checks in `tests/common/conformance.rs`).

mod common;

use std::time::Instant;

use common::capture::{offscreen, uniform};
use common::conformance::{
    accuracy_within, animation_on, assert_watertight, draw, golden_patch_type, gpu_equals_cpu_on,
    watertight_on,
};
use common::gpu::{assert_validation_clean, context};
use common::meshes::mesh;
use glam::DVec3;
use tessera::mesh::INFINITE_SHARPNESS;
use tessera::patch::qas::{NotQas, QasKind, QasSurface};
use tessera::render::animate::twist;
use tessera::render::schemes::qas::QasTables;
use tessera::render::{plan_for_scheme, CaptureRecord, RefusalReason, Scheme, SchemeLimits};
use tessera::subdiv::eval::LimitEvaluator;
use tessera::topology::{is_sharp_edge, Topology};

const SCHEME: Scheme = Scheme::Qas;

fn angle(a: DVec3, b: DVec3) -> f64 {
    a.angle_between(b)
}

/// The limit point a captured QAS point at a node of level 2 should interpolate: quads at
/// their own `(u, v)`; triangles (barycentric `(1 - u - v, u, v)`) at a corner `k` or the
/// midpoint of edge `k -> k+1`, i.e. sub-face `k`'s `(0, 0)` or `(1, 0)`.
fn node_limit(ev: &LimitEvaluator, sides: usize, face: u32, u: f64, v: f64) -> (DVec3, DVec3) {
    let s = if sides == 4 {
        ev.eval(face as usize, 0, u, v)
    } else {
        let w = [1.0 - u - v, u, v];
        match w.iter().position(|&x| x == 1.0) {
            Some(k) => ev.eval(face as usize, k, 0.0, 0.0),
            None => {
                let zero = w.iter().position(|&x| x == 0.0).expect("a level-2 node");
                ev.eval(face as usize, (zero + 1) % 3, 1.0, 0.0)
            }
        }
    }
    .unwrap();
    (s.position, s.normal)
}

/// The corner vertex of `face` at `(u, v)` (quad domain or triangle barycentrics), if any.
fn corner_vertex(topo: &Topology, face: u32, u: f64, v: f64) -> Option<u32> {
    let fv = topo.face_vertices(face);
    let k = if fv.len() == 4 {
        [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
            .iter()
            .position(|&c| c == (u, v))?
    } else {
        [1.0 - u - v, u, v].iter().position(|&w| w == 1.0)?
    };
    Some(fv[k])
}

/// An infinitely sharp vertex with fewer than two sharp edges: the limit has no normal there
/// (each face's mask gives its own); QAS takes the sector's (module docs of `patch::qas`).
fn is_cusp(topo: &Topology, v: u32) -> bool {
    let sharp = topo
        .vertex_edges(v)
        .iter()
        .filter(|&&e| is_sharp_edge(topo, e))
        .count();
    topo.vertex_sharpness(v) >= INFINITE_SHARPNESS && sharp < 2 && !topo.is_boundary_vertex(v)
}

/// Interpolation: at uniform level 2 every TES point is a corner, an edge midpoint or a quad's
/// centre, i.e. one of the step's limit points; the GPU gives the exact limit there (position
/// within 1e-6 of the diagonal, normal within 1e-5 rad: f32 precision; not at cusps, which have
/// no limit normal) on meshes with triangles, boundaries, creases and semi-sharp creases. Measured:
/// <= 2.8e-7 of the diagonal and 1.2e-7 rad.
#[test]
fn limit_points_interpolated_exactly() {
    let Some(ctx) = context() else { return };
    for name in [
        "catmark_bishop",
        "embedded:mixed",
        "embedded:open",
        "embedded:creased",
        "catmark_car",
    ] {
        let m = mesh(name);
        let ev = LimitEvaluator::new(&m).unwrap();
        let (surface, records) = draw(&ctx, &m, SCHEME, uniform(2.0));
        let diag = m.bbox_diagonal();
        let drawn = surface.part("qas").expect("qas draws");
        let topo = Topology::new(&m).unwrap();
        let (mut worst_p, mut worst_n, mut n) = (0.0f64, 0.0f64, 0);
        // Every point of a level-2 quad is a node; a triangle's inner point (⅓, ⅓) is not.
        let node = |r: &&CaptureRecord| {
            m.face_size(r.face as usize) == 4 || r.u == 0.0 || r.v == 0.0 || r.u + r.v == 1.0
        };
        for r in records
            .iter()
            .filter(|r| drawn.faces().contains(&r.face))
            .filter(node)
        {
            let (u, v) = (f64::from(r.u), f64::from(r.v));
            assert!(
                [0.0, 0.5, 1.0].contains(&u) && [0.0, 0.5, 1.0].contains(&v),
                "{name}: level-2 node ({u}, {v})"
            );
            let (p, nrm) = node_limit(&ev, m.face_size(r.face as usize), r.face, u, v);
            let gp = DVec3::from(r.position.map(f64::from));
            let gn = DVec3::from(r.normal.map(f64::from));
            let mut a = angle(gn, nrm);
            if corner_vertex(&topo, r.face, u, v).is_some_and(|c| is_cusp(&topo, c)) {
                a = 0.0;
            }
            let d = (gp - p).length() / diag;
            assert!(
                d <= 1e-6 && a <= 1e-5,
                "{name}: face {} ({u}, {v}): {d:.2e} of the diagonal, {a:.2e} rad from the limit",
                r.face
            );
            worst_p = worst_p.max(d);
            worst_n = worst_n.max(a);
            n += 1;
        }
        assert!(n > 0, "{name}: nothing compared");
        eprintln!("{name}: {n} limit points: {worst_p:.2e} of the diagonal, {worst_n:.2e} rad");
    }
    assert_validation_clean(&ctx);
}

/// Accuracy against the exact limit at the TES points of level 8 (`tessera error MESH --scheme
/// qas`, closest exact point), bounded by today's figures rounded up (README table).
#[test]
fn accuracy_against_the_exact_limit() {
    accuracy_within(
        SCHEME,
        &[
            ("embedded:mixed", 1.4e-3, 1.4e-2, 2.8e-2),
            ("catmark_cube", 2.1e-3, 3.3e-3, 3.0e-2),
            ("catmark_car", 1.6e-4, 1.6e-3, 1.5e-1),
            ("catmark_bishop", 6.5e-5, 9.0e-4, 1.5e-1),
        ],
    );
}

/// The paper's point: the surface is only C0, but the separate normal patch shades it close to
/// the limit. Over a 9 x 9 grid per quad (CPU construction, the GPU's within 1e-6), the angle
/// between the shading normal (normal patch) and the position patch's geometric normal is
/// reported, and the shading normal is closer to the exact limit normal than the geometric one.
#[test]
fn shading_normals_against_geometric_normals() {
    for name in ["embedded:mixed", "catmark_car", "catmark_bishop"] {
        let m = mesh(name);
        let topo = Topology::new(&m).unwrap();
        let faces: Vec<u32> = (0..topo.face_count() as u32)
            .filter(|&f| topo.has_limit_surface(f) && topo.face_size(f) <= 4)
            .collect();
        let (qas, refused) = QasSurface::build(&topo, &faces);
        assert!(refused.is_empty(), "{name}: {refused:?}");
        let ev = LimitEvaluator::new(&m).unwrap();
        let points = qas.points(m.positions());
        let (mut geo2, mut shade2, mut geo_limit2, mut n) = (0.0, 0.0, 0.0, 0usize);
        let mut geo_max = 0.0f64;
        for (i, p) in qas.patches.iter().enumerate() {
            if p.kind != QasKind::Quad {
                continue;
            }
            let c = qas.control(i, &points);
            let uv: Vec<(f64, f64)> = (0..9)
                .flat_map(|j| (0..9).map(move |i| (i as f64 / 8.0, j as f64 / 8.0)))
                .collect();
            let exact = ev.eval_points(p.face as usize, 0, &uv).unwrap();
            for (&(u, v), e) in uv.iter().zip(&exact) {
                let (_, shade) = c.eval(u, v);
                let geo = c.geometric_normal(u, v);
                let a = angle(shade, geo);
                geo2 += a * a;
                geo_max = geo_max.max(a);
                shade2 += angle(shade, e.normal).powi(2);
                geo_limit2 += angle(geo, e.normal).powi(2);
                n += 1;
            }
        }
        let rms = |s: f64| (s / n as f64).sqrt();
        eprintln!(
            "{name}: shading vs geometric normal RMS {:.3e} max {:.3e} rad; vs the limit normal: \
             shading RMS {:.3e}, geometric RMS {:.3e} ({n} points)",
            rms(geo2),
            geo_max,
            rms(shade2),
            rms(geo_limit2)
        );
        assert!(n > 0);
        assert!(
            rms(shade2) < rms(geo_limit2),
            "{name}: the normal patch does not shade closer to the limit than the geometry"
        );
    }
}

/// Triangles interpolate the corners and edge midpoints only: how far the quadratic triangle's
/// centre (barycentric ⅓, ⅓, ⅓) is from the face point's limit (CPU construction), reported
/// and bounded by today's figure on embedded:mixed (7 triangles).
#[test]
fn triangle_centre_against_the_face_point() {
    let m = mesh("embedded:mixed");
    let topo = Topology::new(&m).unwrap();
    let faces: Vec<u32> = (0..topo.face_count() as u32)
        .filter(|&f| topo.face_size(f) == 3)
        .collect();
    let (qas, refused) = QasSurface::build(&topo, &faces);
    assert!(refused.is_empty());
    let ev = LimitEvaluator::new(&m).unwrap();
    let diag = m.bbox_diagonal();
    let mut worst = 0.0f64;
    for (i, p) in qas.patches.iter().enumerate() {
        let c = qas.control_from(i, m.positions());
        let (centre, _) = c.eval(1.0 / 3.0, 1.0 / 3.0);
        let f = ev.eval(p.face as usize, 0, 1.0, 1.0).unwrap().position;
        worst = worst.max((centre - f).length() / diag);
    }
    eprintln!("triangle centres vs face-point limits: max {worst:.3e} of the diagonal");
    assert!(worst > 0.0 && worst < 2e-2, "{worst:e}");
}

/// GPU == CPU construction (`QasSurface::control_from`) at every captured parameter: 1e-6 of
/// the diagonal, interior normals 1e-5 rad.
#[test]
fn gpu_equals_cpu_construction() {
    gpu_equals_cpu_on(
        SCHEME,
        &["embedded:mixed", "embedded:open", "catmark_car"],
        1e-6,
        1e-5,
    );
}

/// Bitwise watertight on every edge two QAS patches share (quad/quad, quad/triangle,
/// triangle/triangle; smooth, crease and semi-sharp edges), uniform and screen-space levels.
#[test]
fn watertight() {
    watertight_on(
        SCHEME,
        &[
            ("embedded:mixed", 5.0),
            ("embedded:open", 7.0),
            ("embedded:creased", 6.0),
            ("catmark_car", 5.0),
            ("embedded:mixed", 33.0),
        ],
    );
    let Some(ctx) = context() else { return };
    let m = mesh("embedded:mixed");
    let tess = tessera::render::TessSettings {
        mode: tessera::render::TessMode::Adaptive,
        pixels_per_edge: 4.0,
        ..uniform(8.0)
    };
    let (surface, records) = draw(&ctx, &m, SCHEME, tess);
    assert_watertight("mixed screen-space", &surface, &records);
    let (surface, records) = draw(&ctx, &m, SCHEME, distance_mode(8.0));
    assert_watertight("mixed camera distance", &surface, &records);
}

/// The paper's camera-distance metric (`--tess-mode distance`): `level x D / d` per edge, d the
/// eye's distance to the midpoint of the edge's end-vertex limit points, D the bounding-box
/// diagonal by default.
fn distance_mode(level: f32) -> tessera::render::TessSettings {
    tessera::render::TessSettings {
        mode: tessera::render::TessMode::Distance,
        ..uniform(level)
    }
}

/// Camera-distance levels: every captured quad edge has the points its level predicts from the
/// eye's distance (counted on the CPU from the limit points, `ceil(clamp(L D / d, 1, 64))`
/// segments with equal spacing), and the car's nearest faces get more points than its farthest.
#[test]
fn camera_distance_levels() {
    let Some(ctx) = context() else { return };
    let m = mesh("catmark_car");
    let surface =
        tessera::render::plan_for_scheme(&m, SCHEME, &SchemeLimits::from_context(&ctx)).unwrap();
    let render = tessera::render::RenderDesc {
        tess: distance_mode(8.0),
        ..Default::default()
    };
    let mut anim = common::capture::Animation::new(&ctx, &surface, &render, &offscreen(96, 96));
    let records = anim.frame();
    let eye = anim.eye();
    let topo = Topology::new(&m).unwrap();
    let (lo, hi) = surface.bounding_box();
    let reference = (hi - lo).length();
    // The shared limit points the TCS reads (vertex_limit).
    let frames = surface.vertex_frames(&surface.positions);
    let limit = |v: u32| frames.limits[v as usize];
    let qas: std::collections::HashSet<u32> = surface
        .part("qas")
        .unwrap()
        .faces()
        .iter()
        .copied()
        .collect();
    let (mut checked, mut by_face) = (0, std::collections::HashMap::new());
    for r in &records {
        *by_face.entry(r.face).or_insert(0usize) += 1;
    }
    for &f in &qas {
        let fv = topo.face_vertices(f);
        if fv.len() != 4 {
            continue;
        }
        // Edge v = 0 of the quad: corners 0 and 1.
        let d = (0.5 * (limit(fv[0]) + limit(fv[1])) - eye).length();
        let want = (8.0 * reference / d).clamp(1.0, 64.0).ceil() as usize + 1;
        let got = records
            .iter()
            .filter(|r| r.face == f && r.v == 0.0)
            .map(|r| r.u.to_bits())
            .collect::<std::collections::BTreeSet<_>>()
            .len();
        // f32 rounding of d can move a level across an integer: allow one segment.
        assert!(
            got.abs_diff(want) <= 1,
            "face {f}: {got} points on edge v = 0, the distance rule gives {want}"
        );
        checked += 1;
    }
    let centre = |f: u32| {
        let fv = topo.face_vertices(f);
        fv.iter().map(|&v| limit(v)).sum::<DVec3>() / fv.len() as f64
    };
    let nearest = qas.iter().min_by(|&&a, &&b| {
        (centre(a) - eye)
            .length()
            .total_cmp(&(centre(b) - eye).length())
    });
    let farthest = qas.iter().max_by(|&&a, &&b| {
        (centre(a) - eye)
            .length()
            .total_cmp(&(centre(b) - eye).length())
    });
    let (n, f) = (by_face[nearest.unwrap()], by_face[farthest.unwrap()]);
    eprintln!(
        "car, camera distance: {checked} edges checked; nearest face {n} points, farthest {f}"
    );
    assert!(checked > 100 && n > f);
    assert_validation_clean(&ctx);
}

/// Moving the control vertices (stencils re-applied on the CPU, records rewritten) equals
/// rebuilding from the moved mesh, bitwise.
#[test]
fn animation_equals_rebuild() {
    animation_on(SCHEME, "catmark_car");
}

/// The per-frame CPU work of animation (limit stencils applied, patches fitted, records
/// written to bytes): the moved points equal the exact limit of the moved mesh, and the median
/// time over 15 runs is reported (README).
#[test]
fn per_frame_update() {
    for name in ["catmark_car", "catmark_bishop"] {
        let m = mesh(name);
        let limits = SchemeLimits::NO_DEVICE;
        let surface = plan_for_scheme(&m, SCHEME, &limits).unwrap();
        let tables = surface
            .part("qas")
            .unwrap()
            .as_any()
            .downcast_ref::<QasTables>()
            .unwrap();
        let moved = twist(m.positions(), DVec3::Z, 1.5, 0.3);
        let mut times = Vec::new();
        let mut bytes = 0;
        for _ in 0..15 {
            let t = Instant::now();
            let points = tables.surface.points(&moved);
            bytes = tables.record_bytes(&points).len();
            times.push(t.elapsed().as_secs_f64() * 1e3);
        }
        times.sort_by(f64::total_cmp);
        eprintln!(
            "{name}: {} patches, {} stencil weights, per-frame update median {:.2} ms ({bytes} bytes)",
            tables.surface.patches.len(),
            tables.surface.stencil_weights(),
            times[7]
        );
        // The moved corner points are the moved mesh's exact limit.
        let mut mm = m.clone();
        mm.set_positions(&moved).unwrap();
        let ev = LimitEvaluator::new(&mm).unwrap();
        let points = tables.surface.points(&moved);
        let diag = mm.bbox_diagonal();
        for p in tables.surface.patches.iter().take(50) {
            // Slot 0 is corner 0 for both shapes: sub-face 0's (0, 0).
            let got = points.positions[p.points[0] as usize];
            let want = ev.eval(p.face as usize, 0, 0.0, 0.0).unwrap().position;
            assert!(
                (got - want).length() / diag < 1e-12,
                "{name}: face {}",
                p.face
            );
        }
    }
}

/// Coloured by patch type (quads purple, triangles green, the CPU-path pentagon as the
/// reference's colour).
#[test]
fn golden() {
    golden_patch_type(SCHEME, "qas_mixed_patch_type");
}

/// Faces of five or more sides are refused with a typed reason naming the face.
#[test]
fn ngons_refused_by_name() {
    let m = mesh("embedded:mixed");
    let surface = plan_for_scheme(&m, SCHEME, &SchemeLimits::NO_DEVICE).unwrap();
    let r: Vec<_> = surface
        .refusals
        .iter()
        .filter(|r| r.pass == "qas")
        .collect();
    assert_eq!(r.len(), 1, "{r:?}");
    assert_eq!(
        r[0].reason,
        RefusalReason::NotQas(NotQas::Polygon { face: 0, sides: 5 })
    );
    assert!(r[0].to_string().starts_with("face 0: 5 sides"));
}
