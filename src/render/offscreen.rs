//! Offscreen rendering: a [`RenderTarget`] plus a [`SurfaceRenderer`], one submission per
//! frame, optional per-pass GPU timings and pipeline statistics, PNG-ready readback.

use glam::DVec3;
use image::RgbaImage;

use super::camera::{Camera, CameraSpec, UpAxis};
use super::renderer::{CaptureRecord, RenderDesc, SurfaceRenderer};
use super::settings::FrameUniforms;
use super::surface::SurfaceData;
use crate::gpu::{tes_writes_to_host, Context, GpuTimer, PipelineStats, RenderTarget, StatsQuery};
use crate::Result;

/// Image size, samples, camera and background of an offscreen frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OffscreenDesc {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// MSAA samples (1 = off).
    pub samples: u32,
    /// Camera placement.
    pub camera: CameraSpec,
    /// World axis that points up on screen.
    pub up: UpAxis,
    /// Background colour (linear RGBA).
    pub clear: [f32; 4],
}

impl Default for OffscreenDesc {
    fn default() -> Self {
        OffscreenDesc {
            width: 512,
            height: 512,
            samples: 1,
            camera: CameraSpec::Auto,
            up: UpAxis::Z,
            clear: [0.02, 0.025, 0.035, 1.0],
        }
    }
}

/// GPU timings and statistics of one frame.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FrameReport {
    /// `(pass, milliseconds)` from timestamp queries.
    pub passes: Vec<(String, f64)>,
    /// Pipeline statistics of the regular-patch pass.
    pub patch_stats: PipelineStats,
}

/// A render target and a surface renderer, reusable across frames (benchmarks, animation).
pub struct OffscreenSession {
    ctx: Context,
    target: RenderTarget,
    renderer: SurfaceRenderer,
    desc: OffscreenDesc,
    camera: Camera,
    timer: Option<GpuTimer>,
    stats: Option<StatsQuery>,
}

/// Direction towards the key light: above, slightly left of and in front of the camera.
fn key_light(cam: &Camera) -> DVec3 {
    let to_eye = (cam.eye - cam.target).normalize();
    let right = cam
        .up
        .cross(to_eye)
        .normalize_or(cam.up.any_orthonormal_vector());
    (to_eye * 0.6 + cam.up * 0.7 - right * 0.4).normalize()
}

impl OffscreenSession {
    /// Creates the target and uploads the surface. `timings` creates the query pools.
    pub fn new(
        ctx: &Context,
        surface: &SurfaceData,
        render: &RenderDesc,
        desc: &OffscreenDesc,
        timings: bool,
    ) -> Result<OffscreenSession> {
        let target = RenderTarget::new(ctx, desc.width, desc.height, desc.samples)?;
        let renderer = SurfaceRenderer::new(ctx, surface, render, target.format())?;
        let (lo, hi) = surface.bounding_box();
        let aspect = f64::from(desc.width) / f64::from(desc.height.max(1));
        // Fit the drawn surface (patch corner limits and CPU-evaluated points, subsampled).
        let mut points: Vec<DVec3> = surface
            .patches
            .iter()
            .flat_map(|p| p.corner_limits(&surface.positions))
            .collect();
        let step = (surface.fallback.positions.len() / 4096).max(1);
        points.extend(surface.fallback.positions.iter().step_by(step));
        points.extend(surface.gregory_points());
        let camera = Camera::frame_oriented(desc.camera, desc.up, lo, hi, &points, aspect);
        let (timer, stats) = if timings {
            (Some(GpuTimer::new(ctx, 2)?), Some(StatsQuery::new(ctx)?))
        } else {
            (None, None)
        };
        Ok(OffscreenSession {
            ctx: ctx.clone(),
            target,
            renderer,
            desc: *desc,
            camera,
            timer,
            stats,
        })
    }

