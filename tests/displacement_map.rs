//! Displacement from a map (`--displacement FILE.png`, `Displacement::Map`): every scheme moves
//! each TES point by `scale * (value - 0.5)` along its normal, `value` the map sampled at the
//! point's texture coordinate as the CPU mirror (`DisplacementMap::sample`, bilinear over texel
//! centres with wrap-around) computes it; the displaced surface stays bitwise watertight at
//! several levels on `embedded:mixed` (B-spline and Gregory or end-cap patches side by side)
//! with one shared `vt` per vertex; bad input (no `vt`, no map, a missing or corrupt file, a
//! map beyond the device's image size) is a typed error. The golden map `assets/
//! displacement_bumps.png` is [`bumps`] (checked here, rewritten with `TESSERA_UPDATE_GOLDEN=1`).

mod common;

use std::path::PathBuf;

use common::capture::{
    capture, image, offscreen, param_key, points_by_param, scheme_surface, uniform,
};
use common::golden::{check_golden, update_requested};
use common::gpu::{assert_validation_clean, context};
use common::meshes::{mesh, with_shared_uvs};
use common::watertight::{coincident_pairs, map_displacement_seams};
use glam::{DVec2, DVec3};
use tessera::mesh::ObjOptions;
use tessera::render::displace::DisplacementMap;
use tessera::render::{
    render_to_image, CaptureRecord, ColorBy, Displacement, OffscreenDesc, RenderDesc, Scheme,
    SurfaceData,
};
use tessera::subdiv::eval::LimitEvaluator;
use tessera::{ControlMesh, Error};

const SCALE: f32 = 0.2;
/// Side of the golden map.
const BUMPS: u32 = 32;

/// The golden map: `BUMPS x BUMPS` 8-bit texels `round(127.5 + 127 sin(2 pi x) cos(4 pi y))` at
/// the texel centres `x = (i + 0.5) / w`, `y = (j + 0.5) / h`: smooth, periodic (so repeat
/// addressing has no seam), the full range of values.
fn bumps() -> Vec<u8> {
    let tau = std::f64::consts::TAU;
    let n = f64::from(BUMPS);
    (0..BUMPS)
        .flat_map(|j| {
            (0..BUMPS).map(move |i| {
                let (x, y) = ((f64::from(i) + 0.5) / n, (f64::from(j) + 0.5) / n);
                (127.5 + 127.0 * (tau * x).sin() * (2.0 * tau * y).cos()).round() as u8
            })
        })
        .collect()
}

fn asset() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/displacement_bumps.png")
}

fn bumps_map() -> DisplacementMap {
    DisplacementMap::from_u8(BUMPS, BUMPS, bumps()).unwrap()
}

/// `embedded:mixed` with one shared `vt` per vertex.
fn mixed_with_uvs() -> ControlMesh {
    ControlMesh::from_obj_str(
        &with_shared_uvs(&mesh("embedded:mixed")),
        "mixed-uv.obj",
        &ObjOptions::default(),
    )
    .unwrap()
}

fn desc(level: f32, scale: f32) -> RenderDesc {
    RenderDesc {
        tess: uniform(level),
        displacement: Displacement::Map { scale },
        ..RenderDesc::default()
    }
}

fn mapped(ctx: &tessera::gpu::Context, m: &ControlMesh, level: u32, scheme: Scheme) -> SurfaceData {
    let mut surface = scheme_surface(ctx, m, level, scheme);
    surface.set_displacement_map(bumps_map()).unwrap();
    surface
}

#[test]
fn golden_map_asset_is_the_documented_function() {
    let path = asset();
    if update_requested() {
        image::GrayImage::from_raw(BUMPS, BUMPS, bumps())
            .unwrap()
            .save(&path)
            .unwrap();
    }
    let loaded = DisplacementMap::load(&path).unwrap();
    assert_eq!(loaded.size(), (BUMPS, BUMPS));
    assert_eq!(loaded.texels(), bumps_map().texels());
    assert_eq!(loaded.source(), path.display().to_string());
}

