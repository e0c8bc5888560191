//! Drawing offscreen and capturing what the tessellation evaluation shaders emit: the one place
//! of the tests that sets up sessions, sizes capture buffers and decodes them (the render API
//! these name is about to change).

use std::sync::Arc;

use glam::DVec3;
use image::RgbaImage;
use tessera::gpu::{vk, Buffer, Context, MemoryLocation, PipelineStats};
use tessera::mesh::ControlMesh;
use tessera::patch::gregory::GregoryTangents;
use tessera::render::renderer::resolve_tess_for;
use tessera::render::schemes::gregory::irregular_faces;
use tessera::render::schemes::gregory_vs::{select_faces, GregoryVsTables, VsBudget};
use tessera::render::session::{GregorySession, GregoryVariant, SessionOptions};
use tessera::render::{
    capture_capacity_for, render_to_image, surface_for_scheme, surface_for_scheme_with,
    CaptureRecord, ColorBy, OffscreenDesc, OffscreenSession, PlanOptions, RenderDesc, Scheme,
    SchemeLimits, Spacing, SurfaceData, TessMode, TessSettings,
};
use tessera::topology::Topology;

/// A `width x height` single-sample frame with the automatic camera.
pub fn offscreen(width: u32, height: u32) -> OffscreenDesc {
    OffscreenDesc {
        width,
        height,
        ..OffscreenDesc::default()
    }
}

/// Uniform tessellation at `level`, the other settings default.
pub fn uniform(level: f32) -> TessSettings {
    TessSettings {
        level,
        ..TessSettings::default()
    }
}

/// The levels the bitwise-watertight tests draw at: uniform 1, 5 and 8, fractional odd 5 and
/// even 6, and screen-space 8 at 4 pixels per edge.
pub fn watertight_settings() -> Vec<TessSettings> {
    vec![
        uniform(1.0),
        uniform(5.0),
        uniform(8.0),
        TessSettings {
            spacing: Spacing::FractionalOdd,
            ..uniform(5.0)
        },
        TessSettings {
            spacing: Spacing::FractionalEven,
            ..uniform(6.0)
        },
        TessSettings {
            mode: TessMode::Adaptive,
            pixels_per_edge: 4.0,
            ..uniform(8.0)
        },
    ]
}

/// Capture records `patches` patches can emit at `tess`; screen-space and distance levels are
/// taken at the device limit they can reach (64: at most 66^2 points per patch).
pub fn patch_capacity(patches: usize, tess: &TessSettings) -> u32 {
    if tess.mode != TessMode::Uniform {
        let highest = TessSettings {
            level: 64.0,
            spacing: Spacing::FractionalEven,
            max_patch_level: f32::INFINITY,
            ..*tess
        };
        capture_capacity_for(patches, &highest)
    } else {
        capture_capacity_for(patches, tess)
    }
}

/// The faces `surface` draws as GPU Gregory patches (every pass but the exact ones).
pub fn gregory_faces(surface: &SurfaceData) -> Vec<u32> {
    surface.irregular_gpu_faces()
}

/// Capture records everything `surface` draws on the GPU (B-spline and Gregory patches) can emit
/// at `tess`, with the settings the renderer really uses (resolved against the passes; the
/// device clamp can only lower the count).
pub fn surface_capacity(surface: &SurfaceData, tess: &TessSettings) -> u32 {
    patch_capacity(
        surface.patch_count(),
        &resolve_tess_for(f32::INFINITY, surface, tess),
    )
}

/// `render` with TES capture on, sized for `surface`.
fn with_capture(surface: &SurfaceData, render: &RenderDesc) -> RenderDesc {
    RenderDesc {
        capture_capacity: Some(surface_capacity(surface, &render.tess)),
        ..*render
    }
}

/// `mesh` prepared for `scheme` at tessellation level `level` within this device's limits.
pub fn scheme_surface(
    ctx: &Context,
    mesh: &ControlMesh,
    level: u32,
    scheme: Scheme,
) -> SurfaceData {
    surface_for_scheme(mesh, level, scheme, &SchemeLimits::from_context(ctx)).unwrap()
}

/// [`scheme_surface`] with the given edge-tangent lengths (`--gregory-tangents`).
pub fn scheme_surface_with(
    ctx: &Context,
    mesh: &ControlMesh,
    level: u32,
    scheme: Scheme,
    tangents: GregoryTangents,
) -> SurfaceData {
    let opts = PlanOptions::new(SchemeLimits::from_context(ctx)).with_gregory_tangents(tangents);
    surface_for_scheme_with(mesh, level, scheme, &opts).unwrap()
}

