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
/// Bytes before the first capture record (count, capacity, then for triangle capture the first
/// slot stored, one pad word).
pub const CAPTURE_HEADER_BYTES: usize = 16;

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

    /// The most records of this kind one storage-buffer binding holds (`maxStorageBufferRange`).
    pub fn max_records(self, ctx: &Context) -> u32 {
        let range = ctx.info().limits.max_storage_buffer_range as usize;
        (range.saturating_sub(CAPTURE_HEADER_BYTES) / self.record_bytes()).min(u32::MAX as usize)
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
    let mut bytes = vec![0u8; CAPTURE_HEADER_BYTES + capture.record_bytes() * capacity as usize];
    bytes[4..8].copy_from_slice(&capacity.to_le_bytes());
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

/// Resets the record count (host write, between frames).
pub fn reset_capture(buffer: &mut Buffer) -> Result<()> {
    buffer.write(0, &[0u32])
}

/// Sets the first slot a triangle capture stores (header word 2, host write between frames):
/// the frame's triangles `[first, first + capacity)` land in the buffer.
pub fn set_triangle_window(buffer: &mut Buffer, first: u32) -> Result<()> {
    buffer.write(8, &[first])
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
/// drew past the window), naming the triangles the frame drew and the capacity.
pub fn decode_triangles(words: &[u32]) -> Result<Vec<CapturedTriangle>> {
    let (count, first, capacity) = (words[0], words[2], words[1]);
    if u64::from(count) > u64::from(first) + u64::from(capacity) {
        return Err(Error::Invalid(format!(
            "capture overflow: the frame emitted {count} triangles, capacity {capacity} \
             (from slot {first})"
        )));
    }
    Ok(decode_triangle_window(words).1)
}

/// The triangles a triangle-capture buffer's window stored (slots `[first, first + capacity)`
/// of the frame's, header words 2 and 1; fewer when the frame drew fewer), with the number of
/// triangles the frame drew (header word 0, counted past the window too).
pub fn decode_triangle_window(words: &[u32]) -> (u32, Vec<CapturedTriangle>) {
    let (count, capacity, first) = (words[0], words[1], words[2]);
    let stored = count.saturating_sub(first).min(capacity) as usize;
    let f = f32::from_bits;
    let triangles = words[CAPTURE_HEADER_BYTES / 4..]
        .chunks_exact(TRIANGLE_RECORD_BYTES / 4)
        .take(stored)
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
    (count, triangles)
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
        decode_triangle_window, decode_triangles, octahedral_normal, CAPTURE_HEADER_BYTES,
        TRIANGLE_RECORD_BYTES,
    };

    /// A frame that drew more triangles than the buffer holds is an error naming both counts;
    /// within the capacity every record decodes.
    #[test]
    fn triangle_overflow_is_an_error_naming_the_counts() {
        let words = |count: u32, capacity: u32| {
            let mut w = vec![0u32; (CAPTURE_HEADER_BYTES + 3 * TRIANGLE_RECORD_BYTES) / 4];
            w[0] = count;
            w[1] = capacity;
            w
        };
        let e = decode_triangles(&words(5, 3)).unwrap_err().to_string();
        assert!(e.contains("5 triangles") && e.contains("capacity 3"), "{e}");
        assert_eq!(decode_triangles(&words(3, 3)).unwrap().len(), 3);
    }

    /// A window `[first, first + capacity)` holds the frame's slots from `first`: a full middle
    /// chunk, the partial last one, none past the count; overflow is judged past the window.
    #[test]
    fn triangle_window_holds_the_slots_from_first() {
        let words = |count: u32, capacity: u32, first: u32| {
            let mut w = vec![0u32; (CAPTURE_HEADER_BYTES + 3 * TRIANGLE_RECORD_BYTES) / 4];
            w[..3].copy_from_slice(&[count, capacity, first]);
            w
        };
        let stored = |count, first| decode_triangle_window(&words(count, 3, first)).1.len();
        assert_eq!(stored(8, 3), 3);
        assert_eq!(stored(8, 6), 2);
        assert_eq!(stored(8, 9), 0);
        assert_eq!(decode_triangle_window(&words(8, 3, 6)).0, 8);
        assert_eq!(decode_triangles(&words(8, 3, 6)).unwrap().len(), 2);
        let e = decode_triangles(&words(8, 3, 3)).unwrap_err().to_string();
        assert!(
            e.contains("8 triangles") && e.contains("from slot 3"),
            "{e}"
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
