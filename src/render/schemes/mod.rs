//! Patch schemes: one folder per scheme, one line per scheme in [`REGISTRY`].
//!
//! A [`Scheme`] (`--scheme`) is an ordered list of [`PatchScheme`]s. Planning a surface offers
//! every face with a limit surface to the first pass, what it refuses to the next, and so on;
//! faces no pass takes stay on the exact CPU path, with each pass's typed [`Refusal`].
//!
//! A pass lives in three stages, each a trait:
//! - [`PatchScheme`] (a unit value in the registry): which faces it takes and why not the
//!   others, building its CPU tables ([`PassTables`]) once per topology;
//! - [`PassTables`] (pure CPU data, held by [`crate::render::SurfaceData`]): patch counts,
//!   the corner frames its patches read, the largest usable patch level, the capture layout, and
//!   the factory of the GPU pass;
//! - [`PatchPass`] (GPU resources of one surface): records an optional compute pre-pass
//!   (outside the render pass, before any draw) and the draws (inside it) into the caller's
//!   command buffer, and takes new control positions for animation.
//!
//! What the passes share (set-0 bindings, uploads, frames, the chunked draw loop, capture) is in
//! [`crate::render::pass`].

pub mod bspline;
pub mod gregory;
pub mod gregory_stencil;
pub mod gregory_vs;

use std::any::Any;
use std::fmt;
use std::sync::Arc;

use ash::vk;
use glam::DVec3;

use super::pass::{NormalRule, SharedResources, VertexFrames};
use super::renderer::RenderDesc;
use super::settings::Spacing;
use crate::gpu::{Context, TargetFormat};
use crate::patch::gregory::NotGregory;
use crate::topology::Topology;
use crate::Result;

/// The schemes a user picks (`--scheme`); what each draws is its [`REGISTRY`] line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, clap::ValueEnum)]
pub enum Scheme {
    /// Only regular faces on the GPU (bicubic B-splines); every other face from the exact CPU
    /// reference.
    BsplineOnly,
    /// Regular faces as B-splines, irregular triangles and quads as Gregory patches built by the
    /// two-stage construction: vertex shader + TCS (Loop et al. 2009, §4.1-4.2).
    GregoryVs,
    /// Regular faces as B-splines, irregular triangles and quads as Gregory patches from
    /// precomputed one-ring stencils in the TCS (§4.3).
    #[default]
    GregoryStencil,
}

/// One registry line: a user-facing scheme, its command-line name and its passes in order.
pub struct SchemeEntry {
    /// The scheme.
    pub scheme: Scheme,
    /// Command-line name (as `clap` derives it from the variant).
    pub name: &'static str,
    /// Passes, in the order faces are offered to them and drawn.
    pub passes: &'static [&'static dyn PatchScheme],
}

/// Every scheme. Adding one: a [`Scheme`] variant and a line here.
pub static REGISTRY: [SchemeEntry; 3] = [
    SchemeEntry {
        scheme: Scheme::BsplineOnly,
        name: "bspline-only",
        passes: &[&bspline::BSPLINE],
    },
    SchemeEntry {
        scheme: Scheme::GregoryVs,
        name: "gregory-vs",
        passes: &[&bspline::BSPLINE, &gregory_vs::GREGORY_VS],
    },
    SchemeEntry {
        scheme: Scheme::GregoryStencil,
        name: "gregory-stencil",
        passes: &[&bspline::BSPLINE, &gregory_stencil::GREGORY_STENCIL],
    },
];

impl Scheme {
    /// Every scheme, in registry order.
    pub const ALL: [Scheme; 3] = [
        Scheme::BsplineOnly,
        Scheme::GregoryVs,
        Scheme::GregoryStencil,
    ];

