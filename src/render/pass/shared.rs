//! The buffers every pass of a surface shares and their descriptor bindings, defined once.
//!
//! Set 0 of every patch pipeline holds the shared bindings of `glsl/common/frame.glsl`,
//! `capture.glsl` and the watertight corner rules plus the scheme's own bindings
//! ([`set0_layout`]): 0 `Frame` UBO, 2 vertex limit positions, 3 TES or triangle capture (visible
//! to the geometry stage only in pipelines that capture triangles, [`with_geometry_capture`]), 8 control
//! positions, 9 vertex limit normals, 14 face-varying texture coordinates, 15 the displacement
//! map (combined image sampler; a 1 x 1 mid-grey image without a map). A scheme's own tables
//! take the other binding numbers of set 0 (1, 4-7) or sets of their own.

use ash::vk;
use glam::DVec3;

use super::capture::{
    capture_buffer, decode_capture, decode_triangle_window, decode_triangles, reset_capture,
    set_triangle_buckets, Capture, CaptureRecord, CapturedTriangle, TriangleWindow,
};
use super::frames::VertexFrames;
use super::upload::{host_buffer, vec3_bytes, vec4_bytes};
use crate::gpu::{
    Buffer, BufferBinding, Context, DescriptorBinding, DescriptorKind, DescriptorPool, SampledImage,
};
use crate::render::displace::{DisplacementMap, Texels};
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
/// Binding of the face-varying texture coordinates (`glsl/common/texcoord.glsl`).
pub const TEXCOORDS_BINDING: u32 = 14;
/// Binding of the displacement map (`glsl/common/displace.glsl`).
pub const DISPLACEMENT_MAP_BINDING: u32 = 15;

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
            CONTROL_POSITIONS_BINDING,
            VERTEX_NORMALS_BINDING,
            TEXCOORDS_BINDING,
        ]
        .into_iter()
        .chain(own.iter().copied())
        .map(storage_binding),
    );
    v.insert(
        2,
        DescriptorBinding {
            binding: CAPTURE_BINDING,
            kind: DescriptorKind::StorageBuffer,
            stages: storage_stages(),
        },
    );
    v.push(DescriptorBinding {
        binding: DISPLACEMENT_MAP_BINDING,
        kind: DescriptorKind::CombinedImageSampler,
        stages: storage_stages(),
    });
    v
}

/// `layouts` (set 0 first) with the capture binding also visible to the geometry stage, for the
/// pipelines that capture triangles (`capture_triangles.geom`). Only those may name the stage:
/// without the `geometryShader` feature the `GEOMETRY` stage bit must not be used at all, so
/// [`set0_layout`] leaves it out.
pub fn with_geometry_capture(
    mut layouts: Vec<Vec<DescriptorBinding>>,
) -> Vec<Vec<DescriptorBinding>> {
    let capture = layouts
        .first_mut()
        .and_then(|set0| set0.iter_mut().find(|b| b.binding == CAPTURE_BINDING));
    if let Some(b) = capture {
        b.stages |= vk::ShaderStageFlags::GEOMETRY;
    }
    layouts
}

/// The displacement map as a sampled image: 8-bit maps as `R8_UNORM`, 16-bit ones as
/// `R16_UNORM`; without a map a 1 x 1 mid-grey texel (the binding is always valid).
fn upload_map(ctx: &Context, map: Option<&DisplacementMap>) -> Result<SampledImage> {
    let name = "displacement map";
    let Some(map) = map else {
        return ctx.upload_sampled_image(1, 1, vk::Format::R8_UNORM, &[128], name);
    };
    let (w, h) = map.size();
    let max = ctx.info().limits.max_image_dimension_2d;
    if w > max || h > max {
        return Err(Error::Invalid(format!(
            "displacement map {}: {w} x {h} texels exceeds the device's maxImageDimension2D {max}",
            map.source()
        )));
    }
    match map.texels() {
        Texels::U8(t) => ctx.upload_sampled_image(w, h, vk::Format::R8_UNORM, t, name),
        Texels::U16(t) => {
            let bytes: Vec<u8> = t.iter().flat_map(|v| v.to_le_bytes()).collect();
            ctx.upload_sampled_image(w, h, vk::Format::R16_UNORM, &bytes, name)
        }
    }
}