/// Positions bitwise watertight; the tilted normals of the two sides of a smooth shared point
/// agree within NORMAL_SEAM (each side's tangents and texture-coordinate Jacobian are its
/// own: the map composed with the per-face bilinear texture coordinates is only continuous
/// across edges).
#[test]
fn map_displaced_surface_is_watertight_for_every_scheme() {
    let Some(ctx) = context() else { return };
    let m = mixed_with_uvs();
    let mut worst = 0.0f64;
    for scheme in Scheme::ALL {
        for level in [2.0, 5.0, 8.0] {
            let surface = mapped(&ctx, &m, level as u32, scheme);
            let what = format!("{scheme:?} level {level}");
            let (_, angle) =
                map_displacement_seams(&ctx, &m, &surface, |s| desc(level, s), SCALE, &what);
            worst = worst.max(angle);
        }
    }
    eprintln!("largest normal angle across shared smooth points: {worst:.3e} rad");
    assert!(
        worst <= NORMAL_SEAM,
        "{worst} rad across a seam (bound {NORMAL_SEAM})"
    );
    assert_validation_clean(&ctx);
}

/// Largest angle (rad) between the two sides' map-tilted normals at a shared smooth point of
/// `embedded:mixed` (SCALE, the bumps map, levels 2-8, every scheme). Measured: 0.515 (adaptive;
/// 0.40-0.48 the others), while the tilt itself reaches 0.60: this mesh's `vt` (a projection of
/// the control vertices) give the map a cross-edge derivative that jumps at most edges, a kink
/// of the displaced surface itself. On the flat grid, whose texture coordinate is linear in the
/// position, the sides agree within 1.2e-7 (`map_normals_of_a_ramp_on_a_plane_...`).
const NORMAL_SEAM: f64 = 0.55;

/// `loose` for the schemes in `set`, `tight` for the others.
fn bound_for(scheme: Scheme, set: &[Scheme], loose: f64, tight: f64) -> f64 {
    if set.contains(&scheme) {
        loose
    } else {
        tight
    }
}

/// d(s, t)/d(u, v) (columns) of the documented texture-coordinate mapping (`mesh::uv`) at a
/// record in a Ptex domain (a quad's own or a non-quad's sub-face), in f64; `None` for the
/// barycentric domains (triangles drawn whole, Pm sectors), which the exact limit evaluator
/// does not name.
fn texcoord_jacobian(m: &ControlMesh, r: &CaptureRecord) -> Option<[DVec2; 2]> {
    let uvs = m.uvs()?;
    let f = r.face as usize;
    let n = m.face_size(f);
    let c = |k: usize| DVec2::from(uvs.corner(m.face_offsets(), f, k % n).map(f64::from));
    let (u, v) = (f64::from(r.u), f64::from(r.v));
    let pm = r.patch.is_some_and(|p| p.kind >= 16);
    let [c0, c1, c2, c3] = match r.sub_face {
        None if n == 4 => [c(0), c(1), c(2), c(3)],
        Some(k) if n != 4 && !pm => {
            let k = k as usize;
            let centre = (0..n).map(c).sum::<DVec2>() / n as f64;
            [
                c(k),
                (c(k) + c(k + 1)) * 0.5,
                centre,
                (c(k + n - 1) + c(k)) * 0.5,
            ]
        }
        _ => return None,
    };
    Some([
        (c1 - c0) * (1.0 - v) + (c2 - c3) * v,
        (c3 - c0) * (1.0 - u) + (c2 - c1) * u,
    ])
}