    /// The renderer (for `update_positions`).
    pub fn renderer_mut(&mut self) -> &mut SurfaceRenderer {
        &mut self.renderer
    }

    /// The placed camera.
    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// Renders one frame and waits for it. Returns timings when the session has queries.
    pub fn frame(&mut self) -> Result<Option<FrameReport>> {
        let r = *self.renderer.desc();
        let uniforms = FrameUniforms {
            view_proj: self.camera.view_proj(),
            eye: self.camera.eye.as_vec3(),
            viewport: [self.desc.width as f32, self.desc.height as f32],
            tess: r.tess,
            max_level: self.ctx.info().limits.max_tessellation_generation_level as f32,
            light_dir: key_light(&self.camera).as_vec3(),
            color_by: r.color_by,
        };
        self.renderer.set_frame(&uniforms)?;
        if r.capture_capacity.is_some() {
            self.renderer.reset_capture()?;
        }
        let target = &self.target;
        let renderer = &self.renderer;
        let clear = self.desc.clear;
        let capture = r.capture_capacity.is_some();
        let mut timer = self.timer.take();
        let stats = self.stats.take();
        let result = self.ctx.submit_once(|dev, cmd| {
            if let Some(t) = timer.as_mut() {
                t.reset(cmd);
            }
            if let Some(s) = &stats {
                s.reset(cmd);
            }
            target.begin(dev, cmd, clear);
            let pass = match timer.as_mut() {
                Some(t) => Some(t.begin(cmd, "patches (tessellated)")?),
                None => None,
            };
            if let Some(s) = &stats {
                s.begin(cmd);
            }
            renderer.record_patches(cmd);
            if let Some(s) = &stats {
                s.end(cmd);
            }
            if let (Some(t), Some(i)) = (timer.as_mut(), pass) {
                t.end(cmd, i)?;
            }
            let pass = match timer.as_mut() {
                Some(t) => Some(t.begin(cmd, "cpu-evaluated triangles")?),
                None => None,
            };
            renderer.record_fallback(cmd);
            if let (Some(t), Some(i)) = (timer.as_mut(), pass) {
                t.end(cmd, i)?;
            }
            target.end(dev, cmd);
            if capture {
                // Make the TES's storage writes visible to the host read-back.
                tes_writes_to_host(dev, cmd);
            }
            Ok(())
        });
        let report = match (&timer, &stats) {
            (Some(t), Some(s)) if result.is_ok() => Some(FrameReport {
                passes: t.results()?,
                patch_stats: s.results()?,
            }),
            _ => None,
        };
        self.timer = timer;
        self.stats = stats;
        result?;
        Ok(report)
    }

    /// The last frame's image.
    pub fn image(&self) -> Result<RgbaImage> {
        self.target.read_rgba(&self.ctx)
    }

    /// The last frame's captured TES invocations (capture must be on in the [`RenderDesc`]).
    pub fn capture(&self) -> Result<Vec<CaptureRecord>> {
        self.renderer.read_capture()
    }
}

/// Output of [`render_to_image`].
#[derive(Debug, Clone)]
pub struct RenderOutput {
    /// The frame.
    pub image: RgbaImage,
    /// Timings and statistics when requested.
    pub report: Option<FrameReport>,
    /// Captured TES invocations when capture was on.
    pub capture: Option<Vec<CaptureRecord>>,
}

/// Renders `surface` once offscreen.
pub fn render_to_image(
    ctx: &Context,
    surface: &SurfaceData,
    render: &RenderDesc,
    desc: &OffscreenDesc,
    timings: bool,
) -> Result<RenderOutput> {
    let mut session = OffscreenSession::new(ctx, surface, render, desc, timings)?;
    let report = session.frame()?;
    let image = session.image()?;
    let capture = match render.capture_capacity {
        Some(_) => Some(session.capture()?),
        None => None,
    };
    Ok(RenderOutput {
        image,
        report,
        capture,
    })
}
