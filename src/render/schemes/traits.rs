//! The contract between the renderer and a scheme: the three traits every pass implements, what
//! planning yields (tables and typed refusals) and the device limits it plans against (module
//! docs of [`super`]).

use std::any::Any;
use std::fmt;
use std::sync::Arc;

use ash::vk;
use glam::DVec3;

use crate::gpu::{Context, DrawTarget};
use crate::patch::acc::NotAcc;
use crate::patch::gregory::{GregoryTangents, NotGregory};
use crate::patch::pm::NotPm;
use crate::patch::qas::NotQas;
use crate::render::pass::{largest_level, NormalRule, SharedResources, VertexFrames};
use crate::render::settings::{PatchLevelLimit, RenderDesc, Spacing};
use crate::subdiv::adaptive::EndCapSharpness;
use crate::topology::Topology;
use crate::Result;

/// Device limits schemes plan against.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SchemeLimits {
    /// `maxTessellationPatchSize` (largest patch primitive, e.g. a stencil face's one-ring).
    pub max_patch_size: u32,
    /// Components a vertex may pass from the vertex to the tessellation-control stage: the
    /// smaller of `maxVertexOutputComponents` and
    /// `maxTessellationControlPerVertexInputComponents` (the two-stage Gregory variant's budget).
    pub max_vertex_varyings: u32,
}

impl SchemeLimits {
    /// No device: only passes that need no device limits take faces (planning without a GPU,
    /// e.g. `bspline-only`).
    pub const NO_DEVICE: SchemeLimits = SchemeLimits {
        max_patch_size: 0,
        max_vertex_varyings: 0,
    };

    /// The limits of `ctx`'s device.
    pub fn from_context(ctx: &Context) -> SchemeLimits {
        // SAFETY: valid instance and physical device owned by the context.
        let props = unsafe {
            ctx.instance()
                .get_physical_device_properties(ctx.physical_device())
        };
        SchemeLimits {
            max_patch_size: props.limits.max_tessellation_patch_size,
            max_vertex_varyings: props.limits.max_vertex_output_components.min(
                props
                    .limits
                    .max_tessellation_control_per_vertex_input_components,
            ),
        }
    }
}

/// What passes plan against: the device's limits and the settings of schemes that refine.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanOptions {
    /// Device limits.
    pub limits: SchemeLimits,
    /// Isolation level of the feature-adaptive scheme (`--isolation`, `0..=`
    /// [`crate::subdiv::adaptive::MAX_ISOLATION`]).
    pub isolation: u32,
    /// Whether the feature-adaptive scheme stops refining at single-crease patches (a regular
    /// quad whose only feature is one semi-sharp crease line, drawn directly: Nießner, Loop,
    /// Greiner 2012), as OpenSubdiv's `useSingleCreasePatch` (`--single-crease`, on by default).
    pub single_crease: bool,
    /// Edge-tangent lengths of the Gregory construction in `gregory-vs`, `gregory-stencil` and
    /// the adaptive scheme's end caps (`--gregory-tangents paper|optimal`).
    pub gregory_tangents: GregoryTangents,
    /// How the adaptive scheme's end caps treat semi-sharpness left at the isolation level
    /// (`--end-cap-sharpness crease|smooth`).
    pub end_cap_sharpness: EndCapSharpness,
    /// Whether the adaptive scheme's end caps draw exact lattice normals near irregular crease
    /// vertices (`--lattice-normals`, on by default; [`crate::subdiv::adaptive::AdaptiveOptions::lattice_normals`]).
    pub lattice_normals: bool,
    /// Crease scalar of the untagged edges of `--scheme pm` (`--pm-crease-scalar`, eq. 14 of
    /// Myles, Ni, Peters 2008; `None`: 2/3, the smooth surface); tagged edges get
    /// `a · 2^{-sharpness}` ([`crate::patch::pm::crease_scalar`]).
    pub pm_crease_scalar: Option<f64>,
}

impl PlanOptions {
    /// The feature-adaptive isolation level when none is given (the default).
    /// Whether the adaptive scheme draws single-crease patches when not told.
    pub const DEFAULT_SINGLE_CREASE: bool = true;

    /// Whether the adaptive scheme draws lattice normals when not told.
    pub const DEFAULT_LATTICE_NORMALS: bool = true;

