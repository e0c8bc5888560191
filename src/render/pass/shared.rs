//! The buffers every pass of a surface shares and their descriptor bindings, defined once.
//!
//! Set 0 of every patch pipeline holds the shared bindings of `glsl/common/frame.glsl`,
//! `capture.glsl` and the watertight corner rules plus the scheme's own bindings
//! ([`set0_layout`]): 0 `Frame` UBO, 2 vertex limit positions, 3 TES capture, 8 control
//! positions, 9 vertex limit normals. A scheme's own tables take the other binding numbers of
//! set 0 (1, 4-7) or sets of their own.

use ash::vk;
use glam::DVec3;

use super::capture::{capture_buffer, decode_capture, reset_capture, CaptureRecord};
use super::frames::VertexFrames;
use super::upload::{host_buffer, vec3_bytes, vec4_bytes};
use crate::gpu::{Buffer, BufferBinding, Context, DescriptorBinding, DescriptorKind};
use crate::render::settings::FRAME_UNIFORM_BYTES;
use crate::{Error, Result};

/// Binding of the `Frame` uniform block.
pub const FRAME_BINDING: u32 = 0;
/// Binding of the vertex limit positions.
pub const VERTEX_LIMITS_BINDING: u32 = 2;
/// Binding of the TES capture buffer.
pub const CAPTURE_BINDING: u32 = 3;
/// Binding of the control positions (storage view of the position vertex buffer).
pub const CONTROL_POSITIONS_BINDING: u32 = 8;
/// Binding of the vertex limit normals.
pub const VERTEX_NORMALS_BINDING: u32 = 9;

/// Stages that read the shared storage buffers.
pub fn storage_stages() -> vk::ShaderStageFlags {
    vk::ShaderStageFlags::VERTEX
        | vk::ShaderStageFlags::TESSELLATION_CONTROL
        | vk::ShaderStageFlags::TESSELLATION_EVALUATION
}

/// A storage-buffer binding of a scheme's own table in set 0, visible to the vertex and both
/// tessellation stages.
pub fn storage_binding(binding: u32) -> DescriptorBinding {
    DescriptorBinding {
        binding,
        kind: DescriptorKind::StorageBuffer,
        stages: storage_stages(),
    }
}

/// Set 0 of a patch pipeline: the shared bindings, then `own`.
pub fn set0_layout(own: &[u32]) -> Vec<DescriptorBinding> {
    let mut v = vec![DescriptorBinding {
        binding: FRAME_BINDING,
        kind: DescriptorKind::UniformBuffer,
        stages: storage_stages() | vk::ShaderStageFlags::FRAGMENT,
    }];
    v.extend(
        [
            VERTEX_LIMITS_BINDING,
            CAPTURE_BINDING,
            CONTROL_POSITIONS_BINDING,
            VERTEX_NORMALS_BINDING,
        ]
        .into_iter()
        .chain(own.iter().copied())
        .map(storage_binding),
    );
    v
}

/// The buffers shared by every pass of one surface: frame uniforms, control positions, vertex
/// limit frames and the TES capture.
pub struct SharedResources {
    frame: Buffer,
    positions: Buffer,
    vertex_limits: Buffer,
    vertex_normals: Buffer,
    capture: Buffer,
    capture_capacity: Option<u32>,
    vertex_count: usize,
}

impl SharedResources {
    /// Uploads `positions` and `frames`; `capture_capacity` records of TES capture.
    pub fn new(
        ctx: &Context,
        positions: &[DVec3],
        frames: &VertexFrames,
        capture_capacity: Option<u32>,
    ) -> Result<SharedResources> {
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        Ok(SharedResources {
            frame: host_buffer(
                ctx,
                &[0u8; FRAME_UNIFORM_BYTES],
                vk::BufferUsageFlags::UNIFORM_BUFFER,
                "frame uniforms",
            )?,
            positions: host_buffer(
                ctx,
                &vec3_bytes(positions),
                storage | vk::BufferUsageFlags::VERTEX_BUFFER,
                "control positions",
            )?,
            vertex_limits: host_buffer(
                ctx,
                &vec4_bytes(&frames.limits),
                storage,
                "vertex limit positions",
            )?,
            vertex_normals: host_buffer(
                ctx,
                &vec4_bytes(&frames.normals),
                storage,
                "vertex limit normals",
            )?,
            capture: capture_buffer(ctx, capture_capacity.unwrap_or(0))?,
            capture_capacity,
            vertex_count: positions.len(),
        })
    }

