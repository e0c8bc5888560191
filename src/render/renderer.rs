//! [`SurfaceRenderer`]: the GPU passes of one surface over shared buffers, recorded into the
//! caller's command buffer (compute pre-passes before its render pass, draws inside it).

use std::sync::Arc;

use ash::vk;
use glam::DVec3;

use super::cpu_path::CpuPathPass;
use super::fallback::FallbackMesh;
use super::pass::{CaptureRecord, SharedResources, VertexFrames};
use super::schemes::adaptive::ADAPTIVE;
use super::schemes::single_crease::SingleCreaseTables;
use super::schemes::PatchScheme as _;
use super::schemes::{PassContext, PassTables, PatchPass};
pub use super::settings::RenderDesc;
use super::settings::{FrameUniforms, TessSettings};
use super::surface::{vertex_frames, SurfaceData};
use crate::gpu::{Context, Feature, TargetFormat};
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
    tess.resolve(device_max_level, &limits)
}

/// GPU buffer memory of a [`SurfaceRenderer`], in bytes.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct MemoryReport {
    /// Shared buffers: frame uniforms, control positions, vertex limit frames, capture.
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

/// GPU resources of one surface plus its pipelines for one render-target format.
pub struct SurfaceRenderer {
    ctx: Context,
    desc: RenderDesc,
    topology: Option<Arc<Topology>>,
    positions: Vec<DVec3>,
    parts: Vec<Arc<dyn PassTables>>,
    shared: SharedResources,
    passes: Vec<Box<dyn PatchPass>>,
    cpu_path: CpuPathPass,
}

impl SurfaceRenderer {
    /// Uploads `surface`, creates every pass and the pipelines for render targets of format
    /// `target`. The tessellation settings are resolved here, once.
    pub fn new(
        ctx: &Context,
        surface: &SurfaceData,
        desc: &RenderDesc,
        target: TargetFormat,
    ) -> Result<SurfaceRenderer> {
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
        let frames = surface.vertex_frames(&surface.positions);
        let shared = SharedResources::new(ctx, &surface.positions, &frames, desc.capture_capacity)?;
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
            topology: surface.topology.clone(),
            positions: surface.positions.clone(),
            parts: surface.parts.clone(),
            shared,
            passes,
            cpu_path,
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
        self.shared.update(positions, &frames)?;
        for p in &mut self.passes {
            p.update_positions(positions, &frames)?;
        }
        if let Some(mesh) = fallback {
            self.cpu_path.update(mesh)?;
        }
        self.positions = positions.to_vec();
        Ok(())
    }

    /// Run-time crease sharpness: sets each edge (`v0`, `v1`) of `creases` to its `sharpness`
    /// on the single-crease patches (their per-patch sharpness and the limit frames of their
    /// corners), without re-planning. Errors, changing nothing, when the surface has no
    /// single-crease patches or the change leaves what they cover
    /// ([`SingleCreaseTables::with_sharpness`]: the new sharpness must be in `0 < s < 10`, every
    /// face around the edge's end vertices a single-crease patch keeping one sharpness along its
    /// crease line). Call only while no submitted frame that uses this renderer is executing.
    pub fn set_sharpness(&mut self, creases: &[Crease]) -> Result<()> {
        let Some((i, tables)) = self.parts.iter().enumerate().find_map(|(i, p)| {
            p.as_any()
                .downcast_ref::<SingleCreaseTables>()
                .map(|t| (i, t))
        }) else {
            if self.parts.iter().any(|p| p.pass_name() == ADAPTIVE.name()) {
                // The adaptive scheme's refinement kernels bake the crease rules (and the
                // sharpness decides which faces are refined), so new sharpness is a new plan.
                return Err(Error::Invalid(
                    "set_sharpness: --scheme adaptive bakes the sharpness into its refinement \
                     tables and patch layout; plan the surface again with the new creases"
                        .into(),
                ));
            }
            return Err(Error::Invalid(
                "set_sharpness: the surface has no single-crease patches (plan it again with the \
                 new creases)"
                    .into(),
            ));
        };
        let tables: Arc<dyn PassTables> = Arc::new(tables.with_sharpness(creases)?);
        self.passes[i].update_tables(tables.as_ref())?;
        self.parts[i] = tables;
        let frames = vertex_frames(self.topology.as_deref(), &self.parts, &self.positions);
        self.shared.update(&self.positions, &frames)?;
        log::debug!("set_sharpness: {} crease edges changed", creases.len());
        Ok(())
    }

    /// Writes the frame uniforms with the renderer's tessellation settings. Call before
    /// submitting the command buffer that [`Self::record`] filled, while no earlier frame of
    /// this renderer is still executing.
    pub fn set_frame(&mut self, frame: &FrameUniforms) -> Result<()> {
        let max_level = self.ctx.info().limits.max_tessellation_generation_level as f32;
        self.shared
            .write_frame(&frame.to_bytes(&self.desc.tess, max_level))
    }

    /// Records every pass's pre-pass work (outside a render pass, before [`Self::record`]).
    pub fn record_compute(&self, cmd: vk::CommandBuffer) {
        for p in &self.passes {
            p.record_compute(cmd);
        }
    }

    /// Records the tessellated draws of every pass, in order (inside the caller's render pass).
    pub fn record_patches(&self, cmd: vk::CommandBuffer) {
        for p in &self.passes {
            p.record(cmd);
        }
    }

    /// Records the CPU-evaluated triangles (inside the caller's render pass).
    pub fn record_fallback(&self, cmd: vk::CommandBuffer) {
        self.cpu_path.record(cmd);
    }

    /// Records every draw (patches, then CPU-evaluated triangles) inside the caller's render
    /// pass; call [`Self::record_compute`] before the render pass begins.
    pub fn record(&self, cmd: vk::CommandBuffer) {
        self.record_patches(cmd);
        self.record_fallback(cmd);
    }

    /// Resets the capture counter (host write; call between frames, before submitting).
    pub fn reset_capture(&mut self) -> Result<()> {
        self.shared.reset_capture()
    }

    /// Reads the captured TES invocations of the last finished frame, in draw order. Errors if
    /// the capture buffer overflowed (more invocations than its capacity) or capture is off.
    pub fn read_capture(&self) -> Result<Vec<CaptureRecord>> {
        self.shared.read_capture()
    }
}
