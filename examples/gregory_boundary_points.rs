//! Dev tool: the Gregory control points of a mesh's Gregory quads beside OpenSubdiv's
//! Gregory-basis points (`osd_eval MESH 0 0 points`), and captures with OpenSubdiv's points
//! substituted by kind, to see which points carry an accuracy difference (docs/measured.md, issue 10).
//!
//! ```sh
//! cargo run --example gregory_boundary_points -- MESH.obj CAPTURE.txt OSD_POINTS.txt OUTDIR [paper|optimal]
//! python3 tools/osd_eval/metro.py exact.txt OUTDIR/ours.txt DIAGONAL
//! ```
//!
//! `CAPTURE.txt` is a `tessera sample --scheme gregory-stencil` capture; every line of a Gregory
//! quad is re-evaluated on the CPU from the substituted points (other lines are copied), one file
//! per substitution: `ours` (none), `osd` (all 20), `osd_e` (edge points), `osd_f` (face points),
//! `osd_p` (corner points), each restricted to corners of boundary or crease vertices when the name
//! ends in `_b` (`osd_ef_b`: edge and face points), and `osd_f_corner1` (face points at corners
//! of vertices with one face). Prints, per face and corner, the distance of each point from
//! OpenSubdiv's. Run with `TESSERA_GREGORY_TANGENTS` unset for `optimal`.

use glam::DVec3;
use std::collections::HashMap;
use std::fmt::Write as _;
use tessera::mesh::ObjOptions;
use tessera::patch::gregory::{
    check_face_level0, gregory_faces, gregory_patch, gregory_vertices_with, GregoryPatch,
    GregoryQuad, GregoryTangents,
};
use tessera::topology::Topology;
use tessera::ControlMesh;

const KINDS: [&str; 5] = ["P", "Ep", "Em", "Fp", "Fm"];

fn slot(q: &mut GregoryQuad, k: usize, i: usize) -> &mut DVec3 {
    match k {
        0 => &mut q.p[i],
        1 => &mut q.e_plus[i],
        2 => &mut q.e_minus[i],
        3 => &mut q.f_plus[i],
        _ => &mut q.f_minus[i],
    }
}

fn main() -> tessera::Result<()> {
    let a: Vec<String> = std::env::args().collect();
    let bad = |e: std::io::Error| tessera::Error::Invalid(e.to_string());
    let tangents: GregoryTangents = a.get(5).map(|s| s.parse().unwrap()).unwrap_or_default();
    let mesh = ControlMesh::from_obj_file(&a[1], &ObjOptions::default())?;
    let topo = Topology::new(&mesh)?;
    let verts = gregory_vertices_with(&topo, mesh.positions(), tangents);
    let mut osd: HashMap<(u32, usize, usize), DVec3> = HashMap::new();
    for line in std::fs::read_to_string(&a[3]).map_err(bad)?.lines() {
        let t: Vec<&str> = line.split_whitespace().collect();
        let k = KINDS.iter().position(|&n| n == t[2]).unwrap();
        let x: Vec<f64> = t[3..6].iter().map(|s| s.parse().unwrap()).collect();
        osd.insert(
            (t[0].parse().unwrap(), t[1].parse().unwrap(), k),
            DVec3::new(x[0], x[1], x[2]),
        );
    }
    let mut patches: HashMap<u32, GregoryQuad> = HashMap::new();
    for f in gregory_faces(&topo) {
        if check_face_level0(&topo, f).is_err() {
            continue;
        }
        if let Ok(GregoryPatch::Quad(q)) = gregory_patch(&topo, &verts, f) {
            patches.insert(f, q);
        }
    }
    let on_crease = |v: u32| {
        topo.is_boundary_vertex(v)
            || topo
                .vertex_edges(v)
                .iter()
                .any(|&e| topo.edge_sharpness(e) >= tessera::mesh::INFINITE_SHARPNESS)
    };
    let mut faces: Vec<u32> = patches.keys().copied().collect();
    faces.sort();
    for &f in &faces {
        let q = patches[&f];
        let fv = topo.face_vertices(f);
        for (i, &v) in fv.iter().enumerate() {
            let mut line = format!("face {f} corner {i} v{v} crease {}:", on_crease(v));
            for (k, name) in KINDS.iter().enumerate() {
                let mut qq = q;
                if let Some(o) = osd.get(&(f, i, k)) {
                    write!(line, " {name} {:.2e}", (*slot(&mut qq, k, i) - *o).length()).unwrap();
                }
            }
            println!("{line}");
        }
    }
    let variants: [(&str, &[usize], bool); 10] = [
        ("osd_f_corner1", &[3, 4], true),
        ("ours", &[], false),
        ("osd", &[0, 1, 2, 3, 4], false),
        ("osd_e", &[1, 2], false),
        ("osd_f", &[3, 4], false),
        ("osd_p", &[0], false),
        ("osd_b", &[0, 1, 2, 3, 4], true),
        ("osd_e_b", &[1, 2], true),
        ("osd_f_b", &[3, 4], true),
        ("osd_ef_b", &[1, 2, 3, 4], true),
    ];
    let capture = std::fs::read_to_string(&a[2]).map_err(bad)?;
    let dir = std::path::PathBuf::from(&a[4]);
    std::fs::create_dir_all(&dir).map_err(bad)?;
    for (name, kinds, boundary_only) in variants {
        let mut sub = patches.clone();
        for (&f, q) in sub.iter_mut() {
            let fv = topo.face_vertices(f);
            for (i, &v) in fv.iter().enumerate() {
                if name == "osd_f_corner1" && topo.vertex_faces(v).len() != 1 {
                    continue;
                }
                if boundary_only && !on_crease(v) {
                    continue;
                }
                for &k in kinds {
                    if let Some(o) = osd.get(&(f, i, k)) {
                        *slot(q, k, i) = *o;
                    }
                }
            }
        }
        let mut out = String::new();
        for line in capture.lines() {
            let t: Vec<&str> = line.split_whitespace().collect();
            let f: Option<u32> = t.first().and_then(|s| s.parse().ok());
            match f.and_then(|f| sub.get(&f)) {
                Some(q) if t.len() >= 9 => {
                    let (u, v): (f64, f64) = (t[1].parse().unwrap(), t[2].parse().unwrap());
                    let x = q.eval(u, v);
                    let n = x.du.cross(x.dv).normalize_or_zero();
                    let p = x.position;
                    writeln!(
                        out,
                        "{} {u} {v} {} {} {} {} {} {}",
                        t[0], p.x, p.y, p.z, n.x, n.y, n.z
                    )
                    .unwrap();
                }
                _ => writeln!(out, "{line}").unwrap(),
            }
        }
        std::fs::write(dir.join(format!("{name}.txt")), out).map_err(bad)?;
    }
    Ok(())
}
