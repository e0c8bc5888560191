//! The adaptive end caps' sparse rows computed once per connectivity type
//! (`patch::gregory::shared_rows::sparse_face_rows`, what `AdaptiveDrawTables` uses) are
//! the rows of the face-by-face construction (`stencil_table::sparse_face_rows_direct`, kept
//! as the oracle) to 1e-12 per weight (bitwise but where a type's rows are turned from
//! another's: its smooth corners' rings start elsewhere), every id of theirs kept (more only
//! within 1e-12 of zero), same errors. Checked on the
//! end caps of every level and on every face of every level (regular faces, n-gons and holes
//! included, where the errors must agree too), on meshes covering extraordinary vertices,
//! boundaries, infinitely sharp creases and corners, darts, semi-sharp creases, triangles and
//! n-gons, a high-valence pole and a 64-gon.

mod common;

use common::levels::refined_limit;
use common::meshes::{osd, polygon_obj};
use glam::DVec3;
use tessera::mesh::ObjOptions;
use tessera::mesh::{ControlMeshDesc, Corner, Crease};
use tessera::patch::adaptive::AdaptiveDrawTables;
use tessera::patch::gregory::shared_rows::sparse_face_rows;
use tessera::patch::gregory::stencil_table::{sparse_face_rows_direct, vertex_point_id};
use tessera::patch::gregory::{
    check_face_for, gregory_patch_for, gregory_vertex_two_stage, vertex_ring, Coverage, DartLimits,
    GregoryTangents, GregoryVertex, NotGregory, VertexKind, Weights,
};
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

/// How often the neighbour across an end cap's edge needs more than the edge's two corners:
/// its face points there are one-sided (they read its other corners' data), or it has no
/// patch because another corner has no data.
#[derive(Debug, Default, Clone, Copy)]
struct NeighbourCases {
    one_sided: usize,
    no_data_elsewhere: usize,
}

/// The face-by-face rows as the construction made them before its corners were built on
/// demand: the two-stage data of every vertex, each face's patch, and the whole patch of each
/// edge neighbour, of which the four points beside the edge are taken (`StencilType::weights`
/// layout: control points, per edge the neighbour's two edge points, then per edge its two face
/// points; the face's own points where the neighbour has no patch).
fn whole_patch_rows(
    topo: &Topology,
    faces: &[u32],
    tangents: GregoryTangents,
    cases: &mut NeighbourCases,
) -> Vec<Result<Vec<Weights>, NotGregory>> {
    let darts = DartLimits::new();
    let basis = |v: u32| [0, 1, 2].map(|b| Weights::unit(vertex_point_id(topo, v, b)));
    let data: Vec<Option<GregoryVertex<Weights>>> = (0..topo.vertex_count() as u32)
        .map(|v| {
            let cov = Coverage::EndCap;
            gregory_vertex_two_stage(topo, v, &Weights::unit, tangents, cov, &darts, &basis)
        })
        .collect();
    let patch = |g: u32| gregory_patch_for(topo, &data, g, Coverage::EndCap);
    let sides = |v: u32, g: u32| {
        let d = data[v as usize].as_ref()?;
        let j = topo.vertex_faces(v).iter().position(|&h| h == g)?;
        Some(d.one_sided.get(j).copied().unwrap_or(0))
    };
    faces
        .iter()
        .map(|&f| {
            let own = patch(f)?;
            let [p, ep, em, fp, fm] = own.points();
            let fv = topo.face_vertices(f);
            let n = fv.len();
            let mut rows: Vec<Weights> = [p, ep, em, fp, fm].concat();
            let mut face_points = Vec::new();
            for k in 0..n {
                let (x, y) = (fv[k], fv[(k + 1) % n]);
                let g = topo
                    .find_edge(x, y)
                    .and_then(|e| topo.edge_faces(e).iter().copied().find(|&g| g != f));
                let theirs = g.and_then(|g| {
                    let d = topo.face_vertices(g);
                    let m = d.len();
                    let k2 = (0..m).find(|&i| d[i] == y && d[(i + 1) % m] == x)?;
                    let k2n = (k2 + 1) % m;
                    let Ok(q) = patch(g) else {
                        let near = sides(x, g).is_some() && sides(y, g).is_some();
                        if near && check_face_for(topo, g, Coverage::EndCap).is_ok() {
                            cases.no_data_elsewhere += 1;
                        }
                        return None;
                    };
                    if sides(x, g) == Some(2) || sides(y, g) == Some(1) {
                        cases.one_sided += 1;
                    }
                    let [_, ep, em, fp, fm] = q.points();
                    Some([
                        ep[k2n].clone(),
                        em[k2].clone(),
                        fm[k2n].clone(),
                        fp[k2].clone(),
                    ])
                });
                let [ex, ey, fx, fy] = theirs.unwrap_or_else(|| {
                    [
                        em[k].clone(),
                        ep[(k + 1) % n].clone(),
                        fp[k].clone(),
                        fm[(k + 1) % n].clone(),
                    ]
                });
                rows.extend([ex, ey]);
                face_points.extend([fx, fy]);
            }
            rows.extend(face_points);
            Ok(rows)
        })
        .collect()
}

