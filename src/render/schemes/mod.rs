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

pub mod acc;
pub mod adaptive;
pub mod bspline;
pub mod gregory;
pub mod gregory_stencil;
pub mod gregory_vs;
pub mod pm;
pub mod pm_vs;
pub mod qas;
pub mod records;
pub mod single_crease;
pub mod traits;

use std::fmt;

pub use crate::render::settings::PatchLevelLimit;
use crate::Result;
pub use traits::{
    CaptureLayout, PassContext, PassPlan, PassTables, PatchPass, PatchScheme, PlanOptions,
    ReferencePatch, Refusal, RefusalReason, SchemeLimits,
};

/// The schemes a user picks (`--scheme`); what each draws is its [`REGISTRY`] line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, clap::ValueEnum)]
pub enum Scheme {
    /// Only regular faces on the GPU (bicubic B-splines); every other face from the exact CPU
    /// reference.
    BsplineOnly,
    /// Regular faces as B-splines, regular quads with one semi-sharp crease line as
    /// single-crease patches (Nießner et al. 2012), irregular triangles and quads as Gregory
    /// patches built by the two-stage construction: vertex shader + TCS (Loop et al. 2009,
    /// §4.1-4.2).
    GregoryVs,
    /// Regular faces as B-splines, regular quads with one semi-sharp crease line as
    /// single-crease patches (Nießner et al. 2012), irregular triangles and quads as Gregory
    /// patches from precomputed one-ring stencils in the TCS (§4.3).
    #[default]
    GregoryStencil,
    /// Feature-adaptive subdivision (Köbler 2013, Nießner et al. 2012): refined on the GPU
    /// around features to `--isolation`, every face drawn as exact B-spline patches of its
    /// level, transition patches and Gregory end caps; nothing on the CPU path.
    Adaptive,
    /// QAS (Boubekeur, Schlick 2007): one Catmull-Clark step projected to the limit, then per
    /// triangle or quad a quadratic position patch and a quadratic normal patch through those
    /// limit points (C0, smooth shading); faces of five or more sides as a fan of quadratic
    /// triangles around the face point.
    Qas,
    /// ACC patches (Loop, Schaefer 2008 §3-4) of smooth interior quads: bicubic Bézier geometry
    /// patches from the one-ring masks, normals from the u- and v-tangent patches (a continuous
    /// normal field); every other face from the exact CPU reference.
    Acc,
    /// Pm-patches (Myles, Ni, Peters 2008), stencil variant: one G1 patch per triangle, quad or
    /// pentagon of a closed mesh (bicubic for ordinary quads, singular bicubic for polar
    /// triangles, m quartic sectors otherwise), every coefficient a one-ring stencil summed in
    /// the TCS; other facets from the exact CPU reference.
    Pm,
    /// Pm-patches, vertex-stage variant (the paper's GPU construction, §6.1): the per-vertex
    /// quantities of each control vertex in the vertex shader, each patch assembled from its
    /// corners in the TCS, evaluated as `Pm`.
    PmVs,
}

/// One registry line: a user-facing scheme, its command-line name and its passes in order.
pub struct SchemeEntry {
    /// The scheme.
    pub scheme: Scheme,
    /// Command-line name (as `clap` derives it from the variant).
    pub name: &'static str,
    /// Control points each patch type reads (the `tessera compare` column).
    pub control_points: &'static str,
    /// Continuity of the drawn surface by construction (`tessera compare` also measures the
    /// normal jump across patch edges).
    pub continuity: &'static str,
    /// Passes, in the order faces are offered to them and drawn.
    pub passes: &'static [&'static dyn PatchScheme],
}

