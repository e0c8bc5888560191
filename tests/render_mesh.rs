//! The GPU pipeline on the embedded control meshes: TES capture of
//! the regular faces against the exact CPU limit (`LimitEvaluator`), watertightness between
//! regular patches, and the `render` / `sample` commands end to end.

mod common;

use std::process::Command;

use common::capture::{capture, offscreen, uniform};
use common::gpu::{assert_validation_clean, context};
use common::watertight::assert_regular_watertight;
use glam::DVec3;
use tessera::assets::EmbeddedMesh;
use tessera::render::{surface_from_mesh, RenderDesc};
use tessera::subdiv::eval::LimitEvaluator;
use tessera::ControlMesh;

fn meshes() -> Vec<(String, ControlMesh)> {
    EmbeddedMesh::ALL
        .iter()
        .map(|m| (format!("embedded:{}", m.name()), m.load().unwrap()))
        .collect()
}

#[test]
fn regular_faces_match_the_exact_limit() {
    let Some(ctx) = context() else { return };
    for (name, mesh) in meshes() {
        let s = surface_from_mesh(&mesh, 1).unwrap();
        if s.regular_patches().is_empty() {
            continue;
        }
        let ev = LimitEvaluator::new(&mesh).unwrap();
        let render = RenderDesc {
            tess: uniform(5.0),
            ..RenderDesc::default()
        };
        let recs = capture(&ctx, &s, &render, &offscreen(64, 64), false).records;
        assert_eq!(recs.len(), s.regular_patches().len() * 36, "{name}");
        let diag = mesh.bbox_diagonal();
        let mut worst = 0.0f64;
        for r in &recs {
            let l = ev
                .eval(r.face as usize, 0, f64::from(r.u), f64::from(r.v))
                .unwrap();
            let g = DVec3::from(r.position.map(f64::from));
            worst = worst.max((g - l.position).length() / diag);
            let gn = DVec3::from(r.normal.map(f64::from));
            assert!(
                (gn - l.normal).length() < 1e-3,
                "{name}: normal of face {} at ({}, {}): {gn} vs {}",
                r.face,
                r.u,
                r.v,
                l.normal
            );
        }
        assert!(
            worst < 1e-5,
            "{name}: worst error {worst} of the bbox diagonal"
        );
        // Watertight between regular patches: both sides of a shared edge emit the same bits.
        assert_regular_watertight(&name, &s, &recs);
    }
    assert_validation_clean(&ctx);
}

#[test]
fn sample_command_writes_exact_limit_points() {
    if context().is_none() {
        return;
    }
    let out = common::out_dir("render_mesh").join("sample.txt");
    let res = Command::new(env!("CARGO_BIN_EXE_tessera"))
        .args([
            "sample",
            "embedded:open",
            "--tess",
            "3",
            "--scheme",
            "bspline-only",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&res.stderr);
    assert!(res.status.success(), "sample failed: {stderr}");
    assert!(stderr.contains("CPU fallback"), "stderr: {stderr}");
    let mesh = EmbeddedMesh::Open.load().unwrap();
    let s = surface_from_mesh(&mesh, 1).unwrap();
    let ev = LimitEvaluator::new(&mesh).unwrap();
    let text = std::fs::read_to_string(&out).unwrap();
    let _ = std::fs::remove_file(&out);
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), s.regular_patches().len() * 16);
    let diag = mesh.bbox_diagonal();
    for l in lines {
        let f: Vec<&str> = l.split_whitespace().collect();
        assert_eq!(f.len(), 9, "line `{l}`");
        let face: usize = f[0].parse().unwrap();
        let x: Vec<f32> = f[1..].iter().map(|t| t.parse::<f32>().unwrap()).collect();
        let lim = ev.eval(face, 0, f64::from(x[0]), f64::from(x[1])).unwrap();
        let g = DVec3::new(f64::from(x[2]), f64::from(x[3]), f64::from(x[4]));
        assert!((g - lim.position).length() < 1e-5 * diag, "line `{l}`");
    }
}

#[test]
fn render_command_writes_a_png() {
    if context().is_none() {
        return;
    }
    let out = common::out_dir("render_mesh").join("render.png");
    let res = Command::new(env!("CARGO_BIN_EXE_tessera"))
        .args([
            "render",
            "--size",
            "96x64",
            "--tess",
            "3",
            "--timings",
            "--color-by",
            "patch-type",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&res.stdout);
    assert!(
        res.status.success(),
        "render failed: {}",
        String::from_utf8_lossy(&res.stderr)
    );
    assert!(stdout.contains("TES invocations"), "stdout: {stdout}");
    let img = image::open(&out).unwrap().to_rgba8();
    let _ = std::fs::remove_file(&out);
    assert_eq!(img.dimensions(), (96, 64));
    let bg = *img.get_pixel(0, 0);
    assert!(img.pixels().filter(|p| **p != bg).count() > 96 * 64 / 20);
    // Bad input is a typed error, not a panic.
    let bad = Command::new(env!("CARGO_BIN_EXE_tessera"))
        .args(["render", "--size", "0x5", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("size"));
}
