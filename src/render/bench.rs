//! GPU timings of the Gregory pass alone, per construction variant (the paper's Table 1:
//! construction + evaluation of every irregular patch at uniform levels), of the same faces on
//! the exact CPU path, and of the regular B-spline pass. Each pass is timed in a frame of its own:
//! lavapipe's timestamps do not attribute work to passes within one render pass.

use std::time::Instant;

use super::session::{GregorySession, GregoryVariant, SessionOptions};
use crate::gpu::Context;
use crate::mesh::ControlMesh;
use crate::render::fallback::FallbackFace;
use crate::render::offscreen::CPU_PATH_LABEL;
use crate::render::offscreen::{OffscreenDesc, OffscreenSession};
use crate::render::plan::{cpu_faces, plan_for_scheme};
use crate::render::renderer::RenderDesc;
use crate::render::schemes::{Scheme, SchemeLimits};
use crate::render::settings::TessSettings;
use crate::render::surface::SurfaceData;
use crate::topology::Topology;
use crate::{Error, Result};

/// One uniform level of [`bench_gregory`].
#[derive(Debug, Clone, PartialEq)]
pub struct GregoryBenchRow {
    /// Requested uniform level (clamped by the device).
    pub level: f32,
    /// Gregory patches drawn.
    pub gregory_patches: usize,
    /// Regular patches drawn.
    pub regular_patches: usize,
    /// TES invocations of the Gregory pass.
    pub tes_invocations: u64,
    /// Median GPU milliseconds of the Gregory pass (TCS construction + TES evaluation).
    pub gregory_ms: f64,
    /// Median GPU milliseconds of the regular pass.
    pub regular_ms: f64,
}

/// Median of `v` (sorted in place); 0 when empty.
pub fn median(v: &mut [f64]) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    let n = v.len();
    if n == 0 {
        0.0
    } else if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Times `frames` frames (after one warm-up frame) of the Gregory pass of `mesh` with
/// `variant` (plus its regular pass when `with_regular`) at each uniform level; sub-patch
/// splitting above `max_patch_level`, lowered to the pass's own limit as the renderer does
/// ([`crate::render::TessSettings::resolve`]).
#[allow(clippy::too_many_arguments)]
pub fn bench_gregory(
    ctx: &Context,
    mesh: &ControlMesh,
    variant: GregoryVariant,
    with_regular: bool,
    levels: &[f32],
    frames: u32,
    size: (u32, u32),
    max_patch_level: f32,
) -> Result<Vec<GregoryBenchRow>> {
    if frames == 0 {
        return Err(Error::Invalid("bench: at least one frame".into()));
    }
    let max = ctx.info().limits.max_tessellation_generation_level as f32;
    let mut rows = Vec::new();
    for &level in levels {
        let desc = RenderDesc {
            tess: TessSettings {
                level: level.clamp(1.0, max),
                max_patch_level,
                ..TessSettings::default()
            },
            ..RenderDesc::default()
        };
        let opts = SessionOptions {
            variant,
            with_regular,
            width: size.0,
            height: size.1,
        };
        let mut s = GregorySession::new(ctx, mesh, &desc, &opts)?;
        s.frame()?;
        let (mut g, mut r) = (Vec::new(), Vec::new());
        let mut tes = 0;
        for _ in 0..frames {
            let rep = s.frame()?;
            g.push(rep.gregory_ms);
            r.push(rep.regular_ms);
            tes = rep.gregory_stats.tes_invocations;
        }
        rows.push(GregoryBenchRow {
            level: desc.tess.level,
            gregory_patches: s.gregory_faces().len(),
            regular_patches: s.regular_count(),
            tes_invocations: tes,
            gregory_ms: median(&mut g),
            regular_ms: median(&mut r),
        });
    }
    Ok(rows)
}

