//! Conformance of the `gregory-stencil` scheme: regular faces as exact B-splines, irregular
//! triangles and quads as Gregory patches (Loop, Schaefer, Ni, Castaño 2009) built by the
//! stencil construction (one-ring stencils in the TCS, §4.3). Checks in `tests/common/conformance.rs`.

mod common;

gregory_conformance!(
    tessera::render::Scheme::GregoryStencil,
    "gregory_stencil_mixed_patch_type"
);
