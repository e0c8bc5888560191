//! The adaptive end caps' sparse rows computed once per connectivity type
//! (`patch::gregory::shared_rows::sparse_face_rows`, what `AdaptiveDrawTables` uses) are
//! bitwise the rows of the face-by-face construction (`stencil_table::sparse_face_rows_direct`,
//! kept as the oracle): same ids in the same order, same f64 bits, same errors. Checked on the
//! end caps of every level and on every face of every level (regular faces, n-gons and holes
//! included, where the errors must agree too), on meshes covering extraordinary vertices,
//! boundaries, infinitely sharp creases and corners, darts, semi-sharp creases, triangles and
//! n-gons, a high-valence pole and a 64-gon.

mod common;

use common::meshes::{osd, polygon_obj};
use tessera::mesh::ObjOptions;
use tessera::patch::adaptive::AdaptiveDrawTables;
use tessera::patch::gregory::shared_rows::sparse_face_rows;
use tessera::patch::gregory::stencil_table::sparse_face_rows_direct;
use tessera::patch::gregory::{GregoryTangents, NotGregory, Weights};
use tessera::subdiv::adaptive::{AdaptiveRefinement, PatchCensus, PatchType};
use tessera::subdiv::Level;
use tessera::topology::Topology;
use tessera::ControlMesh;

/// One face's rows as `(id, f64 bits)` terms, or its error message.
type RowBits = Result<Vec<Vec<(u32, u64)>>, String>;

/// Rows as comparable bits.
fn bits(rows: &[Result<Vec<Weights>, NotGregory>]) -> Vec<RowBits> {
    rows.iter()
        .map(|r| match r {
            Ok(rows) => Ok(rows
                .iter()
                .map(|w| w.0.iter().map(|&(v, x)| (v, x.to_bits())).collect())
                .collect()),
            Err(e) => Err(e.to_string()),
        })
        .collect()
}

/// Compares both routes on `faces` of `topo`; returns the number of rows with a weight.
fn same_rows(topo: &Topology, faces: &[u32], tangents: GregoryTangents, what: &str) -> usize {
    let shared = bits(&sparse_face_rows(topo, faces, tangents));
    let direct = bits(&sparse_face_rows_direct(topo, faces, tangents));
    assert_eq!(shared.len(), faces.len());
    for ((a, b), f) in shared.iter().zip(&direct).zip(faces) {
        assert_eq!(a, b, "{what}: face {f}");
    }
    shared
        .iter()
        .flatten()
        .flatten()
        .filter(|r| !r.is_empty())
        .count()
}

fn check(name: &str, mesh: &ControlMesh, isolations: &[u32]) {
    let tangents = [GregoryTangents::default(), GregoryTangents::Paper];
    for &iso in isolations {
        let r = AdaptiveRefinement::new(&Level::from_mesh(mesh).unwrap(), iso).unwrap();
        let census = PatchCensus::new(&r);
        let mut caps = 0;
        for l in 0..r.levels.len() {
            let t = r.end_cap_topology(l);
            let faces: Vec<u32> = census
                .patches
                .iter()
                .filter(|p| p.kind == PatchType::EndCap && p.level as usize == l)
                .map(|p| p.face)
                .collect();
            caps += faces.len();
            for tangents in tangents {
                let what = format!("{name} iso {iso} level {l} end caps ({tangents:?})");
                same_rows(&t, &faces, tangents, &what);
            }
            let all: Vec<u32> = (0..t.face_count() as u32).collect();
            let what = format!("{name} iso {iso} level {l} all faces");
            same_rows(&t, &all, tangents[0], &what);
        }
        assert!(caps > 0, "{name} iso {iso}: no end caps to compare");
    }
}

#[test]
fn car_at_isolation_2() {
    check("catmark_car", &osd("catmark_car"), &[2]);
}

#[test]
fn creases_darts_semi_sharp_and_n_gons() {
    for (name, isolations) in [
        ("catmark_cube_creases1", &[1, 3][..]),
        ("catmark_nonquads", &[1, 2]),
        ("catmark_dart_edgeonly", &[1, 2]),
        ("catmark_cubes_semisharp", &[1, 2]),
        ("catmark_cube_corner4", &[2]),
        ("catmark_hole_test2", &[1]),
        ("catmark_tent_creases1", &[2]),
        ("catmark_smoothtris1", &[1]),
    ] {
        check(name, &osd(name), isolations);
    }
}

#[test]
fn high_valence_pole_and_polygon() {
    check("catmark_pole64", &osd("catmark_pole64"), &[1, 2]);
    let gon =
        ControlMesh::from_obj_str(&polygon_obj(64), "64-gon", &ObjOptions::default()).unwrap();
    check("64-gon", &gon, &[1, 2]);
}

/// The end caps' rows are linear in the valence: an n-gon at isolation 1 has one vertex of
/// valence n with n end caps around it; each of its rows reads the vertex's three vertex points
/// (limit point, cosine and sine sums, computed once by the first stage) instead of its whole
/// ring, so the terms of all rows together grow like n (ratio 2 per doubling), where per-cap
/// rows over the ring grow like n² (ratio 4: 26.1 M terms at n = 1000 before the two stages).
#[test]
fn row_terms_grow_linearly_with_valence() {
    let terms: Vec<usize> = [50, 100, 200]
        .iter()
        .map(|&n| {
            let name = format!("{n}-gon");
            let gon =
                ControlMesh::from_obj_str(&polygon_obj(n), &name, &ObjOptions::default()).unwrap();
            let r = AdaptiveRefinement::new(&Level::from_mesh(&gon).unwrap(), 1).unwrap();
            let t = AdaptiveDrawTables::new(&r).unwrap();
            eprintln!(
                "{name}: {} row terms, {} rows",
                t.rows.ids.len(),
                t.rows.len()
            );
            t.rows.ids.len()
        })
        .collect();
    for w in terms.windows(2) {
        let ratio = w[1] as f64 / w[0] as f64;
        assert!(ratio < 2.2, "terms {terms:?}: ratio {ratio} per doubling");
    }
}
