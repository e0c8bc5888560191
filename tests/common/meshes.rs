//! The meshes the tests load: the OpenSubdiv regression shapes in `shared/meshes/osd` beside the
//! checkout, and the embedded meshes.

use std::fmt::Write as _;
use std::path::PathBuf;

use tessera::assets::EmbeddedMesh;
use tessera::mesh::{ControlMesh, ObjOptions};

/// `<checkout>/../shared/meshes/osd`.
pub fn osd_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/meshes/osd")
}

/// The OBJ file of shape `name` (without `.obj`).
pub fn osd_path(name: &str) -> PathBuf {
    osd_dir().join(format!("{name}.obj"))
}

/// Every shape's name (without `.obj`), sorted.
pub fn osd_names() -> Vec<String> {
    let dir = osd_dir();
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .filter_map(|e| {
            let name = e.ok()?.file_name().into_string().ok()?;
            name.strip_suffix(".obj").map(str::to_string)
        })
        .collect();
    names.sort();
    names
}

/// The options a shape of the corpus is meant to be read with (`catmark_lefthanded` is
/// left-handed).
pub fn corpus_options(name: &str) -> ObjOptions {
    ObjOptions {
        left_handed: name == "catmark_lefthanded",
        check_with_tobj: true,
    }
}

/// Shape `name` with the default options, or the loader's error.
pub fn try_osd(name: &str) -> tessera::Result<ControlMesh> {
    ControlMesh::from_obj_file(osd_path(name), &ObjOptions::default())
}

/// Shape `name` with the default options (panics naming the shape).
pub fn osd(name: &str) -> ControlMesh {
    try_osd(name).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Embedded mesh `name` (`mixed`, `open`, `creased`).
pub fn embedded(name: &str) -> ControlMesh {
    EmbeddedMesh::from_name(name)
        .unwrap_or_else(|| panic!("no embedded mesh {name}"))
        .load()
        .unwrap()
}

/// `embedded:NAME` or the name of a shape of the corpus.
pub fn mesh(spec: &str) -> ControlMesh {
    match spec.strip_prefix("embedded:") {
        Some(name) => embedded(name),
        None => osd(spec),
    }
}

/// `catmark_gregory_test0` to `8` with their names, leaving out the ones the mesh layer refuses
/// (`catmark_gregory_test4` is non-manifold on purpose: a typed error).
pub fn gregory_test_meshes() -> Vec<(String, ControlMesh)> {
    (0..9)
        .map(|k| format!("catmark_gregory_test{k}"))
        .filter_map(|name| try_osd(&name).ok().map(|m| (name, m)))
        .collect()
}

/// OBJ text of one regular `n`-sided polygon in the z = 0 plane (unit circumradius).
pub fn polygon_obj(n: usize) -> String {
    let mut t = String::new();
    for k in 0..n {
        let a = k as f64 / n as f64 * std::f64::consts::TAU;
        t += &format!("v {:.6} {:.6} 0\n", a.cos(), a.sin());
    }
    t += "f";
    for k in 1..=n {
        t += &format!(" {k}");
    }
    t.push('\n');
    t
}

/// The faces of the cube with vertex k = (x, y, z) bits (x + 2y + 4z), each counter-clockwise
/// seen from outside.
pub const CUBE_FACES: [[u32; 4]; 6] = [
    [0, 2, 3, 1],
    [4, 5, 7, 6],
    [0, 1, 5, 4],
    [2, 6, 7, 3],
    [0, 4, 6, 2],
    [1, 3, 7, 5],
];

/// A closed capsule: `n` segments, `rings` rings of quads, a triangle fan (polar
/// configuration of valence `n`) at each end; slightly irregular so nothing is symmetric.
pub fn capsule(n: usize, rings: usize) -> ControlMesh {
    let mut s = String::new();
    for r in 0..rings {
        let z = r as f64 - (rings as f64 - 1.0) / 2.0;
        for k in 0..n {
            let a = std::f64::consts::TAU * k as f64 / n as f64 + 0.1 * r as f64;
            let rad = 1.0 + 0.15 * ((3 * k + r) % 4) as f64;
            s += &format!("v {} {} {}\n", rad * a.cos(), rad * a.sin(), z);
        }
    }
    let top = rings * n + 1;
    s += &format!("v 0.1 -0.05 {}\n", rings as f64 / 2.0 + 0.4);
    s += &format!("v -0.05 0.1 {}\n", -(rings as f64) / 2.0 - 0.3);
    let id = |r: usize, k: usize| r * n + (k % n) + 1;
    for r in 0..rings - 1 {
        for k in 0..n {
            s += &format!(
                "f {} {} {} {}\n",
                id(r, k),
                id(r, k + 1),
                id(r + 1, k + 1),
                id(r + 1, k)
            );
        }
    }
    for k in 0..n {
        s += &format!("f {} {} {}\n", id(rings - 1, k), id(rings - 1, k + 1), top);
        s += &format!("f {} {} {}\n", id(0, k + 1), id(0, k), top + 1);
    }
    ControlMesh::from_obj_str(&s, "capsule", &ObjOptions::default()).unwrap()
}

/// `m` written as OBJ with one `vt` per vertex (a function of its position) that every face
/// corner at the vertex references: shared texture coordinates everywhere.
pub fn with_shared_uvs(m: &ControlMesh) -> String {
    let mut text = String::new();
    for p in m.positions() {
        let _ = writeln!(text, "v {} {} {}", p.x, p.y, p.z);
    }
    for p in m.positions() {
        let _ = writeln!(
            text,
            "vt {} {}",
            0.5 * p.x + 0.25 * p.y,
            0.5 * p.z - 0.125 * p.x
        );
    }
    for f in 0..m.face_count() {
        text.push('f');
        for &v in m.face(f) {
            let _ = write!(text, " {}/{}", v + 1, v + 1);
        }
        text.push('\n');
    }
    text
}