/// The host-written buffers of one frame in flight: what the CPU rewrites between frames.
struct FrameSlot {
    frame: Buffer,
    positions: Buffer,
    vertex_limits: Buffer,
    vertex_normals: Buffer,
    /// Version of the positions the buffers hold ([`SharedResources::stage`]).
    version: u64,
}

impl FrameSlot {
    fn new(ctx: &Context, staged: &Staged, k: usize) -> Result<FrameSlot> {
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let name = |what: &str| format!("{what} (frame slot {k})");
        Ok(FrameSlot {
            frame: host_buffer(
                ctx,
                &[0u8; FRAME_UNIFORM_BYTES],
                vk::BufferUsageFlags::UNIFORM_BUFFER,
                &name("frame uniforms"),
            )?,
            positions: host_buffer(
                ctx,
                &staged.positions,
                storage | vk::BufferUsageFlags::VERTEX_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC,
                &name("control positions"),
            )?,
            vertex_limits: host_buffer(ctx, &staged.limits, storage, &name("vertex limits"))?,
            vertex_normals: host_buffer(ctx, &staged.normals, storage, &name("vertex normals"))?,
            version: staged.version,
        })
    }

    fn buffers(&self) -> [&Buffer; 4] {
        [
            &self.frame,
            &self.positions,
            &self.vertex_limits,
            &self.vertex_normals,
        ]
    }
}

/// The latest control positions and limit frames as bytes, with their version.
struct Staged {
    positions: Vec<u8>,
    limits: Vec<u8>,
    normals: Vec<u8>,
    version: u64,
}

/// The buffers shared by every pass of one surface: per frame in flight (`FrameSlot`) the
/// frame uniforms, control positions and vertex limit frames, and with capture on a TES capture
/// buffer (without capture, one minimal buffer bound by every slot: no memory per slot).
///
/// Frames in flight: the host writes only the slot of the frame being prepared
/// ([`Self::write_frame`], [`Self::sync`]), so the frames still executing read their own slots
/// untouched. New positions ([`Self::stage`]) reach each slot when that slot is next prepared.
pub struct SharedResources {
    slots: Vec<FrameSlot>,
    staged: Staged,
    /// Capture on: one buffer per frame slot; off: one minimal buffer every slot binds.
    captures: Vec<Buffer>,
    capture: Option<Capture>,
    vertex_count: usize,
    texcoords: Buffer,
    displacement_map: SampledImage,
}

impl SharedResources {
    /// Uploads `positions` and `frames` into each of `frames_in_flight` slots (at least one);
    /// with `capture`, a capture buffer of that many records per slot; the
    /// texture-coordinate table's words
    /// (`SurfaceData::texcoord_words`); the displacement map, if any.
    pub fn new(
        ctx: &Context,
        positions: &[DVec3],
        frames: &VertexFrames,
        capture: Option<Capture>,
        frames_in_flight: usize,
        texcoords: &[[u32; 4]],
        displacement_map: Option<&DisplacementMap>,
    ) -> Result<SharedResources> {
        let staged = Staged {
            positions: vec3_bytes(positions),
            limits: vec4_bytes(&frames.limits),
            normals: frames.normal_bytes(),
            version: 0,
        };
        let slots = (0..frames_in_flight.max(1))
            .map(|k| FrameSlot::new(ctx, &staged, k))
            .collect::<Result<Vec<_>>>()?;
        let captures = match capture {
            Some(c) => (0..slots.len())
                .map(|k| capture_buffer(ctx, c, k))
                .collect::<Result<Vec<_>>>()?,
            None => vec![capture_buffer(ctx, Capture::TesPoints(0), 0)?],
        };
        Ok(SharedResources {
            slots,
            staged,
            captures,
            capture,
            vertex_count: positions.len(),
            texcoords: ctx.upload_buffer(
                texcoords,
                vk::BufferUsageFlags::STORAGE_BUFFER,
                "texture coordinates",
            )?,
            displacement_map: upload_map(ctx, displacement_map)?,
        })
    }

