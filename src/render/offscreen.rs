//! Offscreen rendering: a [`RenderTarget`] plus a [`SurfaceRenderer`], one submission per
//! frame, optional per-pass GPU timings and pipeline statistics, PNG-ready readback.

use glam::DVec3;
use image::RgbaImage;

use super::camera::{Camera, CameraSpec, UpAxis};
use super::pass::{CaptureRecord, CapturedTriangle, TriangleWindow};
use super::renderer::{RenderDesc, SurfaceRenderer};
use super::settings::FrameUniforms;
use super::surface::SurfaceData;
use crate::gpu::{
    geometry_writes_to_host, tes_writes_to_host, Context, GpuTimer, PipelineStats, RenderTarget,
    StatsQuery,
};
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

/// Label of the CPU-evaluated triangles in [`FrameReport::passes`].
pub const CPU_PATH_LABEL: &str = "cpu-evaluated triangles";

/// GPU timings and statistics of one frame.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FrameReport {
    /// `(pass, milliseconds)` from timestamp queries: each patch pass by its label, then
    /// [`CPU_PATH_LABEL`]. On lavapipe, timestamps inside one render pass do not attribute work
    /// to passes reliably: time a pass alone in a frame of its own when it matters.
    pub passes: Vec<(String, f64)>,
    /// `(pass, milliseconds)` of each patch pass's pre-pass work
    /// ([`crate::render::schemes::PatchPass::record_compute`]: e.g. the adaptive scheme's
    /// refinement and derived-point kernels), timed outside the render pass; about 0 for passes
    /// without any. Not part of [`Self::patch_ms`].
    pub compute: Vec<(String, f64)>,
    /// Pipeline statistics of every patch pass together.
    pub patch_stats: PipelineStats,
    /// Pipeline statistics of each patch pass.
    pub pass_stats: Vec<(String, PipelineStats)>,
}

impl FrameReport {
    /// Milliseconds of the passes labelled `label` (0 when absent).
    pub fn ms(&self, label: &str) -> f64 {
        self.passes
            .iter()
            .filter(|(l, _)| l == label)
            .map(|(_, ms)| ms)
            .sum()
    }

    /// Milliseconds of every tessellated pass.
    pub fn patch_ms(&self) -> f64 {
        self.passes
            .iter()
            .filter(|(l, _)| l != CPU_PATH_LABEL)
            .map(|(_, ms)| ms)
            .sum()
    }

    /// Milliseconds of every pass's pre-pass compute work ([`Self::compute`]).
    pub fn compute_ms(&self) -> f64 {
        self.compute.iter().map(|(_, ms)| ms).sum()
    }

    /// Statistics of the passes labelled `label`.
    pub fn stats(&self, label: &str) -> PipelineStats {
        self.pass_stats
            .iter()
            .filter(|(l, _)| l == label)
            .fold(PipelineStats::default(), |a, (_, s)| add_stats(a, s))
    }
}

fn add_stats(a: PipelineStats, b: &PipelineStats) -> PipelineStats {
    PipelineStats {
        input_vertices: a.input_vertices + b.input_vertices,
        input_primitives: a.input_primitives + b.input_primitives,
        vertex_invocations: a.vertex_invocations + b.vertex_invocations,
        tcs_patches: a.tcs_patches + b.tcs_patches,
        tes_invocations: a.tes_invocations + b.tes_invocations,
        clipping_invocations: a.clipping_invocations + b.clipping_invocations,
        clipping_primitives: a.clipping_primitives + b.clipping_primitives,
        fragment_invocations: a.fragment_invocations + b.fragment_invocations,
    }
}

/// Timestamp and statistics queries of a session: per patch pass one timer slot for its draws
/// and one statistics query, one timer slot for the CPU path; per patch pass one timer slot of
/// its own timer for its compute pre-pass.
struct Queries {
    timer: GpuTimer,
    compute: GpuTimer,
    stats: Vec<StatsQuery>,
}

