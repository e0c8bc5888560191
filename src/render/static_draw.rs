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
//! (`maxStorageBufferRange` / 52 bytes per triangle): a larger frame is captured in chunks whose
//! membership is a property of the triangle, not of the order the device runs the geometry
//! stage in. `capture_triangles.geom` hashes each triangle's positions into one of at most
//! [`MAX_BUCKETS`] buckets ([`triangle_bucket`]) and counts every bucket; the host groups
//! consecutive buckets into chunks of at most C triangles and draws the frame once per chunk,
//! storing the triangles of its buckets, each chunk frame checked against the count frame's
//! bucket counts. The total is bounded by the device's largest memory heap
//! ([`STATIC_BYTES_PER_TRIANGLE`] per triangle); a frame that draws more is an error naming
//! that heap.

use std::collections::HashMap;
use std::ops::Range;

use glam::DVec3;

use super::bench::timed_frames;
use super::camera::Camera;
use super::fallback::FallbackMesh;
use super::offscreen::{OffscreenDesc, OffscreenSession, CPU_PATH_LABEL};
use super::pass::{triangle_bucket, Capture, CapturedTriangle, TriangleWindow, MAX_BUCKETS};
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
    chunks: usize,
    buckets: u32,
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
    /// storage-buffer binding holds). The first frame counts the frame's N triangles per bucket
    /// (`capture_triangles.geom` hashes each triangle's positions, [`triangle_bucket`]) and
    /// stores them all when N <= `chunk`. Otherwise consecutive buckets are grouped into chunks
    /// of at most `chunk` triangles (recounted with more buckets, up to [`MAX_BUCKETS`], while
    /// one bucket alone holds more or there are fewer than 4 buckets per chunk) and the frame is
    /// drawn once per chunk, storing the triangles of its buckets: the same set of triangles
    /// whatever order the device runs the geometry stage in. Errors when a chunk frame's
    /// bucket counts differ from the count frame's, when it stores another number than its
    /// buckets counted or a triangle of another bucket, when one bucket of [`MAX_BUCKETS`]
    /// holds more than `chunk`, and when N triangles of the static draw
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
        let mut count = session.triangle_window()?;
        let drawn = count.drawn;
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
        let (triangles, chunks, buckets) = if drawn <= chunk {
            let all = vec![count.buckets.clone()];
            let buckets = count.bucket_counts.len() as u32;
            (std::mem::take(&mut count.triangles), all, buckets)
        } else {
            let wanted = (4 * drawn.div_ceil(chunk))
                .next_power_of_two()
                .min(MAX_BUCKETS);
            let mut buckets = count.bucket_counts.len() as u32;
            let ranges = loop {
                let grouped = group_buckets(&count.bucket_counts, chunk);
                if buckets < MAX_BUCKETS && (grouped.is_err() || buckets < wanted) {
                    buckets = (4 * buckets).max(wanted).min(MAX_BUCKETS);
                    session.set_triangle_buckets(buckets, 0, 0)?;
                    session.frame()?;
                    count = session.triangle_window()?;
                    continue;
                }
                break grouped.map_err(|(bucket, n)| {
                    Error::Invalid(format!(
                        "static draw: bucket {bucket} of {buckets} holds {n} of the frame's \
                         {drawn} triangles, more than a chunk of {chunk}"
                    ))
                })?;
            };
            let mut triangles = Vec::with_capacity(drawn as usize);
            for (k, range) in ranges.iter().enumerate() {
                session.set_triangle_buckets(buckets, range.start, range.end)?;
                session.frame()?;
                let part = session.triangle_window()?;
                let what = format!(
                    "static draw: chunk {k} of {} (buckets {range:?})",
                    ranges.len()
                );
                check_chunk(&what, &count.bucket_counts, range, &part)?;
                triangles.extend(part.triangles);
            }
            (triangles, ranges, buckets)
        };
        let camera = *session.camera();
        drop(session);
        let captured = triangles.len();
        if captured != drawn as usize {
            return Err(Error::Invalid(format!(
                "static draw: {captured} of the frame's {drawn} triangles captured in {} \
                 chunks of {chunk}",
                chunks.len()
            )));
        }
        let fallback = static_mesh(&surface.fallback, &triangles);
        log::debug!(
            "static draw: {captured} tessellated triangles in {} chunk(s) of at most \
             {chunk} + {cpu} CPU-path triangles, {} vertices",
            chunks.len(),
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
            chunks: chunks.len(),
            buckets,
        })
    }

    /// Capture frames that stored triangles: 1 when the frame fits one capture buffer, else the
    /// chunks of buckets.
    pub fn chunks(&self) -> usize {
        self.chunks
    }

    /// Buckets the captured triangles were hashed into (the modulus of [`triangle_bucket`]).
    pub fn buckets(&self) -> u32 {
        self.buckets
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

/// Consecutive buckets grouped greedily into ranges of at most `chunk` triangles, covering
/// `0..counts.len()`; the bucket and its count when one bucket alone holds more.
fn group_buckets(counts: &[u32], chunk: u32) -> std::result::Result<Vec<Range<u32>>, (u32, u32)> {
    let mut ranges = Vec::new();
    let (mut start, mut sum) = (0u32, 0u64);
    for (b, &n) in (0u32..).zip(counts) {
        if n > chunk {
            return Err((b, n));
        }
        if sum + u64::from(n) > u64::from(chunk) {
            ranges.push(start..b);
            (start, sum) = (b, 0);
        }
        sum += u64::from(n);
    }
    ranges.push(start..counts.len() as u32);
    Ok(ranges)
}

/// Checks one chunk frame against the count frame: the same count in every bucket, as many
/// triangles stored as `range`'s buckets counted, each of them in `range`.
fn check_chunk(
    what: &str,
    counts: &[u32],
    range: &Range<u32>,
    part: &TriangleWindow,
) -> Result<()> {
    if let Some(b) = (0..counts.len().max(part.bucket_counts.len()))
        .find(|&b| counts.get(b) != part.bucket_counts.get(b))
    {
        return Err(Error::Invalid(format!(
            "{what}: the frame drew {:?} triangles in bucket {b}, the count frame {:?} (the \
             chunks need the same frame each time)",
            part.bucket_counts.get(b),
            counts.get(b)
        )));
    }
    let expected: u64 = counts[range.start as usize..range.end as usize]
        .iter()
        .map(|&n| u64::from(n))
        .sum();
    if u64::from(part.stored) != expected || part.triangles.len() as u64 != expected {
        return Err(Error::Invalid(format!(
            "{what}: {} triangles stored ({} read), its buckets counted {expected}",
            part.stored,
            part.triangles.len()
        )));
    }
    let modulus = counts.len() as u32;
    if let Some(t) = part
        .triangles
        .iter()
        .find(|t| !range.contains(&triangle_bucket(&t.positions, modulus)))
    {
        return Err(Error::Invalid(format!(
            "{what}: stored a triangle of bucket {} ({:?})",
            triangle_bucket(&t.positions, modulus),
            t.positions
        )));
    }
    Ok(())
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

#[cfg(test)]
mod tests {
    use super::group_buckets;

    /// Greedy grouping: consecutive buckets while the sum stays within the chunk (exactly full
    /// chunks close at the bucket that would exceed), the ranges covering every bucket once;
    /// one bucket over the chunk is an error naming it and its count.
    #[test]
    fn buckets_group_into_chunks_of_consecutive_buckets() {
        let ranges = |counts: &[u32], chunk| -> Vec<(u32, u32)> {
            let r = group_buckets(counts, chunk).unwrap();
            r.into_iter().map(|r| (r.start, r.end)).collect()
        };
        assert_eq!(
            ranges(&[3, 2, 0, 5, 1, 4, 4], 5),
            [(0, 3), (3, 4), (4, 6), (6, 7)]
        );
        assert_eq!(ranges(&[0, 0, 0], 1), [(0, 3)]);
        assert_eq!(ranges(&[1, 1, 1, 1], 4), [(0, 4)]);
        assert_eq!(group_buckets(&[1, 6, 1], 5), Err((1, 6)));
    }
}
