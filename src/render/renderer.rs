//! [`SurfaceRenderer`]: the GPU passes of one surface over shared buffers, recorded into the
//! caller's command buffer (compute pre-passes before its render pass, draws inside it).

use std::sync::Arc;

use ash::vk;
use glam::DVec3;

use super::cpu_path::CpuPathPass;
use super::fallback::FallbackMesh;
use super::pass::{
    Capture, CaptureRecord, CapturedTriangle, SharedResources, TriangleWindow, VertexFrames,
};
use super::schemes::adaptive::AdaptiveTables;
use super::schemes::single_crease::SingleCreaseTables;
use super::schemes::{PassContext, PassTables, PatchPass};
pub use super::settings::RenderDesc;
use super::settings::{Displacement, FrameFlags, FrameUniforms, TessMode, TessSettings};
use super::surface::{vertex_frames, SurfaceData};
use crate::gpu::{Context, DrawTarget, Feature, TargetFormat};
use crate::mesh::Crease;
use crate::topology::Topology;
use crate::{Error, Result};

/// The tessellation settings a [`SurfaceRenderer`] for `surface` on `ctx`'s device uses for the
/// requested `tess` ([`TessSettings::resolve`] against the device's largest level and every
/// pass's [`crate::render::schemes::PatchLevelLimit`]). Size capture buffers with it
/// ([`crate::render::pass::capture_capacity_for`]).
pub fn resolve_tess(ctx: &Context, surface: &SurfaceData, tess: &TessSettings) -> TessSettings {
    resolve_tess_for(
        ctx.info().limits.max_tessellation_generation_level as f32,
        surface,
        tess,
    )
}

/// As [`resolve_tess`] for a device whose largest tessellation level is `device_max_level`.
pub fn resolve_tess_for(
    device_max_level: f32,
    surface: &SurfaceData,
    tess: &TessSettings,
) -> TessSettings {
    let limits: Vec<_> = surface
        .parts
        .iter()
        .map(|p| p.patch_level_limit(tess.spacing))
        .collect();
    let mut t = tess.resolve(device_max_level, &limits);
    if t.mode == TessMode::Distance && !(t.distance > 0.0 && t.distance.is_finite()) {
        let (lo, hi) = surface.bounding_box();
        t.distance = (hi - lo).length().max(f64::from(f32::MIN_POSITIVE)) as f32;
    }
    t
}

/// Most frames in flight a renderer keeps slots for.
pub const MAX_FRAMES_IN_FLIGHT: u32 = 4;

/// GPU buffer memory of a [`SurfaceRenderer`], in bytes.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct MemoryReport {
    /// Shared buffers: frame uniforms, control positions, vertex limit frames, capture (one per
    /// frame slot when capture is on).
    pub shared: u64,
    /// Each pass's own buffers, by label, in draw order.
    pub passes: Vec<(String, u64)>,
    /// CPU-evaluated triangles' vertex and index buffers.
    pub cpu_path: u64,
}

impl MemoryReport {
    /// Every buffer together.
    pub fn total(&self) -> u64 {
        self.shared + self.cpu_path + self.passes.iter().map(|(_, b)| b).sum::<u64>()
    }

    /// The passes' own buffers together.
    pub fn passes_total(&self) -> u64 {
        self.passes.iter().map(|(_, b)| b).sum()
    }
}

/// How a [`SurfaceRenderer`] fits into the caller's frame loop.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct EngineDesc {
    /// The rendering tessera draws into: formats, render pass or dynamic rendering, descriptor
    /// set and push-constant slots.
    pub target: DrawTarget,
    /// Frames the caller keeps in flight (1-3 typical): the renderer holds that many copies
    /// of its host-written buffers, so preparing one frame never touches another's.
    pub frames_in_flight: u32,
}

impl From<TargetFormat> for EngineDesc {
    /// tessera's own render pass for `target`, one frame in flight.
    fn from(target: TargetFormat) -> EngineDesc {
        EngineDesc {
            target: target.into(),
            frames_in_flight: 1,
        }
    }
}

