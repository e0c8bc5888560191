//! Corners split into sectors by infinitely sharp edges, in the level-0 schemes: the patches of
//! one sector meet at the corner with bitwise-equal normals (the shared frame of the corner's
//! sector), patches of different sectors keep their own. The adaptive scheme has its own test
//! (`scheme_adaptive::watertight_across_levels_and_types`).

mod common;

use common::capture::uniform;
use common::conformance::draw;
use common::gpu::{assert_validation_clean, context};
use common::meshes::mesh;
use common::watertight::assert_coincident_points_equal_by_side;
use tessera::render::{Scheme, Spacing, TessSettings};

/// Meshes with vertices of two or more sectors: crease vertices between B-spline crease patches
/// (inf_crease0, inf_crease1: these failed before sector normals, 6e-8 rad apart), crease
/// vertices of Gregory patches (tent_creases1), crease ends meeting at corners (cubes_infsharp,
/// pyramid_creases1), a corner tag with sharp edges (cube_corner4).
const MESHES: [&str; 6] = [
    "catmark_inf_crease0",
    "catmark_inf_crease1",
    "catmark_cubes_infsharp",
    "catmark_tent_creases1",
    "catmark_pyramid_creases1",
    "catmark_cube_corner4",
];

/// Every level-0 scheme that draws patches at such corners, at uniform 5 and fractional odd 5:
/// points on one side of the sharp features (one face, across a smooth edge, one sector of a
/// vertex) have bitwise-equal positions and normals.
#[test]
fn one_normal_per_sector() {
    let Some(ctx) = context() else { return };
    let settings = [
        uniform(5.0),
        TessSettings {
            spacing: Spacing::FractionalOdd,
            ..uniform(5.0)
        },
    ];
    for scheme in [
        Scheme::BsplineOnly,
        Scheme::GregoryVs,
        Scheme::GregoryStencil,
        Scheme::Acc,
        Scheme::Qas,
        Scheme::Pm,
        Scheme::PmVs,
    ] {
        for name in MESHES {
            let m = mesh(name);
            for tess in settings {
                let (_, records) = draw(&ctx, &m, scheme, tess);
                let pairs = assert_coincident_points_equal_by_side(&m, &records);
                eprintln!("{name} {} {:?}: {pairs} pairs", scheme.name(), tess.spacing);
            }
        }
    }
    assert_validation_clean(&ctx);
}
