//! Every class of hostile, malformed or oversized input tried against the CLI, with what each
//! gets (issue 14). The test runs them all, checks each outcome, and checks that README.md's
//! table between the `input-classes` markers is exactly the table they produce; run with
//! `TESSERA_UPDATE_README=1` to rewrite it after a deliberate change.

mod common;

use std::path::{Path, PathBuf};

/// What a class must get.
enum Expect {
    /// Exit status 0.
    Ok,
    /// A failure whose stderr contains this text.
    Err(&'static str),
}

/// One input class: a file (if any) and the command run on it.
struct Class {
    name: &'static str,
    /// The file written as `DIR/in.obj` (or `DIR/<file name>` with `file`).
    input: Option<Vec<u8>>,
    /// Arguments; `IN` is replaced by the input file, `DIR` by the class's directory.
    args: &'static [&'static str],
    expect: Expect,
}

const QUAD: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
const STRIP: &str = "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\nf 1 2 5 4\nf 2 3 6 5\n";

fn quad_with(extra: &str) -> Option<Vec<u8>> {
    Some(format!("{QUAD}{extra}").into_bytes())
}

fn text(t: &str) -> Option<Vec<u8>> {
    Some(t.as_bytes().to_vec())
}

/// A cone: `n` triangles around one apex (valence n).
fn cone(n: usize) -> Vec<u8> {
    let mut t = String::from("v 0 0 1\n");
    for k in 0..n {
        let a = k as f64 / n as f64 * std::f64::consts::TAU;
        t += &format!("v {:.6} {:.6} 0\n", a.cos(), a.sin());
    }
    for k in 0..n {
        t += &format!("f 1 {} {}\n", k + 2, (k + 1) % n + 2);
    }
    t.into_bytes()
}

