//! TES capture: every evaluation-shader invocation appends one record (`glsl/common/capture.glsl`)
//! to a host-readable buffer shared by all passes of a surface; or triangle capture: every
//! triangle the evaluation stage emits is appended by a pass-through geometry stage
//! (`glsl/surface/capture_triangles.geom`) to the same binding.

use ash::vk;

use crate::gpu::{Buffer, Context, MemoryLocation};
use crate::render::settings::{Spacing, TessSettings};
use crate::{Error, Result};

/// Bytes of one capture record (`CaptureRecord` in `glsl/common/capture.glsl`): face, u, v,
/// position, normal, sub-face, tag, texture coordinate.
pub const CAPTURE_RECORD_BYTES: usize = 52;
/// `sub_face` word of a record in its base face's own domain.
const NO_SUB_FACE: u32 = u32::MAX;
/// Tag bit: the record carries a patch kind and level (`CAPTURE_TAGGED`).
const CAPTURE_TAGGED: u32 = 0x8000_0000;
/// Bytes before the first TES capture record (count, capacity, two pad words).
pub const CAPTURE_HEADER_BYTES: usize = 16;

/// Buckets a triangle capture can count (`MAX_BUCKETS` of `capture_triangles.geom`): the
/// modulus of [`triangle_bucket`] is at most this.
pub const MAX_BUCKETS: u32 = 4096;
/// Bytes before the first captured triangle: count, capacity, the stored buckets' range (first,
/// end), the stored count, the bucket modulus, two pad words, then [`MAX_BUCKETS`] bucket counts.
pub const TRIANGLE_HEADER_BYTES: usize = 32 + 4 * MAX_BUCKETS as usize;
/// Bucket modulus of a fresh triangle-capture buffer.
pub const DEFAULT_BUCKETS: u32 = 256;

/// Bytes of one captured triangle (`capture_triangles.geom`): per vertex the position (3 f32)
/// and the octahedral normal (2 x snorm16), then the colour class.
pub const TRIANGLE_RECORD_BYTES: usize = 52;

/// What the capture buffer of a frame records, and for how many records it has room.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Capture {
    /// One [`CaptureRecord`] per TES invocation.
    TesPoints(u32),
    /// One [`CapturedTriangle`] per triangle the evaluation stage emits.
    Triangles(u32),
}

impl Capture {
    /// Records the buffer has room for.
    pub fn capacity(self) -> u32 {
        match self {
            Capture::TesPoints(c) | Capture::Triangles(c) => c,
        }
    }

    /// Bytes of one record.
    pub fn record_bytes(self) -> usize {
        match self {
            Capture::TesPoints(_) => CAPTURE_RECORD_BYTES,
            Capture::Triangles(_) => TRIANGLE_RECORD_BYTES,
        }
    }

    /// Bytes before the first record.
    pub fn header_bytes(self) -> usize {
        match self {
            Capture::TesPoints(_) => CAPTURE_HEADER_BYTES,
            Capture::Triangles(_) => TRIANGLE_HEADER_BYTES,
        }
    }

    /// The most records of this kind one storage-buffer binding holds (`maxStorageBufferRange`).
    pub fn max_records(self, ctx: &Context) -> u32 {
        let range = ctx.info().limits.max_storage_buffer_range as usize;
        (range.saturating_sub(self.header_bytes()) / self.record_bytes()).min(u32::MAX as usize)
            as u32
    }
}

/// One triangle drawn by a tessellated frame, as the geometry stage saw it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CapturedTriangle {
    /// World positions, in the order the evaluation stage emitted them (its winding).
    pub positions: [[f32; 3]; 3],
    /// Unit normals (decoded from the octahedral encoding: within about 5e-5 rad).
    pub normals: [[f32; 3]; 3],
    /// Colour class of the first vertex (`t_class`, flat).
    pub class: u32,
}