/// Compares the shared rows, the direct rows and the whole-patch rows on `faces` of `topo`;
/// returns the number of rows with a weight.
fn same_rows(
    topo: &Topology,
    faces: &[u32],
    tangents: GregoryTangents,
    what: &str,
    cases: &mut NeighbourCases,
) -> usize {
    // One dart cache each: the shared rows do not lean on the direct construction's solves.
    let shared = sparse_face_rows(topo, faces, tangents, &DartLimits::new());
    let direct = sparse_face_rows_direct(topo, faces, tangents, &DartLimits::new());
    let whole = bits(&whole_patch_rows(topo, faces, tangents, cases));
    assert_eq!(shared.len(), faces.len());
    for (((a, b), c), f) in shared.iter().zip(&direct).zip(&whole).zip(faces) {
        near_rows(a, b, &format!("{what}: face {f}"));
        assert_eq!(
            &bits(std::slice::from_ref(b))[0],
            c,
            "{what}: face {f}, direct rows against whole neighbour patches"
        );
    }
    bits(&direct)
        .iter()
        .flatten()
        .flatten()
        .filter(|r| !r.is_empty())
        .count()
}

/// The shared rows `got` are the direct rows `want` to 1e-12 per weight, with every id of
/// theirs (extra terms within 1e-12 of zero), or the same error.
fn near_rows(
    got: &Result<Vec<Weights>, NotGregory>,
    want: &Result<Vec<Weights>, NotGregory>,
    what: &str,
) {
    let (got, want) = match (got, want) {
        (Ok(a), Ok(b)) => (a, b),
        _ => {
            let e = |r: &Result<_, NotGregory>| r.as_ref().err().map(|e| e.to_string());
            return assert_eq!(e(got), e(want), "{what}");
        }
    };
    assert_eq!(got.len(), want.len(), "{what}");
    for (a, b) in got.iter().zip(want) {
        let mut a = a.0.iter().peekable();
        let extra = |x: f64| assert!(x.abs() <= 1e-12, "{what}: extra term {x:e}");
        for &(id, y) in &b.0 {
            while let Some(&(_, x)) = a.next_if(|x| x.0 < id) {
                extra(x);
            }
            let x = a.next_if(|x| x.0 == id).map(|x| x.1);
            let ok = x.is_some_and(|x| (x - y).abs() <= 1e-12);
            assert!(ok, "{what}: id {id}: {x:?} for {y:e}");
        }
        a.for_each(|&(_, x)| extra(x));
    }
}

fn check(name: &str, mesh: &ControlMesh, isolations: &[u32]) -> NeighbourCases {
    let mut cases = NeighbourCases::default();
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
                same_rows(&t, &faces, tangents, &what, &mut cases);
            }
            let all: Vec<u32> = (0..t.face_count() as u32).collect();
            let what = format!("{name} iso {iso} level {l} all faces");
            same_rows(&t, &all, tangents[0], &what, &mut cases);
        }
        assert!(caps > 0, "{name} iso {iso}: no end caps to compare");
    }
    eprintln!("{name}: {cases:?}");
    cases
}

#[test]
fn car_at_isolation_2() {
    check("catmark_car", &osd("catmark_car"), &[2]);
}

