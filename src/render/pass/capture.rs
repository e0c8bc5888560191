//! TES capture: every evaluation-shader invocation appends one record (`glsl/common/capture.glsl`)
//! to a host-readable buffer shared by all passes of a surface.

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
/// Bytes before the first capture record (count, capacity, two pad words).
pub const CAPTURE_HEADER_BYTES: usize = 16;

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

/// The capture buffer of frame slot `slot` for `capacity` records (a minimal one when capture
/// is off), its header written: count 0, capacity. The capacity is lowered to what one storage-buffer binding can
/// hold (`maxStorageBufferRange`); a frame that emits more is then a capture-overflow error
/// ([`decode_capture`]), never an invalid binding.
pub fn capture_buffer(ctx: &Context, capacity: u32, slot: usize) -> Result<Buffer> {
    let range = ctx.info().limits.max_storage_buffer_range as usize;
    let fits = (range.saturating_sub(CAPTURE_HEADER_BYTES) / CAPTURE_RECORD_BYTES) as u32;
    if capacity > fits {
        log::warn!(
            "TES capture: {capacity} records do not fit one storage buffer \
             (maxStorageBufferRange {range} bytes); capturing at most {fits}"
        );
    }
    let capacity = capacity.min(fits);
    let mut bytes = vec![0u8; CAPTURE_HEADER_BYTES + CAPTURE_RECORD_BYTES * capacity as usize];
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

/// Decodes the records of a capture buffer's words; errors on overflow.
pub fn decode_capture(words: &[u32], capacity: u32) -> Result<Vec<CaptureRecord>> {
    let count = words[0];
    if count > capacity {
        return Err(Error::Invalid(format!(
            "TES capture overflow: {count} invocations, capacity {capacity}"
        )));
    }
    let f = f32::from_bits;
    Ok(words[CAPTURE_HEADER_BYTES / 4..]
        .chunks_exact(CAPTURE_RECORD_BYTES / 4)
        .take(count as usize)
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
        .collect())
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
