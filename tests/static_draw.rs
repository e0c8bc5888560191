//! The static baseline of `tessera bench --static` (`render::static_draw`): the triangles one
//! tessellated frame drew, captured by a pass-through geometry stage, drawn again from a static
//! vertex + index buffer without tessellation.

mod common;

use tessera::render::schemes::{PlanOptions, SchemeLimits};
use tessera::render::static_draw::StaticDraw;
use tessera::render::{
    surface_for_scheme_with, CameraSpec, OffscreenDesc, OffscreenSession, RenderDesc, Scheme,
    SurfaceData,
};

use common::capture::{offscreen, uniform};
use common::gpu::{assert_validation_clean, context};
use common::meshes::mesh;

/// Pixels whose colour differs by more than 2 in some channel (8-bit), and pixels covered
/// (not the black background) in `a`.
fn differing(a: &image::RgbaImage, b: &image::RgbaImage) -> (usize, usize) {
    let covered = a
        .pixels()
        .filter(|p| p.0[0] != 0 || p.0[1] != 0 || p.0[2] != 0)
        .count();
    let differ = a
        .pixels()
        .zip(b.pixels())
        .filter(|(p, q)| (0..3).any(|c| p.0[c].abs_diff(q.0[c]) > 2))
        .count();
    (differ, covered)
}

/// For `--scheme gregory-stencil` (patches and CPU-path faces) and `--scheme adaptive` at
/// isolation 2 (transition patches between levels 0-2, end caps) on `catmark_car`, uniform levels
/// 3 and 6: the static draw holds exactly the frame's clipping-stage primitives (pipeline
/// statistics, counted independently of the capture) plus its CPU-path triangles, and renders the
/// same image but for at most 0.1 % of the covered pixels (measured: none of about 12,600 differs
/// by more than 2 in a channel; 32 differ by 1-2 at gregory-stencil level 3, the normals passing
/// through a 2 x 16-bit octahedral encoding). A static mesh that drops the transition patches'
/// triangles fails the count (adaptive level 3: 40,610 against 85,218), as does one without the
/// CPU-path triangles (gregory-stencil), and the CPU tessellation at the uniform level this
/// replaced (2 level² per quad domain: 28,350 at level 3 against the adaptive frame's 85,218).
#[test]
fn static_draw_is_the_frame_s_triangles() {
    let Some(ctx) = context() else { return };
    for (name, scheme, isolation) in [
        ("catmark_car", Scheme::GregoryStencil, 0),
        ("catmark_car", Scheme::Adaptive, 2),
    ] {
        let m = mesh(name);
        let diag = m.bbox_diagonal();
        for level in [3u32, 6] {
            let opts = PlanOptions::new(SchemeLimits::from_context(&ctx)).with_isolation(isolation);
            let surface: SurfaceData = surface_for_scheme_with(&m, level, scheme, &opts).unwrap();
            let render = RenderDesc {
                tess: uniform(level as f32),
                ..RenderDesc::default()
            };
            let off = OffscreenDesc {
                camera: CameraSpec::Orbit {
                    azimuth_deg: 30.0,
                    elevation_deg: 40.0,
                    distance: 1.6 * diag,
                },
                clear: [0.0, 0.0, 0.0, 1.0],
                ..offscreen(240, 240)
            };
            let mut session = OffscreenSession::new(&ctx, &surface, &render, &off, true).unwrap();
            let report = session.frame().unwrap().expect("timings");
            let frame_image = session.image().unwrap();
            drop(session);
            let clipped = report.patch_stats.clipping_invocations as usize;
            let cpu = surface.fallback.indices.len() / 3;
            assert_eq!(
                cpu > 0,
                scheme == Scheme::GregoryStencil,
                "{name}: CPU-path faces only with gregory-stencil"
            );
            let fixed = StaticDraw::capture(&ctx, &surface, &render, &off).unwrap();
            let what = format!("{name} {scheme:?} isolation {isolation} level {level}");
            assert_eq!(
                fixed.captured(),
                clipped,
                "{what}: captured triangles against the frame's clipping-stage primitives"
            );
            assert_eq!(fixed.triangles(), clipped + cpu, "{what}: static triangles");
            let mut stat = fixed.session(&ctx, &off).unwrap();
            let ms = stat
                .frame()
                .unwrap()
                .expect("timings")
                .ms(tessera::render::CPU_PATH_LABEL);
            let (differ, covered) = differing(&frame_image, &stat.image().unwrap());
            eprintln!(
                "{what}: {clipped} tessellated + {cpu} CPU-path triangles, {} static vertices; \
                 {covered} covered pixels, {differ} differ; static {ms:.3} ms",
                fixed.mesh().positions.len()
            );
            assert!(covered > 4000, "{what}: the mesh must fill the frame");
            assert!(
                differ * 1000 <= covered,
                "{what}: {differ} of {covered} pixels differ between the frame and its static draw"
            );
        }
    }
    assert_validation_clean(&ctx);
}