    pub const DEFAULT_ISOLATION: u32 = 3;

    /// `limits` with the default settings.
    pub fn new(limits: SchemeLimits) -> PlanOptions {
        PlanOptions {
            limits,
            isolation: Self::DEFAULT_ISOLATION,
            single_crease: Self::DEFAULT_SINGLE_CREASE,
            gregory_tangents: GregoryTangents::default(),
            end_cap_sharpness: EndCapSharpness::default(),
            lattice_normals: Self::DEFAULT_LATTICE_NORMALS,
            pm_crease_scalar: None,
        }
    }

    /// The same options with the adaptive end caps' lattice normals on or off.
    pub fn with_lattice_normals(self, lattice_normals: bool) -> PlanOptions {
        PlanOptions {
            lattice_normals,
            ..self
        }
    }

    /// The same options with the Pm crease scalar of untagged edges (`None`: smooth, 2/3).
    pub fn with_pm_crease_scalar(self, pm_crease_scalar: Option<f64>) -> PlanOptions {
        PlanOptions {
            pm_crease_scalar,
            ..self
        }
    }

    /// The same options with the given Gregory edge-tangent lengths.
    pub fn with_gregory_tangents(self, gregory_tangents: GregoryTangents) -> PlanOptions {
        PlanOptions {
            gregory_tangents,
            ..self
        }
    }

    /// The same options with isolation level `isolation`.
    pub fn with_isolation(self, isolation: u32) -> PlanOptions {
        PlanOptions { isolation, ..self }
    }

    /// The same options with the given end-cap sharpness.
    pub fn with_end_cap_sharpness(self, end_cap_sharpness: EndCapSharpness) -> PlanOptions {
        PlanOptions {
            end_cap_sharpness,
            ..self
        }
    }

    /// The same options with single-crease patches on or off.
    pub fn with_single_crease(self, single_crease: bool) -> PlanOptions {
        PlanOptions {
            single_crease,
            ..self
        }
    }
}

/// Why a pass does not take a face.
#[derive(Debug, Clone, PartialEq)]
pub enum RefusalReason {
    /// Not a regular quad (extraordinary vertex, not a quad, or a sharp feature the B-spline
    /// patch cannot reproduce).
    NotRegular,
    /// Not a regular quad with one semi-sharp crease line
    /// ([`crate::patch::single_crease::SingleCreasePatch`]).
    NotSingleCrease,
    /// The Gregory construction does not cover the face.
    NotGregory(NotGregory),
    /// A QAS limit mask failed ([`NotQas`]).
    NotQas(NotQas),
    /// ACC draws smooth interior quads only ([`NotAcc`]).
    NotAcc(NotAcc),
    /// The Pm construction does not cover the facet ([`NotPm`]).
    NotPm(NotPm),
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
    /// The feature-adaptive scheme cannot build the face's patches (e.g. an end cap the Gregory
    /// construction does not cover); the scheme takes every face or fails.
    Adaptive(String),
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
            RefusalReason::NotSingleCrease => write!(
                f,
                "face {face}: not a regular quad with a single semi-sharp crease line"
            ),
            RefusalReason::NotGregory(e) => e.fmt(f),
            RefusalReason::NotQas(e) => e.fmt(f),
            RefusalReason::NotAcc(e) => e.fmt(f),
            RefusalReason::NotPm(e) => e.fmt(f),
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
            RefusalReason::Device(why) | RefusalReason::Adaptive(why) => {
                write!(f, "face {face}: {why}")
            }
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
    /// and 2; faces of five or more sides (QAS fans) per sub-face as [`Self::SubFaces`].
    FaceDomainOrBarycentric,
    /// Quads in the face's domain; other faces per sub-face (the record's `sub_face`; `f:k u v`
    /// as `tessera limit` writes it), sub-face `k` with `(0, 0)` at corner `k`, as
    /// [`crate::subdiv::eval::LimitEvaluator`] parameterises it.
    SubFaces,
}

/// A patch evaluated on the CPU: `(u, v)` to position and unit normal.
pub type ReferencePatch = Box<dyn Fn(f64, f64) -> (DVec3, DVec3) + Send + Sync>;