/// GPU resources of one surface plus its pipelines for one render-target format.
///
/// Frames in flight ([`EngineDesc::frames_in_flight`] = N): each [`Self::set_frame`] prepares
/// the next of N frame slots (frame uniforms, control positions, limit frames, CPU-path
/// triangles) and the following [`Self::record_compute`] / [`Self::record`] use that slot. The
/// caller guarantees, with its own fences, that the frame which last used the slot (N frames
/// back) has finished before calling `set_frame`; frames N-1 back may still execute.
///
/// Dropping is safe on every path and never panics: it waits for the device (the caller's
/// frames may still read the buffers; a failed wait, e.g. a lost device, is logged and the
/// resources are destroyed anyway, as Vulkan allows after device loss), then each buffer,
/// image and pool follows the context's rule after a timed-out submission ([`Context`]).
pub struct SurfaceRenderer {
    ctx: Context,
    desc: RenderDesc,
    /// Frame slot of the frame being prepared and recorded; the next `set_frame` takes the next.
    slot: usize,
    next_slot: usize,
    topology: Option<Arc<Topology>>,
    positions: Vec<DVec3>,
    parts: Vec<Arc<dyn PassTables>>,
    shared: SharedResources,
    passes: Vec<Box<dyn PatchPass>>,
    cpu_path: CpuPathPass,
    /// The surface has texture coordinates (`Frame.flags.z`).
    texcoords: bool,
}

impl SurfaceRenderer {
    /// Uploads `surface`, creates every pass and the pipelines for render targets of format
    /// `target` (tessera's render pass, one frame in flight). The tessellation settings are
    /// resolved here, once.
    pub fn new(
        ctx: &Context,
        surface: &SurfaceData,
        desc: &RenderDesc,
        target: TargetFormat,
    ) -> Result<SurfaceRenderer> {
        Self::for_engine(ctx, surface, desc, &target.into())
    }

    /// As [`Self::new`], drawing into the caller's rendering with its frames in flight
    /// ([`EngineDesc`]).
    pub fn for_engine(
        ctx: &Context,
        surface: &SurfaceData,
        desc: &RenderDesc,
        engine: &EngineDesc,
    ) -> Result<SurfaceRenderer> {
        if !(1..=MAX_FRAMES_IN_FLIGHT).contains(&engine.frames_in_flight) {
            return Err(Error::Invalid(format!(
                "frames_in_flight {} is outside 1..={MAX_FRAMES_IN_FLIGHT}",
                engine.frames_in_flight
            )));
        }
        let target = &engine.target;
        let mut desc = *desc;
        desc.tess = resolve_tess(ctx, surface, &desc.tess);
        if desc.wireframe {
            ctx.require(&[Feature::FillModeNonSolid])?;
        }
        if !surface.parts.is_empty() {
            ctx.require(&[Feature::TessellationShader])?;
        }
        if desc.capture_capacity.is_some() {
            ctx.require(&[Feature::VertexPipelineStoresAndAtomics])?;
        }
        let capture =
            match (desc.capture_capacity, desc.capture_triangles) {
                (Some(_), Some(_)) => return Err(Error::Invalid(
                    "RenderDesc: capture_capacity (TES points) and capture_triangles are exclusive"
                        .into(),
                )),
                (Some(c), None) => Some(Capture::TesPoints(c)),
                (None, Some(c)) => {
                    ctx.require(&[
                        Feature::GeometryShader,
                        Feature::VertexPipelineStoresAndAtomics,
                    ])?;
                    Some(Capture::Triangles(c))
                }
                (None, None) => None,
            };
        let map = match desc.displacement {
            Displacement::Map { .. } => {
                let Some(map) = surface.displacement_map.as_deref() else {
                    return Err(Error::Invalid(
                        "Displacement::Map without a map: give the surface one with SurfaceData::set_displacement_map".into(),
                    ));
                };
                if surface.texcoords.is_none() || surface.topology.is_none() {
                    return Err(Error::MissingTexCoords {
                        map: map.source().to_string(),
                    });
                }
                Some(map)
            }
            _ => None,
        };
        let frames = surface.vertex_frames(&surface.positions);
        let shared = SharedResources::new(
            ctx,
            &surface.positions,
            &frames,
            capture,
            engine.frames_in_flight as usize,
            &surface.texcoord_words(),
            map,
        )?;
        let pc = PassContext {
            ctx,
            shared: &shared,
            positions: &surface.positions,
            frames: &frames,
            desc: &desc,
            target,
        };
        let passes = surface
            .parts
            .iter()
            .map(|p| p.create_pass(&pc))
            .collect::<Result<Vec<_>>>()?;
        let cpu_path = CpuPathPass::new(ctx, &surface.fallback, &shared, &desc, target)?;
        Ok(SurfaceRenderer {
            ctx: ctx.clone(),
            desc,
            slot: 0,
            next_slot: 0,
            topology: surface.topology.clone(),
            positions: surface.positions.clone(),
            parts: surface.parts.clone(),
            shared,
            passes,
            cpu_path,
            texcoords: surface.texcoords.is_some() && surface.topology.is_some(),
        })
    }