#[test]
fn creases_darts_semi_sharp_and_n_gons() {
    let mut cases = NeighbourCases::default();
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
        let c = check(name, &osd(name), isolations);
        cases.one_sided += c.one_sided;
        cases.no_data_elsewhere += c.no_data_elsewhere;
    }
    // Both neighbour cases that read more than the edge's two corners occur.
    assert!(cases.one_sided > 0, "{cases:?}");
    assert!(cases.no_data_elsewhere > 0, "{cases:?}");
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
    linear_in_valence("n-gon", [50, 100, 200], |n| {
        ControlMesh::from_obj_str(&polygon_obj(n), "n-gon", &ObjOptions::default()).unwrap()
    });
}

/// The row terms of `mesh(n)` at isolation 1 (default tangents) for the three valences `n`
/// (each twice the one before) grow like n: ratio below 2.2 per doubling (per-cap rows over
/// the ring tend to 4).
fn linear_in_valence(what: &str, valences: [usize; 3], mesh: impl Fn(usize) -> ControlMesh) {
    let terms: Vec<usize> = valences
        .iter()
        .map(|&n| {
            let r = AdaptiveRefinement::new(&Level::from_mesh(&mesh(n)).unwrap(), 1).unwrap();
            let t = AdaptiveDrawTables::new(&r).unwrap();
            assert!(!t.end_caps.is_empty(), "{what} {n}: no end caps");
            eprintln!(
                "{what} {n}: {} row terms, {} rows, {} vertex points",
                t.rows.ids.len(),
                t.rows.len(),
                t.vertex_point_count()
            );
            t.rows.ids.len()
        })
        .collect();
    for w in terms.windows(2) {
        let ratio = w[1] as f64 / w[0] as f64;
        assert!(
            ratio < 2.2,
            "{what}: terms {terms:?}, ratio {ratio} per doubling"
        );
    }
}

/// A fan of `n` triangles around vertex 0 (rim vertices 1..=n on a wavy circle), closed or
/// (`open`) missing its last triangle; infinitely sharp spokes to the rim vertices `spokes`
/// and an infinitely sharp vertex 0 with `corner`. At isolation 1 vertex 0 keeps valence `n`
/// with `n` end caps (or `n - 1`) around it.
fn fan(n: usize, spokes: &[usize], corner: bool, open: bool) -> ControlMesh {
    let mut positions = vec![DVec3::new(0.0, 0.0, 0.3)];
    positions.extend((0..n).map(|k| {
        let a = k as f64 / n as f64 * std::f64::consts::TAU;
        DVec3::new(a.cos(), a.sin(), 0.1 * (3.0 * a).sin())
    }));
    let faces = if open { n - 1 } else { n };
    let face_vertices = (0..faces as u32)
        .flat_map(|k| [0, 1 + k, 1 + (k + 1) % n as u32])
        .collect();
    let sharp = tessera::mesh::INFINITE_SHARPNESS;
    ControlMesh::new(ControlMeshDesc {
        positions,
        face_sizes: vec![3; faces],
        face_vertices,
        creases: spokes
            .iter()
            .map(|&k| Crease {
                v0: 0,
                v1: k as u32,
                sharpness: sharp,
            })
            .collect(),
        corners: if corner {
            vec![Corner {
                vertex: 0,
                sharpness: sharp,
            }]
        } else {
            Vec::new()
        },
        ..Default::default()
    })
    .unwrap()
}

/// The same at every end-cap rule with an `O(n)` ring (the two-stage first stage of darts and
/// crease sectors, `GregoryVertex::vertex_points`), and at corners and cones, whose rows read
/// `O(1)` ring points without a first stage: a crease through the centre of a triangle fan
/// (two crease sectors of n/2 faces), a boundary vertex (one sector of n - 1 faces), a dart, a
/// corner with the same crease (two wide corner sectors) and a cone. Fails on rows with the
/// crease sectors' cross-boundary tangents or the dart's limit masks expanded over the ring
/// (main d4c964b, before this first stage: ratios 2.98 and 3.31 on the crease fan, 3.36 and
/// 3.62 on the boundary fan, 2.59 and 2.91 on the dart fan; corners and cones were linear).
#[test]
fn row_terms_grow_linearly_at_creases_darts_corners_and_cones() {
    let valences = [50, 100, 200];
    linear_in_valence("crease fan", valences, |n| {
        fan(n, &[1, 1 + n / 2], false, false)
    });
    linear_in_valence("boundary fan", valences, |n| fan(n, &[], false, true));
    linear_in_valence("dart fan", valences, |n| fan(n, &[1], false, false));
    linear_in_valence("corner fan", valences, |n| {
        fan(n, &[1, 1 + n / 2], true, false)
    });
    linear_in_valence("cone fan", valences, |n| fan(n, &[], true, false));
}

