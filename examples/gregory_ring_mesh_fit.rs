//! What the rule family of `patch::gregory::tangents_tri` (one edge-tangent factor `s` and one
//! transversal factor `ρ` per ring face-size sequence) can do on one mesh: the factors fitted on
//! the mesh itself instead of on the characteristic nets (every smooth vertex whose ring holds a
//! triangle and otherwise quads; one pair per ring key), by the same ICP normal distance to the
//! exact limit (`gregory::accuracy::closest_exact`, 5 rounds). Prints the RMS normal distance
//! (mesh units) per round, from the paper's construction, and the fitted pairs. A second argument
//! `s` keeps `ρ = 1`.
//!
//! ```sh
//! cargo run --release --example gregory_ring_mesh_fit -- MESH.obj [s]
//! ```

use std::collections::BTreeMap;
use tessera::mesh::ObjOptions;
use tessera::patch::gregory::accuracy::{closest_exact, nearby_exact_samples};
use tessera::patch::gregory::tangent_fit::solve_normal_equations;
use tessera::patch::gregory::tangents_tri::{ring_face_sizes, ring_key, RingFactors};
use tessera::patch::gregory::tangents_tri_fit::{face_samples, with_factors};
use tessera::patch::gregory::{
    check_face, gregory_faces, gregory_patch, gregory_vertices_with, GregoryTangents,
};
use tessera::subdiv::eval::LimitEvaluator;
use tessera::topology::Topology;
use tessera::ControlMesh;

fn main() -> tessera::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let fix_rho = args.get(1).is_some_and(|s| s == "s");
    let mesh = ControlMesh::from_obj_file(&args[0], &ObjOptions::default())?;
    let topo = Topology::new(&mesh)?;
    let ev = LimitEvaluator::new(&mesh)?;
    let dense = ev.eval_all_grids(16)?;
    let paper = gregory_vertices_with(&topo, mesh.positions(), GregoryTangents::Paper);
    let mut keys: BTreeMap<Vec<u8>, usize> = BTreeMap::new();
    let mut key_of = vec![None; topo.vertex_count()];
    for v in 0..topo.vertex_count() as u32 {
        let sizes = ring_face_sizes(&topo, v);
        let smooth = paper[v as usize]
            .as_ref()
            .is_some_and(|g| g.kind == tessera::patch::gregory::VertexKind::Smooth);
        if smooth && sizes.contains(&3) && sizes.iter().all(|&k| k <= 4) {
            let n = keys.len();
            key_of[v as usize] = Some(*keys.entry(ring_key(&sizes)).or_insert(n));
        }
    }
    let nk = keys.len();
    let faces: Vec<u32> = gregory_faces(&topo)
        .into_iter()
        .filter(|&f| check_face(&topo, f).is_ok())
        .collect();
    let build = |fs: &[RingFactors]| {
        let mut verts = paper.clone();
        for (v, k) in key_of.iter().enumerate() {
            if let (Some(k), Some(g)) = (k, paper[v].as_ref()) {
                verts[v] = Some(with_factors(g, fs[*k]));
            }
        }
        faces
            .iter()
            .map(|&f| gregory_patch(&topo, &verts, f).unwrap())
            .collect::<Vec<_>>()
    };
    let mut fs = vec![RingFactors::ONE; nk];
    let unknowns = if fix_rho { nk } else { 2 * nk };
    let cands: Vec<_> = faces
        .iter()
        .map(|&f| nearby_exact_samples(&topo, &dense, f))
        .collect();
    for round in 0..5 {
        let base = build(&fs);
        let mut dirs = Vec::new();
        for k in 0..unknowns {
            let mut g = fs.clone();
            if k < nk {
                g[k].tangent += 1.0;
            } else {
                g[k - nk].transversal += 1.0;
            }
            dirs.push(build(&g));
        }
        let mut a = vec![vec![0.0; unknowns]; unknowns];
        let mut b = vec![0.0; unknowns];
        let (mut e2, mut w) = (0.0, 0.0);
        for (i, &f) in faces.iter().enumerate() {
            for (u, v) in face_samples(topo.face_size(f) == 3) {
                let x = base[i].eval(u, v).position;
                let l = closest_exact(&ev, x, &cands[i], f)?;
                let n = l.sample.normal;
                let d0 = (x - l.sample.position).dot(n);
                let g: Vec<f64> = dirs
                    .iter()
                    .map(|p| (p[i].eval(u, v).position - x).dot(n))
                    .collect();
                for r in 0..unknowns {
                    b[r] -= d0 * g[r];
                    for c in 0..unknowns {
                        a[r][c] += g[r] * g[c];
                    }
                }
                e2 += d0 * d0;
                w += 1.0;
            }
        }
        println!("round {round}: RMS normal distance {:.4e}", (e2 / w).sqrt());
        let x = solve_normal_equations(a, b);
        for k in 0..nk {
            fs[k].tangent += x[k];
            if !fix_rho {
                fs[k].transversal += x[nk + k];
            }
        }
    }
    for (key, &k) in &keys {
        println!(
            "{key:?}: s {:.4} rho {:.4}",
            fs[k].tangent, fs[k].transversal
        );
    }
    Ok(())
}