    /// The render description, its tessellation settings resolved.
    pub fn desc(&self) -> &RenderDesc {
        &self.desc
    }

    /// The tessellation settings in use ([`resolve_tess`]).
    pub fn tess(&self) -> &TessSettings {
        &self.desc.tess
    }

    /// The CPU tables of the passes, in draw order.
    pub fn parts(&self) -> &[Arc<dyn PassTables>] {
        &self.parts
    }

    /// The passes, in draw order.
    pub fn passes(&self) -> &[Box<dyn PatchPass>] {
        &self.passes
    }

    /// Number of patches drawn through the tessellation stages, over every pass.
    pub fn patch_count(&self) -> u32 {
        self.passes.iter().map(|p| p.patch_count()).sum()
    }

    /// GPU buffer memory of the surface: `(shared buffers, each pass's own in draw order, CPU-path
    /// triangles)` in bytes ([`PatchPass::memory_bytes`]).
    pub fn memory_bytes(&self) -> MemoryReport {
        MemoryReport {
            shared: self.shared.memory_bytes(),
            passes: self
                .passes
                .iter()
                .map(|p| (p.label().to_string(), p.memory_bytes()))
                .collect(),
            cpu_path: self.cpu_path.memory_bytes(),
        }
    }

    /// Number of CPU-evaluated triangles.
    pub fn fallback_triangle_count(&self) -> u32 {
        self.cpu_path.triangle_count()
    }