/// A render target and a surface renderer, reusable across frames (benchmarks, animation).
pub struct OffscreenSession {
    ctx: Context,
    target: RenderTarget,
    renderer: SurfaceRenderer,
    desc: OffscreenDesc,
    camera: Camera,
    queries: Option<Queries>,
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
        let frames = surface.vertex_frames(&surface.positions);
        let (lo, hi) = surface.bounding_box_with(&frames);
        let aspect = f64::from(desc.width) / f64::from(desc.height.max(1));
        // Fit the drawn surface (patch corner limits and CPU-evaluated points, subsampled).
        let points = surface.framing_points(&frames);
        let camera = Camera::frame_oriented(desc.camera, desc.up, lo, hi, &points, aspect);
        let queries = if timings {
            let n = renderer.passes().len() as u32;
            Some(Queries {
                timer: GpuTimer::new(ctx, n + 1)?,
                compute: GpuTimer::new(ctx, n.max(1))?,
                stats: (0..n)
                    .map(|_| StatsQuery::new(ctx))
                    .collect::<Result<_>>()?,
            })
        } else {
            None
        };
        Ok(OffscreenSession {
            ctx: ctx.clone(),
            target,
            renderer,
            desc: *desc,
            camera,
            queries,
        })
    }

    /// The renderer (for `update_positions`).
    pub fn renderer_mut(&mut self) -> &mut SurfaceRenderer {
        &mut self.renderer
    }

    /// The renderer.
    pub fn renderer(&self) -> &SurfaceRenderer {
        &self.renderer
    }

    /// The placed camera.
    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// Places the camera explicitly.
    pub fn set_camera(&mut self, camera: Camera) {
        self.camera = camera;
    }

    /// Renders one frame and waits for it. Returns timings when the session has queries.
    pub fn frame(&mut self) -> Result<Option<FrameReport>> {
        self.frame_of(None)
    }

    /// Every patch pass's draw groups
    /// ([`crate::render::schemes::PatchPass::draw_groups`]): `(pass, group, label)`.
    pub fn draw_groups(&self) -> Vec<(usize, usize, String)> {
        self.renderer
            .passes()
            .iter()
            .enumerate()
            .flat_map(|(p, pass)| {
                pass.draw_groups()
                    .into_iter()
                    .enumerate()
                    .map(move |(g, label)| (p, g, label))
            })
            .collect()
    }

    /// A frame of one draw group alone (every pass's compute pre-pass, then only group `group`
    /// of patch pass `pass`, no CPU-path triangles), timed and counted as that pass: lavapipe's
    /// timestamps do not attribute work to draws within one render pass, a frame of its own
    /// does. Returns timings when the session has queries.
    pub fn group_frame(&mut self, pass: usize, group: usize) -> Result<Option<FrameReport>> {
        self.frame_of(Some((pass, group)))
    }

    /// A frame of everything, or with `only = Some((pass, group))` of that draw group alone.
    fn frame_of(&mut self, only: Option<(usize, usize)>) -> Result<Option<FrameReport>> {
        let r = *self.renderer.desc();
        let uniforms = FrameUniforms {
            view_proj: self.camera.view_proj(),
            eye: self.camera.eye.as_vec3(),
            viewport: [self.desc.width as f32, self.desc.height as f32],
            light_dir: key_light(&self.camera).as_vec3(),
            color_by: r.color_by,
        };
        self.renderer.set_frame(&uniforms)?;
        let capture = r.capture_capacity.is_some() || r.capture_triangles.is_some();
        if capture {
            self.renderer.reset_capture()?;
        }
        let target = &self.target;
        let renderer = &self.renderer;
        let clear = self.desc.clear;
        let frame_slot = renderer.frame_slot();
        let mut queries = self.queries.take();
        let result = self.ctx.submit_once(|dev, cmd| {
            if let Some(q) = queries.as_mut() {
                q.timer.reset(cmd);
                q.compute.reset(cmd);
                q.stats.iter().for_each(|s| s.reset(cmd));
            }
            // Each pass's compute pre-pass, timed on its own (outside the render pass, so the
            // timestamps bracket exactly its dispatches and barriers).
            for pass in renderer.passes() {
                let slot = match queries.as_mut() {
                    Some(q) => Some(q.compute.begin(cmd, pass.label())?),
                    None => None,
                };
                pass.record_compute(cmd, frame_slot);
                if let (Some(q), Some(i)) = (queries.as_mut(), slot) {
                    q.compute.end(cmd, i)?;
                }
            }
            target.begin(dev, cmd, clear);
            for (k, pass) in renderer.passes().iter().enumerate() {
                if only.is_some_and(|(p, _)| p != k) {
                    continue;
                }
                let slot = match queries.as_mut() {
                    Some(q) => {
                        let i = q.timer.begin(cmd, pass.label())?;
                        q.stats[k].begin(cmd);
                        Some(i)
                    }
                    None => None,
                };
                match only {
                    Some((_, group)) => pass.record_group(cmd, frame_slot, group),
                    None => pass.record(cmd, frame_slot),
                }
                if let (Some(q), Some(i)) = (queries.as_mut(), slot) {
                    q.stats[k].end(cmd);
                    q.timer.end(cmd, i)?;
                }
            }
            let slot = match queries.as_mut() {
                Some(q) => Some(q.timer.begin(cmd, CPU_PATH_LABEL)?),
                None => None,
            };
            if only.is_none() {
                renderer.record_fallback(cmd);
            }
            if let (Some(q), Some(i)) = (queries.as_mut(), slot) {
                q.timer.end(cmd, i)?;
            }
            target.end(dev, cmd);
            if r.capture_capacity.is_some() {
                // Make the TES's storage writes visible to the host read-back.
                tes_writes_to_host(dev, cmd);
            }
            if r.capture_triangles.is_some() {
                // The geometry stage's (triangle capture).
                geometry_writes_to_host(dev, cmd);
            }
            Ok(())
        });
        let report = match &queries {
            Some(q) if result.is_ok() => {
                // A group frame began only its own pass's statistics query.
                let pass_stats = renderer
                    .passes()
                    .iter()
                    .zip(&q.stats)
                    .enumerate()
                    .filter(|(k, _)| only.is_none_or(|(p, _)| p == *k))
                    .map(|(_, (p, s))| Ok((p.label().to_string(), s.results()?)))
                    .collect::<Result<Vec<_>>>()?;
                Some(FrameReport {
                    passes: q.timer.results()?,
                    compute: q.compute.results()?,
                    patch_stats: pass_stats
                        .iter()
                        .fold(PipelineStats::default(), |a, (_, s)| add_stats(a, s)),
                    pass_stats,
                })
            }
            _ => None,
        };
        self.queries = queries;
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

    /// The last frame's triangles ([`RenderDesc::capture_triangles`] must be on).
    pub fn triangles(&self) -> Result<Vec<CapturedTriangle>> {
        self.renderer.read_triangles()
    }

    /// Triangles the last frame drew ([`RenderDesc::capture_triangles`] must be on; counted
    /// past the capacity too).
    pub fn triangles_drawn(&self) -> Result<u32> {
        self.renderer.triangles_drawn()
    }

    /// What the last frame's triangle capture saw ([`SurfaceRenderer::read_triangle_window`]).
    pub fn triangle_window(&self) -> Result<TriangleWindow> {
        self.renderer.read_triangle_window()
    }

    /// The bucket modulus and stored bucket range of the next frames' triangle capture
    /// ([`SurfaceRenderer::set_triangle_buckets`]).
    pub fn set_triangle_buckets(&mut self, buckets: u32, first: u32, end: u32) -> Result<()> {
        self.renderer.set_triangle_buckets(buckets, first, end)
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
