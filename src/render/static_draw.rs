//! The static baseline of a tessellated frame (issue 8: GPU time "beside the static draw of the
//! same triangles"): one frame of the surface is drawn with a pass-through geometry stage that
//! captures every triangle the tessellator produced ([`RenderDesc::capture_triangles`],
//! `glsl/surface/capture_triangles.geom`); those triangles, with the frame's CPU-path
//! triangles, become one static vertex + index buffer drawn by the plain vertex/fragment
//! pipeline of the CPU path (`glsl/surface/mesh.vert`) with the same camera and raster state,
//! timed by its timestamps in a frame of its own. No tessellation stage runs: what the
//! tessellated frame costs beyond this is the price of tessellating on the GPU every frame.
//!
//! The triangles are the frame's own for every scheme (transition fans, clamped levels,
//! culled patches included), unlike a CPU tessellation at the uniform level, which matches only
//! frames of whole patches. One capture buffer is bounded by one storage-buffer binding
//! (`maxStorageBufferRange` / 52 bytes per triangle): a larger frame is captured in chunks, the
//! same frame drawn once per chunk, each storing the triangles whose atomic slot falls in
//! `[k C, (k + 1) C)` (`capture_triangles.geom`'s window). The chunks rely on every frame
//! drawing its triangles in the same slot order (true of lavapipe, whose geometry stage runs
//! on one thread in draw order; Vulkan does not promise it): the count of every chunk frame is
//! checked, and `tests/static_draw.rs` checks the chunked triangles against one chunk. The total
//! is bounded by the device's largest memory heap ([`STATIC_BYTES_PER_TRIANGLE`] per
//! triangle); a frame that draws more is an error naming that heap.

use std::collections::HashMap;

use glam::DVec3;

use super::bench::timed_frames;
use super::camera::Camera;
use super::fallback::FallbackMesh;
use super::offscreen::{OffscreenDesc, OffscreenSession, CPU_PATH_LABEL};
use super::pass::{Capture, CapturedTriangle};
use super::renderer::RenderDesc;
use super::settings::Displacement;
use super::surface::SurfaceData;
use crate::gpu::Context;
use crate::{Error, Result};

/// Bytes the static draw of one triangle may need at most: three unshared vertices of the CPU
/// path (68 bytes each) and three 32-bit indices. The frame's triangles times this must fit the
/// device's largest memory heap.
pub const STATIC_BYTES_PER_TRIANGLE: u64 = 3 * 68 + 12;

/// The triangles of one tessellated frame, as a static mesh.
pub struct StaticDraw {
    surface: SurfaceData,
    camera: Camera,
    render: RenderDesc,
    captured: usize,
}

impl StaticDraw {
    /// Captures the triangles one frame of `surface` draws with `render` into a target of
    /// `desc` (its camera, culling and tessellation settings) plus the surface's CPU-path
    /// triangles, in chunks of as many triangles as one storage-buffer binding holds
    /// ([`Self::capture_in_chunks`]).
    pub fn capture(
        ctx: &Context,
        surface: &SurfaceData,
        render: &RenderDesc,
        desc: &OffscreenDesc,
    ) -> Result<StaticDraw> {
        let chunk = Capture::Triangles(0).max_records(ctx);
        StaticDraw::capture_in_chunks(ctx, surface, render, desc, chunk)
    }