/// The bucket of a triangle in a capture whose modulus is `buckets` (1..=[`MAX_BUCKETS`]): the
/// 32-bit MurmurHash3 of its nine position words modulo `buckets`, as `capture_triangles.geom`
/// computes it on the device.
pub fn triangle_bucket(positions: &[[f32; 3]; 3], buckets: u32) -> u32 {
    murmur3_words(positions.iter().flatten().map(|x| x.to_bits())) % buckets.clamp(1, MAX_BUCKETS)
}

/// MurmurHash3_x86_32 (Appleby, SMHasher) with seed 0 of the little-endian bytes of `words`.
fn murmur3_words(words: impl Iterator<Item = u32>) -> u32 {
    let (mut h, mut len) = (0u32, 0u32);
    for w in words {
        let k = w
            .wrapping_mul(0xcc9e_2d51)
            .rotate_left(15)
            .wrapping_mul(0x1b87_3593);
        h = (h ^ k)
            .rotate_left(13)
            .wrapping_mul(5)
            .wrapping_add(0xe654_6b64);
        len += 4;
    }
    h ^= len;
    h ^= h >> 16;
    h = h.wrapping_mul(0x85eb_ca6b);
    h ^= h >> 13;
    h = h.wrapping_mul(0xc2b2_ae35);
    h ^ (h >> 16)
}

/// The unit vector of the octahedral encoding `packSnorm2x16(e)` of
/// `glsl/surface/capture_triangles.geom` (Cigolle et al. 2014, "A survey of efficient
/// representations for independent unit vectors", Listing 1).
pub fn octahedral_normal(word: u32) -> [f32; 3] {
    let snorm = |h: u32| (f32::from(h as u16 as i16) / 32767.0).clamp(-1.0, 1.0);
    let (x, y) = (snorm(word & 0xffff), snorm(word >> 16));
    let z = 1.0 - x.abs() - y.abs();
    let (x, y) = if z < 0.0 {
        ((1.0 - y.abs()) * x.signum(), (1.0 - x.abs()) * y.signum())
    } else {
        (x, y)
    };
    let l = (x * x + y * y + z * z).sqrt();
    [x / l, y / l, z / l]
}

/// One captured TES invocation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CaptureRecord {
    /// Base-mesh face.
    pub face: u32,
    /// Face parameter u (see the scheme's [`crate::render::schemes::CaptureLayout`]).
    pub u: f32,
    /// Face parameter v.
    pub v: f32,
    /// Position.
    pub position: [f32; 3],
    /// Unit normal.
    pub normal: [f32; 3],
    /// Sub-face `k` of a non-quad base face whose `(u, v)` the record is in (`f:k` in
    /// `tessera sample`); `None` for the base face's own domain.
    pub sub_face: Option<u32>,
    /// The patch that produced the point, for schemes that tag it (the adaptive scheme).
    pub patch: Option<CapturedPatch>,
    /// Texture coordinate (s, t) at the point ([`crate::mesh::uv`]); zero when the surface has
    /// no texture coordinates.
    pub texcoord: [f32; 2],
}

/// The patch kind and level a capture record was tagged with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct CapturedPatch {
    /// Kind code (`KIND_*` of `glsl/adaptive/adaptive.glsl`: the adaptive patch types, then
    /// transition).
    pub kind: u8,
    /// Refinement level of the patch.
    pub level: u8,
}