    /// The descriptor writes of the shared bindings followed by `own`. A shared binding that
    /// `own` also writes is left to `own` (a pass with its own control points or vertex frames,
    /// e.g. the adaptive scheme's refined buffer and GPU-computed frames).
    pub fn bindings<'a>(&'a self, own: &[BufferBinding<'a>]) -> Vec<BufferBinding<'a>> {
        let sb = |binding, buffer| BufferBinding {
            binding,
            kind: DescriptorKind::StorageBuffer,
            buffer,
        };
        let mut v = vec![
            BufferBinding {
                binding: FRAME_BINDING,
                kind: DescriptorKind::UniformBuffer,
                buffer: &self.frame,
            },
            sb(VERTEX_LIMITS_BINDING, &self.vertex_limits),
            sb(CAPTURE_BINDING, &self.capture),
            sb(CONTROL_POSITIONS_BINDING, &self.positions),
            sb(VERTEX_NORMALS_BINDING, &self.vertex_normals),
        ];
        v.retain(|b| own.iter().all(|o| o.binding != b.binding));
        v.extend_from_slice(own);
        v
    }

    /// Writes set 0 of a pass: the shared bindings and the pass's `own`.
    pub fn write_set0(&self, ctx: &Context, set: vk::DescriptorSet, own: &[BufferBinding<'_>]) {
        ctx.write_buffer_descriptors(set, &self.bindings(own));
    }

    /// The control-position vertex buffer (tightly packed f32 xyz).
    pub fn positions(&self) -> vk::Buffer {
        self.positions.raw()
    }

    /// Bytes of GPU memory of the shared buffers (frame uniforms, control positions, vertex
    /// limit frames, capture).
    pub fn memory_bytes(&self) -> u64 {
        [
            &self.frame,
            &self.positions,
            &self.vertex_limits,
            &self.vertex_normals,
            &self.capture,
        ]
        .iter()
        .map(|b| b.size())
        .sum()
    }

    /// Number of control vertices.
    pub fn vertex_count(&self) -> usize {
        self.vertex_count
    }

    /// Writes the frame uniform block.
    pub fn write_frame(&mut self, bytes: &[u8]) -> Result<()> {
        self.frame.write(0, bytes)
    }

    /// Animation: new control positions and their limit frames.
    pub fn update(&mut self, positions: &[DVec3], frames: &VertexFrames) -> Result<()> {
        if positions.len() != self.vertex_count {
            return Err(Error::Invalid(format!(
                "update_positions: got {} positions, the surface has {} vertices",
                positions.len(),
                self.vertex_count
            )));
        }
        self.positions.write(0, &vec3_bytes(positions))?;
        self.vertex_limits.write(0, &vec4_bytes(&frames.limits))?;
        self.vertex_normals.write(0, &vec4_bytes(&frames.normals))
    }

    /// Resets the capture counter (host write; between frames).
    pub fn reset_capture(&mut self) -> Result<()> {
        reset_capture(&mut self.capture)
    }

    /// The captured TES invocations of the last finished frame, in draw order.
    pub fn read_capture(&self) -> Result<Vec<CaptureRecord>> {
        let Some(capacity) = self.capture_capacity else {
            return Err(Error::Invalid(
                "capture is not enabled in RenderDesc".into(),
            ));
        };
        decode_capture(&self.capture.read::<u32>()?, capacity)
    }
}
