//! `tessera bench --crease-sharpness S1,S2,...`: the paper's Fig. 2 (Nießner, Loop, Greiner
//! 2012): GPU milliseconds per frame and GPU memory of the patch data of `--scheme adaptive` at
//! one tessellation level while every crease tag is set to each sharpness, with single-crease
//! patches and without (refining the creases instead), as a table and optionally a PNG plot.

use std::path::Path;

use super::glyphs::{draw_text, fill};
use image::{Rgb, RgbImage};
use tessera::gpu::Context;
use tessera::mesh::ControlMesh;
use tessera::render::bench::median;
use tessera::render::schemes::adaptive::AdaptiveTables;
use tessera::render::{
    OffscreenDesc, OffscreenSession, RenderDesc, SurfaceData, TessSettings, CPU_PATH_LABEL,
};
use tessera::{Error, Result};

use super::render::surface_for;

/// What the sweep measures at one sharpness, with or without single-crease patches.
#[derive(Debug, Clone, Copy)]
pub struct SweepRow {
    /// Crease sharpness.
    pub sharpness: f32,
    /// Single-crease patches on.
    pub single_crease: bool,
    /// Patch primitives drawn.
    pub patches: usize,
    /// Median GPU ms per frame (refinement, derived points and patch draws).
    pub frame_ms: f64,
    /// GPU memory of the patch data ([`AdaptiveTables::gpu_memory_bytes`]).
    pub bytes: usize,
}

/// The sweep's settings.
pub struct Sweep<'a> {
    /// Sharpness values.
    pub sharpness: &'a [f32],
    /// Uniform tessellation level.
    pub level: f32,
    /// Isolation level.
    pub isolation: u32,
    /// Timed frames per configuration.
    pub frames: u32,
    /// Image size.
    pub size: (u32, u32),
}

/// Runs the sweep on `mesh` and prints one row per configuration.
pub fn run(ctx: &Context, mesh: &ControlMesh, sweep: &Sweep<'_>) -> Result<Vec<SweepRow>> {
    println!(
        "{:>9} {:>13} {:>9} {:>14} {:>12}",
        "sharpness", "single-crease", "patches", "frame ms (med)", "patch MB"
    );
    let mut rows = Vec::new();
    for &s in sweep.sharpness {
        let mut m = mesh.clone();
        m.set_crease_sharpness(s)?;
        for single_crease in [true, false] {
            let surface = surface_for(
                ctx,
                &m,
                sweep.level,
                tessera::render::Scheme::Adaptive,
                &super::render::AdaptiveArgs {
                    isolation: sweep.isolation,
                    single_crease,
                    gregory_tangents: Default::default(),
                    end_cap_sharpness: Default::default(),
                    lattice_normals: tessera::render::PlanOptions::DEFAULT_LATTICE_NORMALS,
                    pm_crease_scalar: None,
                },
            )?;
            let tables = surface.parts[0]
                .as_any()
                .downcast_ref::<AdaptiveTables>()
                .ok_or_else(|| Error::Invalid("bench: no adaptive tables".into()))?;
            let row = SweepRow {
                sharpness: s,
                single_crease,
                patches: tables.primitive_count(),
                frame_ms: frame_ms(ctx, &surface, sweep)?,
                bytes: tables.gpu_memory_bytes(),
            };
            println!(
                "{:>9} {:>13} {:>9} {:>14.3} {:>12.3}",
                row.sharpness,
                row.single_crease,
                row.patches,
                row.frame_ms,
                row.bytes as f64 / 1e6
            );
            rows.push(row);
        }
    }
    Ok(rows)
}

/// Median GPU ms per frame of `surface` (after one warm-up frame).
fn frame_ms(ctx: &Context, surface: &SurfaceData, sweep: &Sweep<'_>) -> Result<f64> {
    let render = RenderDesc {
        tess: TessSettings {
            level: sweep.level,
            ..TessSettings::default()
        },
        ..RenderDesc::default()
    };
    let desc = OffscreenDesc {
        width: sweep.size.0,
        height: sweep.size.1,
        ..OffscreenDesc::default()
    };
    let mut session = OffscreenSession::new(ctx, surface, &render, &desc, true)?;
    session.frame()?;
    let mut total = Vec::new();
    for _ in 0..sweep.frames {
        let r = session
            .frame()?
            .ok_or_else(|| Error::Invalid("bench: no timings returned".into()))?;
        total.push(r.patch_ms() + r.ms(CPU_PATH_LABEL));
    }
    Ok(median(&mut total))
}

