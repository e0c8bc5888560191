//! The fitted Gregory edge-tangent lengths (`patch::gregory::tangents`): the table is what the fit
//! computes, each entry is a minimum of the fitted error, and on meshes the fitted tangents are
//! closer to the exact limit than the paper's (closest-point distance, `gregory::accuracy`).

mod common;

use common::meshes::mesh as load;
use tessera::mesh::{ControlMesh, ObjOptions};
use tessera::patch::adaptive::decayed_fit::decayed_fit_terms;
use tessera::patch::gregory::accuracy::{measure_tangents, AccuracyOptions, AccuracyReport};
use tessera::patch::gregory::tangent_fit::{
    band_fit_error, band_fit_scales, band_fit_terms, crease_fit_scale, crease_fit_terms, fit_error,
    fit_scale, fit_terms,
};
use tessera::patch::gregory::tangents::{DECAYED_CORNER_SCALE, MAX_FITTED_VALENCE, OPTIMAL_SCALE};
use tessera::patch::gregory::tangents_boundary::{
    BAND_CENTRE_SCALE, BAND_TWO_SCALE, CREASE_SCALE, MAX_FITTED_CREASE_SECTOR,
};
use tessera::patch::gregory::GregoryTangents;

#[test]
fn table_entries_are_the_fit() {
    // A few entries recomputed from scratch (the example regenerates all of them).
    for n in [3, 5, 7, 12] {
        let s = fit_scale(n).unwrap();
        assert!(
            (s - OPTIMAL_SCALE[n - 3]).abs() < 1e-5,
            "valence {n}: fit {s}, table {}",
            OPTIMAL_SCALE[n - 3]
        );
    }
    assert_eq!(OPTIMAL_SCALE[1], 1.0, "valence 4 keeps the bicubic");
}

/// Entries of the decayed-corner table recomputed from scratch
/// (`examples/decayed_corner_table.rs` regenerates all of them): the fit is its minimum, below
/// the smooth end caps' factor, which the fit on these rings finds too long.
#[test]
fn decayed_corner_entries_are_the_fit() {
    for n in [7, 16, 20] {
        let &(_, s) = DECAYED_CORNER_SCALE.iter().find(|(m, _)| *m == n).unwrap();
        let t = decayed_fit_terms(n).unwrap();
        let fit = -t[1] / t[2];
        assert!((fit - s).abs() < 1e-4, "valence {n}: fit {fit}, table {s}");
        let smooth = GregoryTangents::EndCaps.ring_factors(&vec![4; n]).tangent;
        assert!(s < smooth, "valence {n}: {s} against the smooth {smooth}");
        assert!(fit_error(&t, smooth) > fit_error(&t, s), "valence {n}");
    }
}

/// ±2 % on the table entry `s` of the fit with terms `t` increases the fitted error, and the
/// paper's factor 1 is worse (the point of the tables).
fn assert_minimum(t: &[f64; 3], s: f64, what: &str) {
    let at = fit_error(t, s);
    for k in [0.98, 1.02] {
        assert!(
            fit_error(t, k * s) > at,
            "{what}: {k} x s* does not increase the error"
        );
    }
    assert!(fit_error(t, 1.0) > at, "{what}");
}

#[test]
fn every_entry_is_a_minimum() {
    for n in (3..=MAX_FITTED_VALENCE).filter(|&n| n != 4) {
        assert_minimum(
            &fit_terms(n).unwrap(),
            OPTIMAL_SCALE[n - 3],
            &format!("valence {n}"),
        );
    }
}

#[test]
fn crease_table_entries_are_the_fit() {
    for k in [3, 4, 7] {
        let s = crease_fit_scale(k).unwrap();
        assert!(
            (s - CREASE_SCALE[k - 3]).abs() < 1e-5,
            "crease sector of {k} faces: fit {s}, table {}",
            CREASE_SCALE[k - 3]
        );
    }
    // The half-ring of two faces is the regular boundary: the construction reproduces the
    // bicubic B-spline there, so the fit's error vanishes at the paper's factor 1 (which checks
    // the fit's boundary net and error terms against an exact case).
    let t = crease_fit_terms(2).unwrap();
    assert!(fit_error(&t, 1.0) < 1e-24, "{t:?}");
}

