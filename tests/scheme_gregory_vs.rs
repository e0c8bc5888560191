//! Conformance of the `gregory-vs` scheme: regular faces as exact B-splines, irregular
//! triangles and quads as Gregory patches (Loop, Schaefer, Ni, Castaño 2009) built by the
//! two-stage construction (vertex shader + TCS, §4.1-4.2). Checks in `tests/common/conformance.rs`.

mod common;

gregory_conformance!(
    tessera::render::Scheme::GregoryVs,
    "gregory_vs_mixed_patch_type"
);