/// The capture buffer of frame slot `slot` for `capture` (a minimal one when capture is off),
/// its header written: count 0, capacity. The capacity is lowered to what one storage-buffer
/// binding can hold ([`Capture::max_records`]); a frame that emits more is then a
/// capture-overflow error ([`decode_capture`], [`decode_triangles`]), never an invalid binding.
pub fn capture_buffer(ctx: &Context, capture: Capture, slot: usize) -> Result<Buffer> {
    let fits = capture.max_records(ctx);
    let capacity = capture.capacity();
    if capacity > fits {
        log::warn!(
            "capture: {capacity} records do not fit one storage buffer \
             (maxStorageBufferRange {} bytes); capturing at most {fits}",
            ctx.info().limits.max_storage_buffer_range
        );
    }
    let capacity = capacity.min(fits);
    let mut bytes = vec![0u8; capture.header_bytes() + capture.record_bytes() * capacity as usize];
    bytes[4..8].copy_from_slice(&capacity.to_le_bytes());
    if let Capture::Triangles(_) = capture {
        // Every bucket stored: [0, DEFAULT_BUCKETS) of DEFAULT_BUCKETS.
        bytes[12..16].copy_from_slice(&DEFAULT_BUCKETS.to_le_bytes());
        bytes[20..24].copy_from_slice(&DEFAULT_BUCKETS.to_le_bytes());
    }
    let mut b = Buffer::new(
        ctx,
        bytes.len() as u64,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::GpuToCpu,
        &format!("tes capture (frame slot {slot})"),
    )?;
    b.write(0, &bytes)?;
    Ok(b)
}

/// Resets the record count, and for a triangle capture the stored count and the bucket counts
/// (host write, between frames).
pub fn reset_capture(buffer: &mut Buffer, capture: Capture) -> Result<()> {
    buffer.write(0, &[0u32])?;
    if let Capture::Triangles(_) = capture {
        buffer.write(16, &[0u32])?;
        buffer.write(32, &[0u32; MAX_BUCKETS as usize])?;
    }
    Ok(())
}

/// Sets the buckets a triangle capture hashes into (`buckets`, 1..=[`MAX_BUCKETS`]) and the
/// range `first..end` of them the next frames store (header words 5, 2 and 3; host write
/// between frames).
pub fn set_triangle_buckets(buffer: &mut Buffer, buckets: u32, first: u32, end: u32) -> Result<()> {
    if buckets == 0 || buckets > MAX_BUCKETS || first > end || end > buckets {
        return Err(Error::Invalid(format!(
            "triangle capture: buckets {first}..{end} of {buckets} (at most {MAX_BUCKETS})"
        )));
    }
    buffer.write(8, &[first, end])?;
    buffer.write(20, &[buckets])
}

/// The records (`record_bytes` each) of a capture buffer's words; errors when the count exceeds
/// `capacity`, naming `what` the records are.
fn records<'a>(
    words: &'a [u32],
    capacity: u32,
    record_bytes: usize,
    what: &str,
) -> Result<impl Iterator<Item = &'a [u32]>> {
    let count = words[0];
    if count > capacity {
        return Err(Error::Invalid(format!(
            "capture overflow: the frame emitted {count} {what}, capacity {capacity}"
        )));
    }
    Ok(words[CAPTURE_HEADER_BYTES / 4..]
        .chunks_exact(record_bytes / 4)
        .take(count as usize))
}

/// Decodes the records of a capture buffer's words; errors on overflow.
pub fn decode_capture(words: &[u32], capacity: u32) -> Result<Vec<CaptureRecord>> {
    let f = f32::from_bits;
    Ok(
        records(words, capacity, CAPTURE_RECORD_BYTES, "TES invocations")?
            .map(|r| CaptureRecord {
                face: r[0],
                u: f(r[1]),
                v: f(r[2]),
                position: [f(r[3]), f(r[4]), f(r[5])],
                normal: [f(r[6]), f(r[7]), f(r[8])],
                sub_face: (r[9] != NO_SUB_FACE).then_some(r[9]),
                patch: (r[10] & CAPTURE_TAGGED != 0).then(|| CapturedPatch {
                    kind: (r[10] & 0xff) as u8,
                    level: ((r[10] >> 8) & 0xff) as u8,
                }),
                texcoord: [f(r[11]), f(r[12])],
            })
            .collect(),
    )
}

