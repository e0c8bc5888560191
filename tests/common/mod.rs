//! Helpers shared by the integration tests, once each: the validated GPU context and its skip
//! rule ([`gpu`]), the OpenSubdiv meshes beside the checkout ([`meshes`]), synthetic surfaces
//! and independent CPU references ([`surfaces`], [`reference`]), drawing with TES capture
//! ([`capture`]), the bitwise watertightness check ([`watertight`]) and golden images compared
//! with FLIP ([`golden`]), and the checks every scheme passes ([`conformance`]).
//!
//! Every test crate compiles the whole module and uses a part of it.
#![allow(dead_code)]

pub mod capture;
pub mod conformance;
pub mod crease_grid;
pub mod golden;
pub mod gpu;
pub mod levels;
pub mod meshes;
pub mod reference;
pub mod surfaces;
pub mod watertight;

use std::path::PathBuf;

/// The directory for files a test writes, `<target>/tmp/<sub>`, created if missing.
pub fn out_dir(sub: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(sub);
    std::fs::create_dir_all(&dir)
        .unwrap_or_else(|e| panic!("create test output dir {}: {e}", dir.display()));
    dir
}
