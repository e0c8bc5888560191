//! Reliability (issue 14): huge output streams in bounded memory, OBJ byte-order marks and line
//! ends, short error excerpts, coordinates that would overflow, input that would draw nothing,
//! output files in the format their extension names, resource limits with their flags, and the
//! GPU memory estimate checked before allocating.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use common::meshes::osd_path;
use tessera::mesh::ObjOptions;
use tessera::{ControlMesh, Error};

fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_tessera"));
    c.env("TESSERA_VALIDATION", "1");
    c
}

/// Runs the CLI: (success, stdout, stderr).
fn run(args: &[&str]) -> (bool, String, String) {
    let out = bin().args(args).output().unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn dir() -> PathBuf {
    common::out_dir("reliability")
}

fn write(name: &str, text: &[u8]) -> PathBuf {
    let p = dir().join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn obj(text: &str) -> tessera::Result<ControlMesh> {
    ControlMesh::from_obj_str(text, "test", &ObjOptions::default())
}

const QUAD: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";

/// The largest resident set of a child process, polled from `/proc` until it exits (the test
/// samples often enough for a process that runs a second or more).
fn peak_rss_kb(mut cmd: Command) -> (bool, u64) {
    let mut child = cmd
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let status_path = format!("/proc/{}/status", child.id());
    let mut peak = 0u64;
    loop {
        if let Ok(text) = std::fs::read_to_string(&status_path) {
            if let Some(kb) = text
                .lines()
                .find_map(|l| l.strip_prefix("VmHWM:"))
                .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<u64>().ok())
            {
                peak = peak.max(kb);
            }
        }
        if let Some(status) = child.try_wait().unwrap() {
            return (status.success(), peak);
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
}

/// `limit --grid 600` on the cube writes 2.2 M lines (~180 MB): the samples used to be collected
/// in memory first (about 400 MB here; grid 5000 passed 13 GB). Streamed, the peak stays a few
/// MB beyond the mesh.
#[test]
fn limit_streams_its_output_in_bounded_memory() {
    let mut cmd = bin();
    cmd.arg("limit")
        .arg(osd_path("catmark_cube"))
        .args(["--grid", "600", "--out", "/dev/null"]);
    let (ok, peak) = peak_rss_kb(cmd);
    assert!(ok);
    assert!(peak > 0, "no RSS sampled");
    assert!(peak < 64 * 1024, "peak RSS {peak} kB");
}

/// The streamed output is the evaluator's grid, line for line, on a mesh with non-quads and a
/// grid whose rows span several work units.
#[test]
fn limit_streamed_output_is_the_evaluator_grid() {
    let out = dir().join("limit_mixed.txt");
    let (ok, _, err) = run(&["limit", "embedded:mixed", "--grid", "70", "--out", s(&out)]);
    assert!(ok, "{err}");
    let text = std::fs::read_to_string(&out).unwrap();
    let mesh = tessera::assets::load_mesh("embedded:mixed", &ObjOptions::default()).unwrap();
    let ev = tessera::subdiv::eval::LimitEvaluator::new(&mesh).unwrap();
    let mut lines = text.lines();
    for f in 0..mesh.face_count() {
        for g in ev.eval_grid(f, 70).unwrap() {
            let p = g.sample.position.as_vec3();
            let head = if mesh.face_size(f) == 4 {
                format!("{f}")
            } else {
                format!("{f}:{}", g.sub)
            };
            let want = format!(
                "{head} {:?} {:?} {:?} {:?} {:?}",
                g.u as f32, g.v as f32, p.x, p.y, p.z
            );
            let line = lines.next().expect("too few lines");
            assert!(line.starts_with(&want), "{line} vs {want}");
        }
    }
    assert!(lines.next().is_none());
}

#[test]
fn obj_accepts_a_byte_order_mark_and_any_line_ends() {
    let plain = obj(QUAD).unwrap();
    for text in [
        format!("\u{feff}{QUAD}"),
        QUAD.replace('\n', "\r\n"),
        format!("\u{feff}{}", QUAD.replace('\n', "\r\n")),
        QUAD.replace('\n', "\r"),
    ] {
        let m = obj(&text).unwrap_or_else(|e| panic!("{text:?}: {e}"));
        assert_eq!(m.positions(), plain.positions());
        assert_eq!(m.face_vertices(), plain.face_vertices());
    }
    // Line numbers still count CRLF lines once.
    let e = obj("v 0 0 0\r\nv 1 0 0\r\nbogus\r\n").unwrap_err();
    assert!(matches!(e, Error::Parse { line: 3, .. }), "{e}");
    // Through a file, as a Windows editor writes it.
    let p = write(
        "bom_crlf.obj",
        format!("\u{feff}{}", QUAD.replace('\n', "\r\n")).as_bytes(),
    );
    let (ok, _, err) = run(&["info", s(&p)]);
    assert!(ok, "{err}");
}

/// A 6 MB line that is wrong gives an error of a few hundred bytes quoting an excerpt.
#[test]
fn an_error_on_a_huge_line_quotes_a_short_excerpt() {
    let huge = "1".repeat(6 << 20);
    for text in [
        format!("v 0 0 0\nv {huge}x 0 0\n"),
        format!("v 0 0 0\nq{huge}\n"),
        format!("{QUAD}f 1 2 {huge}\n"),
        format!("{QUAD}t crease 2/1 0 1 {huge}x\n"),
        format!("{QUAD}t crease {huge}/1 0 1 1\n"),
    ] {
        let e = obj(&text).unwrap_err().to_string();
        assert!(e.len() < 400, "{} bytes: {}", e.len(), &e[..400]);
        assert!(e.contains('…'), "{e}");
    }
    let p = write("huge_line.obj", format!("v 0 0 0 {huge}x\n").as_bytes());
    let (ok, _, err) = run(&["info", s(&p)]);
    assert!(!ok);
    assert!(
        err.len() < 400 && err.contains("line 1"),
        "{}",
        &err[..err.len().min(400)]
    );
}

/// Coordinates near 1e308 loaded and rendered an empty image with exit status 0. The library
/// refuses magnitudes over 1e30 (f64 evaluation and f32 conversion overflow), the GPU commands
/// those over 1e9 (the f32 pipeline's normals overflow), naming the vertex.
#[test]
fn coordinates_that_would_overflow_are_refused_naming_the_vertex() {
    let e = obj("v 0 0 0\nv 1 0 0\nv 1 1e308 0\nv 0 1 0\nf 1 2 3 4\n").unwrap_err();
    assert!(
        matches!(e, Error::CoordinateTooLarge { vertex: 2, .. }),
        "{e}"
    );
    assert!(obj("v 0 0 0\nv 1 0 0\nv 1 1e29 0\nv 0 1 0\nf 1 2 3 4\n").is_ok());
    let mut m = obj(QUAD).unwrap();
    let mut p = m.positions().to_vec();
    p[1].x = -1e31;
    assert!(matches!(
        m.set_positions(&p),
        Err(Error::CoordinateTooLarge { vertex: 1, .. })
    ));
    let f = write(
        "big.obj",
        b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 2e10 0\nf 1 2 3 4\n",
    );
    let png = dir().join("big.png");
    for args in [
        vec!["render", s(&f), "--out", s(&png)],
        vec!["sample", s(&f), "--out", "/dev/null"],
    ] {
        let (ok, _, err) = run(&args);
        assert!(!ok, "{args:?}");
        assert!(err.contains("vertex 3") && err.contains("1e9"), "{err}");
    }
    // The CPU path takes it.
    let (ok, _, err) = run(&["limit", s(&f), "--out", "/dev/null"]);
    assert!(ok, "{err}");
}

/// Every face a hole: `render` wrote an empty image with exit status 0.
#[test]
fn a_mesh_that_draws_nothing_is_an_error() {
    let f = write("all_holes.obj", format!("{QUAD}t hole 1/0 0\n").as_bytes());
    let png = dir().join("holes.png");
    std::fs::remove_file(&png).ok();
    for args in [
        vec!["render", s(&f), "--out", s(&png)],
        vec!["limit", s(&f)],
        vec!["sample", s(&f), "--out", "/dev/null"],
    ] {
        let (ok, out, err) = run(&args);
        assert!(!ok, "{args:?}");
        assert!(out.is_empty());
        assert!(err.contains("nothing to draw"), "{err}");
    }
    assert!(!png.exists());
}

#[test]
fn out_writes_the_format_its_extension_names() {
    let jpg = dir().join("x.jpg");
    let png = dir().join("x.PNG");
    for (p, magic) in [
        (&jpg, &[0xffu8, 0xd8, 0xff][..]),
        (&png, &[0x89, b'P', b'N', b'G'][..]),
    ] {
        std::fs::remove_file(p).ok();
        let (ok, _, err) = run(&["render", "--size", "64x48", "--out", s(p)]);
        assert!(ok, "{err}");
        let bytes = std::fs::read(p).unwrap();
        assert_eq!(&bytes[..magic.len()], magic, "{}", p.display());
    }
    let img = image::open(&jpg).unwrap();
    assert_eq!((img.width(), img.height()), (64, 48));
    for (out, wanted) in [
        ("x.bmp", "unsupported image format `.bmp`"),
        ("x", "no file extension"),
    ] {
        let p = dir().join(out);
        let (ok, _, err) = run(&["render", "--out", s(&p)]);
        assert!(!ok && err.contains(wanted), "{err}");
        assert!(!p.exists());
    }
}

/// `--out` into a missing directory said "cannot read".
#[test]
fn out_into_a_missing_directory_cannot_write() {
    let p = dir().join("no/such/dir/x.png");
    let (ok, _, err) = run(&["render", "--out", s(&p)]);
    assert!(!ok);
    assert!(
        err.contains("cannot write") && err.contains("does not exist"),
        "{err}"
    );
    assert!(!err.contains("cannot read"), "{err}");
    let t = dir().join("no/such/dir/x.txt");
    for args in [
        vec!["limit", "embedded:mixed", "--out", s(&t)],
        vec!["sample", "embedded:mixed", "--out", s(&t)],
    ] {
        let (ok, _, err) = run(&args);
        assert!(!ok && err.contains("cannot write"), "{err}");
    }
}

/// Each limit is named with its flag in the error; the flag raises it.
#[test]
fn input_limits_name_themselves_and_their_flags() {
    let cube = osd_path("catmark_cube");
    let cube = s(&cube);
    for (flag, low, named) in [
        (
            "--max-vertices",
            "7",
            "control vertices: 8 exceeds the limit 7",
        ),
        ("--max-faces", "5", "faces: 6 exceeds the limit 5"),
        ("--max-face-size", "3", "face 0 size: 4 exceeds the limit 3"),
        (
            "--max-valence",
            "2",
            "vertex 0 valence (faces around it): 3 exceeds the limit 2",
        ),
    ] {
        let (ok, _, err) = run(&["limit", cube, flag, low, "--out", "/dev/null"]);
        assert!(!ok);
        assert!(err.contains(named) && err.contains(flag), "{err}");
        let (ok, _, err) = run(&["limit", cube, flag, "1000", "--out", "/dev/null"]);
        assert!(ok, "{err}");
    }
    // The defaults refuse a 2000-sided polygon (its CPU path takes minutes) until raised.
    let f = write(
        "polygon2000.obj",
        common::meshes::polygon_obj(2000).as_bytes(),
    );
    let (ok, _, err) = run(&["render", s(&f), "--out", s(&dir().join("p.png"))]);
    assert!(!ok && err.contains("--max-face-size"), "{err}");
}

/// A 16384 x 16384 frame needs ~3 GiB of targets, more than lavapipe's 2 GiB heap: refused
/// before allocating, naming the estimate and the heap.
#[test]
fn gpu_memory_is_checked_against_the_heap_before_allocating() {
    let png = dir().join("huge.png");
    let (ok, _, err) = run(&["render", "--size", "16384x16384", "--out", s(&png)]);
    assert!(!ok);
    assert!(
        err.contains("GiB of GPU memory") && err.contains("largest heap"),
        "{err}"
    );
    assert!(!png.exists());
}

/// A GPU timeout (injected with a 1 ms wait) is an error, and every object the frame created
/// drops safely while the GPU may still use it: no crash, no validation error (destroying a
/// buffer or image in use would be one), and the context renders again afterwards.
#[test]
fn a_gpu_timeout_is_an_error_and_every_object_drops_safely() {
    use tessera::gpu::{ContextDesc, GpuError};
    use tessera::render::{
        render_to_image, surface_for_scheme_with, OffscreenDesc, PlanOptions, RenderDesc, Scheme,
        SchemeLimits,
    };
    let Some(ctx) = common::gpu::context_with(ContextDesc {
        timeout_ms: 1,
        ..ContextDesc::default()
    }) else {
        return;
    };
    let mesh = tessera::assets::EmbeddedMesh::Mixed.load().unwrap();
    let opts = PlanOptions::new(SchemeLimits::from_context(&ctx));
    let surface = surface_for_scheme_with(&mesh, 64, Scheme::default(), &opts).unwrap();
    let mut render = RenderDesc::default();
    render.tess.level = 64.0;
    let desc = OffscreenDesc {
        width: 1024,
        height: 1024,
        samples: 4,
        ..OffscreenDesc::default()
    };
    let mut timeouts = 0;
    for _ in 0..3 {
        match render_to_image(&ctx, &surface, &render, &desc, false) {
            Err(Error::Gpu(GpuError::Timeout(1))) => timeouts += 1,
            Ok(_) => {}
            Err(e) => panic!("{e}"),
        }
    }
    assert!(timeouts > 0, "no timeout injected");
    common::gpu::assert_validation_clean(&ctx);
}