    /// [`Self::capture`] with at most `chunk` triangles per capture buffer (lowered to what one
    /// storage-buffer binding holds): the first frame stores slots `[0, chunk)` and counts the
    /// frame's N triangles; frame k of the `ceil(N / chunk)` stores `[k chunk, (k + 1) chunk)`.
    /// Errors when a chunk frame draws another count, and when N triangles of the static draw
    /// ([`STATIC_BYTES_PER_TRIANGLE`] each) exceed the device's largest memory heap.
    pub fn capture_in_chunks(
        ctx: &Context,
        surface: &SurfaceData,
        render: &RenderDesc,
        desc: &OffscreenDesc,
        chunk: u32,
    ) -> Result<StaticDraw> {
        if render.displacement != Displacement::None {
            return Err(Error::Invalid(
                "static draw: a displaced frame is not supported (its CPU-path triangles are \
                 displaced in the vertex stage, the captured ones already were)"
                    .into(),
            ));
        }
        let chunk = chunk.min(Capture::Triangles(0).max_records(ctx));
        if chunk == 0 {
            return Err(Error::Invalid(
                "static draw: a capture chunk holds at least one triangle".into(),
            ));
        }
        let capturing = RenderDesc {
            capture_capacity: None,
            capture_triangles: Some(chunk),
            ..*render
        };
        let mut session = OffscreenSession::new(ctx, surface, &capturing, desc, false)?;
        session.frame()?;
        let (drawn, mut triangles) = session.triangle_window()?;
        let cpu = surface.fallback.indices.len() / 3;
        let heap = ctx.largest_heap_bytes();
        let need = (u64::from(drawn) + cpu as u64) * STATIC_BYTES_PER_TRIANGLE;
        if need > heap {
            return Err(Error::Invalid(format!(
                "static draw: the frame drew {drawn} triangles (+ {cpu} CPU-path); their static \
                 draw may need {need} bytes ({STATIC_BYTES_PER_TRIANGLE} per triangle), more than \
                 the device's largest memory heap ({heap} bytes): lower --tess"
            )));
        }
        let chunks = drawn.div_ceil(chunk);
        triangles.reserve(drawn as usize - triangles.len());
        for k in 1..chunks {
            session.set_triangle_window(k * chunk)?;
            session.frame()?;
            let (again, part) = session.triangle_window()?;
            if again != drawn {
                return Err(Error::Invalid(format!(
                    "static draw: chunk {k} of {chunks}: the frame drew {again} triangles, the \
                     first {drawn} (the chunks need the same frame each time)"
                )));
            }
            triangles.extend(part);
        }
        let camera = *session.camera();
        drop(session);
        let captured = triangles.len();
        if captured != drawn as usize {
            return Err(Error::Invalid(format!(
                "static draw: {captured} of the frame's {drawn} triangles captured in {chunks} \
                 chunks of {chunk}"
            )));
        }
        let fallback = static_mesh(&surface.fallback, &triangles);
        log::debug!(
            "static draw: {captured} tessellated triangles in {chunks} chunk(s) of at most \
             {chunk} + {cpu} CPU-path triangles, {} vertices",
            fallback.positions.len()
        );
        Ok(StaticDraw {
            surface: SurfaceData {
                positions: surface.positions.clone(),
                fallback,
                ..SurfaceData::default()
            },
            camera,
            render: RenderDesc {
                capture_capacity: None,
                capture_triangles: None,
                ..*render
            },
            captured,
        })
    }

    /// Triangles drawn (tessellated and CPU-path).
    pub fn triangles(&self) -> usize {
        self.surface.fallback.indices.len() / 3
    }

    /// Of [`Self::triangles`], those the tessellation stages produced.
    pub fn captured(&self) -> usize {
        self.captured
    }

    /// The triangles (positions, normals, classes, indices; vertices shared where the
    /// evaluation stage emitted bitwise the same one).
    pub fn mesh(&self) -> &FallbackMesh {
        &self.surface.fallback
    }

    /// The surface to draw: no patch pass, every triangle on the static path.
    pub fn surface(&self) -> &SurfaceData {
        &self.surface
    }

    /// A session drawing the static triangles into a target of `desc` with the captured
    /// frame's camera and raster state, with timings.
    pub fn session(&self, ctx: &Context, desc: &OffscreenDesc) -> Result<OffscreenSession> {
        let mut session = OffscreenSession::new(ctx, &self.surface, &self.render, desc, true)?;
        session.set_camera(self.camera);
        Ok(session)
    }

    /// Median GPU milliseconds of drawing the triangles over `frames` frames (after one warm-up
    /// frame) into a target of `desc`.
    pub fn time(&self, ctx: &Context, desc: &OffscreenDesc, frames: u32) -> Result<f64> {
        if frames == 0 {
            return Err(Error::Invalid("static draw: at least one frame".into()));
        }
        timed_frames(&mut self.session(ctx, desc)?, frames, CPU_PATH_LABEL)
    }
}

/// `cpu` (the frame's CPU-path triangles) followed by `captured`, vertices shared where
/// position, normal and class are bitwise equal. Domain points are dropped: the static draw
/// neither displaces nor looks up texture coordinates.
fn static_mesh(cpu: &FallbackMesh, captured: &[CapturedTriangle]) -> FallbackMesh {
    let mut mesh = FallbackMesh {
        positions: cpu.positions.clone(),
        normals: cpu.normals.clone(),
        classes: cpu.classes.clone(),
        indices: cpu.indices.clone(),
        ..FallbackMesh::default()
    };
    let mut index: HashMap<[u32; 7], u32> = HashMap::new();
    for t in captured {
        for (p, n) in t.positions.iter().zip(&t.normals) {
            let key = [
                p[0].to_bits(),
                p[1].to_bits(),
                p[2].to_bits(),
                n[0].to_bits(),
                n[1].to_bits(),
                n[2].to_bits(),
                t.class,
            ];
            let k = *index.entry(key).or_insert_with(|| {
                mesh.positions.push(vec3(*p));
                mesh.normals.push(vec3(*n));
                mesh.classes.push(t.class);
                (mesh.positions.len() - 1) as u32
            });
            mesh.indices.push(k);
        }
    }
    mesh
}

fn vec3(v: [f32; 3]) -> DVec3 {
    DVec3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2]))
}