/// Every scheme. Adding one: a [`Scheme`] variant and a line here.
pub static REGISTRY: [SchemeEntry; 8] = [
    SchemeEntry {
        scheme: Scheme::BsplineOnly,
        name: "bspline-only",
        control_points: "16 (B-spline); other faces on the CPU",
        continuity: "exact limit: C2, G1 at extraordinary vertices",
        passes: &[&bspline::BSPLINE],
    },
    SchemeEntry {
        scheme: Scheme::GregoryVs,
        name: "gregory-vs",
        control_points: "16 (B-spline, single-crease), 20 / 15 (Gregory quad / tri, from the 1-ring in VS + TCS)",
        continuity: "exact on B-spline and single-crease patches; Gregory faces approximate, G1 by construction",
        passes: &[
            &bspline::BSPLINE,
            &single_crease::SINGLE_CREASE,
            &gregory_vs::GREGORY_VS,
        ],
    },
    SchemeEntry {
        scheme: Scheme::GregoryStencil,
        name: "gregory-stencil",
        control_points: "16 (B-spline, single-crease), 20 / 15 (Gregory quad / tri, one-ring stencils in the TCS)",
        continuity: "exact on B-spline and single-crease patches; Gregory faces approximate, G1 by construction",
        passes: &[
            &bspline::BSPLINE,
            &single_crease::SINGLE_CREASE,
            &gregory_stencil::GREGORY_STENCIL,
        ],
    },
    SchemeEntry {
        scheme: Scheme::Adaptive,
        name: "adaptive",
        control_points: "16 (B-spline, single-crease, transition, every level), 20 (Gregory end caps at the isolation level)",
        continuity: "exact except the end caps (approximate, G1 by construction), whose area shrinks 4x per level",
        passes: &[&adaptive::ADAPTIVE],
    },
    SchemeEntry {
        scheme: Scheme::Qas,
        name: "qas",
        control_points: "9 + 9 (biquadratic position and normal patches, quads), 6 + 6 (quadratic triangles; n-gons: n fan triangles), from one Catmull-Clark step's limit points",
        continuity: "C0 positions (bitwise watertight), normals continuous across edges from the normal patch; interpolates the step's limit points",
        passes: &[&qas::QAS],
    },
    SchemeEntry {
        scheme: Scheme::Acc,
        name: "acc",
        control_points: "16 (bicubic geometry patch from the one-ring masks) + 12 + 12 tangent-patch vectors for its normals",
        continuity: "exact on regular quads; geometry C0 next to extraordinary vertices, normals continuous from the tangent patches",
        passes: &[&acc::ACC],
    },
    SchemeEntry {
        scheme: Scheme::Pm,
        name: "pm",
        control_points: "16 (ordinary bicubic), 13 (polar singular bicubic), 19 / 25 / 31 (Pm-patch of 3 / 4 / 5 quartic sectors), one-ring stencils in the TCS",
        continuity: "G1 everywhere by construction (C1 between ordinary patches); approximates Catmull-Clark (ordinary quads on regular rings exact)",
        passes: &[&pm::PM],
    },
    SchemeEntry {
        scheme: Scheme::PmVs,
        name: "pm-vs",
        control_points: "16 (ordinary bicubic), 13 (polar singular bicubic), 19 / 25 / 31 (Pm-patch of 3 / 4 / 5 quartic sectors), per-vertex stage in VS + assembly in TCS",
        continuity: "as pm (the same construction and evaluation; G1 everywhere, C1 between ordinary patches)",
        passes: &[&pm_vs::PM_VS],
    },
];

impl Scheme {
    /// Every scheme, in registry order.
    pub const ALL: [Scheme; 8] = [
        Scheme::BsplineOnly,
        Scheme::GregoryVs,
        Scheme::GregoryStencil,
        Scheme::Adaptive,
        Scheme::Qas,
        Scheme::Acc,
        Scheme::Pm,
        Scheme::PmVs,
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
    /// [`SchemeEntry::control_points`].
    pub fn control_points(self) -> &'static str {
        self.entry().control_points
    }

    /// [`SchemeEntry::continuity`].
    pub fn continuity(self) -> &'static str {
        self.entry().continuity
    }

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