/// One uniform level of [`bench_paths`]: the same Gregory faces drawn every way, and the
/// regular faces' B-spline pass.
#[derive(Debug, Clone, PartialEq)]
pub struct PathsBenchRow {
    /// Uniform level.
    pub level: f32,
    /// Faces the stencil variant draws.
    pub gregory_patches: usize,
    /// Faces the two-stage variant draws (differs where a valence or ring exceeds its limit).
    pub two_stage_patches: usize,
    /// TES invocations of the Gregory pass.
    pub tes_invocations: u64,
    /// Median GPU ms, stencil variant (§4.3).
    pub stencil_ms: f64,
    /// Median GPU ms, two-stage variant (§4.1-4.2).
    pub two_stage_ms: f64,
    /// Wall-clock ms to evaluate the same faces exactly on the CPU at this level (once per
    /// frame when animating).
    pub cpu_eval_ms: f64,
    /// Median GPU ms to draw the CPU-evaluated triangles.
    pub cpu_draw_ms: f64,
    /// Regular B-spline patches of the mesh.
    pub regular_patches: usize,
    /// Median GPU ms of the regular pass alone.
    pub regular_ms: f64,
}

/// Median GPU ms of the passes labelled `label` over `frames` frames of `session`, after one
/// warm-up frame.
pub(crate) fn timed_frames(
    session: &mut OffscreenSession,
    frames: u32,
    label: &str,
) -> Result<f64> {
    session.frame()?;
    let mut v = Vec::new();
    for _ in 0..frames {
        let r = session
            .frame()?
            .ok_or_else(|| Error::Invalid("bench: no timings returned".into()))?;
        v.push(r.ms(label));
    }
    Ok(median(&mut v))
}

/// For each level: the Gregory pass alone with both variants (the faces both take), the same
/// faces on the exact CPU path (evaluation wall-clock + GPU draw), and the regular pass alone.
pub fn bench_paths(
    ctx: &Context,
    mesh: &ControlMesh,
    levels: &[f32],
    frames: u32,
    size: (u32, u32),
    max_patch_level: f32,
) -> Result<Vec<PathsBenchRow>> {
    let topo = Topology::new(mesh)?;
    let mut regular = plan_for_scheme(mesh, Scheme::BsplineOnly, &SchemeLimits::from_context(ctx))?;
    regular.fallback_faces.clear();
    let regular_patches = regular.regular_patches().len();
    let off = OffscreenDesc {
        width: size.0,
        height: size.1,
        ..OffscreenDesc::default()
    };
    let mut rows = Vec::new();
    for &level in levels {
        let alone = |variant| {
            bench_gregory(
                ctx,
                mesh,
                variant,
                false,
                &[level],
                frames,
                size,
                max_patch_level,
            )
        };
        let (stencil, two) = (
            alone(GregoryVariant::Stencil)?,
            alone(GregoryVariant::TwoStage)?,
        );
        let (s, t) = (&stencil[0], &two[0]);
        let render = RenderDesc {
            tess: TessSettings {
                level: s.level,
                max_patch_level,
                ..TessSettings::default()
            },
            ..RenderDesc::default()
        };
        // The stencil session's faces, on the CPU path.
        let opts = SessionOptions {
            variant: GregoryVariant::Stencil,
            with_regular: false,
            width: 16,
            height: 16,
        };
        let faces: Vec<FallbackFace> = GregorySession::new(ctx, mesh, &render, &opts)?
            .gregory_faces()
            .iter()
            .map(|&f| FallbackFace::new(f, topo.face_size(f) as u32))
            .collect();
        let t0 = Instant::now();
        let fallback = cpu_faces(mesh, &faces, s.level.ceil() as u32)?;
        let cpu_eval_ms = t0.elapsed().as_secs_f64() * 1e3;
        let cpu_surface = SurfaceData {
            positions: mesh.positions().to_vec(),
            fallback_faces: faces,
            fallback,
            ..SurfaceData::default()
        };
        let mut cpu = OffscreenSession::new(ctx, &cpu_surface, &render, &off, true)?;
        let cpu_draw_ms = timed_frames(&mut cpu, frames, CPU_PATH_LABEL)?;
        let regular_ms = if regular_patches == 0 {
            0.0
        } else {
            let mut reg = OffscreenSession::new(ctx, &regular, &render, &off, true)?;
            timed_frames(&mut reg, frames, "bspline patches")?
        };
        rows.push(PathsBenchRow {
            level: s.level,
            gregory_patches: s.gregory_patches,
            two_stage_patches: t.gregory_patches,
            tes_invocations: s.tes_invocations,
            stencil_ms: s.gregory_ms,
            two_stage_ms: t.gregory_ms,
            cpu_eval_ms,
            cpu_draw_ms,
            regular_patches,
            regular_ms,
        });
    }
    Ok(rows)
}
