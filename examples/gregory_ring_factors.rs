//! The fitted factors of `patch::gregory::tangents_tri` (edge tangents `s` and transversal
//! vectors `ρ` at smooth vertices whose ring holds triangles): prints the fit for the ring
//! configurations of the given meshes (or a default list) with the fitted RMS distance at the
//! paper's `(1, 1)` and at the fit, and the closest-point accuracy (`gregory::accuracy`) of
//! each mesh with the paper's and the optimal tangents.
//!
//! ```sh
//! cargo run --release --example gregory_ring_factors -- [MESH.obj | embedded:NAME]...
//! ```
//! Without arguments it fits the rings `tangents_tri::FITTED_FACTORS` tabulates and prints the
//! table to paste.

use std::collections::BTreeSet;
use tessera::mesh::ObjOptions;
use tessera::patch::gregory::accuracy::{measure_tangents, AccuracyOptions};
use tessera::patch::gregory::tangents_tri::{ring_face_sizes, ring_key, RingFactors};
use tessera::patch::gregory::tangents_tri_fit::{fit_error, fit_factors, fit_terms};
use tessera::patch::gregory::GregoryTangents;
use tessera::topology::Topology;
use tessera::ControlMesh;

fn load(path: &str) -> tessera::Result<ControlMesh> {
    if let Some(name) = path.strip_prefix("embedded:") {
        tessera::assets::EmbeddedMesh::from_name(name)
            .ok_or_else(|| tessera::Error::Invalid(format!("no embedded mesh {name}")))?
            .load()
    } else {
        ControlMesh::from_obj_file(path, &ObjOptions::default())
    }
}

/// The keys `tangents_tri::FITTED_FACTORS` tabulates: all-triangle rings of valence 3 to 24,
/// and every ring of triangles and quads with both, of valence 3 to 8.
fn tabulated_keys() -> BTreeSet<Vec<u8>> {
    let mut keys: BTreeSet<Vec<u8>> = (3..=24).map(|n| vec![3; n]).collect();
    for n in 3..=8usize {
        for bits in 0..1u32 << n {
            let sizes: Vec<usize> = (0..n).map(|i| 3 + (bits >> i & 1) as usize).collect();
            if sizes.contains(&3) && sizes.contains(&4) {
                keys.insert(ring_key(&sizes));
            }
        }
    }
    keys
}

fn main() -> tessera::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut keys: BTreeSet<Vec<u8>> = BTreeSet::new();
    let mut meshes = Vec::new();
    for path in &args {
        let mesh = load(path)?;
        let topo = Topology::new(&mesh)?;
        for v in 0..topo.vertex_count() as u32 {
            let sizes = ring_face_sizes(&topo, v);
            if !topo.is_boundary_vertex(v)
                && sizes.len() >= 3
                && sizes.contains(&3)
                && sizes.iter().all(|&k| k <= 4)
            {
                keys.insert(ring_key(&sizes));
            }
        }
        meshes.push((path.clone(), mesh));
    }
    if args.is_empty() {
        keys.extend(tabulated_keys());
    }
    println!("ring            s         rho       RMS paper   RMS fitted");
    let mut table = Vec::new();
    for key in &keys {
        let sizes: Vec<usize> = key.iter().map(|&k| k as usize).collect();
        let f = fit_factors(&sizes)?;
        let t = fit_terms(&sizes, f)?;
        println!(
            "{:<15} {:.6}  {:.6}  {:.4e}  {:.4e}",
            format!("{sizes:?}"),
            f.tangent,
            f.transversal,
            fit_error(&t, RingFactors::ONE).max(0.0).sqrt(),
            fit_error(&t, f).max(0.0).sqrt()
        );
        table.push(format!(
            "    (&{key:?}, {:?}, {:?}),",
            f.tangent as f32, f.transversal as f32
        ));
    }
    if args.is_empty() {
        println!(
            "\npub const FITTED_FACTORS: &[(&[u8], f32, f32)] = &[\n{}\n];",
            table.join("\n")
        );
    }
    let options = AccuracyOptions {
        grid: 8,
        include_regular: false,
    };
    for (path, mesh) in &meshes {
        for t in [GregoryTangents::Paper, GregoryTangents::Optimal] {
            let r = measure_tangents(mesh, &options, t, false)?.0;
            println!(
                "{path} {t}: RMS {:.3e} max {:.3e} normal RMS {:.3e} max {:.3e}",
                r.rms_distance, r.max_distance, r.rms_normal, r.max_normal
            );
        }
    }
    Ok(())
}