#[test]
fn every_crease_entry_is_a_minimum() {
    for k in 3..=MAX_FITTED_CREASE_SECTOR {
        let what = format!("crease sector of {k} faces");
        assert_minimum(&crease_fit_terms(k).unwrap(), CREASE_SCALE[k - 3], &what);
    }
}

#[test]
fn band_table_entries_are_the_fit() {
    for k in [3, 5, 9] {
        let (centre, two) = band_fit_scales(k).unwrap();
        assert!(
            (centre - BAND_CENTRE_SCALE[k - 3]).abs() < 1e-5
                && (two - BAND_TWO_SCALE[k - 3]).abs() < 1e-5,
            "band of {k} faces: fit ({centre}, {two}), table ({}, {})",
            BAND_CENTRE_SCALE[k - 3],
            BAND_TWO_SCALE[k - 3]
        );
    }
}

/// Each band entry pair is the minimum of the joint fit: ±2 % on either factor increases the
/// fitted error, and the paper's factors (1, 1) and the half-ring's `CREASE_SCALE` with the
/// exact two-face factor 1 (what `optimal` took before the 2-ring key) are worse.
#[test]
fn every_band_entry_is_a_minimum() {
    for k in 3..=MAX_FITTED_CREASE_SECTOR {
        let t = band_fit_terms(k).unwrap();
        let (c, two) = (BAND_CENTRE_SCALE[k - 3], BAND_TWO_SCALE[k - 3]);
        let at = band_fit_error(&t, c, two);
        for f in [0.98, 1.02] {
            assert!(
                band_fit_error(&t, f * c, two) > at,
                "band {k}: centre x {f}"
            );
            assert!(band_fit_error(&t, c, f * two) > at, "band {k}: two x {f}");
        }
        assert!(band_fit_error(&t, 1.0, 1.0) > at, "band {k}: paper");
        assert!(
            band_fit_error(&t, CREASE_SCALE[k - 3], 1.0) > at,
            "band {k}: half-ring factor"
        );
    }
}

fn measured(name: &str, tangents: GregoryTangents) -> AccuracyReport {
    let options = AccuracyOptions {
        grid: 6,
        include_regular: false,
    };
    measure_tangents(&load(name), &options, tangents, false)
        .unwrap()
        .0
}

#[test]
fn fitted_tangents_beat_the_papers_on_quad_meshes() {
    // Not everywhere: on meshes whose valence-3 vertices sit in nearly flat regions
    // (`catmark_gregory_test0`, the pawn and the rook) the paper's longer tangents are closer,
    // see docs/measured.md's table. Meshes with crease sectors of three or more faces:
    // `crease_rule_reaches_its_measured_bounds`.
    for name in ["catmark_cube", "catmark_gregory_test8"] {
        let paper = measured(name, GregoryTangents::Paper);
        let optimal = measured(name, GregoryTangents::Optimal);
        assert!(paper.faces == optimal.faces && paper.faces > 0);
        assert!(
            optimal.rms_distance < paper.rms_distance && optimal.rms_normal < paper.rms_normal,
            "{name}: optimal {optimal:?} paper {paper:?}"
        );
    }
}