/// The GPU's displaced points and normals against the CPU mirror at the captured texture
/// coordinates. Normals: `DisplacementMap::shading_normal` of the undisplaced GPU normal with
/// the exact limit's partials (`LimitEvaluator`) and the mapping's Jacobian in f64, at every
/// point of a Ptex domain but the domain corners (where the limit's partials at an
/// extraordinary vertex are arbitrarily scaled); within NORMAL_MIRROR where the scheme's
/// patches are the exact limit, NORMAL_MIRROR_APPROX where their tangents approximate it.
/// Tolerance: lavapipe (llvmpipe) filters 8-bit unorm texels in 8-bit fixed point: the bilinear
/// weights have 8 sub-texel bits (an error of up to `largest_step / 256` over both axes) and the
/// filtered value is returned as a multiple of 1/255 (truncated: up to 1/255 off); with f32
/// rounding of `p + s d n` (1e-6 of the diagonal) the bound is `scale (1/255 + largest_step /
/// 256) + 1e-6 diagonal`. Measured: 0.98/255 of the scale at most (mostly the 8-bit result).
#[test]
fn map_displacement_matches_the_cpu_mirror() {
    let Some(ctx) = context() else { return };
    let m = mixed_with_uvs();
    let diag = m.bbox_diagonal();
    let map = bumps_map();
    let bound = f64::from(SCALE) * (1.0 / 255.0 + map.largest_step() / 256.0) + 1e-6 * diag;
    let ev = LimitEvaluator::new(&m).unwrap();
    let mut normal_worst = 0.0f64;
    for scheme in Scheme::ALL {
        let surface = mapped(&ctx, &m, 5, scheme);
        let run = |scale| capture(&ctx, &surface, &desc(5.0, scale), &offscreen(64, 64), false);
        let plain = points_by_param(&run(0.0).records);
        let (mut worst, mut largest, mut n) = (0.0f64, 0.0f64, 0);
        let (mut tilt_worst, mut tilt_largest, mut tilted) = (0.0f64, 0.0f64, 0);
        for r in run(SCALE).records {
            let Some(Some([p, nrm])) = plain.get(&param_key(&r)) else {
                continue;
            };
            let n0 = DVec3::from(nrm.map(f64::from));
            let got_n = DVec3::from(r.normal.map(f64::from));
            let corner = (r.u == 0.0 || r.u == 1.0) && (r.v == 0.0 || r.v == 1.0);
            if let (Some(jac), false) = (texcoord_jacobian(&m, &r), corner) {
                let s = ev
                    .eval(
                        r.face as usize,
                        r.sub_face.unwrap_or(0) as usize,
                        f64::from(r.u),
                        f64::from(r.v),
                    )
                    .unwrap();
                let st = DVec2::from(r.texcoord.map(f64::from));
                let want_n = map.shading_normal(n0, [s.du, s.dv], st, jac, f64::from(SCALE));
                tilt_worst = tilt_worst.max(got_n.angle_between(want_n));
                tilt_largest = tilt_largest.max(got_n.angle_between(n0));
                tilted += 1;
            }
            let p = DVec3::from(p.map(f64::from));
            let want = map.displaced(
                p,
                DVec3::from(nrm.map(f64::from)),
                DVec2::from(r.texcoord.map(f64::from)),
                f64::from(SCALE),
            );
            let got = DVec3::from(r.position.map(f64::from));
            worst = worst.max((got - want).length());
            largest = largest.max((got - p).length());
            n += 1;
        }
        eprintln!(
            "{scheme:?}: {n} points, largest deviation from the CPU mirror {worst:.2e} (bound \
             {bound:.2e}), largest move {largest:.4}; {tilted} normals within {tilt_worst:.2e} \
             rad of the mirror, tilted by up to {tilt_largest:.3} rad"
        );
        assert!(tilted > 100, "{scheme:?}: only {tilted} normals compared");
        let approx = [Scheme::GregoryVs, Scheme::GregoryStencil, Scheme::Qas];
        let normal_bound = bound_for(scheme, &approx, NORMAL_MIRROR_APPROX, NORMAL_MIRROR);
        assert!(
            tilt_worst <= normal_bound,
            "{scheme:?}: normal {tilt_worst} rad from the CPU mirror (bound {normal_bound})"
        );
        // The map really tilts the normals (by far more than the bound).
        assert!(
            tilt_largest > 0.1,
            "{scheme:?}: largest tilt {tilt_largest}"
        );
        normal_worst = normal_worst.max(tilt_worst);
        assert!(n > 100, "{scheme:?}: only {n} points compared");
        assert!(
            worst <= bound,
            "{scheme:?}: {worst:e} from the CPU mirror (bound {bound:e})"
        );
        // The map spans [0, 1]: the points really moved (by up to scale / 2).
        assert!(
            largest > 0.3 * f64::from(SCALE),
            "{scheme:?}: largest move {largest}"
        );
    }
    eprintln!("normals: largest angle from the CPU mirror over the schemes {normal_worst:.3e} rad");
    assert_validation_clean(&ctx);
}