fn classes() -> Vec<Class> {
    use Expect::{Err, Ok};
    let info: &'static [&'static str] = &["info", "IN"];
    let c = |name, input, args, expect| Class {
        name,
        input,
        args,
        expect,
    };
    vec![
        // ---- reading the file
        c("missing file", None, info, Err("cannot read DIR/in.obj: No such file")),
        c("a directory as the mesh", None, &["info", "DIR"], Err("cannot read DIR")),
        c("unknown embedded mesh", None, &["info", "embedded:nothing"], Err("no embedded mesh `nothing`")),
        c("empty file", text(""), info, Err("empty mesh: no vertices")),
        c("comments only", text("# nothing\n# here\n"), info, Err("empty mesh: no vertices")),
        c("vertices, no faces", text("v 0 0 0\nv 1 0 0\n"), info, Err("empty mesh: no faces")),
        c("binary garbage", Some(vec![0x00, 0xff, 0xfe, 0x13, 0x37, b'\n', 0x80, 0x81]), info, Err("unknown OBJ statement")),
        c("terminal escape sequence in a bad line", text("\x1b[2J\x1b[31mboom\n"), info, Err("unknown OBJ statement `\\u{1b}[2J\\u{1b}[31mboom`")),
        c("UTF-8 byte-order mark", Some([&[0xef, 0xbb, 0xbf][..], QUAD.as_bytes()].concat()), info, Ok),
        c("CRLF line ends", text(&QUAD.replace('\n', "\r\n")), info, Ok),
        c("CR-only line ends (classic Mac)", text(&QUAD.replace('\n', "\r")), info, Ok),
        c("unknown statement", quad_with("frobnicate 1 2\n"), info, Err("line 6: unknown OBJ statement `frobnicate`")),
        c("valid but unused statement (`l`)", quad_with("l 1 2\n"), info, Ok),
        c("6 MB line", Some(format!("v 0 0 0 {}x\n", "1".repeat(6 << 20)).into_bytes()), info, Err("… (6291465 bytes)")),
        // ---- vertices
        c("vertex with 2 coordinates", text("v 0 0\n"), info, Err("a vertex needs 3 coordinates")),
        c("vertex coordinate not a number", text("v 0 zero 0\n"), info, Err("`zero` is not a number")),
        c("homogeneous w = 0", text("v 0 0 0 0\n"), info, Err("homogeneous coordinate w = 0")),
        c("NaN coordinate", text("v 0 0 0\nv 1 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3 4\n"), info, Err("vertex 2 has a non-finite coordinate")),
        c("infinite coordinate (1e400)", text("v 0 0 0\nv 1 0 0\nv 1 1e400 0\nv 0 1 0\nf 1 2 3 4\n"), info, Err("vertex 2 has a non-finite coordinate")),
        c("coordinate 1e308", text("v 0 0 0\nv 1 0 0\nv 1 1e308 0\nv 0 1 0\nf 1 2 3 4\n"), info, Err("vertex 2 has a coordinate of magnitude 1e308, beyond the supported 1e30")),
        c("coordinate 1e20, drawn on the GPU", text("v 0 0 0\nv 1 0 0\nv 1 1e20 0\nv 0 1 0\nf 1 2 3 4\n"), &["render", "IN", "--out", "DIR/x.png"], Err("vertex 2 has a coordinate of magnitude 1e20, beyond the supported 1e9")),
        c("coordinate 1e20, CPU limit", text("v 0 0 0\nv 1 0 0\nv 1 1e20 0\nv 0 1 0\nf 1 2 3 4\n"), &["limit", "IN", "--out", "DIR/x.txt"], Ok),
        // ---- faces
        c("face index 0", text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n"), info, Err("vertex index 0 (OBJ indices start at 1)")),
        c("face index beyond the vertices", text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"), info, Err("vertex 9 does not exist (the file has 3)")),
        c("relative index before the first vertex", text("v 0 0 0\nf -1 -2 -5\n"), info, Err("relative index -2 reaches before the first vertex")),
        c("face index not a number", text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 c\n"), info, Err("`c` is not a vertex reference")),
        c("face index beyond u32", text("v 0 0 0\nf 1 2 99999999999\n"), info, Err("vertex index 99999999999 is too large")),
        c("face with 2 vertices", text("v 0 0 0\nv 1 0 0\nf 1 2\n"), info, Err("face 0 has 2 vertices (at least 3 needed)")),
        c("repeated vertex in a face", text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 1 3\n"), info, Err("face 0 uses vertex 0 more than once")),
        c("non-manifold edge (3 faces)", text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n"), info, Err("non-manifold edge 0-1: used by 3 faces")),
        c("bow-tie vertex", text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv -1 0 0\nv -1 -1 0\nf 1 2 3\nf 1 4 5\n"), info, Err("non-manifold vertex 0: its faces form 2 separate fans")),
        c("inconsistent winding", text(&STRIP.replace("f 2 3 6 5", "f 2 5 6 3")), info, Err("inconsistent winding")),
        c("unreferenced vertices", quad_with("v 5 5 5\n"), info, Ok),
        // ---- texture coordinates (`vt`)
        c("texture coordinate beyond the vt lines", text("v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\nvt 0 0\nf 1/1 2/1 5/1 4/1\nf 2/1 3/1 6/9 5/1\n"), info, Err("face 1: texture coordinate 9 does not exist (the file has 1)")),
        c("texture coordinate index 0", text("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/0 2/1 3/1\n"), info, Err("face 0: texture coordinate index 0 (OBJ indices start at 1)")),
        c("texture coordinates on some faces only (warning)", text("v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\nvt 0 0\nf 1/1 2/1 5/1 4/1\nf 2 3 6 5\n"), info, Ok),
        c("texture coordinates on some corners only", text("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2 3/1\n"), info, Err("face 0: texture coordinates on some corners only")),
        c("texture coordinate not a number", text("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 nan\nf 1/1 2/1 3/1\n"), info, Err("`nan` is not a finite number")),
        // ---- displacement maps (`--displacement FILE.png`; run from the checkout)
        c("displacement map missing", None, &["render", "--displacement", "DIR/none.png", "--out", "DIR/x.png"], Err("cannot read DIR/none.png: No such file")),
        c("displacement map not an image", text(QUAD), &["render", "--displacement", "IN", "--out", "DIR/x.png"], Err("cannot decode image DIR/in.obj")),
        c("displacement map on a mesh without vt", None, &["render", "--displacement", "assets/displacement_bumps.png", "--out", "DIR/x.png"], Err("the mesh has no texture coordinates (OBJ `vt` lines")),
        c("displacement map on a mesh with vt", text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n"), &["render", "IN", "--displacement", "assets/displacement_bumps.png", "--size", "32x32", "--out", "DIR/x.png"], Ok),
        // ---- tags
        c("tag without counts", quad_with("t crease\n"), info, Err("a tag needs a name and nint/nfloat[/nstring] counts")),
        c("tag counts not numbers", quad_with("t crease a/b 0 1 1\n"), info, Err("bad argument counts `a/b`")),
        c("tag counts disagree with the line", quad_with("t crease 2/1 0 1\n"), info, Err("counts `2/1` announce 3 arguments, the line has 2")),
        c("crease with an odd number of indices", quad_with("t crease 3/1 0 1 2 1\n"), info, Err("crease expects 2k vertex indices")),
        c("negative tag index", quad_with("t crease 2/1 0 -1 1\n"), info, Err("`-1` is not a non-negative integer index")),
        c("crease on a missing edge", quad_with("t crease 2/1 0 2 1\n"), info, Err("crease 0: 0-2 is not an edge of the mesh")),
        c("crease vertex out of range", quad_with("t crease 2/1 0 9 1\n"), info, Err("crease 0: index 9 out of range (limit 4)")),
        c("negative sharpness", quad_with("t crease 2/1 0 1 -2\n"), info, Err("crease 0: invalid sharpness -2")),
        c("NaN sharpness", quad_with("t corner 1/1 0 nan\n"), info, Err("corner 0: invalid sharpness NaN")),
        c("corner out of range", quad_with("t corner 1/1 7 1\n"), info, Err("corner 0: index 7 out of range (limit 4)")),
        c("hole out of range", quad_with("t hole 1/0 3\n"), info, Err("hole 0: index 3 out of range (limit 1)")),
        c("interpolateboundary mode 5", quad_with("t interpolateboundary 1/0 5\n"), info, Err("interpolateboundary mode 5 (expected 0, 1 or 2)")),
        c("unknown creasemethod", quad_with("t creasemethod 0/0/1 sharp\n"), info, Err("creasemethod `sharp` (expected normal or chaikin)")),
        c("unknown smoothtriangles", quad_with("t smoothtriangles 0/0/1 loop\n"), info, Err("smoothtriangles `loop`")),
        c("unknown tag (warning)", quad_with("t frobnicate 0/0\n"), info, Ok),
        // ---- nothing to draw
        c("every face a hole: render", quad_with("t hole 1/0 0\n"), &["render", "IN", "--out", "DIR/x.png"], Err("nothing to draw")),
        c("every face a hole: limit", quad_with("t hole 1/0 0\n"), &["limit", "IN"], Err("nothing to draw")),
        c("no interpolated boundary on an open quad", quad_with("t interpolateboundary 1/0 0\n"), &["limit", "IN"], Err("nothing to draw")),
        // ---- resource limits
        c("more vertices than --max-vertices", text(QUAD), &["limit", "IN", "--max-vertices", "3"], Err("control vertices: 4 exceeds the limit 3 (raise it with --max-vertices)")),
        c("more faces than --max-faces", text(STRIP), &["limit", "IN", "--max-faces", "1"], Err("faces: 2 exceeds the limit 1 (raise it with --max-faces)")),
        c("2000-sided polygon", Some(common::meshes::polygon_obj(2000).into_bytes()), &["render", "IN", "--out", "DIR/x.png"], Err("face 0 size: 2000 exceeds the limit 1024 (raise it with --max-face-size)")),
        c("valence-2000 cone", Some(cone(2000)), &["limit", "IN"], Err("vertex 0 valence (faces around it): 2000 exceeds the limit 1024 (raise it with --max-valence)")),
        c("GPU memory over the heap (--size 16384x16384)", None, &["render", "--size", "16384x16384", "--out", "DIR/x.png"], Err("GiB of GPU memory, more than the device's largest heap")),
        // ---- arguments and output
        c("--grid 0", None, &["limit", "embedded:mixed", "--grid", "0"], Err("--grid must be at least 1")),
        c("--size 0x5", None, &["render", "--size", "0x5", "--out", "DIR/x.png"], Err("width and height must be in 1..=16384")),
        c("--size not WxH", None, &["render", "--size", "big", "--out", "DIR/x.png"], Err("expected WxH")),
        c("--size beyond 16384", None, &["render", "--size", "20000x10", "--out", "DIR/x.png"], Err("width and height must be in 1..=16384")),
        c("--tess 0", None, &["render", "--tess", "0", "--out", "DIR/x.png"], Err("the tessellation level must be at least 1")),
        c("--msaa 3", None, &["render", "--msaa", "3", "--out", "DIR/x.png"], Err("--msaa 3: the device supports")),
        c("--camera garbage", None, &["render", "--camera", "north", "--out", "DIR/x.png"], Err("camera")),
        c("--up w", None, &["render", "--up", "w", "--out", "DIR/x.png"], Err("`w`")),
        c("--out .bmp", None, &["render", "--out", "DIR/x.bmp"], Err("unsupported image format `.bmp` (use .png, .jpg or .jpeg)")),
        c("--out without extension", None, &["render", "--out", "DIR/x"], Err("no file extension")),
        c("--out .jpg", None, &["render", "--size", "32x32", "--out", "DIR/x.jpg"], Ok),
        c("--out into a missing directory", None, &["render", "--out", "DIR/no/x.png"], Err("cannot write DIR/no/x.png: the directory DIR/no does not exist")),
        c("limit --out into a missing directory", None, &["limit", "embedded:mixed", "--out", "DIR/no/x.txt"], Err("cannot write DIR/no/x.txt: No such file or directory")),
        c("TESSERA_DEVICE names no device", None, &["render", "--out", "DIR/x.png", "ENV:TESSERA_DEVICE=nonexistent"], Err("TESSERA_DEVICE=\"nonexistent\" matches no Vulkan device; devices:")),
    ]
}

/// What a class got: exit status and the first `error:` line (or the first stderr line).
struct Outcome {
    ok: bool,
    line: String,
}

fn run_class(class: &Class, dir: &Path) -> Outcome {
    let d = dir.to_str().unwrap();
    let input = dir.join("in.obj");
    if let Some(bytes) = &class.input {
        std::fs::write(&input, bytes).unwrap();
    }
    let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_tessera"));
    cmd.env("TESSERA_VALIDATION", "1");
    for a in class.args {
        if let Some(kv) = a.strip_prefix("ENV:") {
            let (k, v) = kv.split_once('=').unwrap();
            cmd.env(k, v);
            continue;
        }
        cmd.arg(a.replace("IN", input.to_str().unwrap()).replace("DIR", d));
    }
    let out = cmd.output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).replace(d, "DIR");
    let line = stderr
        .lines()
        .find(|l| l.starts_with("error:"))
        .or_else(|| stderr.lines().find(|l| l.starts_with("warning:")))
        .unwrap_or("")
        .to_string();
    Outcome {
        ok: out.status.success(),
        line,
    }
}

/// Keeps the table independent of the device: the heap's size and name are elided.
fn normalise(line: &str) -> String {
    let mut s = line.to_string();
    if let Some(at) = s.find("largest heap (") {
        let start = at + "largest heap (".len();
        if let Some(end) = s[start..].find("):") {
            s.replace_range(start..start + end, "…");
        }
    }
    if let Some(at) = s.find("needs about ") {
        let start = at + "needs about ".len();
        if let Some(end) = s[start..].find(" GiB") {
            s.replace_range(start..start + end, "N");
        }
    }
    if let Some(at) = s.find("devices:") {
        s.truncate(at + "devices:".len());
        s.push_str(" …");
    }
    s
}

fn cell(s: &str) -> String {
    s.replace('|', "\\|").replace('`', "'")
}

const BEGIN: &str = "<!-- input-classes:begin (generated by tests/input_classes.rs) -->";
const END: &str = "<!-- input-classes:end -->";

#[test]
fn every_input_class_gets_its_answer_and_the_readme_lists_them() {
    let classes = classes();
    assert!(classes.len() >= 40, "{} classes", classes.len());
    let root = common::out_dir("input_classes");
    let mut table = format!(
        "{BEGIN}\n{} input classes, each run by `tests/input_classes.rs` (`DIR` is a scratch \
         directory, `IN` the input file):\n\n| # | input | command | exit | message |\n|---|---|---|---|---|\n",
        classes.len()
    );
    let mut failures = Vec::new();
    for (k, class) in classes.iter().enumerate() {
        let dir: PathBuf = root.join(format!("c{k:02}"));
        std::fs::remove_dir_all(&dir).ok();
        std::fs::create_dir_all(&dir).unwrap();
        let got = run_class(class, &dir);
        let good = match class.expect {
            Expect::Ok => got.ok,
            Expect::Err(text) => !got.ok && got.line.contains(text),
        };
        if !good {
            failures.push(format!("{}: exit ok={} `{}`", class.name, got.ok, got.line));
        }
        let args: Vec<&str> = class
            .args
            .iter()
            .copied()
            .filter(|a| !a.starts_with("ENV:"))
            .collect();
        let env: String = class
            .args
            .iter()
            .filter_map(|a| a.strip_prefix("ENV:"))
            .map(|e| format!("{e} "))
            .collect();
        let message = if got.line.is_empty() {
            "—".to_string()
        } else {
            normalise(&got.line)
        };
        table += &format!(
            "| {} | {} | `{env}tessera {}` | {} | {} |\n",
            k + 1,
            cell(class.name),
            cell(&args.join(" ")),
            if got.ok { 0 } else { 1 },
            cell(&message)
        );
    }
    table += END;
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    let readme_path = Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md");
    let readme = std::fs::read_to_string(&readme_path).unwrap();
    let (Some(b), Some(e)) = (readme.find(BEGIN), readme.find(END)) else {
        panic!("README.md has no input-classes markers");
    };
    let current = &readme[b..e + END.len()];
    if current != table {
        if std::env::var("TESSERA_UPDATE_README").as_deref() == Ok("1") {
            let new = format!("{}{}{}", &readme[..b], table, &readme[e + END.len()..]);
            std::fs::write(&readme_path, new).unwrap();
        } else {
            panic!(
                "README.md's input-class table is out of date (TESSERA_UPDATE_README=1 rewrites it); \
                 expected:\n{table}"
            );
        }
    }
}
