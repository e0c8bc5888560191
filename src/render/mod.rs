//! Rendering of subdivision surfaces through the Vulkan tessellation stages (on top of
//! [`crate::gpu`]). A surface is planned per scheme ([`schemes`]: one folder per scheme, one
//! registry line each) into parts drawn by GPU passes over shared machinery ([`pass`]); faces no
//! pass takes are evaluated exactly on the CPU ([`fallback`], drawn by [`cpu_path`]).

pub mod accuracy;
pub mod animate;
pub mod bench;
pub mod camera;
pub mod compare;
pub mod continuity;
pub mod cpu_path;
pub mod displace;
pub mod fallback;
pub mod heatmap;
pub mod offscreen;
pub mod pass;
pub mod plan;
pub mod renderer;
pub mod schemes;
pub mod seams;
pub mod session;
pub mod settings;
pub mod static_draw;
pub mod surface;

pub use camera::{Camera, CameraSpec, UpAxis};
pub use fallback::{FallbackFace, FallbackMesh, PatchClass};
pub use offscreen::{
    render_to_image, FrameReport, OffscreenDesc, OffscreenSession, RenderOutput, CPU_PATH_LABEL,
};
pub use pass::{capture_capacity_for, CaptureRecord, CapturedTriangle};
pub use plan::{
    cpu_faces, plan_for_scheme, plan_for_scheme_with, plan_passes, surface_for_scheme,
    surface_for_scheme_with, surface_from_mesh, surface_with,
};
pub use renderer::{
    resolve_tess, resolve_tess_for, EngineDesc, MemoryReport, RenderDesc, SurfaceRenderer,
    MAX_FRAMES_IN_FLIGHT,
};
pub use schemes::{
    PassTables, PatchPass, PatchScheme, PlanOptions, Refusal, RefusalReason, Scheme, SchemeLimits,
};
pub use settings::{
    ColorBy, Displacement, FrameFlags, FrameUniforms, Spacing, TessMode, TessSettings,
};
pub use surface::SurfaceData;
