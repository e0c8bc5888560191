//! Conformance of the single-crease pass (Nießner, Loop, Greiner 2012) in the Gregory schemes:
//! regular quads with one semi-sharp crease line drawn as single-crease patches, exact against
//! the Catmull-Clark limit and the CPU construction, bitwise watertight with their neighbours,
//! sharpness changed at run time.

mod common;

use common::capture::uniform;
use common::conformance::{assert_gpu_equals_cpu, assert_matches_limit, assert_watertight, draw};
use common::crease_grid::{face, grid, line, torus};
use common::gpu::context;
use common::meshes::osd;
use tessera::render::Scheme;

const SCHEME: Scheme = Scheme::GregoryStencil;
const PASS: &str = "single-crease";

#[test]
fn smoke() {
    let Some(ctx) = context() else { return };
    for s in [0.3f32, 1.0, 1.7, 2.0, 2.5, 4.5, 9.9] {
        for (name, m) in [("grid", grid(&line(|_| s))), ("torus", torus(&line(|_| s)))] {
            let (surface, records) = draw(&ctx, &m, SCHEME, uniform(6.0));
            let what = format!("{name} s = {s}");
            eprintln!(
                "{what}: faces {:?}",
                surface.part(PASS).map(|p| p.faces().len())
            );
            assert_matches_limit(&what, &m, &surface, &records, PASS, 1e-3, 1e-1);
            assert_gpu_equals_cpu(&what, &m, &surface, &records, 1e-3, 1e-1);
            assert_watertight(&what, &surface, &records);
        }
    }
    let _ = (face(0, 0), osd("catmark_single_crease"));
}