    /// Number of frame slots (frames in flight).
    pub fn slot_count(&self) -> usize {
        self.slots.len()
    }

    /// The descriptor writes of the shared bindings of frame slot `slot` followed by `own`. A
    /// shared binding that `own` also writes is left to `own` (a pass with its own control
    /// points or vertex frames, e.g. the adaptive scheme's refined buffer and GPU-computed
    /// frames).
    pub fn bindings<'a>(
        &'a self,
        slot: usize,
        own: &[BufferBinding<'a>],
    ) -> Vec<BufferBinding<'a>> {
        let s = &self.slots[slot];
        let sb = |binding, buffer| BufferBinding {
            binding,
            kind: DescriptorKind::StorageBuffer,
            buffer,
        };
        let mut v = vec![
            BufferBinding {
                binding: FRAME_BINDING,
                kind: DescriptorKind::UniformBuffer,
                buffer: &s.frame,
            },
            sb(VERTEX_LIMITS_BINDING, &s.vertex_limits),
            sb(CAPTURE_BINDING, self.capture(slot)),
            sb(CONTROL_POSITIONS_BINDING, &s.positions),
            sb(VERTEX_NORMALS_BINDING, &s.vertex_normals),
            sb(TEXCOORDS_BINDING, &self.texcoords),
        ];
        v.retain(|b| own.iter().all(|o| o.binding != b.binding));
        v.extend_from_slice(own);
        v
    }

    /// Allocates set 0 of a pass once per frame slot from `pool` (sized for
    /// [`Self::slot_count`] sets of `layout`) and writes each: the slot's shared bindings and
    /// the pass's `own`. Index the result by slot.
    pub fn set0_per_slot(
        &self,
        ctx: &Context,
        pool: &DescriptorPool,
        layout: vk::DescriptorSetLayout,
        own: &[BufferBinding<'_>],
    ) -> Result<Vec<vk::DescriptorSet>> {
        (0..self.slots.len())
            .map(|slot| {
                let set = pool.allocate(layout)?;
                ctx.write_buffer_descriptors(set, &self.bindings(slot, own));
                ctx.write_image_descriptor(set, DISPLACEMENT_MAP_BINDING, &self.displacement_map);
                Ok(set)
            })
            .collect()
    }

    /// The control-position vertex buffer of frame slot `slot` (tightly packed f32 xyz).
    pub fn positions(&self, slot: usize) -> vk::Buffer {
        self.slots[slot].positions.raw()
    }

    /// Bytes of GPU memory of the shared buffers (every slot's frame uniforms, control
    /// positions and vertex limit frames; the capture).
    pub fn memory_bytes(&self) -> u64 {
        self.slots
            .iter()
            .flat_map(|s| s.buffers())
            .map(|b| b.size())
            .sum::<u64>()
            + self.captures.iter().map(|b| b.size()).sum::<u64>()
            + self.texcoords.size()
    }

    /// Number of control vertices.
    pub fn vertex_count(&self) -> usize {
        self.vertex_count
    }

    /// Writes the frame uniform block of `slot` (the GPU must be done with that slot).
    pub fn write_frame(&mut self, slot: usize, bytes: &[u8]) -> Result<()> {
        self.slots[slot].frame.write(0, bytes)
    }

    /// Animation: new control positions and their limit frames, kept on the host until each
    /// slot is prepared ([`Self::sync`]).
    pub fn stage(&mut self, positions: &[DVec3], frames: &VertexFrames) -> Result<()> {
        if positions.len() != self.vertex_count {
            return Err(Error::Invalid(format!(
                "update_positions: got {} positions, the surface has {} vertices",
                positions.len(),
                self.vertex_count
            )));
        }
        self.staged = Staged {
            positions: vec3_bytes(positions),
            limits: vec4_bytes(&frames.limits),
            normals: frames.normal_bytes(),
            version: self.staged.version + 1,
        };
        Ok(())
    }

    /// Brings `slot` to the latest staged positions if it holds older ones (the GPU must be
    /// done with that slot). Returns whether it wrote.
    pub fn sync(&mut self, slot: usize) -> Result<bool> {
        let st = &self.staged;
        let s = &mut self.slots[slot];
        if s.version == st.version {
            return Ok(false);
        }
        s.positions.write(0, &st.positions)?;
        s.vertex_limits.write(0, &st.limits)?;
        s.vertex_normals.write(0, &st.normals)?;
        s.version = st.version;
        Ok(true)
    }

    /// The capture buffer frame slot `slot` binds.
    fn capture(&self, slot: usize) -> &Buffer {
        &self.captures[slot.min(self.captures.len() - 1)]
    }

    /// Resets the capture counter of frame slot `slot` (host write; the GPU must be done with
    /// that slot).
    pub fn reset_capture(&mut self, slot: usize) -> Result<()> {
        let k = slot.min(self.captures.len() - 1);
        let capture = self.capture.unwrap_or(Capture::TesPoints(0));
        reset_capture(&mut self.captures[k], capture)
    }

    /// The TES invocations captured by the frame that last used slot `slot` (it must have
    /// finished), in draw order.
    pub fn read_capture(&self, slot: usize) -> Result<Vec<CaptureRecord>> {
        let Some(Capture::TesPoints(capacity)) = self.capture else {
            return Err(Error::Invalid(
                "TES capture is not enabled in RenderDesc (capture_capacity)".into(),
            ));
        };
        decode_capture(&self.captured_words(slot)?, capacity)
    }

    /// The triangles captured by the frame that last used slot `slot` (it must have finished),
    /// in no particular order.
    pub fn read_triangles(&self, slot: usize) -> Result<Vec<CapturedTriangle>> {
        self.triangle_capture()?;
        decode_triangles(&self.captured_words(slot)?)
    }

    /// Triangles the frame that last used slot `slot` drew (counted past the capacity too).
    pub fn triangles_drawn(&self, slot: usize) -> Result<u32> {
        self.triangle_capture()?;
        Ok(self.captured_words(slot)?[0])
    }

    /// What the triangle capture of the frame that last used slot `slot` saw (it must have
    /// finished): its count, its bucket counts and the triangles of the stored buckets
    /// ([`Self::set_triangle_buckets`]).
    pub fn read_triangle_window(&self, slot: usize) -> Result<TriangleWindow> {
        self.triangle_capture()?;
        Ok(decode_triangle_window(&self.captured_words(slot)?))
    }

    /// The bucket modulus and the stored bucket range `first..end` of every frame slot's
    /// triangle capture (host write; the GPU must be done with every slot).
    pub fn set_triangle_buckets(&mut self, buckets: u32, first: u32, end: u32) -> Result<()> {
        self.triangle_capture()?;
        self.captures
            .iter_mut()
            .try_for_each(|b| set_triangle_buckets(b, buckets, first, end))
    }

    fn triangle_capture(&self) -> Result<()> {
        match self.capture {
            Some(Capture::Triangles(_)) => Ok(()),
            _ => Err(Error::Invalid(
                "triangle capture is not enabled in RenderDesc (capture_triangles)".into(),
            )),
        }
    }

    /// The words of frame slot `slot`'s capture buffer.
    fn captured_words(&self, slot: usize) -> Result<Vec<u32>> {
        if slot >= self.slots.len() {
            return Err(Error::Invalid(format!(
                "read_capture: frame slot {slot} of {}",
                self.slots.len()
            )));
        }
        self.capture(slot).read::<u32>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Without `geometryShader` no layout may name the geometry stage: set 0 leaves it out, and
    /// only the capture binding of a triangle-capturing pipeline gains it.
    #[test]
    fn geometry_stage_only_where_triangles_are_captured() {
        let geometry = |b: &DescriptorBinding| b.stages.contains(vk::ShaderStageFlags::GEOMETRY);
        let set0 = set0_layout(&[1, 4]);
        assert!(!set0.iter().any(geometry));
        let captured = with_geometry_capture(vec![set0.clone(), vec![storage_binding(0)]]);
        for (a, b) in set0.iter().zip(&captured[0]) {
            assert_eq!(
                geometry(b),
                a.binding == CAPTURE_BINDING,
                "binding {}",
                a.binding
            );
            assert_eq!(a.stages | b.stages, b.stages);
        }
        assert!(!captured[1].iter().any(geometry));
    }
}
