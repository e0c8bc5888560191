//! Rendering of subdivision surfaces through the Vulkan tessellation stages (on top of
//! [`crate::gpu`]): regular faces as bicubic B-spline patches evaluated by TCS/TES, every other
//! face with a limit surface (for now) as triangles evaluated by the CPU reference.

pub mod animate;
pub mod camera;
pub mod compare;
pub mod fallback;
pub mod gpu_accuracy;
pub mod gregory_layout;
pub mod gregory_pass;
pub mod gregory_stencil;
pub mod gregory_vs;
pub mod heatmap;
pub mod layout;
pub mod offscreen;
mod patch_pipeline;
pub mod renderer;
pub mod scene;
pub mod scheme;
pub mod settings;
pub mod surface;

pub use camera::{Camera, CameraSpec, UpAxis};
pub use compare::{compare_images, CompareReport, CompareThreshold};
pub use fallback::{FallbackFace, FallbackMesh, PatchClass};
pub use layout::BSplinePatch;
pub use offscreen::{render_to_image, FrameReport, OffscreenDesc, OffscreenSession, RenderOutput};
pub use renderer::{CaptureRecord, RenderDesc, SurfaceRenderer};
pub use scene::{surface_from_mesh, surface_with, SurfacePlan};
pub use scheme::{surface_for_scheme, GregorySurface, Scheme, SchemeLimits};
pub use settings::{ColorBy, FrameUniforms, Spacing, TessMode, TessSettings};
pub use surface::SurfaceData;