    /// The registry line of this scheme.
    pub fn entry(self) -> &'static SchemeEntry {
        REGISTRY
            .iter()
            .find(|e| e.scheme == self)
            .expect("every Scheme has a registry line")
    }

    /// Command-line name.
    pub fn name(self) -> &'static str {
        self.entry().name
    }

    /// The passes drawing this scheme's faces, in order.
    pub fn passes(self) -> &'static [&'static dyn PatchScheme] {
        self.entry().passes
    }

    /// Parses a command-line name.
    pub fn parse(s: &str) -> Result<Scheme> {
        REGISTRY
            .iter()
            .find(|e| e.name == s)
            .map(|e| e.scheme)
            .ok_or_else(|| {
                let names: Vec<&str> = REGISTRY.iter().map(|e| e.name).collect();
                crate::Error::Invalid(format!("scheme `{s}`: expected {}", names.join(", ")))
            })
    }
}

impl fmt::Display for Scheme {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Device limits schemes plan against.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SchemeLimits {
    /// Two-stage Gregory variant's varyings budget (`None`: the variant is unavailable).
    pub vs: Option<gregory_vs::VsBudget>,
    /// `maxTessellationPatchSize` (largest patch primitive, e.g. a stencil face's one-ring).
    pub max_patch_size: u32,
}

impl SchemeLimits {
    /// No device: only passes that need no device limits take faces (planning without a GPU,
    /// e.g. `bspline-only`).
    pub const NO_DEVICE: SchemeLimits = SchemeLimits {
        vs: None,
        max_patch_size: 0,
    };

    /// The limits of `ctx`'s device.
    pub fn from_context(ctx: &Context) -> SchemeLimits {
        SchemeLimits {
            vs: gregory_vs::vs_budget(ctx),
            max_patch_size: ctx.info().limits.max_tessellation_patch_size,
        }
    }
}

/// Why a pass does not take a face.
#[derive(Debug, Clone, PartialEq)]
pub enum RefusalReason {
    /// Not a regular quad (extraordinary vertex, not a quad, or a sharp feature the B-spline
    /// patch cannot reproduce).
    NotRegular,
    /// The Gregory construction does not cover the face.
    NotGregory(NotGregory),
    /// The face's one-ring exceeds the largest patch primitive.
    RingTooLarge {
        /// One-ring size.
        ring: usize,
        /// Largest primitive (`maxTessellationPatchSize` or the layout's limit).
        max: usize,
    },
    /// A corner's per-vertex data exceeds the two-stage variant's varyings.
    VaryingsBudget {
        /// The vertex.
        vertex: u32,
        /// Its ring edges.
        edges: usize,
        /// Smooth-vertex limit.
        max_smooth: usize,
        /// Boundary/crease-vertex limit.
        max_sectored: usize,
    },
    /// The device cannot run the pass at all.
    Device(String),
}

/// A face a pass does not take, and why (the caller reads it; the renderer logs a summary).
#[derive(Debug, Clone, PartialEq)]
pub struct Refusal {
    /// Base-mesh face.
    pub face: u32,
    /// The pass that refused it.
    pub pass: &'static str,
    /// Why.
    pub reason: RefusalReason,
}

impl fmt::Display for Refusal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let face = self.face;
        match &self.reason {
            RefusalReason::NotRegular => write!(f, "face {face}: not a regular patch"),
            RefusalReason::NotGregory(e) => e.fmt(f),
            RefusalReason::RingTooLarge { ring, max } => write!(
                f,
                "face {face}: one-ring of {ring} vertices exceeds the {max}-vertex stencil patch"
            ),
            RefusalReason::VaryingsBudget {
                vertex,
                edges,
                max_smooth,
                max_sectored,
            } => write!(
                f,
                "face {face}: vertex {vertex} has {edges} ring edges, over the two-stage variant's varyings budget ({max_smooth} smooth, {max_sectored} at boundaries/creases)"
            ),
            RefusalReason::Device(why) => write!(f, "face {face}: {why}"),
        }
    }
}

/// What a pass's plan yields: its tables (none when it takes no face) and its refusals.
pub struct PassPlan {
    /// CPU tables of the accepted faces.
    pub tables: Option<Arc<dyn PassTables>>,
    /// The other candidates, each with the reason.
    pub refused: Vec<Refusal>,
}