/// One frame of `surface`.
pub fn image(
    ctx: &Context,
    surface: &SurfaceData,
    render: &RenderDesc,
    off: &OffscreenDesc,
) -> RgbaImage {
    render_to_image(ctx, surface, render, off, false)
        .expect("render")
        .image
}

/// `mesh` drawn with `scheme` at level 8, coloured by patch type (regular gold, irregular quad
/// purple, triangle green; the paper's Fig. 1), 256 x 256: the patch-type goldens.
pub fn patch_type_image(ctx: &Context, mesh: &ControlMesh, scheme: Scheme) -> RgbaImage {
    let render = RenderDesc {
        tess: uniform(8.0),
        color_by: ColorBy::PatchType,
        ..RenderDesc::default()
    };
    image(
        ctx,
        &scheme_surface(ctx, mesh, 8, scheme),
        &render,
        &offscreen(256, 256),
    )
}

/// A frame with every TES invocation captured.
pub struct Captured {
    /// The picture.
    pub image: RgbaImage,
    /// One record per TES invocation.
    pub records: Vec<CaptureRecord>,
    /// Pipeline statistics of the patch pass, when asked for.
    pub stats: Option<PipelineStats>,
}

/// One frame of `surface` with TES capture (the buffer sized by [`surface_capacity`]); `stats`
/// also queries the patch pass's pipeline statistics.
pub fn capture(
    ctx: &Context,
    surface: &SurfaceData,
    render: &RenderDesc,
    off: &OffscreenDesc,
    stats: bool,
) -> Captured {
    let out = render_to_image(ctx, surface, &with_capture(surface, render), off, stats)
        .expect("render with capture");
    Captured {
        image: out.image,
        records: out.capture.expect("capture"),
        stats: out.report.map(|r| r.patch_stats),
    }
}

/// An offscreen session capturing every frame, whose control vertices move between frames.
pub struct Animation {
    session: OffscreenSession,
}

impl Animation {
    /// Uploads `surface`; capture is sized by [`surface_capacity`].
    pub fn new(
        ctx: &Context,
        surface: &SurfaceData,
        render: &RenderDesc,
        off: &OffscreenDesc,
    ) -> Animation {
        let render = with_capture(surface, render);
        let session = OffscreenSession::new(ctx, surface, &render, off, false).expect("session");
        Animation { session }
    }

    /// Renders a frame and returns its capture.
    pub fn frame(&mut self) -> Vec<CaptureRecord> {
        self.session.frame().expect("frame");
        self.session.capture().expect("capture")
    }

    /// Moves the control vertices (topology unchanged).
    pub fn move_to(&mut self, positions: &[DVec3]) -> tessera::Result<()> {
        self.session
            .renderer_mut()
            .update_positions(positions, None)
    }

    /// New crease sharpness on the single-crease patches (`SurfaceRenderer::set_sharpness`).
    pub fn set_sharpness(&mut self, creases: &[tessera::mesh::Crease]) -> tessera::Result<()> {
        self.session.renderer_mut().set_sharpness(creases)
    }

    /// The camera's eye (world).
    pub fn eye(&self) -> DVec3 {
        self.session.camera().eye
    }

    /// The last frame's picture.
    pub fn image(&self) -> RgbaImage {
        self.session.image().expect("image")
    }
}

/// What a [`GregorySession`] drew: the TES capture and the faces drawn as Gregory patches.
pub struct GregoryCapture {
    /// One record per TES invocation.
    pub records: Vec<CaptureRecord>,
    /// The faces drawn as Gregory patches.
    pub gregory: Vec<u32>,
}

/// One `size x size` frame of the Gregory faces of `mesh` (and its regular faces when
/// `with_regular`) through the stencil session with `variant`.
pub fn gregory_session_capture(
    ctx: &Context,
    mesh: &ControlMesh,
    render: &RenderDesc,
    variant: GregoryVariant,
    with_regular: bool,
    size: u32,
) -> GregoryCapture {
    let opts = SessionOptions {
        variant,
        with_regular,
        width: size,
        height: size,
    };
    let mut s = GregorySession::new(ctx, mesh, render, &opts).expect("Gregory session");
    s.frame().expect("frame");
    GregoryCapture {
        records: s.capture().expect("capture"),
        gregory: s.gregory_faces().to_vec(),
    }
}

