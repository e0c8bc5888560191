//! The static baseline of `tessera bench --static` (`render::static_draw`): every face
//! tessellated once on the CPU at the frame's uniform level draws as many triangles as the
//! tessellated frame of whole B-spline patches at that level, over the same silhouette.

mod common;

use tessera::render::static_draw::StaticDraw;
use tessera::render::{CameraSpec, OffscreenDesc, OffscreenSession, RenderDesc, Scheme};

use common::capture::{offscreen, scheme_surface, uniform};
use common::gpu::{assert_validation_clean, context};
use common::meshes::mesh;

/// Pixels that are not the black background.
fn covered(img: &image::RgbaImage) -> Vec<bool> {
    img.pixels()
        .map(|p| p.0[0] != 0 || p.0[1] != 0 || p.0[2] != 0)
        .collect()
}

/// On `catmark_torus` (every face a regular quad, so every face a whole B-spline patch): at
/// uniform levels 3 and 6 the static triangles number the tessellated frame's clipping-stage
/// primitives (2 level² per patch), and the two images cover the same pixels but for at most 1 %
/// of the covered ones (measured: none of about 10,400 differ; the orbit centre comes from each
/// surface's framing points, patch corners against sampled static points). A static mesh at
/// another level fails the count.
#[test]
fn static_draw_matches_the_tessellated_frame() {
    let Some(ctx) = context() else { return };
    let m = mesh("catmark_torus");
    let diag = m.bbox_diagonal();
    for level in [3u32, 6] {
        let surface = scheme_surface(&ctx, &m, level, Scheme::BsplineOnly);
        assert!(
            surface.fallback_faces.is_empty(),
            "torus: every face a patch"
        );
        let render = RenderDesc {
            tess: uniform(level as f32),
            cull_patches: false,
            ..RenderDesc::default()
        };
        let off = OffscreenDesc {
            camera: CameraSpec::Orbit {
                azimuth_deg: 30.0,
                elevation_deg: 40.0,
                distance: 1.5 * diag,
            },
            clear: [0.0, 0.0, 0.0, 1.0],
            ..offscreen(200, 200)
        };
        let mut session = OffscreenSession::new(&ctx, &surface, &render, &off, true).unwrap();
        let report = session.frame().unwrap().expect("timings");
        let tessellated = report.patch_stats.clipping_invocations as usize;
        let fixed = StaticDraw::new(&m, level).unwrap();
        assert_eq!(
            fixed.triangles(),
            tessellated,
            "level {level}: static triangles against the tessellated frame's"
        );
        assert_eq!(
            fixed.triangles(),
            2 * (level * level) as usize * m.face_count()
        );
        let ms = fixed.time(&ctx, &render, &off, 1).unwrap();
        assert!(ms > 0.0, "level {level}: the static draw was not timed");
        let a = covered(&common::capture::image(&ctx, &surface, &render, &off));
        let b = covered(&common::capture::image(
            &ctx,
            fixed.surface(),
            &render,
            &off,
        ));
        let inside = a.iter().filter(|&&c| c).count();
        let differ = a.iter().zip(&b).filter(|(x, y)| x != y).count();
        eprintln!(
            "torus level {level}: {} triangles both; {inside} covered pixels, {differ} differ; \
             static {ms:.3} ms",
            fixed.triangles()
        );
        assert!(inside > 5000, "the torus must fill the frame");
        assert!(
            differ * 100 <= inside,
            "level {level}: {differ} of {inside} pixels differ between the silhouettes"
        );
    }
    assert_validation_clean(&ctx);
}