    /// Animation: new control positions (same topology). The vertex limit frames are recomputed
    /// on the CPU, every pass rebuilds its patches on the GPU. `fallback`, when given, replaces
    /// the CPU-evaluated triangles (same count). Call only while no submitted frame that uses
    /// this renderer is still executing.
    pub fn update_positions(
        &mut self,
        positions: &[DVec3],
        fallback: Option<&FallbackMesh>,
    ) -> Result<()> {
        if positions.len() != self.shared.vertex_count() {
            return Err(Error::Invalid(format!(
                "update_positions: got {} positions, the surface has {} vertices",
                positions.len(),
                self.shared.vertex_count()
            )));
        }
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(Error::Invalid(format!(
                "update_positions: vertex {i} has a non-finite coordinate"
            )));
        }
        let frames: VertexFrames = vertex_frames(self.topology.as_deref(), &self.parts, positions);
        self.shared.stage(positions, &frames)?;
        for p in &mut self.passes {
            p.update_positions(positions, &frames)?;
        }
        if let Some(mesh) = fallback {
            self.cpu_path.update(mesh)?;
        }
        self.positions = positions.to_vec();
        if self.shared.slot_count() == 1 {
            // One frame in flight: the caller waited for it, the slot is free now.
            self.sync_slot(0)?;
        }
        Ok(())
    }

    /// Brings frame slot `slot` to the latest positions and CPU-path triangles.
    fn sync_slot(&mut self, slot: usize) -> Result<()> {
        self.shared.sync(slot)?;
        self.cpu_path.sync(slot)
    }

    /// Run-time crease sharpness: sets each edge (`v0`, `v1`) of `creases` to its `sharpness`
    /// without re-planning. Errors, changing nothing, when the change needs a new plan:
    /// - single-crease patches of the Gregory schemes ([`SingleCreaseTables::with_sharpness`]):
    ///   the new sharpness must be in `0 < s < 10` and every face around the edge's end vertices
    ///   a single-crease patch keeping one sharpness along its crease line; only their
    ///   per-patch sharpness and corner frames change;
    /// - `--scheme adaptive` ([`AdaptiveTables::with_sharpness`]): any sharpness (0 removes the
    ///   crease, 10 makes it infinitely sharp) as long as the new refinement has the same layout
    ///   (the same faces refined to the same levels: typically the same integer part of the
    ///   sharpness); the kernels' weights, stencil rows and patch sharpness are rewritten in
    ///   place, which costs a CPU re-tabulation of the surface (the car: about as long as
    ///   planning its adaptive pass) but no GPU allocation or pipeline.
    ///
    /// Call only while no submitted frame that uses this renderer is executing.
    pub fn set_sharpness(&mut self, creases: &[Crease]) -> Result<()> {
        let found = self.parts.iter().enumerate().find_map(|(i, p)| {
            let any = p.as_any();
            let tables: Result<Arc<dyn PassTables>> =
                if let Some(t) = any.downcast_ref::<SingleCreaseTables>() {
                    t.with_sharpness(creases).map(|t| Arc::new(t) as _)
                } else {
                    let t = any.downcast_ref::<AdaptiveTables>()?;
                    t.with_sharpness(creases)
                        .map(|t| Arc::new(t) as _)
                        .map_err(|e| Error::Invalid(format!("set_sharpness: {e}")))
                };
            Some((i, tables))
        });
        let Some((i, tables)) = found else {
            return Err(Error::Invalid(
                "set_sharpness: the surface has no single-crease or adaptive patches (plan it \
                 again with the new creases)"
                    .into(),
            ));
        };
        let tables = tables?;
        self.passes[i]
            .update_tables(tables.as_ref())
            .map_err(|e| Error::Invalid(format!("set_sharpness: {e}")))?;
        if let Some(t) = tables.as_any().downcast_ref::<AdaptiveTables>() {
            // Every face is the adaptive pass's: the surface's topology is its base level.
            self.topology = Some(Arc::new(t.adaptive.levels[0].topology().clone()));
        }
        self.parts[i] = tables;
        let frames = vertex_frames(self.topology.as_deref(), &self.parts, &self.positions);
        self.shared.stage(&self.positions, &frames)?;
        for slot in 0..self.shared.slot_count() {
            self.shared.sync(slot)?;
        }
        log::debug!("set_sharpness: {} crease edges changed", creases.len());
        Ok(())
    }

    /// Prepares the next frame: takes the next frame slot, writes its frame uniforms with the
    /// renderer's tessellation settings, brings it to the latest positions and, with capture
    /// on, resets the slot's capture buffer. Call once per frame before recording it, when the
    /// frame that last used this slot ([`EngineDesc::frames_in_flight`] frames back) has
    /// finished; later frames may still run.
    pub fn set_frame(&mut self, frame: &FrameUniforms) -> Result<()> {
        let max_level = self.ctx.info().limits.max_tessellation_generation_level as f32;
        self.slot = self.next_slot;
        self.next_slot = (self.slot + 1) % self.shared.slot_count();
        // Capture measures the whole surface: never cull while the TES captures.
        let flags = FrameFlags {
            cull: self.desc.cull_patches && self.desc.capture_capacity.is_none(),
            texcoords: self.texcoords,
        };
        let bytes = frame.to_bytes(&self.desc.tess, max_level, self.desc.displacement, flags);
        self.shared.write_frame(self.slot, &bytes)?;
        if self.desc.capture_capacity.is_some() || self.desc.capture_triangles.is_some() {
            self.shared.reset_capture(self.slot)?;
        }
        self.sync_slot(self.slot)
    }

    /// The frame slot the last [`Self::set_frame`] prepared (what recording uses).
    pub fn frame_slot(&self) -> usize {
        self.slot
    }

    /// Number of frame slots ([`EngineDesc::frames_in_flight`]).
    pub fn frames_in_flight(&self) -> usize {
        self.shared.slot_count()
    }

    /// Records every pass's pre-pass work (outside a render pass, before [`Self::record`]).
    pub fn record_compute(&self, cmd: vk::CommandBuffer) {
        for p in &self.passes {
            p.record_compute(cmd, self.slot);
        }
    }

    /// Records the tessellated draws of every pass, in order (inside the caller's render pass).
    pub fn record_patches(&self, cmd: vk::CommandBuffer) {
        for p in &self.passes {
            p.record(cmd, self.slot);
        }
    }

    /// Records the CPU-evaluated triangles (inside the caller's render pass).
    pub fn record_fallback(&self, cmd: vk::CommandBuffer) {
        self.cpu_path.record(cmd, self.slot);
    }

    /// Records every draw (patches, then CPU-evaluated triangles) inside the caller's render
    /// pass; call [`Self::record_compute`] before the render pass begins.
    pub fn record(&self, cmd: vk::CommandBuffer) {
        self.record_patches(cmd);
        self.record_fallback(cmd);
    }

    /// Resets the capture counter of the current frame slot (host write; [`Self::set_frame`]
    /// already does; call before submitting, e.g. to record the slot's frame again).
    pub fn reset_capture(&mut self) -> Result<()> {
        self.shared.reset_capture(self.slot)
    }

    /// Reads the TES invocations captured by the frame of the current slot (the last
    /// [`Self::set_frame`]), in draw order, once it has finished. Errors if the capture buffer
    /// overflowed (more invocations than its capacity) or capture is off.
    pub fn read_capture(&self) -> Result<Vec<CaptureRecord>> {
        self.shared.read_capture(self.slot)
    }

    /// Reads the TES invocations captured by the frame that last used frame slot `slot`
    /// ([`Self::frame_slot`] when it was recorded), once it has finished: with frames in
    /// flight every slot has its own capture buffer, so a frame's records stay readable while
    /// the next frames (other slots) run; wait only for that frame's fence.
    pub fn read_capture_slot(&self, slot: usize) -> Result<Vec<CaptureRecord>> {
        self.shared.read_capture(slot)
    }

    /// Reads the triangles captured by the frame of the current slot
    /// ([`RenderDesc::capture_triangles`]) once it has finished. Errors if the frame drew more
    /// than the capacity (the message names both) or triangle capture is off.
    pub fn read_triangles(&self) -> Result<Vec<CapturedTriangle>> {
        self.shared.read_triangles(self.slot)
    }

    /// Triangles the frame of the current slot drew, counted by the triangle capture even past
    /// its capacity (size the capacity with it).
    pub fn triangles_drawn(&self) -> Result<u32> {
        self.shared.triangles_drawn(self.slot)
    }

    /// What the triangle capture of the frame of the current slot saw (its count, its bucket
    /// counts, the triangles of the stored buckets), once it has finished.
    pub fn read_triangle_window(&self) -> Result<TriangleWindow> {
        self.shared.read_triangle_window(self.slot)
    }

    /// Hashes the next frames' triangles into `buckets` buckets (1..=[`super::pass::MAX_BUCKETS`];
    /// [`super::pass::triangle_bucket`]) and stores those of buckets `first..end` (all of 256 at creation):
    /// a frame larger than one capture buffer is read in chunks of buckets, one frame each.
    /// Host write: no frame may be in flight.
    pub fn set_triangle_buckets(&mut self, buckets: u32, first: u32, end: u32) -> Result<()> {
        self.shared.set_triangle_buckets(buckets, first, end)
    }
}

impl Drop for SurfaceRenderer {
    /// Waits for the device to finish (frames the caller submitted may still read the
    /// renderer's buffers) before the buffers are destroyed. A lost device or a failed wait is
    /// logged and the resources are destroyed anyway, which Vulkan allows after device loss.
    fn drop(&mut self) {
        if let Err(e) = self.ctx.wait_idle() {
            log::warn!("dropping a SurfaceRenderer: waiting for the device failed ({e}); destroying its resources anyway");
        }
    }
}
