//! GPU timings of the Gregory pass alone, per construction variant (the paper's Table 1:
//! construction + evaluation of every irregular patch at uniform levels), and of the regular
//! B-spline pass drawn with it.

use super::session::{GregorySession, GregoryVariant, SessionOptions};
use crate::gpu::Context;
use crate::mesh::ControlMesh;
use crate::render::renderer::RenderDesc;
use crate::render::settings::TessSettings;
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

fn median(v: &mut [f64]) -> f64 {
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
/// splitting above `max_patch_level` as the renderer does.
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
