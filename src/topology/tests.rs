use super::*;
use crate::mesh::{
    BoundaryInterpolation, ControlMesh, ControlMeshDesc, Crease, INFINITE_SHARPNESS,
};
use glam::DVec3;

/// An `n x m` grid of unit quads in the plane z = 0, counter-clockwise seen from +z.
fn grid(n: u32, m: u32) -> ControlMeshDesc {
    let mut d = ControlMeshDesc::default();
    for j in 0..=m {
        for i in 0..=n {
            d.positions.push(DVec3::new(i as f64, j as f64, 0.0));
        }
    }
    let id = |i: u32, j: u32| j * (n + 1) + i;
    for j in 0..m {
        for i in 0..n {
            d.face_sizes.push(4);
            d.face_vertices
                .extend([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    d
}

fn cube() -> ControlMeshDesc {
    let mut d = ControlMeshDesc::default();
    for k in 0..8 {
        d.positions.push(DVec3::new(
            (k & 1) as f64,
            ((k >> 1) & 1) as f64,
            ((k >> 2) & 1) as f64,
        ));
    }
    // Outward counter-clockwise faces of the unit cube (vertex k = x + 2y + 4z).
    let faces = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    for f in faces {
        d.face_sizes.push(4);
        d.face_vertices.extend(f);
    }
    d
}

/// Checks the one-ring invariants of every vertex against the face arrays.
fn check_rings(t: &Topology) {
    for v in 0..t.vertex_count() as u32 {
        let faces = t.vertex_faces(v);
        let locals = t.vertex_face_locals(v);
        let edges = t.vertex_edges(v);
        let boundary = t.is_boundary_vertex(v);
        assert_eq!(edges.len(), faces.len() + boundary as usize, "vertex {v}");
        for (i, (&f, &l)) in faces.iter().zip(locals).enumerate() {
            let fv = t.face_vertices(f);
            let fe = t.face_edges(f);
            let n = fv.len();
            assert_eq!(fv[l as usize], v);
            // Edge i leaves v along face i; edge i + 1 enters v along face i.
            assert_eq!(edges[i], fe[l as usize], "vertex {v} face {i}");
            let next = edges[(i + 1) % edges.len()];
            assert_eq!(next, fe[(l as usize + n - 1) % n], "vertex {v} face {i}");
            // Consecutive faces share the edge between them.
            if i + 1 < faces.len() || !boundary {
                let g = faces[(i + 1) % faces.len()];
                assert!(t.edge_faces(next).contains(&f) && t.edge_faces(next).contains(&g));
            }
        }
        if boundary {
            assert!(t.is_boundary_edge(edges[0]));
            assert!(t.is_boundary_edge(*edges.last().unwrap()));
        }
    }
    for e in 0..t.edge_count() as u32 {
        let [a, b] = t.edge_vertices(e);
        let f = t.edge_faces(e)[0];
        let l = t.edge_face_locals(e)[0] as usize;
        let fv = t.face_vertices(f);
        assert_eq!((fv[l], fv[(l + 1) % fv.len()]), (a, b));
        assert_eq!(t.face_edges(f)[l], e);
    }
}

#[test]
fn cube_counts_and_rings() {
    let mesh = ControlMesh::new(cube()).unwrap();
    let t = Topology::new(&mesh).unwrap();
    assert_eq!(
        (t.vertex_count(), t.edge_count(), t.face_count()),
        (8, 12, 6)
    );
    // Euler characteristic of a sphere.
    assert_eq!(8 - 12 + 6, 2);
    check_rings(&t);
    for v in 0..8 {
        assert_eq!(t.valence(v), 3);
        assert!(!t.is_boundary_vertex(v));
    }
    assert!(t.edge_sharpnesses().iter().all(|&s| s == 0.0));
    assert_eq!(t.face_class(0), FaceClass::IrregularQuad);
}

#[test]
fn grid_rings_are_counter_clockwise() {
    let d = grid(3, 3);
    let pos = d.positions.clone();
    let mesh = ControlMesh::new(d).unwrap();
    let t = Topology::new(&mesh).unwrap();
    assert_eq!(
        (t.vertex_count(), t.edge_count(), t.face_count()),
        (16, 24, 9)
    );
    check_rings(&t);
    // Interior vertex 5 = (1,1): edge directions must turn counter-clockwise by 90 degrees.
    let v = 5;
    let dirs: Vec<DVec3> = t
        .vertex_edges(v)
        .iter()
        .map(|&e| pos[t.other_vertex(e, v) as usize] - pos[v as usize])
        .collect();
    assert_eq!(dirs.len(), 4);
    for i in 0..4 {
        let c = dirs[i].cross(dirs[(i + 1) % 4]);
        assert!(c.z > 0.5, "edge {i} -> {} is not counter-clockwise", i + 1);
    }
    // Boundary vertex 1 = (1,0): starts at a boundary edge, faces counter-clockwise.
    let e = t.vertex_edges(1);
    assert_eq!(e.len(), 3);
    assert_eq!(t.other_vertex(e[0], 1), 2);
    assert_eq!(t.other_vertex(e[1], 1), 5);
    assert_eq!(t.other_vertex(e[2], 1), 0);
    // Boundary rule: boundary edges infinitely sharp, valence-2 corners sharp (EdgeAndCorner).
    assert_eq!(t.edge_sharpness(e[0]), INFINITE_SHARPNESS);
    assert_eq!(t.edge_sharpness(e[1]), 0.0);
    assert_eq!(t.vertex_sharpness(0), INFINITE_SHARPNESS);
    assert_eq!(t.vertex_sharpness(1), 0.0);
    assert_eq!(t.face_class(4), FaceClass::RegularQuad);
    assert_eq!(t.face_class(0), FaceClass::Boundary);
    assert_eq!(t.find_edge(5, 6), t.find_edge(6, 5));
    // Face 4 = (1,1): across its edges k = 0..3 lie faces (1,0), (2,1), (1,2), (0,1).
    let across: Vec<_> = (0..4).map(|k| t.adjacent_face(4, k)).collect();
    assert_eq!(across, [Some(1), Some(5), Some(7), Some(3)]);
    assert_eq!(t.adjacent_face(0, 0), None);
    assert!(t.find_edge(5, 10).is_none());
}

#[test]
fn edge_only_and_none_boundaries() {
    let mut d = grid(3, 3);
    d.options.boundary = BoundaryInterpolation::EdgeOnly;
    let t = Topology::new(&ControlMesh::new(d).unwrap()).unwrap();
    assert_eq!(t.vertex_sharpness(0), 0.0);
    assert!(t.has_limit_surface(0));
    let mut d = grid(3, 3);
    d.options.boundary = BoundaryInterpolation::None;
    let t = Topology::new(&ControlMesh::new(d).unwrap()).unwrap();
    assert!(!t.has_limit_surface(0));
    assert!(t.has_limit_surface(4));
}

#[test]
fn creases_classify_faces() {
    let mut d = grid(5, 5);
    // Crease along the edge (2,2)-(3,2): vertices 14 and 15.
    d.creases.push(Crease {
        v0: 14,
        v1: 15,
        sharpness: 2.5,
    });
    let t = Topology::new(&ControlMesh::new(d).unwrap()).unwrap();
    let e = t.find_edge(15, 14).unwrap();
    assert_eq!(t.edge_sharpness(e), 2.5);
    // Face (2,2) has the crease on its edge; face (1,1) touches vertex 14 = (2,2).
    assert_eq!(t.face_class(12), FaceClass::Creased);
    assert_eq!(t.face_class(6), FaceClass::Creased);
    // Face (1,3) touches neither crease vertex nor an edge incident to the crease.
    assert_eq!(t.face_class(16), FaceClass::RegularQuad);
}

#[test]
fn structural_errors_are_reported() {
    // Three triangles on one edge 0-1.
    let fo = vec![0, 3, 6, 9];
    let fv = vec![0, 1, 2, 1, 0, 3, 1, 0, 4];
    let err = build(5, fo, fv, true).unwrap_err();
    assert!(format!("{err}").contains("non-manifold edge"), "{err}");
    // Two triangles touching only at vertex 0 (bow-tie).
    let err = build(5, vec![0, 3, 6], vec![0, 1, 2, 0, 3, 4], true).unwrap_err();
    assert!(format!("{err}").contains("non-manifold vertex 0"), "{err}");
    // Non-strict: two fans listed one after the other.
    let t = build(5, vec![0, 3, 6], vec![0, 1, 2, 0, 3, 4], false).unwrap();
    assert_eq!(t.vertex_faces(0).len(), 2);
    assert_eq!(t.vertex_edges(0).len(), 4);
    // Same-direction edge: faces 0-1-2 and 0-1-3.
    let err = build(4, vec![0, 3, 6], vec![0, 1, 2, 0, 1, 3], true).unwrap_err();
    assert!(format!("{err}").contains("winding"), "{err}");
    // Repeated vertex.
    let err = build(4, vec![0, 4], vec![0, 1, 1, 2], true).unwrap_err();
    assert!(format!("{err}").contains("repeated"), "{err}");
}

#[test]
fn face_classes_follow_the_documented_order() {
    let mut d = grid(5, 5);
    // Hole wins over everything; a sharp vertex makes faces around it Creased.
    d.holes.push(0);
    d.corners.push(crate::mesh::Corner {
        vertex: 14,
        sharpness: 0.5,
    });
    // A triangle fan replacing face (3,3): vertices 21, 22, 28, 27 plus a centre.
    d.positions.push(DVec3::new(3.5, 3.5, 0.0));
    let c = 36u32;
    let mut fv = Vec::new();
    let mut fs = Vec::new();
    for f in 0..25usize {
        let q = &d.face_vertices[4 * f..4 * f + 4];
        if f == 18 {
            for k in 0..4 {
                fs.push(3);
                fv.extend([q[k], q[(k + 1) % 4], c]);
            }
        } else {
            fs.push(4);
            fv.extend_from_slice(q);
        }
    }
    d.face_vertices = fv;
    d.face_sizes = fs;
    let t = Topology::new(&ControlMesh::new(d).unwrap()).unwrap();
    assert_eq!(t.face_class(0), FaceClass::Hole);
    assert!(!t.has_limit_surface(0));
    assert_eq!(t.face_class(1), FaceClass::Boundary);
    assert_eq!(t.face_class(7), FaceClass::Creased);
    assert_eq!(t.face_class(18), FaceClass::Triangle);
    // Face 13 = (3,2) shares vertices (3,3), (4,3) with the fan: valence 4, triangles around.
    assert_eq!(t.face_class(13), FaceClass::IrregularQuad);
    // Face 8 = (3,1): interior, valence 4, quads only, no sharpness near it.
    assert_eq!(t.face_class(8), FaceClass::RegularQuad);
}

/// `with_semi_sharpness_as_crease` against the rule edge by edge: semi-sharp edges from the
/// threshold on infinitely sharp and promoted, below it smooth, smooth, infinitely sharp and
/// boundary edges kept and not promoted, semi-sharp vertices smooth; applied again to its own
/// output (promoted edges stay promoted, nothing new) and borrowed when nothing is semi-sharp.
#[test]
fn semi_sharpness_as_crease_follows_the_rule_per_edge() {
    let mut d = grid(4, 4);
    let sharpness = [
        (6, 7, 0.5),
        (7, 8, 1.0),
        (11, 12, 2.5),
        (12, 13, 0.0),
        (16, 17, 10.0),
    ];
    for (v0, v1, s) in sharpness {
        d.creases.push(Crease {
            v0,
            v1,
            sharpness: s,
        });
    }
    d.corners.push(crate::mesh::Corner {
        vertex: 18,
        sharpness: 0.75,
    });
    let t = Topology::new(&ControlMesh::new(d).unwrap()).unwrap();
    let caps = t.with_semi_sharpness_as_crease(1.0);
    assert!(matches!(caps, std::borrow::Cow::Owned(_)));
    let mut promoted = 0;
    for e in 0..t.edge_count() as u32 {
        let s = t.edge_sharpness(e);
        let semi = s > 0.0 && s < INFINITE_SHARPNESS;
        let expected = match (semi, s >= 1.0) {
            (true, true) => INFINITE_SHARPNESS,
            (true, false) => 0.0,
            (false, _) => s,
        };
        assert_eq!(caps.edge_sharpness(e), expected, "edge {e}");
        assert_eq!(caps.is_promoted_edge(e), semi && s >= 1.0, "edge {e}");
        promoted += usize::from(caps.is_promoted_edge(e));
    }
    assert_eq!(promoted, 2);
    assert_eq!(caps.vertex_sharpness(18), 0.0);
    // A second application: no semi-sharpness left, borrowed, the promoted edges kept.
    let again = caps.with_semi_sharpness_as_crease(1.0);
    assert!(matches!(again, std::borrow::Cow::Borrowed(_)));
    // Promoted edges survive an application that changes something else.
    let mut semi = caps.into_owned();
    let e = semi.find_edge(1, 6).unwrap();
    semi.edge_sharpness[e as usize] = 3.0;
    let third = semi.with_semi_sharpness_as_crease(1.0);
    assert_eq!(
        (0..t.edge_count() as u32)
            .filter(|&e| third.is_promoted_edge(e))
            .count(),
        3
    );
    // Nothing semi-sharp: borrowed.
    let plain = Topology::new(&ControlMesh::new(grid(2, 2)).unwrap()).unwrap();
    assert!(matches!(
        plain.with_semi_sharpness_as_crease(1.0),
        std::borrow::Cow::Borrowed(_)
    ));
}