#[test]
fn band_tables_bring_band_meshes_closer() {
    // `--gregory-tangents bands` on the two meshes with bands, measured independently by the
    // docs/measured.md's Metro-style distance as 1.15x OpenSubdiv from 1.22x and 1.36x; here the
    // closest-point measure of `measured` on `xord_boundary` (its fans one face deep are the
    // band the fit was made on). Every face without a band keeps `Optimal`'s bits.
    let optimal = measured("catmark_xord_boundary", GregoryTangents::Optimal);
    let bands = measured("catmark_xord_boundary", GregoryTangents::Bands);
    assert!(optimal.faces == bands.faces && bands.faces > 0);
    assert!(
        bands.rms_distance < 0.95 * optimal.rms_distance,
        "bands {bands:?} optimal {optimal:?}"
    );
    for name in [
        "catmark_cube",
        "catmark_gregory_test6",
        "catmark_cubes_infsharp",
    ] {
        let (o, b) = (
            measured(name, GregoryTangents::Optimal),
            measured(name, GregoryTangents::Bands),
        );
        assert_eq!(format!("{o:?}"), format!("{b:?}"), "{name} has no band");
    }
}

/// `assets/jittered/NAME.obj` (`examples/jitter_mesh.rs`).
fn jittered(name: &str) -> ControlMesh {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets/jittered")
        .join(format!("{name}.obj"));
    ControlMesh::from_obj_file(&path, &ObjOptions::default()).unwrap()
}

/// Optimal's crease rule (`s(k) T`, one-sided face points beside sharp edges, B-spline face
/// points at one-face corners) on the meshes of docs/measured.md's boundary table whose Gregory faces
/// touch crease sectors of three or more quads: RMS distance and normal (grid 6, closest exact
/// point, `gregory::accuracy`) below bounds measured with it (about 3 % above). gregory_test3 and
/// its jittered copy beat the paper (pre-change, with reflected face points: 8.67e-4 and 8.4e-4,
/// above their bounds); xord_boundary does not (docs/measured.md: the exact corner plane keeps it at
/// OpenSubdiv's 1.36×).
#[test]
fn crease_rule_reaches_its_measured_bounds() {
    let options = AccuracyOptions {
        grid: 6,
        include_regular: false,
    };
    let mut failed = Vec::new();
    for (name, mesh, bound, beats_paper) in [
        (
            "catmark_gregory_test3",
            load("catmark_gregory_test3"),
            BOUND_T3,
            true,
        ),
        (
            "jittered gregory_test3",
            jittered("gregory_test3"),
            BOUND_T3J,
            true,
        ),
        (
            "catmark_xord_boundary",
            load("catmark_xord_boundary"),
            BOUND_XB,
            false,
        ),
        (
            "jittered xord_boundary",
            jittered("xord_boundary"),
            BOUND_XBJ,
            false,
        ),
    ] {
        let run = |t| measure_tangents(&mesh, &options, t, false).unwrap().0;
        let (paper, optimal) = (run(GregoryTangents::Paper), run(GregoryTangents::Optimal));
        eprintln!(
            "{name}: optimal {:.3e} / {:.3e}, paper {:.3e} / {:.3e}",
            optimal.rms_distance, optimal.rms_normal, paper.rms_distance, paper.rms_normal
        );
        assert!(paper.faces == optimal.faces && paper.faces > 0);
        if optimal.rms_distance >= bound.0 || optimal.rms_normal >= bound.1 {
            failed.push(format!("{name}: optimal {optimal:?}"));
        }
        if beats_paper && optimal.rms_distance >= paper.rms_distance {
            failed.push(format!("{name}: optimal {optimal:?} paper {paper:?}"));
        }
    }
    assert!(failed.is_empty(), "{failed:?}");
}

// Measured (RMS distance, normal): gregory_test3 7.24e-4 / 3.67e-2, jittered 6.66e-4 / 3.71e-2
// (paper 1.41e-3 / 4.84e-2); xord_boundary 1.43e-3 / 3.36e-2, jittered 1.40e-3 / 3.30e-2 (paper
// 1.10e-3 / 2.96e-2).
const BOUND_T3: (f64, f64) = (7.46e-4, 3.78e-2);
const BOUND_T3J: (f64, f64) = (6.86e-4, 3.82e-2);
const BOUND_XB: (f64, f64) = (1.47e-3, 3.46e-2);
const BOUND_XBJ: (f64, f64) = (1.44e-3, 3.40e-2);
