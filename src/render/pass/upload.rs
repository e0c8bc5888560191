//! Buffer uploads and the byte layouts of point arrays (std430).

use ash::vk;
use glam::DVec3;

use crate::gpu::{Buffer, Context, MemoryLocation};
use crate::Result;

/// Smallest buffer created: shaders never read the padding, Vulkan forbids empty buffers.
const MIN_BUFFER_BYTES: usize = 64;

/// A host-visible buffer holding `bytes` (at least `MIN_BUFFER_BYTES`): data rewritten by
/// the host (positions, limit frames, uniforms).
pub fn host_buffer(
    ctx: &Context,
    bytes: &[u8],
    usage: vk::BufferUsageFlags,
    name: &str,
) -> Result<Buffer> {
    let mut b = Buffer::new(
        ctx,
        bytes.len().max(MIN_BUFFER_BYTES) as u64,
        usage,
        MemoryLocation::CpuToGpu,
        name,
    )?;
    b.write(0, bytes)?;
    Ok(b)
}

/// A device-local buffer holding `bytes` (at least `MIN_BUFFER_BYTES`): tables fixed for the
/// topology.
pub fn device_buffer(
    ctx: &Context,
    bytes: &[u8],
    usage: vk::BufferUsageFlags,
    name: &str,
) -> Result<Buffer> {
    if bytes.len() >= MIN_BUFFER_BYTES {
        return ctx.upload_buffer(bytes, usage, name);
    }
    let mut padded = bytes.to_vec();
    padded.resize(MIN_BUFFER_BYTES, 0);
    ctx.upload_buffer(&padded, usage, name)
}

/// Words as little-endian bytes.
pub fn u32_bytes(words: &[u32]) -> Vec<u8> {
    words.iter().flat_map(|w| w.to_le_bytes()).collect()
}

/// Floats as little-endian bytes.
pub fn f32_bytes(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|w| w.to_le_bytes()).collect()
}

/// Points as tightly packed f32 triples (vertex buffers, `float[]` storage).
pub fn vec3_bytes(points: &[DVec3]) -> Vec<u8> {
    let mut out = Vec::with_capacity(points.len() * 12);
    for p in points {
        for c in p.as_vec3().to_array() {
            out.extend_from_slice(&c.to_le_bytes());
        }
    }
    out
}

/// Points as f32 quadruples with w = 1 (std430 `vec4[]`).
pub fn vec4_bytes(points: &[DVec3]) -> Vec<u8> {
    let mut out = Vec::with_capacity(points.len() * 16);
    for p in points {
        for c in p.as_vec3().extend(1.0).to_array() {
            out.extend_from_slice(&c.to_le_bytes());
        }
    }
    out
}