/// Decodes the triangles of a triangle-capture buffer's words; errors on overflow (the frame
/// stored more than the capacity), naming the triangles stored and the capacity.
pub fn decode_triangles(words: &[u32]) -> Result<Vec<CapturedTriangle>> {
    let w = decode_triangle_window(words);
    if w.stored > w.triangles.len() as u32 {
        return Err(Error::Invalid(format!(
            "capture overflow: the frame emitted {} triangles in buckets {}..{} of {}, capacity {}",
            w.stored,
            w.buckets.start,
            w.buckets.end,
            w.bucket_counts.len(),
            words[1]
        )));
    }
    Ok(w.triangles)
}

/// What one frame's triangle capture saw (`capture_triangles.geom`).
#[derive(Debug, Clone, PartialEq)]
pub struct TriangleWindow {
    /// Triangles the frame drew (header word 0).
    pub drawn: u32,
    /// Of those, the ones in the stored buckets (header word 4, counted past the capacity too).
    pub stored: u32,
    /// The bucket range stored (header words 2 and 3).
    pub buckets: std::ops::Range<u32>,
    /// Triangles the frame drew per bucket (as many as the bucket modulus, header word 5).
    pub bucket_counts: Vec<u32>,
    /// The stored triangles, at most the capacity, in no particular order.
    pub triangles: Vec<CapturedTriangle>,
}

/// The [`TriangleWindow`] of a triangle-capture buffer's words.
pub fn decode_triangle_window(words: &[u32]) -> TriangleWindow {
    let (drawn, capacity, stored) = (words[0], words[1], words[4]);
    let modulus = words[5].clamp(1, MAX_BUCKETS) as usize;
    let f = f32::from_bits;
    let triangles = words[TRIANGLE_HEADER_BYTES / 4..]
        .chunks_exact(TRIANGLE_RECORD_BYTES / 4)
        .take(stored.min(capacity) as usize)
        .map(|r| {
            let vertex = |i: usize| &r[4 * i..4 * i + 4];
            CapturedTriangle {
                positions: [0, 1, 2].map(|i| {
                    let v = vertex(i);
                    [f(v[0]), f(v[1]), f(v[2])]
                }),
                normals: [0, 1, 2].map(|i| octahedral_normal(vertex(i)[3])),
                class: r[12],
            }
        })
        .collect();
    TriangleWindow {
        drawn,
        stored,
        buckets: words[2]..words[3],
        bucket_counts: words[8..8 + modulus].to_vec(),
        triangles,
    }
}

/// Capture capacity (records) sufficient for `tess` (uniform) over `patches` patches: per
/// (sub-)patch at most `(ceil(level / split) + 2)^2` domain points. Pass the settings the
/// renderer resolved ([`crate::render::SurfaceRenderer::tess`] or
/// [`crate::render::resolve_tess`]).
pub fn capture_capacity_for(patches: usize, tess: &TessSettings) -> u32 {
    let split = u64::from(tess.split());
    let sub = tess.level.max(1.0) / split as f32;
    let n = (sub.ceil() as u64) + if tess.spacing == Spacing::Equal { 1 } else { 2 };
    (patches as u64 * split * split * n * n).min(u64::from(u32::MAX / 64)) as u32
}

#[cfg(test)]
mod tests {
    use super::{
        decode_triangle_window, decode_triangles, murmur3_words, octahedral_normal,
        triangle_bucket, MAX_BUCKETS, TRIANGLE_HEADER_BYTES, TRIANGLE_RECORD_BYTES,
    };

    /// Header and three records of a triangle capture: `drawn` triangles, `stored` of them in
    /// buckets `first..end` of 4 (counts 1, 2, 3, 4), `capacity` records.
    fn words(drawn: u32, capacity: u32, stored: u32, first: u32, end: u32) -> Vec<u32> {
        let mut w = vec![0u32; (TRIANGLE_HEADER_BYTES + 3 * TRIANGLE_RECORD_BYTES) / 4];
        w[..6].copy_from_slice(&[drawn, capacity, first, end, stored, 4]);
        w[8..12].copy_from_slice(&[1, 2, 3, 4]);
        w
    }

