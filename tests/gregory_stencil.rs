//! The stencil form of the Gregory construction (§4.3): stencils reproduce the direct
//! construction, shared points are bitwise equal in both neighbours (§4.5), too-large rings are
//! refused by name.

mod common;

use common::meshes::mesh as load;
use glam::DVec3;
use tessera::mesh::ControlMesh;
use tessera::patch::gregory::stencil::{gregory_stencil, NoStencil, MAX_RING};
use tessera::patch::gregory::stencil_table::GregoryStencilTable as StencilTable;
use tessera::patch::gregory::{gregory_patch_at, GregoryPatch};
use tessera::topology::Topology;

const MESHES: [&str; 12] = [
    "catmark_cube",
    "catmark_nonquads",
    "catmark_smoothtris0",
    "catmark_gregory_test0",
    "catmark_gregory_test1",
    "catmark_gregory_test6",
    "catmark_inf_crease1",
    "catmark_helmet",
    "catmark_pawn",
    "embedded:mixed",
    "embedded:open",
    "embedded:creased",
];

/// The five control-point arrays of a patch.
type Parts<'a> = (
    &'a [DVec3],
    &'a [DVec3],
    &'a [DVec3],
    &'a [DVec3],
    &'a [DVec3],
);

/// Control points of a directly built patch in stencil row order.
fn direct_rows(p: &GregoryPatch) -> Vec<DVec3> {
    let (pp, ep, em, fp, fm): Parts = match p {
        GregoryPatch::Quad(q) => (&q.p, &q.e_plus, &q.e_minus, &q.f_plus, &q.f_minus),
        GregoryPatch::Triangle(t) => (&t.p, &t.e_plus, &t.e_minus, &t.f_plus, &t.f_minus),
    };
    (0..pp.len())
        .flat_map(|i| [pp[i], ep[i], em[i], fp[i], fm[i]])
        .collect()
}

#[test]
fn stencils_reproduce_the_direct_construction() {
    let mut checked = 0;
    for name in MESHES {
        let mesh = load(name);
        let topo = Topology::new(&mesh).unwrap();
        let scale = mesh.bbox_diagonal();
        for f in 0..topo.face_count() as u32 {
            let Ok(direct) = gregory_patch_at(&topo, mesh.positions(), f) else {
                continue;
            };
            let st = gregory_stencil(&topo, f).unwrap();
            assert!(st.ring.len() <= MAX_RING && st.ring.windows(2).all(|w| w[0] < w[1]));
            let rows = st.apply(mesh.positions());
            let expected = direct_rows(&direct);
            assert_eq!(rows.len(), expected.len());
            for (r, (a, b)) in rows.iter().zip(&expected).enumerate() {
                assert!(
                    (*a - *b).length() < 1e-12 * scale.max(1.0),
                    "{name} face {f} row {r}: {a} vs {b}"
                );
            }
            // Affine invariance: every row's weights sum to 1.
            for r in 0..st.rows() {
                let s: f64 = st.row(r).iter().sum();
                assert!((s - 1.0).abs() < 1e-12, "{name} face {f} row {r}: sum {s}");
            }
            checked += 1;
        }
    }
    assert!(checked > 500, "{checked}");
}

fn f32_positions(mesh: &ControlMesh) -> Vec<[f32; 3]> {
    mesh.positions()
        .iter()
        .map(|p| p.as_vec3().to_array())
        .collect()
}

#[test]
fn table_types_reproduce_patches_and_shared_points_are_bitwise_equal() {
    for name in MESHES {
        let mesh = load(name);
        let topo = Topology::new(&mesh).unwrap();
        let table = StencilTable::new(&topo, 0..topo.face_count() as u32);
        let pos32 = f32_positions(&mesh);
        let scale = mesh.bbox_diagonal();
        let mut by_face = vec![None; topo.face_count()];
        for (i, p) in table.patches.iter().enumerate() {
            by_face[p.face as usize] = Some(i);
            let direct = direct_rows(&gregory_patch_at(&topo, mesh.positions(), p.face).unwrap());
            for (r, d) in direct.iter().enumerate() {
                let g = table.eval_f32(p, r, &pos32);
                let g = DVec3::new(g[0] as f64, g[1] as f64, g[2] as f64);
                assert!(
                    (g - *d).length() < 1e-5 * scale,
                    "{name} face {} row {r}",
                    p.face
                );
            }
        }
        assert!(table.types.len() <= table.patches.len());
        // Shared corner and edge points: for every edge between two stencil patches, the corner
        // points of both ends and the edge points on the edge, from either side.
        let mut shared = 0;
        for e in 0..topo.edge_count() as u32 {
            let faces = topo.edge_faces(e);
            if faces.len() != 2 {
                continue;
            }
            let (Some(a), Some(b)) = (by_face[faces[0] as usize], by_face[faces[1] as usize])
            else {
                continue;
            };
            let (pa, pb) = (&table.patches[a], &table.patches[b]);
            let la = topo.edge_face_locals(e)[0] as usize;
            let lb = topo.edge_face_locals(e)[1] as usize;
            let na = topo.face_size(faces[0]);
            let nb = topo.face_size(faces[1]);
            // Face a runs the edge from its corner la to la+1, face b from lb+1 to lb.
            let pairs = [
                (5 * la, 5 * ((lb + 1) % nb)),         // p at the start vertex
                (5 * ((la + 1) % na), 5 * lb),         // p at the end vertex
                (5 * la + 1, 5 * ((lb + 1) % nb) + 2), // e+ of a at start == e- of b
                (5 * ((la + 1) % na) + 2, 5 * lb + 1), // e- of a at end == e+ of b
            ];
            for (ra, rb) in pairs {
                let x = table.eval_f32(pa, ra, &pos32);
                let y = table.eval_f32(pb, rb, &pos32);
                assert_eq!(
                    x.map(f32::to_bits),
                    y.map(f32::to_bits),
                    "{name} edge {e}: rows {ra}/{rb} of faces {}/{}",
                    pa.face,
                    pb.face
                );
                shared += 1;
            }
        }
        eprintln!(
            "{name}: {} patches, {} types, {} skipped, {shared} shared points",
            table.patches.len(),
            table.types.len(),
            table.skipped.len()
        );
    }
}

#[test]
fn too_large_rings_are_refused_by_name() {
    let mesh = load("catmark_pole64");
    let topo = Topology::new(&mesh).unwrap();
    let table = StencilTable::new(&topo, 0..topo.face_count() as u32);
    let too_large: Vec<_> = table
        .skipped
        .iter()
        .filter_map(|s| match s {
            NoStencil::TooLarge { face, ring } => Some((*face, *ring)),
            _ => None,
        })
        .collect();
    assert!(!too_large.is_empty());
    for (f, ring) in too_large {
        assert!(ring > MAX_RING);
        let err = gregory_stencil(&topo, f).unwrap_err();
        assert!(err.to_string().contains(&format!("face {f}")), "{err}");
    }
}