/// Series colours: with single-crease patches (teal, as `--color-by patch-type`), without
/// (orange).
const COLORS: [Rgb<u8>; 2] = [Rgb([40, 160, 170]), Rgb([230, 120, 30])];

/// Axis labels in the CLI's 3x5 font.
fn label(img: &mut RgbImage, x: i64, y: i64, text: &str, scale: i64) {
    draw_text(img, x, y, text, scale, Rgb([40; 3]));
}

/// A thick line from a to b.
fn line(img: &mut RgbImage, a: (f64, f64), b: (f64, f64), c: Rgb<u8>) {
    let n = ((b.0 - a.0).abs().max((b.1 - a.1).abs()) as usize).max(1);
    for k in 0..=n {
        let t = k as f64 / n as f64;
        let (x, y) = (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1));
        fill(img, x as i64 - 1, y as i64 - 1, 3, 3, c);
    }
}

/// Writes the Fig. 2 plot: two panels over the sharpness axis, frame ms (left) and patch-data
/// MB (right), one line per series (teal: single-crease patches, orange: without), y axes from 0
/// with the maximum written at the top, x ticks at every sharpness.
pub fn plot(rows: &[SweepRow], path: &Path) -> Result<()> {
    let (w, h) = (1000u32, 420u32);
    let mut img = RgbImage::from_pixel(w, h, Rgb([255; 3]));
    let values: [fn(&SweepRow) -> f64; 2] = [|r| r.frame_ms, |r| r.bytes as f64 / 1e6];
    let s_min = rows
        .iter()
        .map(|r| r.sharpness)
        .fold(f32::INFINITY, f32::min) as f64;
    let s_max = rows.iter().map(|r| r.sharpness).fold(0.0, f32::max) as f64;
    for (panel, value) in values.iter().enumerate() {
        let (x0, y0, pw, ph) = (60.0 + 500.0 * panel as f64, 30.0, 400.0, 330.0);
        let y_max = rows.iter().map(value).fold(0.0, f64::max) * 1.1;
        let to = |s: f64, v: f64| {
            let x = x0 + pw * (s - s_min) / (s_max - s_min).max(1e-9);
            (x, y0 + ph - ph * v / y_max.max(1e-12))
        };
        line(&mut img, (x0, y0), (x0, y0 + ph), Rgb([40; 3]));
        line(&mut img, (x0, y0 + ph), (x0 + pw, y0 + ph), Rgb([40; 3]));
        label(
            &mut img,
            x0 as i64 - 50,
            y0 as i64,
            &format!("{:.1}", y_max),
            3,
        );
        label(&mut img, x0 as i64 - 20, (y0 + ph) as i64 - 15, "0", 3);
        let mut ticks: Vec<f64> = rows.iter().map(|r| f64::from(r.sharpness)).collect();
        ticks.dedup();
        for s in ticks {
            let (x, y) = to(s, 0.0);
            line(&mut img, (x, y), (x, y + 6.0), Rgb([40; 3]));
            label(&mut img, x as i64 - 4, y as i64 + 12, &format!("{s}"), 2);
        }
        for (series, color) in [true, false].into_iter().zip(COLORS) {
            let pts: Vec<(f64, f64)> = rows
                .iter()
                .filter(|r| r.single_crease == series)
                .map(|r| to(f64::from(r.sharpness), value(r)))
                .collect();
            for p in pts.windows(2) {
                line(&mut img, p[0], p[1], color);
            }
            for p in pts {
                fill(&mut img, p.0 as i64 - 4, p.1 as i64 - 4, 9, 9, color);
            }
        }
    }
    img.save(path)
        .map_err(|e| Error::Invalid(format!("--plot {}: {e}", path.display())))
}