    /// A frame that stored more triangles than the buffer holds is an error naming the stored
    /// count and the capacity; within the capacity every record decodes.
    #[test]
    fn triangle_overflow_is_an_error_naming_the_counts() {
        let e = decode_triangles(&words(10, 3, 5, 0, 4))
            .unwrap_err()
            .to_string();
        assert!(e.contains("5 triangles") && e.contains("capacity 3"), "{e}");
        assert_eq!(decode_triangles(&words(10, 3, 3, 0, 4)).unwrap().len(), 3);
    }

    /// The window reports the frame's count, the stored count, the stored range and one count
    /// per bucket of the modulus (header word 5), and decodes `min(stored, capacity)` records.
    #[test]
    fn triangle_window_holds_the_stored_buckets() {
        let w = decode_triangle_window(&words(10, 3, 2, 1, 3));
        assert_eq!((w.drawn, w.stored, w.buckets), (10, 2, 1..3));
        assert_eq!(w.bucket_counts, [1, 2, 3, 4]);
        assert_eq!(w.triangles.len(), 2);
        assert_eq!(
            decode_triangle_window(&words(10, 3, 7, 0, 4))
                .triangles
                .len(),
            3
        );
    }

    /// The bucket hash is MurmurHash3_x86_32 with seed 0: the published SMHasher vectors of
    /// 0, 4 and 8 bytes; a triangle's bucket is that of its 36 position bytes (little-endian);
    /// `capture_triangles.geom` declares the same bucket bound.
    #[test]
    fn triangle_bucket_is_murmur3_of_the_positions() {
        for (words, hash) in [
            (vec![], 0),
            (vec![0xffff_ffffu32], 0x7629_3b50),
            (vec![0x8765_4321], 0xf55b_516b),
            (vec![0], 0x2362_f9de),
        ] {
            assert_eq!(murmur3_words(words.iter().copied()), hash, "{words:x?}");
        }
        let t = [[0.25f32, -1.5, 3.0], [1e-3, 2.0, -0.0], [7.0, 8.5, -9.25]];
        let h = murmur3_words(t.iter().flatten().map(|x| x.to_bits()));
        for m in [1, 7, 256, MAX_BUCKETS] {
            assert_eq!(triangle_bucket(&t, m), h % m, "modulo {m}");
        }
        let geom = include_str!("../../../glsl/surface/capture_triangles.geom");
        assert!(
            geom.contains(&format!("#define MAX_BUCKETS {MAX_BUCKETS}\n")),
            "capture_triangles.geom's MAX_BUCKETS"
        );
    }

    /// `packSnorm2x16(e)` of a point `e` of [-1, 1]^2.
    fn pack(e: [f32; 2]) -> u32 {
        let h = |x: f32| u32::from((x * 32767.0).round() as i16 as u16);
        h(e[0]) | (h(e[1]) << 16)
    }

    /// The octahedral map (Cigolle et al. 2014): the upper half as is, the lower half folded
    /// across the diagonals; decoded against the closed-form inverse of a few points.
    #[test]
    fn octahedral_normals_decode() {
        for (e, n) in [
            ([0.0, 0.0], [0.0f32, 0.0, 1.0]),
            ([1.0, 0.0], [1.0, 0.0, 0.0]),
            ([0.0, -1.0], [0.0, -1.0, 0.0]),
            ([1.0, 1.0], [0.0, 0.0, -1.0]),
            // z < 0: (x, y) = ((1 - |ey|) sgn ex, (1 - |ex|) sgn ey) = (0.25, -0.5), z = -0.25.
            ([0.5, -0.75], [0.25, -0.5, -0.25]),
            ([0.25, -0.25], [0.25, -0.25, 0.5]),
        ] {
            let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            let d = octahedral_normal(pack(e));
            for k in 0..3 {
                assert!((d[k] - n[k] / l).abs() < 1e-4, "{e:?}: {d:?} against {n:?}");
            }
        }
    }
}
