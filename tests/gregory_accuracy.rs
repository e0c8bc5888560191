//! The accuracy measurement (`patch::gregory::accuracy`): exact patches measure as exact, the
//! closest-point distance never exceeds the equal-(u,v) error, and the figures are finite.

mod common;

use common::meshes::osd;
use tessera::patch::gregory::accuracy::{measure, AccuracyOptions};

#[test]
fn regular_faces_measure_as_exact() {
    // catmark_torus is all regular: sampled anyway, their Gregory patches reproduce the
    // B-spline, which is the exact limit, so the measurement must find (almost) nothing.
    let mesh = osd("catmark_torus");
    let r = measure(
        &mesh,
        &AccuracyOptions {
            grid: 4,
            include_regular: true,
        },
    )
    .unwrap();
    assert!(r.faces > 0 && r.faces == r.regular, "{r:?}");
    assert!(
        r.max_distance < 1e-9 && r.max_uv < 1e-12 && r.max_normal < 1e-6,
        "{r:?}"
    );
}

#[test]
fn distance_is_bounded_by_the_equal_parameter_error() {
    for name in ["catmark_cube", "catmark_gregory_test1", "catmark_nonquads"] {
        let r = measure(&osd(name), &AccuracyOptions::default()).unwrap();
        assert!(r.faces > 0 && r.samples > 0);
        assert!(
            r.max_distance > 0.0 && r.max_distance.is_finite(),
            "{name}: {r:?}"
        );
        // Closest point is at most as far as the point at the same parameters (quad samples).
        if r.triangles == 0 {
            assert!(r.rms_distance <= r.rms_uv + 1e-15, "{name}: {r:?}");
            assert!(r.max_distance <= r.max_uv + 1e-15, "{name}: {r:?}");
        }
        assert!(
            r.rms_normal <= r.max_normal && r.max_normal < 0.5,
            "{name}: {r:?}"
        );
    }
}