/// How the `u v` of a captured record relate to the base face (`tessera sample` docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CaptureLayout {
    /// Every record in the base face's own quad domain (quads) — (0,0) at corner 0.
    FaceDomain,
    /// Quads in the face's domain; a triangle drawn whole as barycentric weights of corners 1
    /// and 2.
    FaceDomainOrBarycentric,
}

/// How far a pass can be tessellated per (sub-)patch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PatchLevelLimit {
    /// Largest (sub-)patch level drawn well; higher uniform levels are split into sub-patches.
    pub max_patch_level: f32,
    /// Whether patches may be split at all (false: drawn whole whatever the level).
    pub splittable: bool,
}

impl Default for PatchLevelLimit {
    fn default() -> Self {
        PatchLevelLimit {
            max_patch_level: f32::INFINITY,
            splittable: true,
        }
    }
}

/// A pass as the registry lists it: which faces it takes, building its CPU tables.
pub trait PatchScheme: Sync {
    /// Short name (logs, refusals, timing labels).
    fn name(&self) -> &'static str;

    /// Takes what it can of `candidates` (faces of `topo` with a limit surface that no earlier
    /// pass took): tables for the accepted faces, a typed refusal for each other.
    fn plan(&self, topo: &Arc<Topology>, candidates: &[u32], limits: &SchemeLimits) -> PassPlan;
}

/// What a pass's GPU resources are created from.
pub struct PassContext<'a> {
    /// The device.
    pub ctx: &'a Context,
    /// Buffers and bindings shared by every pass of the surface.
    pub shared: &'a SharedResources,
    /// Control positions.
    pub positions: &'a [DVec3],
    /// Vertex limit frames.
    pub frames: &'a VertexFrames,
    /// Render description, its tessellation settings resolved ([`crate::render::resolve_tess`]).
    pub desc: &'a RenderDesc,
    /// Format of the render targets the pipelines draw into.
    pub target: TargetFormat,
}

/// The CPU tables of one pass of one surface (built once per topology; pure data).
pub trait PassTables: fmt::Debug + Send + Sync + Any {
    /// Name of the pass (as its [`PatchScheme::name`]).
    fn pass_name(&self) -> &'static str;

    /// Base faces drawn, in draw order.
    fn faces(&self) -> &[u32];

    /// Patches drawn (a face may need several).
    fn patch_count(&self) -> usize;

    /// Writes the limit position and normal of each of its patch corners not yet written
    /// (passes run in registry order: the first that has a vertex wins).
    fn corner_frames(&self, positions: &[DVec3], rule: NormalRule<'_>, frames: &mut VertexFrames);

    /// Limit points for camera framing (patch corners).
    fn framing_points(&self, frames: &VertexFrames) -> Vec<DVec3>;

    /// Largest usable patch level for `spacing`.
    fn patch_level_limit(&self, _spacing: Spacing) -> PatchLevelLimit {
        PatchLevelLimit::default()
    }

    /// How captured `u v` relate to the base face.
    fn capture_layout(&self) -> CaptureLayout {
        CaptureLayout::FaceDomain
    }

    /// Creates the GPU pass.
    fn create_pass(&self, pc: &PassContext<'_>) -> Result<Box<dyn PatchPass>>;

    /// `self` as [`Any`] (typed access for scheme-specific tools and tests).
    fn as_any(&self) -> &dyn Any;
}

/// The GPU resources of one pass of one surface.
pub trait PatchPass {
    /// Timing label.
    fn label(&self) -> &'static str;

    /// Patches drawn.
    fn patch_count(&self) -> u32;

    /// Records work that must run before any draw of the frame, outside the render pass (e.g.
    /// compute refinement of the control points). Default: none.
    fn record_compute(&self, _cmd: vk::CommandBuffer) {}

    /// Records the draws inside the caller's render pass.
    fn record(&self, cmd: vk::CommandBuffer);

    /// Animation: new control positions and their limit frames (same topology; the shared
    /// buffers are already updated). Call while no frame using the pass is executing.
    fn update_positions(&mut self, positions: &[DVec3], frames: &VertexFrames) -> Result<()>;
}
