//! Times the CPU preprocessing of `--scheme adaptive` on one mesh (what `benches/adaptive.rs`
//! does for the car, for any OBJ), single run per step: for profiling
//! (`perf record`) and peak memory (`/usr/bin/time -v`) of inputs too slow for criterion.
//!
//! ```sh
//! cargo run --release --example adaptive_preprocess -- MESH.obj [ISOLATION] [REPEAT] [cold] [no-lattice]
//! # a 1000-gon:
//! python3 -c "import math; n=1000; print(*[f'v {math.cos(2*math.pi*k/n):.6f} {math.sin(2*math.pi*k/n):.6f} 0' for k in range(n)], 'f ' + ' '.join(map(str, range(1, n + 1))), sep='\n')" > gon1000.obj
//! ```

use std::sync::Arc;
use std::time::Instant;

use tessera::mesh::ObjOptions;
use tessera::patch::adaptive::AdaptiveDrawTables;
use tessera::render::schemes::adaptive::AdaptiveTables;
use tessera::render::{PlanOptions, SchemeLimits};
use tessera::subdiv::adaptive::{AdaptiveOptions, AdaptiveRefinement};
use tessera::subdiv::Level;
use tessera::topology::Topology;
use tessera::ControlMesh;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let spec = args
        .first()
        .ok_or("usage: adaptive_preprocess MESH.obj [ISOLATION] [REPEAT] [cold] [no-lattice]")?;
    let isolation: u32 = args.get(1).map_or(Ok(2), |s| s.parse())?;
    // REPEAT builds of the whole `AdaptiveTables::new` (for `perf record`; 0: none).
    let repeat: u32 = args.get(2).map_or(Ok(1), |s| s.parse())?;
    // `cold`: without the refinement and draw tables of the default options first, so the
    // first `AdaptiveTables::new` is the process's first build (instruction counts of a single
    // cold build: `… 1 cold` minus `… 0 cold`).
    let flags = args.get(3..).unwrap_or_default();
    let cold = flags.iter().any(|s| s == "cold");
    // `no-lattice`: every build without the lattice normal frames (`--lattice-normals false`,
    // `AdaptiveOptions::lattice_normals`).
    let lattice_normals = !flags.iter().any(|s| s == "no-lattice");
    if let Some(unknown) = flags.iter().find(|s| *s != "cold" && *s != "no-lattice") {
        return Err(format!("unknown flag {unknown:?} (cold, no-lattice)").into());
    }
    let options = ObjOptions::default();
    let mesh = ControlMesh::from_obj_file(spec, &options)?;
    let topo = Arc::new(Topology::new(&mesh)?);
    if !cold {
        let base = Level::from_topology((*topo).clone());
        let t = Instant::now();
        let refinement = AdaptiveRefinement::with_options(
            &base,
            AdaptiveOptions {
                lattice_normals,
                ..AdaptiveOptions::new(isolation)
            },
        )?;
        println!("AdaptiveRefinement::new {:.3} s", t.elapsed().as_secs_f64());
        let t = Instant::now();
        let draw = AdaptiveDrawTables::new(&refinement)?;
        println!(
            "AdaptiveDrawTables::new {:.3} s ({} end caps, {} row terms)",
            t.elapsed().as_secs_f64(),
            draw.end_caps.len(),
            draw.rows.ids.len()
        );
    }
    if repeat == 0 {
        return Ok(());
    }
    let faces: Vec<u32> = (0..topo.face_count() as u32).collect();
    let opts = PlanOptions::new(SchemeLimits::NO_DEVICE)
        .with_isolation(isolation)
        .with_lattice_normals(lattice_normals);
    let t = Instant::now();
    let tables =
        AdaptiveTables::new(&topo, &faces, &opts).map_err(|(f, e)| format!("face {f}: {e}"))?;
    println!(
        "AdaptiveTables::new {:.3} s ({} row terms)",
        t.elapsed().as_secs_f64(),
        tables.draw.rows.ids.len()
    );
    drop(tables);
    if repeat > 1 {
        let t = Instant::now();
        for _ in 1..repeat {
            AdaptiveTables::new(&topo, &faces, &opts).map_err(|(f, e)| format!("face {f}: {e}"))?;
        }
        let each = t.elapsed().as_secs_f64() / f64::from(repeat - 1);
        println!("AdaptiveTables::new {:.3} ms each", 1e3 * each);
    }
    Ok(())
}
