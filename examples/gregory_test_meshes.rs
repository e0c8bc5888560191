//! Writes the two test meshes of the Gregory triangle rule (`patch::gregory::tangents_tri`):
//!
//! - `assets/uvsphere_tricaps.obj`: a uv-sphere of radius 1, 8 longitudes × 5 latitude rings
//!   (polar angles `kπ/6`, `k = 1..=5`), quads between the rings and each pole fanned by 8
//!   triangles (poles of valence 8, all triangles; the first rings' vertices two triangles and
//!   two quads);
//! - `assets/prism_tqp.obj`: a prism of height 1.2 over a decagon of radius 1 whose caps are
//!   split into a pentagon (radius 0.5, corners at the decagon's even corners' angles), five
//!   triangles and five quads: triangles, quads and pentagons in one ring.
//!
//! ```sh
//! cargo run --example gregory_test_meshes -- assets
//! ```
//! `tests/gregory_triangles.rs` regenerates both and compares them with the files.

use std::f64::consts::PI;
use std::fmt::Write as _;

/// OBJ text of `positions` and 0-based `faces`.
pub fn obj(comment: &str, positions: &[[f64; 3]], faces: &[Vec<usize>]) -> String {
    let mut s = format!("# {comment}\n");
    for p in positions {
        let _ = writeln!(s, "v {:.9} {:.9} {:.9}", p[0], p[1], p[2]);
    }
    for f in faces {
        let idx: Vec<String> = f.iter().map(|i| (i + 1).to_string()).collect();
        let _ = writeln!(s, "f {}", idx.join(" "));
    }
    s
}

/// The uv-sphere with triangle caps (module docs).
pub fn uvsphere_tricaps() -> String {
    let (lon, lat) = (8usize, 5usize);
    let mut p = vec![[0.0, 0.0, 1.0]];
    for k in 1..=lat {
        let th = k as f64 * PI / (lat + 1) as f64;
        for j in 0..lon {
            let ph = 2.0 * PI * j as f64 / lon as f64;
            p.push([th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()]);
        }
    }
    p.push([0.0, 0.0, -1.0]);
    let ring = |k: usize, j: usize| 1 + k * lon + j % lon;
    let south = p.len() - 1;
    let mut f = Vec::new();
    for j in 0..lon {
        f.push(vec![0, ring(0, j), ring(0, j + 1)]);
    }
    for k in 0..lat - 1 {
        for j in 0..lon {
            f.push(vec![
                ring(k, j),
                ring(k + 1, j),
                ring(k + 1, j + 1),
                ring(k, j + 1),
            ]);
        }
    }
    for j in 0..lon {
        f.push(vec![south, ring(lat - 1, j + 1), ring(lat - 1, j)]);
    }
    obj(
        "uv-sphere, 8 longitudes x 5 latitudes, triangle-fanned poles (examples/gregory_test_meshes.rs)",
        &p,
        &f,
    )
}

/// The triangle/quad/pentagon prism (module docs).
pub fn prism_tqp() -> String {
    let mut p = Vec::new();
    // Per cap (z = ±0.6): 10 outer corners, then 5 inner ones.
    for z in [0.6, -0.6] {
        for i in 0..10 {
            let a = 2.0 * PI * i as f64 / 10.0;
            p.push([a.cos(), a.sin(), z]);
        }
        for k in 0..5 {
            let a = 2.0 * PI * (2 * k) as f64 / 10.0;
            p.push([0.5 * a.cos(), 0.5 * a.sin(), z]);
        }
    }
    let o = |cap: usize, i: usize| cap * 15 + i % 10;
    let inner = |cap: usize, k: usize| cap * 15 + 10 + k % 5;
    let mut f: Vec<Vec<usize>> = Vec::new();
    for cap in 0..2 {
        let mut cap_faces = vec![(0..5).map(|k| inner(cap, k)).collect::<Vec<_>>()];
        for k in 0..5 {
            cap_faces.push(vec![inner(cap, k), o(cap, 2 * k), o(cap, 2 * k + 1)]);
            cap_faces.push(vec![
                inner(cap, k),
                o(cap, 2 * k + 1),
                o(cap, 2 * k + 2),
                inner(cap, k + 1),
            ]);
        }
        for mut face in cap_faces {
            if cap == 1 {
                face.reverse(); // the bottom cap faces down
            }
            f.push(face);
        }
    }
    for i in 0..10 {
        f.push(vec![o(1, i), o(1, i + 1), o(0, i + 1), o(0, i)]);
    }
    obj(
        "prism over a decagon, caps split into a pentagon, 5 triangles and 5 quads (examples/gregory_test_meshes.rs)",
        &p,
        &f,
    )
}

#[allow(dead_code)]
fn main() -> std::io::Result<()> {
    let dir = std::path::PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "assets".into()));
    std::fs::write(dir.join("uvsphere_tricaps.obj"), uvsphere_tricaps())?;
    std::fs::write(dir.join("prism_tqp.obj"), prism_tqp())?;
    Ok(())
}
