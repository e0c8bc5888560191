//! Displacement along the normal (`--displacement procedural`): every scheme moves each TES point
//! by `scale * d(p)` along its normal as the CPU reference (`render::displace`) computes it from
//! the undisplaced capture, and the displaced surface stays bitwise watertight at several levels
//! on `embedded:mixed` (B-spline and Gregory or end-cap patches side by side; smooth, so the
//! normals on shared edges are bitwise equal).

mod common;

use common::capture::{capture, offscreen, param_key, points_by_param, scheme_surface, uniform};
use common::gpu::{assert_validation_clean, context};
use common::meshes::mesh;
use common::watertight::assert_displacement_keeps_seams;
use glam::DVec3;
use tessera::render::displace::displaced;
use tessera::render::{Displacement, RenderDesc, Scheme};

const SCHEMES: [Scheme; 8] = [
    Scheme::BsplineOnly,
    Scheme::GregoryStencil,
    Scheme::GregoryVs,
    Scheme::Adaptive,
    Scheme::Qas,
    Scheme::Acc,
    Scheme::Pm,
    Scheme::PmVs,
];
const SCALE: f32 = 0.08;

fn desc(level: f32, scale: f32) -> RenderDesc {
    RenderDesc {
        tess: uniform(level),
        displacement: Displacement::Procedural { scale },
        ..RenderDesc::default()
    }
}

#[test]
fn displaced_surface_is_watertight_for_every_scheme() {
    let Some(ctx) = context() else { return };
    let m = mesh("embedded:mixed");
    for scheme in SCHEMES {
        for level in [2.0, 5.0, 8.0] {
            let surface = scheme_surface(&ctx, &m, level as u32, scheme);
            let what = format!("{scheme:?} level {level}");
            assert_displacement_keeps_seams(&ctx, &m, &surface, |s| desc(level, s), SCALE, &what);
        }
    }
    assert_validation_clean(&ctx);
}

#[test]
fn displacement_matches_the_cpu_reference() {
    let Some(ctx) = context() else { return };
    let m = mesh("embedded:mixed");
    let diag = m.bbox_diagonal();
    for scheme in SCHEMES {
        let surface = scheme_surface(&ctx, &m, 5, scheme);
        let run = |scale| capture(&ctx, &surface, &desc(5.0, scale), &offscreen(64, 64), false);
        let plain = points_by_param(&run(0.0).records);
        let (mut worst_p, mut worst_n, mut largest, mut n) = (0.0f64, 0.0f64, 0.0f64, 0);
        for r in run(SCALE).records {
            let Some(Some([p, nrm])) = plain.get(&param_key(&r)) else {
                continue;
            };
            let (p, nrm) = (
                DVec3::from(p.map(f64::from)),
                DVec3::from(nrm.map(f64::from)),
            );
            let (want_p, want_n) = displaced(p, nrm, f64::from(SCALE));
            let got_p = DVec3::from(r.position.map(f64::from));
            let got_n = DVec3::from(r.normal.map(f64::from));
            worst_p = worst_p.max((got_p - want_p).length() / diag);
            worst_n = worst_n.max(got_n.angle_between(want_n));
            largest = largest.max((got_p - p).length());
            n += 1;
        }
        eprintln!(
            "{scheme:?}: {n} points, position {worst_p:.2e} of the diagonal, normal {worst_n:.2e} \
             rad, largest move {largest:.4}"
        );
        assert!(n > 100, "{scheme:?}: only {n} points compared");
        assert!(
            worst_p < 1e-6,
            "{scheme:?}: position off by {worst_p:e} of the diagonal"
        );
        assert!(worst_n < 1e-4, "{scheme:?}: normal off by {worst_n:e} rad");
        // d reaches most of [-1, 1] over the surface: the points really moved.
        assert!(
            largest > 0.5 * f64::from(SCALE),
            "{scheme:?}: largest move {largest}"
        );
    }
    assert_validation_clean(&ctx);
}
