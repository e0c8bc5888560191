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

/// The triangles of a static mesh, each as the bits of its vertices' positions and normals and
/// its class, sorted.
fn triangle_multiset(mesh: &tessera::render::FallbackMesh) -> Vec<[u64; 19]> {
    let mut triangles: Vec<[u64; 19]> = mesh
        .indices
        .chunks_exact(3)
        .map(|t| {
            let mut key = [0u64; 19];
            for (i, &v) in t.iter().enumerate() {
                let (p, n) = (mesh.positions[v as usize], mesh.normals[v as usize]);
                let words = [p.x, p.y, p.z, n.x, n.y, n.z].map(f64::to_bits);
                key[6 * i..6 * i + 6].copy_from_slice(&words);
            }
            key[18] = u64::from(mesh.classes[t[0] as usize]);
            key
        })
        .collect();
    triangles.sort_unstable();
    triangles
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
        for level in [3u32, 6] {
            let (surface, render, off) = frame_of(&ctx, name, scheme, isolation, level, 240);
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

/// `name` on `scheme` at `isolation`, uniform level `level`, in a `size`² target on black, seen
/// from azimuth 30°, elevation 40°, 1.6 bounding-box diagonals away.
fn frame_of(
    ctx: &tessera::gpu::Context,
    name: &str,
    scheme: Scheme,
    isolation: u32,
    level: u32,
    size: u32,
) -> (SurfaceData, RenderDesc, OffscreenDesc) {
    let m = mesh(name);
    let opts = PlanOptions::new(SchemeLimits::from_context(ctx)).with_isolation(isolation);
    let surface = surface_for_scheme_with(&m, level, scheme, &opts).unwrap();
    let render = RenderDesc {
        tess: uniform(level as f32),
        ..RenderDesc::default()
    };
    let off = OffscreenDesc {
        camera: CameraSpec::Orbit {
            azimuth_deg: 30.0,
            elevation_deg: 40.0,
            distance: 1.6 * m.bbox_diagonal(),
        },
        clear: [0.0, 0.0, 0.0, 1.0],
        ..offscreen(size, size)
    };
    (surface, render, off)
}

/// A frame captured in chunks (`StaticDraw::capture_in_chunks`; `tessera bench --static` takes
/// chunks of one storage-buffer binding, 2,580,794 triangles on lavapipe) is the frame captured
/// whole: car adaptive isolation 2 at uniform level 3 (85,218 triangles) in chunks of at most
/// 25,000 (consecutive buckets of the triangles' position hash, at least four chunks) gives the
/// clipping-stage primitive count, the same static mesh as a multiset of triangles (positions,
/// normals and class bitwise; the order of the triangles within and across chunks is not
/// the frame's slot order) and the same image. A chunk's bucket range off by one on the device
/// (`range.end - 1`) or in the geometry stage (`bucket <= bucket_end`), dropping the last chunk,
/// or a host bucket hash other than the device's (modulus + 1) fail it.
#[test]
fn static_draw_in_chunks_is_the_whole_capture() {
    let Some(ctx) = context() else { return };
    let (surface, render, off) = frame_of(&ctx, "catmark_car", Scheme::Adaptive, 2, 3, 240);
    let mut session = OffscreenSession::new(&ctx, &surface, &render, &off, true).unwrap();
    let clipped = session
        .frame()
        .unwrap()
        .expect("timings")
        .patch_stats
        .clipping_invocations as usize;
    drop(session);
    let chunk = 25_000u32;
    assert!(
        clipped > 3 * chunk as usize && clipped % chunk as usize != 0,
        "{clipped} triangles: at least four chunks, the last partial"
    );
    let whole = StaticDraw::capture(&ctx, &surface, &render, &off).unwrap();
    let chunked = StaticDraw::capture_in_chunks(&ctx, &surface, &render, &off, chunk).unwrap();
    assert_eq!(whole.chunks(), 1, "one chunk");
    eprintln!(
        "{clipped} triangles in {} chunks of at most {chunk}",
        chunked.chunks()
    );
    assert!(
        chunked.chunks() >= 4,
        "{} chunks of {chunk}",
        chunked.chunks()
    );
    assert_eq!(whole.captured(), clipped, "one chunk");
    assert_eq!(chunked.captured(), clipped, "chunks of {chunk}");
    let (a, b) = (
        triangle_multiset(whole.mesh()),
        triangle_multiset(chunked.mesh()),
    );
    assert_eq!(a.len(), clipped, "static triangles");
    assert!(
        a == b,
        "the chunked static mesh holds other triangles than the whole capture"
    );
    let image = |s: &StaticDraw| {
        let mut session = s.session(&ctx, &off).unwrap();
        session.frame().unwrap();
        session.image().unwrap()
    };
    let (differ, covered) = differing(&image(&whole), &image(&chunked));
    assert!(covered > 4000, "the mesh must fill the frame");
    assert_eq!(differ, 0, "{differ} of {covered} pixels differ");
    let e = StaticDraw::capture_in_chunks(&ctx, &surface, &render, &off, 0)
        .err()
        .expect("an empty chunk is an error")
        .to_string();
    assert!(e.contains("at least one triangle"), "{e}");
    assert_validation_clean(&ctx);
}

/// A frame of many chunks recounts with more buckets: `catmark_cube` adaptive isolation 2 at
/// uniform level 4 (192 triangles) in chunks of at most 2 triangles (96 chunks or more; 256
/// buckets are fewer than 4 per chunk, and some bucket of 256 holds 3) recounts with at least
/// 1024 buckets and gives the triangles of one chunk as a multiset. With chunks of one triangle
/// two triangles share a bucket even of 4096: a typed error naming the bucket, its count and
/// the 4096 buckets (a capture that never recounts names 256, one that recounts once 1024).
#[test]
fn static_draw_recounts_with_more_buckets() {
    let Some(ctx) = context() else { return };
    let (surface, render, off) = frame_of(&ctx, "catmark_cube", Scheme::Adaptive, 2, 4, 64);
    let whole = StaticDraw::capture(&ctx, &surface, &render, &off).unwrap();
    let chunked = StaticDraw::capture_in_chunks(&ctx, &surface, &render, &off, 2).unwrap();
    let n = whole.captured();
    eprintln!(
        "{n} triangles in {} chunks of at most 2, {} buckets",
        chunked.chunks(),
        chunked.buckets()
    );
    assert_eq!(n, 192, "triangles");
    assert!(chunked.chunks() >= 96, "{} chunks", chunked.chunks());
    assert!(chunked.buckets() >= 1024, "{} buckets", chunked.buckets());
    assert_eq!(chunked.captured(), n);
    assert!(
        triangle_multiset(whole.mesh()) == triangle_multiset(chunked.mesh()),
        "the chunked static mesh holds other triangles than the whole capture"
    );
    let e = StaticDraw::capture_in_chunks(&ctx, &surface, &render, &off, 1)
        .err()
        .expect("two triangles in one bucket of 4096")
        .to_string();
    assert!(
        e.contains("of 4096 holds") && e.contains("more than a chunk of 1"),
        "{e}"
    );
    assert_validation_clean(&ctx);
}
