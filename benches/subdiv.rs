//! Topology, refinement and stencil benchmarks on `catmark_car` (1,575 quads) and on the car
//! refined three times (100,800 quads) as a new control mesh; and reading a generated
//! 1000 x 1000-quad grid (1M faces, 52 MB of OBJ text) with its topology, the work of
//! `tessera info` on it (issue: under 1 s and 500 MB).
//!
//! OpenSubdiv 3.5 Far on the same 2-core machines (issue 2): topology creation 40.5 ms, uniform
//! refinement of the topology to level 3 727 ms, level-3 stencil table 6.6 s (all on the
//! 100,800-quad mesh), level-3 stencil table of the original car 83 ms.

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use std::time::Duration;
use tessera::mesh::ObjOptions;
use tessera::subdiv::{Level, StencilTable};
use tessera::topology::Topology;
use tessera::ControlMesh;

const CAR: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../shared/meshes/osd/catmark_car.obj"
);

fn car() -> ControlMesh {
    ControlMesh::from_obj_file(CAR, &ObjOptions::default()).expect("catmark_car loads")
}

/// The car refined three times, with its decayed crease sharpness, as a control mesh.
fn car_level3() -> ControlMesh {
    let base = car();
    let mut level = Level::from_mesh(&base).expect("car topology");
    let mut pos = base.positions().to_vec();
    for _ in 0..3 {
        let (child, m) = level.refine();
        pos = m.apply_vec(&pos);
        level = child;
    }
    ControlMesh::new(level.to_mesh_desc(pos)).expect("refined car is valid")
}

fn benches(c: &mut Criterion) {
    let car = car();
    let big = car_level3();
    assert_eq!(big.face_count(), 100_800);
    let big_level = Level::from_mesh(&big).expect("level");
    let car_level = Level::from_mesh(&car).expect("level");

    let mut g = c.benchmark_group("car3_100800_quads");
    g.sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(8));
    g.bench_function("topology_new", |b| {
        b.iter(|| black_box(Topology::new(black_box(&big)).expect("topology")))
    });
    g.bench_function("refine_topology_to_level3", |b| {
        b.iter(|| {
            let l1 = big_level.refine_topology();
            let l2 = l1.refine_topology();
            black_box(l2.refine_topology())
        })
    });
    // OpenSubdiv's default uniform refinement (fullTopologyInLastLevel = false): full topology
    // for levels 1 and 2, face vertices only for level 3.
    g.bench_function("refine_to_level3_last_level_face_vertices", |b| {
        b.iter(|| black_box(big_level.uniform_face_vertices(3)))
    });
    g.bench_function("stencil_table_level3", |b| {
        b.iter(|| black_box(StencilTable::from_level(&big_level, 3)))
    });
    let table = StencilTable::from_level(&big_level, 3);
    let mut dst = vec![glam::DVec3::ZERO; table.len()];
    g.bench_function("stencil_apply_level3", |b| {
        b.iter(|| table.apply(black_box(big.positions()), &mut dst))
    });
    drop(table);
    g.finish();

    let mut g = c.benchmark_group("car_1575_quads");
    g.sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3));
    g.bench_function("stencil_table_level3", |b| {
        b.iter(|| black_box(StencilTable::from_level(&car_level, 3)))
    });
    g.finish();
}

/// OBJ text of an `n x n` grid of quads over a bumpy height field (what `tessera info` was
/// measured on).
fn grid_obj(n: usize) -> String {
    use std::fmt::Write as _;
    let mut s = String::with_capacity(n * n * 52);
    for j in 0..=n {
        for i in 0..=n {
            let z = 0.1 * ((i * 7 + j * 13) % 17) as f64 / 17.0;
            let _ = writeln!(s, "v {:.4} {:.4} {z:.4}", i as f64 * 0.01, j as f64 * 0.01);
        }
    }
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i + 1;
            let _ = writeln!(s, "f {a} {} {} {}", a + 1, a + n + 2, a + n + 1);
        }
    }
    s
}

fn load_1m(c: &mut Criterion) {
    let text = grid_obj(1000);
    let mut g = c.benchmark_group("grid_1m_quads");
    g.sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(10));
    g.bench_function("obj_read_and_topology", |b| {
        b.iter(|| {
            let m = ControlMesh::from_obj_str(black_box(&text), "grid", &ObjOptions::default())
                .expect("grid loads");
            black_box(Topology::new(&m).expect("topology"))
        })
    });
    g.finish();
}

criterion_group!(subdiv, benches, load_1m);
criterion_main!(subdiv);
