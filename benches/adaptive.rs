//! CPU preprocessing of `--scheme adaptive` on `catmark_car` (1,575 quads): what
//! `AdaptiveTables::new` does before anything reaches the GPU — the feature-adaptive refinement
//! (`AdaptiveRefinement::new`), the kernels' subdivision tables (`RefinementTables::adaptive`)
//! and the draw tables (`AdaptiveDrawTables::new`: frame slots, stencil rows, patch records,
//! transition fans, end caps) — at isolation 2 and 4, each step alone and the whole.
//!
//! Yardstick (issue 8): OpenSubdiv 3.5 on the same 2-core machines, car at isolation 2:
//! `Far::TopologyRefiner::RefineAdaptive` 3.0 ms + `Far::PatchTableFactory` with Gregory-basis
//! end caps 4.3 ms = 7.3 ms; target half of it, 3.65 ms.

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use std::sync::Arc;
use std::time::Duration;
use tessera::mesh::ObjOptions;
use tessera::patch::adaptive::AdaptiveDrawTables;
use tessera::render::schemes::adaptive::AdaptiveTables;
use tessera::render::{PlanOptions, SchemeLimits};
use tessera::subdiv::adaptive::AdaptiveRefinement;
use tessera::subdiv::tables::RefinementTables;
use tessera::subdiv::Level;
use tessera::topology::Topology;
use tessera::ControlMesh;

const CAR: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../shared/meshes/osd/catmark_car.obj"
);

fn benches(c: &mut Criterion) {
    let car = ControlMesh::from_obj_file(CAR, &ObjOptions::default()).expect("catmark_car loads");
    let topo = Arc::new(Topology::new(&car).expect("car topology"));
    let faces: Vec<u32> = (0..topo.face_count() as u32).collect();
    let base = Level::from_topology((*topo).clone());
    let mut g = c.benchmark_group("adaptive_car");
    g.sample_size(20)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(5));
    for isolation in [2u32, 4] {
        let adaptive = AdaptiveRefinement::new(&base, isolation).expect("refines");
        g.bench_function(format!("iso{isolation}_refine_adaptive"), |b| {
            b.iter(|| black_box(AdaptiveRefinement::new(black_box(&base), isolation).unwrap()))
        });
        g.bench_function(format!("iso{isolation}_refinement_tables"), |b| {
            b.iter(|| black_box(RefinementTables::adaptive(black_box(&adaptive)).unwrap()))
        });
        g.bench_function(format!("iso{isolation}_draw_tables"), |b| {
            b.iter(|| black_box(AdaptiveDrawTables::new(black_box(&adaptive)).unwrap()))
        });
        g.bench_function(format!("iso{isolation}_adaptive_tables_new"), |b| {
            let opts = PlanOptions::new(SchemeLimits::NO_DEVICE).with_isolation(isolation);
            b.iter(|| black_box(AdaptiveTables::new(black_box(&topo), &faces, &opts).unwrap()))
        });
    }
    g.finish();
}

criterion_group!(adaptive, benches);
criterion_main!(adaptive);
