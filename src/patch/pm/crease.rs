//! Crease scalars (paper eq. 14, §7 "Shape can be controlled locally using crease scalars") from
//! the mesh's sharpness tags and a uniform scalar.
//!
//! Each edge carries one scalar `a` in `[0, 1]`, used at both of its ends (the paper has one per
//! vertex and outgoing edge; the tags are per edge, so both ends agree):
//! - untagged edges: the base scalar `a_0`, [`SMOOTH_CREASE`] `= 2/3` (eq. 13; the paper's
//!   dodecahedron uses `a_0` uniformly from 1/10 to 4/5, Fig. 10), or `--pm-crease-scalar`;
//! - an edge of sharpness `s`: `a(s) = a_0 · 2^{-s}`, and `a = 0` from
//!   [`INFINITE_SHARPNESS`] on.
//!
//! Why `2^{-s}`: in eq. (14) the face point `f_j` leaves the line of spoke `j` only through the
//! terms `a_j (1 - a_{j+1})/2 · p_{3j+3} + a_j a_{j+1}/4 · (p_{3j+3} + p̄_j)` (and their
//! counterparts for `p - p_{3j}`), all proportional to `a_j`: the width of the rounded band
//! next to the edge is linear in `a`. Catmull-Clark with sharpness `s` applies the sharp rule
//! for `s` steps and then smooth ones, each step halving the edge lengths, so its rounded band
//! is `2^{-s}` as wide as the smooth surface's. `a = 0` (infinitely sharp) puts `f_j` and
//! `f_{j-1}` on the edge (a C0 crease at vertices whose edges are all sharp: the control
//! polyhedron, `tests/pm.rs`). Vertex (corner) tags are not read: a scalar per edge cannot pin
//! one vertex without sharpening its edges.
//!
//! Checked numerically (`tests/pm.rs`), as the OCR leaves the paper's claims without figures:
//! - `a = 2/3` everywhere is eq. (13) (expanding (14): `p` gets `(1 - a) + a²/4 =
//!   4/9`, each spoke end `a/2 - a²/4 = 2/9`, `p̄` `a²/4 = 1/9`);
//! - `a = 0` everywhere (or every edge infinitely sharp) is the control polyhedron;
//! - `a = 4/5` uniformly is "sphere-like" (§7, Fig. 10): the regular dodecahedron's radial
//!   spread is 0.044 against 0.083 at 2/3 and 0.229 at 0, falling monotonically up to 0.9
//!   (0.032), so 4/5 is rounder than the default but not the roundest;
//! - sharper tags move a tagged edge's cubic monotonically towards its control edge, and the
//!   tags bring the surface 2-11× closer (RMS) to the creased Catmull-Clark limit than Pm
//!   ignoring them on the shared crease meshes.

use super::vertex::{PmOptions, SMOOTH_CREASE};
use crate::mesh::INFINITE_SHARPNESS;
use crate::topology::Topology;

/// The crease scalar of an edge of sharpness `sharpness` when untagged edges have `base`:
/// `base · 2^{-sharpness}`, `0` from [`INFINITE_SHARPNESS`] on (module docs).
pub fn crease_scalar(base: f64, sharpness: f32) -> f64 {
    if sharpness >= INFINITE_SHARPNESS {
        0.0
    } else if sharpness <= 0.0 {
        base
    } else {
        base * (-f64::from(sharpness)).exp2()
    }
}

impl PmOptions {
    /// The scalars of `topo`'s edges from its sharpness tags, untagged edges at `base`
    /// ([`SMOOTH_CREASE`] when `None`; module docs of `crease`). Without tags and without a
    /// base the options stay smooth (`crease: None`, eq. 13).
    pub fn with_crease_tags(self, topo: &Topology, base: Option<f64>) -> PmOptions {
        let tagged = topo.edge_sharpnesses().iter().any(|&s| s > 0.0);
        if !tagged && base.is_none() {
            return self;
        }
        let a0 = base.unwrap_or(SMOOTH_CREASE);
        PmOptions {
            crease: Some(
                topo.edge_sharpnesses()
                    .iter()
                    .map(|&s| crease_scalar(a0, s))
                    .collect(),
            ),
            ..self
        }
    }
}