/// Largest angle (rad) between a GPU map-tilted normal and the CPU mirror with the exact
/// limit's tangents (`embedded:mixed`, SCALE, level 5) for the schemes whose GPU patches on this
/// mesh are the exact limit (B-spline, adaptive; ACC and Pm draw only its regular faces).
/// Measured: 2.5e-7 (f32), 2.0e-6 for the adaptive scheme (its end caps at the isolation level).
const NORMAL_MIRROR: f64 = 5e-6;

/// As NORMAL_MIRROR for the approximating schemes (Gregory, QAS): their parameterisation near
/// extraordinary vertices is not the limit's, so their tangents differ. Measured: 0.132.
const NORMAL_MIRROR_APPROX: f64 = 0.15;

#[test]
fn bad_maps_and_meshes_without_texture_coordinates_are_refused() {
    // A mesh without `vt`.
    let plain = tessera::render::plan_for_scheme(
        &mesh("embedded:mixed"),
        Scheme::BsplineOnly,
        &tessera::render::SchemeLimits::NO_DEVICE,
    )
    .unwrap();
    let mut s = plain.clone();
    let e = s.set_displacement_map(bumps_map()).unwrap_err();
    assert!(matches!(e, Error::MissingTexCoords { .. }), "{e}");
    assert!(e.to_string().contains("texture coordinates"), "{e}");
    // Files: missing, not an image.
    let dir = std::env::temp_dir().join(format!("tessera-dispmap-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let missing = dir.join("missing.png");
    let e = DisplacementMap::load(&missing).unwrap_err();
    assert!(matches!(e, Error::Io { .. }), "{e}");
    assert!(e.to_string().contains("missing.png"), "{e}");
    let corrupt = dir.join("corrupt.png");
    let mut bytes = std::fs::read(asset()).unwrap();
    bytes.truncate(40);
    std::fs::write(&corrupt, &bytes).unwrap();
    let e = DisplacementMap::load(&corrupt).unwrap_err();
    assert!(matches!(e, Error::Image { .. }), "{e}");
    assert!(e.to_string().contains("corrupt.png"), "{e}");
    let text = dir.join("text.png");
    std::fs::write(&text, "v 0 0 0\n").unwrap();
    let e = DisplacementMap::load(&text).unwrap_err();
    assert!(e.to_string().contains("text.png"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
    // Texels that do not fill the size.
    let e = DisplacementMap::from_u8(4, 4, vec![0; 15]).unwrap_err();
    assert!(matches!(e, Error::SizeMismatch { .. }), "{e}");

    let Some(ctx) = context() else { return };
    let m = mixed_with_uvs();
    let refused = |surface: &SurfaceData| {
        render_to_image(&ctx, surface, &desc(2.0, 0.1), &offscreen(32, 32), false).unwrap_err()
    };
    // Map mode without a map on the surface.
    let surface = scheme_surface(&ctx, &m, 2, Scheme::BsplineOnly);
    let e = refused(&surface);
    assert!(e.to_string().contains("set_displacement_map"), "{e}");
    // A surface whose texture coordinates were dropped after the map was set.
    let mut dropped = mapped(&ctx, &m, 2, Scheme::BsplineOnly);
    dropped.texcoords = None;
    let e = refused(&dropped);
    assert!(matches!(e, Error::MissingTexCoords { .. }), "{e}");
    // Wider than the device allows.
    let max = ctx.info().limits.max_image_dimension_2d;
    let mut wide = scheme_surface(&ctx, &m, 2, Scheme::BsplineOnly);
    wide.set_displacement_map(
        DisplacementMap::from_u8(max + 1, 1, vec![0; max as usize + 1]).unwrap(),
    )
    .unwrap();
    let e = refused(&wide);
    let msg = e.to_string();
    assert!(
        msg.contains(&format!("{} x 1", max + 1)) && msg.contains(&max.to_string()),
        "{msg}"
    );
    assert_validation_clean(&ctx);
}

/// `embedded:mixed` displaced by the bumps map (scale 0.3, level 16), seen from the side so the
/// silhouette shows the bumps, shaded with the map-tilted normals.
#[test]
fn golden_map_displacement() {
    let Some(ctx) = context() else { return };
    let m = mixed_with_uvs();
    let surface = mapped(&ctx, &m, 16, Scheme::GregoryStencil);
    let render = RenderDesc {
        color_by: ColorBy::PatchType,
        ..desc(16.0, 0.3)
    };
    let off = OffscreenDesc {
        ..offscreen(256, 256)
    };
    check_golden(
        "map_displacement_mixed",
        &image(&ctx, &surface, &render, &off),
    );
    assert_validation_clean(&ctx);
}

/// The CPU mirror with each scheme's own parameterisation: as
/// `map_displacement_matches_the_cpu_mirror`, with the partials taken by central differences
/// of the undisplaced captured points one lattice step apart (level 16, inner lattice points of
/// the Ptex domains), not the exact limit's. Independent of how the shaders form their
/// tangents, and as sharp for the approximating schemes (Gregory, QAS: their parameterisation
/// near extraordinary vertices is not the limit's) as for the exact ones: within
/// NORMAL_OWN_TANGENTS (the differences' O(h^2) error).
#[test]
fn map_normals_follow_each_schemes_own_tangents() {
    const LEVEL: u32 = 16;
    let Some(ctx) = context() else { return };
    let m = mixed_with_uvs();
    let map = bumps_map();
    let h = 1.0 / f64::from(LEVEL);
    let mut worst = 0.0f64;
    for scheme in Scheme::ALL {
        let surface = mapped(&ctx, &m, LEVEL, scheme);
        let run = |scale| {
            capture(
                &ctx,
                &surface,
                &desc(LEVEL as f32, scale),
                &offscreen(64, 64),
                false,
            )
            .records
        };
        let lattice = |r: &CaptureRecord| {
            let l = LEVEL as f32;
            (
                r.face,
                r.sub_face,
                (r.u * l).round() as i64,
                (r.v * l).round() as i64,
            )
        };
        // Only points on the level's lattice (the adaptive scheme's finer patches also emit
        // points between), each lattice point once.
        let on_lattice = |r: &CaptureRecord| {
            let l = LEVEL as f32;
            (r.u * l - (r.u * l).round()).abs() < 1e-4 && (r.v * l - (r.v * l).round()).abs() < 1e-4
        };
        let plain: std::collections::HashMap<_, _> = run(0.0)
            .into_iter()
            .filter(on_lattice)
            .map(|r| (lattice(&r), r))
            .collect();
        let (mut n, mut scheme_worst) = (0, 0.0f64);
        for r in run(SCALE).into_iter().filter(on_lattice) {
            let Some(jac) = texcoord_jacobian(&m, &r) else {
                continue;
            };
            let (f, sub, i, j) = lattice(&r);
            let at = |di: i64, dj: i64| plain.get(&(f, sub, i + di, j + dj));
            let (Some(c), Some(e), Some(w), Some(no), Some(so)) =
                (at(0, 0), at(1, 0), at(-1, 0), at(0, 1), at(0, -1))
            else {
                continue;
            };
            let p = |q: &CaptureRecord| DVec3::from(q.position.map(f64::from));
            let tangents = [(p(e) - p(w)) / (2.0 * h), (p(no) - p(so)) / (2.0 * h)];
            let n0 = DVec3::from(c.normal.map(f64::from));
            let st = DVec2::from(r.texcoord.map(f64::from));
            let want = map.shading_normal(n0, tangents, st, jac, f64::from(SCALE));
            let got = DVec3::from(r.normal.map(f64::from));
            scheme_worst = scheme_worst.max(got.angle_between(want));
            n += 1;
        }
        eprintln!(
            "{scheme:?}: {n} normals within {scheme_worst:.2e} rad of the own-tangent mirror"
        );
        assert!(n > 1000, "{scheme:?}: only {n} normals compared");
        let gregory = [Scheme::GregoryVs, Scheme::GregoryStencil, Scheme::Adaptive];
        let bound = bound_for(scheme, &gregory, NORMAL_OWN_GREGORY, NORMAL_OWN_TANGENTS);
        assert!(
            scheme_worst <= bound,
            "{scheme:?}: {scheme_worst} rad (bound {bound})"
        );
        worst = worst.max(scheme_worst);
    }
    eprintln!("own tangents: largest angle {worst:.3e} rad");
    assert_validation_clean(&ctx);
}

/// Largest angle (rad) between a GPU map-tilted normal and the CPU mirror with the scheme's own
/// tangents from central differences. Measured: 3.7e-4 (B-spline, ACC, Pm; 9.5e-5 at level 32:
/// the differences' h^2), 2.1e-6 for QAS (quadratic: the differences are exact).
const NORMAL_OWN_TANGENTS: f64 = 5e-4;

/// As NORMAL_OWN_TANGENTS for the schemes with Gregory patches (the adaptive scheme's end caps):
/// their evaluation stage forms tangents, as its normal, with the face points frozen (not the
/// patch's exact derivative). Measured: 5.7e-3 at level 16, 6.0e-3 at 32 (not the differences'
/// error) with the paper's tangents (`TESSERA_GREGORY_TANGENTS=paper`); 1.55e-2 at level 16
/// under the default `optimal`, whose triangle-ring factors (transversal vectors scaled by
/// ρ = 1.3-3) set the face points farther from where the frozen derivative assumes them;
/// adaptive 5.5e-3 (its end caps are quads).
const NORMAL_OWN_GREGORY: f64 = 2e-2;

/// Side of the flat grid: `GRID x GRID` unit-square quads.
const GRID: usize = 6;

/// The plane z = 0 as a `GRID x GRID` grid of quads over [0, 1]^2 (counter-clockwise seen from
/// +z), one `vt` per vertex `(0.1 + 0.8 x, 0.1 + 0.8 y)`: the texture coordinate is linear in
/// the position, away from the map's wrap seam.
fn flat_grid() -> ControlMesh {
    use std::fmt::Write;
    let mut text = String::new();
    let n = GRID;
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (i as f64 / n as f64, j as f64 / n as f64);
            let _ = writeln!(text, "v {x} {y} 0");
            let _ = writeln!(text, "vt {} {}", 0.1 + 0.8 * x, 0.1 + 0.8 * y);
        }
    }
    let id = |i: usize, j: usize| j * (n + 1) + i + 1;
    for j in 0..n {
        for i in 0..n {
            let c = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
            let _ = writeln!(text, "f {}", c.map(|k| format!("{k}/{k}")).join(" "));
        }
    }
    ControlMesh::from_obj_str(&text, "flat-grid.obj", &ObjOptions::default()).unwrap()
}

/// Faces of the flat grid with no boundary vertex (their limit patches are regular, so every
/// scheme's position is linear in (u, v) and the texture coordinate linear in the position).
fn inner_face(face: u32) -> bool {
    let (i, j) = (face as usize % GRID, face as usize / GRID);
    (1..GRID - 1).contains(&i) && (1..GRID - 1).contains(&j)
}

/// A linear ramp map d = a s + b t + c: a flat plane displaced by it is the plane z = S d(s(x),
/// t(y)), whose normal is known in closed form: normalize(-S a ds/dx, -S b dt/dy, 1). The map's
/// texels are (64 + 4 i + 2 j) / 255 (`RAMP_W x RAMP_H`), so between the first and last texel
/// centres the bilinear filter is exactly linear: a = 4 RAMP_W / 255, b = 2 RAMP_H / 255; the
/// coordinates stay in [0.1, 0.9], inside them. Every scheme, level 8, the inner faces' points:
/// within RAMP_BOUND of the closed form.
#[test]
fn map_normals_of_a_ramp_on_a_plane_are_the_tilted_plane() {
    const RAMP_W: u32 = 32;
    const RAMP_H: u32 = 16;
    let Some(ctx) = context() else { return };
    let m = flat_grid();
    let texels = (0..RAMP_H)
        .flat_map(|j| (0..RAMP_W).map(move |i| (64 + 4 * i + 2 * j) as u8))
        .collect();
    let ramp = DisplacementMap::from_u8(RAMP_W, RAMP_H, texels).unwrap();
    let s = f64::from(SCALE);
    let (a, b) = (
        4.0 * f64::from(RAMP_W) / 255.0,
        2.0 * f64::from(RAMP_H) / 255.0,
    );
    let want = DVec3::new(-s * a * 0.8, -s * b * 0.8, 1.0).normalize();
    let mut worst = 0.0f64;
    for scheme in Scheme::ALL {
        let mut surface = scheme_surface(&ctx, &m, 8, scheme);
        surface.set_displacement_map(ramp.clone()).unwrap();
        let records = capture(&ctx, &surface, &desc(8.0, SCALE), &offscreen(64, 64), false).records;
        let (mut n, mut scheme_worst) = (0, 0.0f64);
        for r in records.iter().filter(|r| inner_face(r.face)) {
            let got = DVec3::from(r.normal.map(f64::from));
            scheme_worst = scheme_worst.max(got.angle_between(want));
            n += 1;
        }
        // The texture coordinate is linear in the position here: the two sides' normals agree.
        let mut seam = 0.0f64;
        for (i, j) in coincident_pairs(&m, &records) {
            let (a, b) = (&records[i], &records[j]);
            if inner_face(a.face) && inner_face(b.face) {
                let n = |r: &CaptureRecord| DVec3::from(r.normal.map(f64::from));
                seam = seam.max(n(a).angle_between(n(b)));
            }
        }
        eprintln!(
            "{scheme:?}: {n} points within {scheme_worst:.2e} rad of the tilted plane, shared \
             points' normals within {seam:.2e} rad"
        );
        worst = worst.max(seam);
        assert!(n >= 4 * 81, "{scheme:?}: only {n} inner points captured");
        worst = worst.max(scheme_worst);
    }
    eprintln!(
        "ramp: largest angle {worst:.3e} rad (tilt {:.4} rad)",
        want.angle_between(DVec3::Z)
    );
    assert!(
        worst <= RAMP_BOUND,
        "{worst} rad from the tilted plane (bound {RAMP_BOUND})"
    );
    assert_validation_clean(&ctx);
}

/// Largest angle (rad) between a ramp-displaced plane's GPU normal and its closed form, or
/// between the two sides' normals at a shared point. Measured: 1.2e-7 (f32; tilt 0.083).
const RAMP_BOUND: f64 = 5e-7;

/// The geometric check: on the flat grid (no curvature, so the first-order normal is the
/// displaced surface's exact normal) displaced by a smooth 16-bit map, every inner domain point
/// whose four lattice neighbours lie in the same bilinear texel cell (the filtered map is
/// quadratic in (u, v) there, so central differences are exact up to rounding and the filter's
/// precision) has its captured normal within FD_BOUND of the normal of the central differences
/// of the captured displaced positions. Every scheme, level 16.
#[test]
fn map_normals_agree_with_finite_differences_of_the_displaced_points() {
    const SIDE: u32 = 8;
    const LEVEL: u32 = 16;
    let Some(ctx) = context() else { return };
    let m = flat_grid();
    let tau = std::f64::consts::TAU;
    let texels = (0..SIDE)
        .flat_map(|j| {
            (0..SIDE).map(move |i| {
                let (x, y) = ((f64::from(i) + 0.5) / 8.0, (f64::from(j) + 0.5) / 8.0);
                (32767.5 + 29000.0 * (tau * x).sin() * (tau * y).cos()).round() as u16
            })
        })
        .collect();
    let map = DisplacementMap::from_u16(SIDE, SIDE, texels).unwrap();
    let cell = |st: [f32; 2]| st.map(|c| (f64::from(c) * f64::from(SIDE) - 0.5).floor() as i64);
    let mut worst = 0.0f64;
    for scheme in Scheme::ALL {
        let mut surface = scheme_surface(&ctx, &m, LEVEL, scheme);
        surface.set_displacement_map(map.clone()).unwrap();
        let render = desc(LEVEL as f32, SCALE);
        let records = capture(&ctx, &surface, &render, &offscreen(64, 64), false).records;
        let lattice = |r: &CaptureRecord| {
            let l = LEVEL as f32;
            (r.face, (r.u * l).round() as i64, (r.v * l).round() as i64)
        };
        let by_point: std::collections::HashMap<_, _> = records
            .iter()
            .filter(|r| inner_face(r.face) && r.sub_face.is_none())
            .map(|r| (lattice(r), r))
            .collect();
        let (mut n, mut scheme_worst, mut tilt) = (0, 0.0f64, 0.0f64);
        for (&(f, i, j), r) in &by_point {
            let at = |di: i64, dj: i64| by_point.get(&(f, i + di, j + dj));
            let (Some(e), Some(w), Some(no), Some(so)) = (at(1, 0), at(-1, 0), at(0, 1), at(0, -1))
            else {
                continue;
            };
            if [e, w, no, so]
                .iter()
                .any(|q| cell(q.texcoord) != cell(r.texcoord))
            {
                continue;
            }
            let p = |q: &CaptureRecord| DVec3::from(q.position.map(f64::from));
            let fd = (p(e) - p(w)).cross(p(no) - p(so)).normalize();
            let got = DVec3::from(r.normal.map(f64::from));
            scheme_worst = scheme_worst.max(got.angle_between(fd));
            tilt = tilt.max(got.angle_between(DVec3::Z));
            n += 1;
        }
        eprintln!(
            "{scheme:?}: {n} points, normals within {scheme_worst:.2e} rad of the finite \
             differences (tilted by up to {tilt:.3} rad)"
        );
        assert!(n > 200, "{scheme:?}: only {n} points compared");
        assert!(tilt > 0.2, "{scheme:?}: largest tilt {tilt}");
        worst = worst.max(scheme_worst);
    }
    eprintln!("finite differences: largest angle {worst:.3e} rad");
    assert!(
        worst <= FD_BOUND,
        "{worst} rad from the finite differences (bound {FD_BOUND})"
    );
    assert_validation_clean(&ctx);
}

/// Largest angle (rad) between a captured normal and the finite-difference normal of the
/// displaced points on the flat grid (16-bit map, level 16). Measured: 5.9e-6 (ACC; 3.0e-6 the
/// others), for tilts up to 0.38.
const FD_BOUND: f64 = 2e-5;