/// Darts of valence 3 to 200 (one infinitely sharp spoke of a triangle fan) take end caps at
/// isolation 1: `AdaptiveDrawTables::new` succeeds (main refused the faces from valence 48 with
/// `NotGregory::Cusp`: the power iteration of the dart's limit masks stalled). And the
/// construction's limit position and tangent plane at the dart are the limit surface's:
/// - the position is where 40 local refinements of the vertex converge (Aitken-extrapolated,
///   the crate's refinement, not the masks), to 1e-9 of the fan's radius;
/// - position and normal are the same from the once-refined mesh, whose vertex is a dart of
///   the same valence over another ring (a mask that is not an exact left eigenvector of the
///   dart's subdivision matrix gives another point or plane: e.g. the smooth masks, i.e. the
///   crease rule dropped from `dart_matrix`, miss by 5e-2 at valence 3), to 1e-12 and 1e-10.
#[test]
fn darts_of_any_valence_take_end_caps_at_their_exact_limit() {
    for n in [3, 10, 40, 48, 64, 100, 200] {
        let mesh = fan(n, &[1], false, false);
        let level = Level::from_mesh(&mesh).unwrap();
        let r = AdaptiveRefinement::new(&level, 1).unwrap();
        let t = AdaptiveDrawTables::new(&r).unwrap_or_else(|e| panic!("dart {n}: {e}"));
        assert!(!t.end_caps.is_empty(), "dart {n}: no end caps");
        let limit = |level: &Level, positions: &[DVec3], v: u32| {
            let ring = vertex_ring(level.topology(), positions, v);
            let g =
                GregoryVertex::new(&ring, GregoryTangents::default(), &DartLimits::new()).unwrap();
            assert_eq!((g.kind, g.n), (VertexKind::Dart, n));
            let j = (n / 4).max(1);
            (g.p, (g.e[0] - g.p).cross(g.e[j] - g.p).normalize())
        };
        let (p0, n0) = limit(&level, mesh.positions(), 0);
        let (child, refine) = level.refine();
        let positions = refine.apply_vec(mesh.positions());
        let (p1, n1) = limit(&child, &positions, level.child_vertex_point(0));
        let refined = refined_limit(&level, mesh.positions(), 0, 40);
        let (e_refined, e_p, e_n) = (
            (p0 - refined).length(),
            (p0 - p1).length(),
            (n0 - n1).length(),
        );
        eprintln!(
            "dart {n}: position vs 40 refinements {e_refined:.1e}, vs the refined mesh's dart \
             {e_p:.1e}; normal vs the refined mesh's {e_n:.1e}"
        );
        assert!(e_refined < 1e-9, "dart {n}: {e_refined:e} from refinement");
        assert!(
            e_p < 1e-12,
            "dart {n}: position moves by {e_p:e} under refinement"
        );
        assert!(
            e_n < 1e-10,
            "dart {n}: normal turns by {e_n:e} under refinement"
        );
    }
}

/// Bands (`tangents_boundary::sector_band`: a two-face crease sector whose inner edge ends on
/// a crease vertex of three or more faces) at level 0, the end caps of isolation 0: under
/// `Scaled`, which scales the band sectors' inner edge points and not those of other two-face
/// sectors, the shared rows are still the face-by-face ones. The face key needs no band word:
/// the inner edge's far end is a corner of both faces of the sector, keyed in full (its edges'
/// sharpness and face counts give its sectors); fails if the key dropped the corners' edge
/// sharpness or face counts.
#[test]
fn bands_at_level_zero_share_rows() {
    for name in ["catmark_gregory_test3", "catmark_xord_boundary"] {
        let mesh = osd(name);
        let topo = Topology::new(&mesh).unwrap();
        let faces: Vec<u32> = (0..topo.face_count() as u32).collect();
        for t in [GregoryTangents::Scaled(0.7), GregoryTangents::default()] {
            assert!(
                same_rows(&topo, &faces, t, name, &mut NeighbourCases::default()) > 0,
                "{name}"
            );
        }
    }
}