/// A record's place: its face and the bits of its (u, v).
pub fn param_key(r: &CaptureRecord) -> (u32, u32, u32) {
    (r.face, r.u.to_bits(), r.v.to_bits())
}

/// A captured position and normal.
pub type PointAndNormal = [[f32; 3]; 2];

/// The captured points and normals by parameter ([`param_key`]); a parameter captured twice
/// with different results (shared domain points of sub-faces, several TES invocations) maps to
/// `None`.
pub fn points_by_param(
    records: &[CaptureRecord],
) -> std::collections::HashMap<(u32, u32, u32), Option<PointAndNormal>> {
    let mut out = std::collections::HashMap::new();
    for r in records {
        let v = [r.position, r.normal];
        out.entry(param_key(r))
            .and_modify(|e: &mut Option<PointAndNormal>| {
                if *e != Some(v) {
                    *e = None
                }
            })
            .or_insert(Some(v));
    }
    out
}

/// `records` sorted by [`param_key`], then sub-face (sub-faces of one face share parameters).
pub fn sorted(mut records: Vec<CaptureRecord>) -> Vec<CaptureRecord> {
    records.sort_by_key(|r| (param_key(r), r.sub_face));
    records
}

/// A TES capture buffer written by the shaders: a 16-byte header (invocation count, capacity)
/// and up to `capacity` records of `record_words` 32-bit words.
pub struct CaptureBuffer {
    buffer: Buffer,
    capacity: u32,
    record_words: usize,
}

impl CaptureBuffer {
    /// A host-readable storage buffer with the header written (count 0).
    pub fn new(ctx: &Context, capacity: u32, record_words: usize, name: &str) -> CaptureBuffer {
        let bytes = 16 + 4 * record_words as u64 * u64::from(capacity);
        let mut buffer = Buffer::new(
            ctx,
            bytes,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::GpuToCpu,
            name,
        )
        .expect("capture buffer");
        buffer
            .write(0, &[0u32, capacity, 0, 0])
            .expect("capture header");
        CaptureBuffer {
            buffer,
            capacity,
            record_words,
        }
    }

    /// The buffer, for binding.
    pub fn buffer(&self) -> &Buffer {
        &self.buffer
    }

    /// The invocations counted and the words of the records that fit.
    pub fn read(&self) -> (u32, Vec<u32>) {
        let words: Vec<u32> = self.buffer.read().expect("read capture");
        let kept = words[0].min(self.capacity) as usize;
        (words[0], words[4..4 + kept * self.record_words].to_vec())
    }
}

/// Draws only the Gregory faces of `mesh` with the two-stage pass built for `budget` (uniform
/// level 5, 64 x 64) and returns the capture sorted by [`param_key`].
pub fn gregory_vs_capture_with_budget(
    ctx: &Context,
    mesh: &ControlMesh,
    budget: VsBudget,
) -> Vec<CaptureRecord> {
    let topo = Arc::new(Topology::new(mesh).unwrap());
    let (faces, _) = select_faces(&topo, &irregular_faces(&topo), budget);
    let tess = uniform(5.0);
    let desc = RenderDesc {
        tess,
        color_by: ColorBy::PatchType,
        capture_capacity: Some(patch_capacity(faces.len(), &tess)),
        ..RenderDesc::default()
    };
    // Only the Gregory part: its corners' frames come from the Gregory construction.
    let surface = SurfaceData {
        positions: mesh.positions().to_vec(),
        topology: Some(topo.clone()),
        parts: vec![Arc::new(GregoryVsTables::new(
            topo,
            &faces,
            budget,
            Default::default(),
        ))],
        ..SurfaceData::default()
    };
    let records = render_to_image(ctx, &surface, &desc, &offscreen(64, 64), false)
        .unwrap()
        .capture
        .unwrap();
    sorted(records)
}

/// The longest edge of the triangles of `mesh` (e.g. a frame's triangle capture,
/// `render::static_draw`), in model units.
pub fn longest_triangle_edge(mesh: &tessera::render::FallbackMesh) -> f64 {
    mesh.indices
        .chunks_exact(3)
        .flat_map(|t| {
            let p = |k: usize| mesh.positions[t[k] as usize];
            [
                p(0).distance(p(1)),
                p(1).distance(p(2)),
                p(2).distance(p(0)),
            ]
        })
        .fold(0.0f64, f64::max)
}