/// A pass as the registry lists it: which faces it takes, building its CPU tables.
pub trait PatchScheme: Sync {
    /// Short name (logs, refusals, timing labels).
    fn name(&self) -> &'static str;

    /// Takes what it can of `candidates` (faces of `topo` with a limit surface that no earlier
    /// pass took): tables for the accepted faces, a typed refusal for each other.
    fn plan(&self, topo: &Arc<Topology>, candidates: &[u32], opts: &PlanOptions) -> PassPlan;

    /// Whether a refusal of this pass is an error rather than a face for the next pass or the
    /// CPU path (a scheme that promises to draw every face).
    fn takes_every_face(&self) -> bool {
        false
    }

    /// Whether this pass builds level-0 Gregory patches, the only construction that reads the
    /// frozen crease factors of `--gregory-tangents fitted` (`patch::gregory::vertex_fit`): the
    /// plan fits them only when a pass does.
    fn reads_fitted_crease_factors(&self) -> bool {
        false
    }
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
    pub target: &'a DrawTarget,
}

impl PassContext<'_> {
    /// The largest level of a (sub-)patch drawn in `split` sub-patches per side (1: whole), for
    /// [`crate::render::pass::PatchDraws::max_level`].
    pub fn largest_level(&self, split: u32) -> f32 {
        let device_max = self.ctx.info().limits.max_tessellation_generation_level as f32;
        largest_level(&self.desc.tess, device_max, split)
    }
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

    /// Whether the patches equal the exact limit (B-spline, single-crease), rather than
    /// approximate it (Gregory). Default: approximate.
    fn exact(&self) -> bool {
        false
    }

    /// How captured `u v` relate to the base face.
    fn capture_layout(&self) -> CaptureLayout {
        CaptureLayout::FaceDomain
    }

    /// The CPU reference of the patch this pass draws for `face` (the construction the GPU
    /// reproduces, from `crate::patch`): position and unit normal at a captured `(u, v)` (see
    /// [`Self::capture_layout`]). `None` when the pass does not draw `face`.
    fn reference(&self, positions: &[DVec3], face: u32) -> Option<ReferencePatch>;

    /// [`Self::reference`] of each of `faces` (a pass whose references share costly data, such
    /// as a whole refined surface, builds it once here).
    fn references(&self, positions: &[DVec3], faces: &[u32]) -> Vec<Option<ReferencePatch>> {
        faces
            .iter()
            .map(|&f| self.reference(positions, f))
            .collect()
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
    /// `slot` is the frame slot being recorded (its shared buffers and sets).
    fn record_compute(&self, _cmd: vk::CommandBuffer, _slot: usize) {}

    /// Records the draws of frame slot `slot` inside the caller's render pass.
    fn record(&self, cmd: vk::CommandBuffer, slot: usize);

    /// Labels of the draw groups [`Self::record`] records one after another (each with a
    /// pipeline of its own), for per-draw measurements
    /// ([`crate::render::OffscreenSession::group_frame`]). Default: one, the whole pass.
    fn draw_groups(&self) -> Vec<String> {
        vec![self.label().to_string()]
    }

    /// Records only draw group `group` of [`Self::draw_groups`] of frame slot `slot`. Default:
    /// the whole pass.
    fn record_group(&self, cmd: vk::CommandBuffer, slot: usize, _group: usize) {
        self.record(cmd, slot);
    }

    /// Bytes of GPU buffer memory the pass holds of its own (tables, indices, computed points;
    /// not the renderer's shared buffers). Default: 0.
    fn memory_bytes(&self) -> u64 {
        0
    }

    /// Animation: new control positions and their limit frames (same topology; the shared
    /// buffers are already updated). Call while no frame using the pass is executing.
    fn update_positions(&mut self, positions: &[DVec3], frames: &VertexFrames) -> Result<()>;

    /// Run-time data change of the same structure: `tables` (the same faces, e.g. new crease
    /// sharpness, [`super::single_crease::SingleCreaseTables::with_sharpness`]) replaces the
    /// tables the pass was created from. Call while no frame using the pass is executing.
    /// Default: an error, the pass has no run-time data.
    fn update_tables(&mut self, _tables: &dyn PassTables) -> Result<()> {
        Err(crate::Error::Invalid(format!(
            "{}: no run-time table changes (plan the surface again)",
            self.label()
        )))
    }
}
