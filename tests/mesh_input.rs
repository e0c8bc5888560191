//! Mesh input: validation errors (variant and named element), the OBJ reader with tags, its
//! robustness against malformed files, and the OpenSubdiv regression corpus.

mod common;

use common::meshes::{corpus_options, osd_dir, osd_names, osd_path, CUBE_FACES};
use glam::DVec3;
use tessera::error::TagKind;
use tessera::mesh::{
    BoundaryInterpolation, ControlMeshDesc, Corner, Crease, CreaseMethod, MeshWarning, ObjOptions,
};
use tessera::{ControlMesh, Error};

/// A 2x1 strip of quads: vertices 0..6 on a grid, faces (0,1,4,3) and (1,2,5,4).
fn strip() -> ControlMeshDesc {
    ControlMeshDesc {
        positions: vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(2.0, 1.0, 0.0),
        ],
        face_sizes: vec![4, 4],
        face_vertices: vec![0, 1, 4, 3, 1, 2, 5, 4],
        ..Default::default()
    }
}

fn err(desc: ControlMeshDesc) -> Error {
    ControlMesh::new(desc).expect_err("the description is invalid")
}

fn obj(text: &str) -> tessera::Result<ControlMesh> {
    ControlMesh::from_obj_str(text, "test", &ObjOptions::default())
}

/// Six times the signed volume enclosed by a closed mesh (fan triangulation of each face).
fn signed_volume6(m: &ControlMesh) -> f64 {
    let p = m.positions();
    (0..m.face_count())
        .map(|f| {
            let face = m.face(f);
            let a = p[face[0] as usize];
            (1..face.len() - 1)
                .map(|k| a.dot(p[face[k] as usize].cross(p[face[k + 1] as usize])))
                .sum::<f64>()
        })
        .sum()
}

#[test]
fn valid_strip_loads() {
    let m = ControlMesh::new(strip()).unwrap();
    assert_eq!(m.vertex_count(), 6);
    assert_eq!(m.face_count(), 2);
    assert_eq!(m.face(1), &[1, 2, 5, 4]);
    assert!(m.warnings().is_empty());
}

#[test]
fn empty_mesh() {
    assert!(matches!(
        err(ControlMeshDesc::default()),
        Error::EmptyMesh(_)
    ));
    let mut d = strip();
    d.face_sizes.clear();
    d.face_vertices.clear();
    assert!(matches!(err(d), Error::EmptyMesh(_)));
}

#[test]
fn size_mismatch() {
    let mut d = strip();
    d.face_vertices.pop();
    assert_eq!(
        err(d),
        Error::SizeMismatch {
            what: "face_vertices length vs. sum of face_sizes",
            expected: 8,
            found: 7
        }
    );
}

#[test]
fn face_with_fewer_than_three_vertices() {
    let mut d = strip();
    d.face_sizes = vec![4, 2, 2];
    d.face_vertices = vec![0, 1, 4, 3, 1, 2, 5, 4];
    assert_eq!(err(d), Error::FaceTooSmall { face: 1, size: 2 });
}

#[test]
fn out_of_range_index_names_face_and_corner() {
    let mut d = strip();
    d.face_vertices[6] = 99;
    assert_eq!(
        err(d),
        Error::IndexOutOfRange {
            face: 1,
            corner: 2,
            index: 99,
            vertex_count: 6
        }
    );
}

#[test]
fn non_finite_coordinates() {
    let mut d = strip();
    d.positions[4].y = f64::NAN;
    assert_eq!(err(d), Error::NonFiniteCoordinate { vertex: 4 });
    let mut d = strip();
    d.positions[2].z = f64::NEG_INFINITY;
    assert_eq!(err(d), Error::NonFiniteCoordinate { vertex: 2 });
}

#[test]
fn repeated_vertex_in_small_and_large_faces() {
    let mut d = strip();
    d.face_vertices = vec![0, 1, 4, 3, 1, 2, 1, 4];
    assert_eq!(err(d), Error::RepeatedVertex { face: 1, vertex: 1 });
    // A 10-gon (sorted path of the check) with vertex 7 twice.
    let d = ControlMeshDesc {
        positions: vec![DVec3::ZERO; 10],
        face_sizes: vec![10],
        face_vertices: vec![0, 1, 2, 3, 7, 4, 5, 6, 7, 8],
        ..Default::default()
    };
    assert_eq!(err(d), Error::RepeatedVertex { face: 0, vertex: 7 });
}

#[test]
fn non_manifold_edge_names_its_vertices() {
    // Three quads hinged on the edge 1-4 (a "book" with three pages).
    let mut d = strip();
    d.positions.push(DVec3::new(1.0, 0.0, 1.0));
    d.positions.push(DVec3::new(1.0, 1.0, 1.0));
    d.face_sizes.push(4);
    d.face_vertices.extend([1, 6, 7, 4]);
    assert_eq!(
        err(d),
        Error::NonManifoldEdge {
            v0: 1,
            v1: 4,
            face_count: 3
        }
    );
}

#[test]
fn bow_tie_vertex_open_and_closed() {
    // Two triangles touching only at vertex 2.
    let d = ControlMeshDesc {
        positions: vec![DVec3::ZERO; 5],
        face_sizes: vec![3, 3],
        face_vertices: vec![0, 1, 2, 2, 3, 4],
        ..Default::default()
    };
    assert_eq!(err(d), Error::NonManifoldVertex { vertex: 2, fans: 2 });
    // Two closed tetrahedra sharing vertex 3: no boundary, still two fans around 3.
    let tet = |o: u32, apex: u32| {
        let (a, b, c) = (o, o + 1, o + 2);
        vec![a, c, b, a, b, apex, b, c, apex, c, a, apex]
    };
    let mut fv = tet(0, 3);
    fv.extend(tet(4, 3));
    let d = ControlMeshDesc {
        positions: (0..7).map(|i| DVec3::splat(i as f64)).collect(),
        face_sizes: vec![3; 8],
        face_vertices: fv,
        ..Default::default()
    };
    assert_eq!(err(d), Error::NonManifoldVertex { vertex: 3, fans: 2 });
}

#[test]
fn inconsistent_winding_names_faces_and_edge() {
    let mut d = strip();
    // Face 1 reversed: (4,5,2,1) uses 4->1? no: its edges are 4->5, 5->2, 2->1, 1->4.
    // Face 0 (0,1,4,3) uses 1->4 too.
    d.face_vertices = vec![0, 1, 4, 3, 4, 5, 2, 1];
    assert_eq!(
        err(d),
        Error::InconsistentWinding {
            face0: 0,
            face1: 1,
            v0: 1,
            v1: 4
        }
    );
}

#[test]
fn crease_must_be_an_edge() {
    let mut d = strip();
    d.creases = vec![
        Crease {
            v0: 4,
            v1: 1,
            sharpness: 1.0,
        },
        Crease {
            v0: 0,
            v1: 4,
            sharpness: 2.0,
        },
    ];
    assert_eq!(
        err(d),
        Error::CreaseNotAnEdge {
            crease: 1,
            v0: 0,
            v1: 4
        }
    );
}

#[test]
fn bad_sharpness_names_the_tag() {
    let mut d = strip();
    d.creases = vec![Crease {
        v0: 1,
        v1: 2,
        sharpness: -0.5,
    }];
    assert_eq!(
        err(d),
        Error::InvalidSharpness {
            kind: TagKind::Crease,
            index: 0,
            sharpness: -0.5
        }
    );
    let mut d = strip();
    d.corners = vec![
        Corner {
            vertex: 0,
            sharpness: 3.0,
        },
        Corner {
            vertex: 2,
            sharpness: f32::NAN,
        },
    ];
    assert!(matches!(
        err(d),
        Error::InvalidSharpness { kind: TagKind::Corner, index: 1, sharpness } if sharpness.is_nan()
    ));
}

#[test]
fn tag_indices_out_of_range() {
    let mut d = strip();
    d.holes = vec![1, 2];
    assert_eq!(
        err(d),
        Error::TagIndexOutOfRange {
            kind: TagKind::Hole,
            index: 1,
            value: 2,
            limit: 2
        }
    );
    let mut d = strip();
    d.corners = vec![Corner {
        vertex: 6,
        sharpness: 1.0,
    }];
    assert_eq!(
        err(d),
        Error::TagIndexOutOfRange {
            kind: TagKind::Corner,
            index: 0,
            value: 6,
            limit: 6
        }
    );
    let mut d = strip();
    d.creases = vec![Crease {
        v0: 1,
        v1: 60,
        sharpness: 1.0,
    }];
    assert_eq!(
        err(d),
        Error::TagIndexOutOfRange {
            kind: TagKind::Crease,
            index: 0,
            value: 60,
            limit: 6
        }
    );
}

#[test]
fn unreferenced_vertices_are_a_warning() {
    let mut d = strip();
    d.positions.push(DVec3::ONE);
    d.positions.insert(0, DVec3::ONE);
    for v in &mut d.face_vertices {
        *v += 1;
    }
    let m = ControlMesh::new(d).unwrap();
    assert_eq!(
        m.warnings(),
        &[MeshWarning::UnreferencedVertices(vec![0, 7])]
    );
}

/// The unit cube wound clockwise seen from outside.
fn clockwise_cube() -> ControlMeshDesc {
    let positions = (0..8)
        .map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64))
        .collect();
    // Counter-clockwise from outside, then reversed.
    ControlMeshDesc {
        positions,
        face_sizes: vec![4; 6],
        face_vertices: CUBE_FACES
            .iter()
            .flat_map(|f| f.iter().rev().copied())
            .collect(),
        ..Default::default()
    }
}

#[test]
fn left_handed_flag_reverses_faces() {
    let cw = ControlMesh::new(clockwise_cube()).unwrap();
    assert!((signed_volume6(&cw) + 6.0).abs() < 1e-12);
    let mut d = clockwise_cube();
    d.left_handed = true;
    let ccw = ControlMesh::new(d).unwrap();
    assert!((signed_volume6(&ccw) - 6.0).abs() < 1e-12);
    // Corner 0 stays first.
    assert_eq!(ccw.face(0), &[1, 0, 2, 3]);
    assert_eq!(cw.face(0), &[1, 3, 2, 0]);
}

/// Deterministic pseudo-random descriptions: construction must return, never panic.
#[test]
fn construction_never_panics_on_random_descriptions() {
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut next = move |n: u32| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % n.max(1) as u64) as u32
    };
    let (mut ok, mut refused) = (0, 0);
    for _ in 0..3000 {
        let nv = next(8);
        let nf = next(6);
        let positions = (0..nv)
            .map(|_| match next(40) {
                0 => DVec3::new(f64::NAN, 0.0, 0.0),
                1 => DVec3::splat(f64::INFINITY),
                k => DVec3::new(k as f64, next(5) as f64, next(3) as f64),
            })
            .collect();
        let face_sizes: Vec<u32> = (0..nf).map(|_| next(6)).collect();
        let total: u32 = (face_sizes.iter().sum::<u32>() + next(3)).saturating_sub(1);
        let face_vertices = (0..total).map(|_| next(nv + 2)).collect();
        let creases = (0..next(3))
            .map(|_| Crease {
                v0: next(nv + 1),
                v1: next(nv + 1),
                sharpness: next(12) as f32 - 1.0,
            })
            .collect();
        let corners = (0..next(2))
            .map(|_| Corner {
                vertex: next(nv + 1),
                sharpness: if next(5) == 0 { f32::NAN } else { 2.0 },
            })
            .collect();
        let holes = (0..next(2)).map(|_| next(nf + 1)).collect();
        let desc = ControlMeshDesc {
            positions,
            face_sizes,
            face_vertices,
            creases,
            corners,
            holes,
            left_handed: next(2) == 1,
            ..Default::default()
        };
        match ControlMesh::new(desc) {
            Ok(_) => ok += 1,
            Err(_) => refused += 1,
        }
    }
    assert!(refused > 0);
    let _ = ok;
}

// ---------------------------------------------------------------------------------------------
// OBJ reader

/// Vertex order must be the file's `v` order even when faces use vertices out of order, skip
/// one, split into objects/groups and use `v/vt/vn` or negative relative references; positions
/// must keep f64 precision.
#[test]
fn obj_keeps_file_vertex_indices() {
    let text = "\
# comment
v 0.1 0 0
v 1 0 0
v 5 5 5
v 1 1 0
v 0 1 0
vt 0 0
vn 0 0 1
o first
f 4/1/1 5/1/1 1/1/1
g second
v 2 0 0
v 2 1 0
f 2//1 -2 -1 4
s off
f 1 2 4 # trailing comment
";
    let m = obj(text).unwrap();
    assert_eq!(m.vertex_count(), 7);
    assert_eq!(m.face_count(), 3);
    assert_eq!(m.face(0), &[3, 4, 0]);
    assert_eq!(m.face(1), &[1, 5, 6, 3]);
    assert_eq!(m.face(2), &[0, 1, 3]);
    assert_eq!(m.positions()[0].x, 0.1f64);
    assert_eq!(m.positions()[2], DVec3::splat(5.0));
    assert_eq!(m.positions()[6], DVec3::new(2.0, 1.0, 0.0));
    // Texture coordinates on face 0 only: read without them, with a warning.
    assert!(m.uvs().is_none());
    assert_eq!(
        m.warnings(),
        &[
            MeshWarning::PartialTexCoords { face: 1 },
            MeshWarning::UnreferencedVertices(vec![2])
        ]
    );
}

const SQUARE2X2: &str = "\
v 0 0 0
v 1 0 0
v 2 0 0
v 0 1 0
v 1 1 0
v 2 1 0
v 0 2 0
v 1 2 0
v 2 2 0
f 1 2 5 4
f 2 3 6 5
f 4 5 8 7
f 5 6 9 8
";

#[test]
fn obj_tags() {
    let text = format!(
        "{SQUARE2X2}\
t crease 2/1 3 4 1.5
t crease 4/1/0 4 5 1 4 10
t crease 4/2 4 7 0 1 0.25 3
t corner 1/1 0 2
t corner 2/1 2 6 4.5
t corner 2/2 8 5 1 0.5
t hole 1/0 3
t interpolateboundary 1/0/0 2
t creasemethod 0/0/1 chaikin
t facevaryinginterpolateboundary 1/0/0 1
t smoothtriangles 0/0/1 smooth
t sparkle 1/0 3
"
    );
    let m = obj(&text).unwrap();
    let c = |v0, v1, sharpness| Crease { v0, v1, sharpness };
    assert_eq!(
        m.creases(),
        &[
            c(3, 4, 1.5),
            c(4, 5, 10.0),
            c(1, 4, 10.0),
            c(4, 7, 0.25),
            c(0, 1, 3.0)
        ]
    );
    let k = |vertex, sharpness| Corner { vertex, sharpness };
    assert_eq!(
        m.corners(),
        &[k(0, 2.0), k(2, 4.5), k(6, 4.5), k(8, 1.0), k(5, 0.5)]
    );
    assert!(m.is_hole(3) && !m.is_hole(0) && !m.is_hole(2));
    assert_eq!(m.options().boundary, BoundaryInterpolation::EdgeOnly);
    assert_eq!(m.options().crease_method, CreaseMethod::Chaikin);
    assert_eq!(
        m.warnings(),
        &[
            MeshWarning::SmoothTrianglesIgnored { line: 24 },
            MeshWarning::UnknownTag {
                line: 25,
                name: "sparkle".into()
            }
        ]
    );
    let none = obj(&format!("{SQUARE2X2}t interpolateboundary 1/0 0\n")).unwrap();
    assert_eq!(none.options().boundary, BoundaryInterpolation::None);
    let default = obj(SQUARE2X2).unwrap();
    assert_eq!(
        default.options().boundary,
        BoundaryInterpolation::EdgeAndCorner
    );
    assert_eq!(default.options().crease_method, CreaseMethod::Normal);
}

/// Asserts a parse error on `line` whose text is `text`.
fn assert_parse_error(result: tessera::Result<ControlMesh>, line: usize, text: &str) {
    match result {
        Err(Error::Parse {
            line: l, text: t, ..
        }) => {
            assert_eq!((l, t.as_str()), (line, text));
        }
        other => panic!("expected a parse error on line {line}, got {other:?}"),
    }
}

#[test]
fn malformed_tags_name_line_and_text() {
    let cases = [
        "t crease 2/1 0 1",
        "t crease 3/1 0 1 2 1.0",
        "t crease 4/3 0 1 1 2 1 2 3",
        "t crease 2/1 0 x 1.0",
        "t crease 2/1 -1 0 1.0",
        "t corner 1/1 0 soft",
        "t corner 2/0 0 1",
        "t hole 1/1 0 1.0",
        "t interpolateboundary 1/0 7",
        "t interpolateboundary 0/0",
        "t creasemethod 0/0/1 wobbly",
        "t smoothtriangles 0/0/1 loop",
        "t crease",
        "t crease a/b 0 1 1",
        "t crease 2/1/0/4 0 1 1",
    ];
    for case in cases {
        assert_parse_error(obj(&format!("{SQUARE2X2}{case}\n")), 14, case);
    }
}

#[test]
fn tag_errors_from_validation() {
    assert_eq!(
        obj(&format!("{SQUARE2X2}t crease 2/1 0 4 1\n")).unwrap_err(),
        Error::CreaseNotAnEdge {
            crease: 0,
            v0: 0,
            v1: 4
        }
    );
    assert!(matches!(
        obj(&format!("{SQUARE2X2}t corner 1/1 1 nan\n")).unwrap_err(),
        Error::InvalidSharpness {
            kind: TagKind::Corner,
            index: 0,
            ..
        }
    ));
    assert_eq!(
        obj(&format!("{SQUARE2X2}t hole 2/0 0 4\n")).unwrap_err(),
        Error::TagIndexOutOfRange {
            kind: TagKind::Hole,
            index: 1,
            value: 4,
            limit: 4
        }
    );
}

#[test]
fn malformed_files_give_typed_errors() {
    let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    assert_parse_error(obj(&format!("{tri}f 0 1 2\n")), 4, "f 0 1 2");
    assert_parse_error(obj(&format!("{tri}f 1 2 9\n")), 4, "f 1 2 9");
    assert_parse_error(obj(&format!("{tri}f -1 -2 -4\n")), 4, "f -1 -2 -4");
    assert_parse_error(obj(&format!("{tri}f 1 2 x\n")), 4, "f 1 2 x");
    assert_parse_error(obj(&format!("{tri}f 1 2 /3\n")), 4, "f 1 2 /3");
    assert_parse_error(
        obj(&format!("{tri}f 1 2 99999999999999999999\n")),
        4,
        "f 1 2 99999999999999999999",
    );
    assert_parse_error(obj("v 1 2\nv 0 0 0\n"), 1, "v 1 2");
    assert_parse_error(obj("v 1 2 3 4 5\n"), 1, "v 1 2 3 4 5");
    assert_parse_error(obj("v 1 2 z\n"), 1, "v 1 2 z");
    assert_parse_error(obj("v 1 2 3 0\n"), 1, "v 1 2 3 0");
    assert_parse_error(
        obj("\u{7f}ELF\u{1}\u{1}\0\0garbage\n"),
        1,
        // Control characters are quoted escaped (nothing a terminal would act on).
        "\\u{7f}ELF\\u{1}\\u{1}\\u{0}\\u{0}garbage",
    );
    // A face using a vertex defined later is fine; one beyond the whole file is not.
    assert!(obj("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n").is_ok());
    assert_parse_error(obj("f 1 2 4\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"), 1, "f 1 2 4");

    assert!(matches!(obj(""), Err(Error::EmptyMesh(_))));
    assert!(matches!(obj("# nothing\n\n"), Err(Error::EmptyMesh(_))));
    assert!(matches!(obj(tri), Err(Error::EmptyMesh(_))));
    assert_eq!(
        obj(&format!("{tri}v nan 0 0\nf 1 2 4\n")).unwrap_err(),
        Error::NonFiniteCoordinate { vertex: 3 }
    );
    assert_eq!(
        obj(&format!("{tri}v 0 inf 0\nf 1 2 3\n")).unwrap_err(),
        Error::NonFiniteCoordinate { vertex: 3 }
    );
    assert_eq!(
        obj(&format!("{tri}f 1 2 3\nf 1 2\n")).unwrap_err(),
        Error::FaceTooSmall { face: 1, size: 2 }
    );
    assert_eq!(
        obj(&format!("{tri}f\n")).unwrap_err(),
        Error::FaceTooSmall { face: 0, size: 0 }
    );
    // Bad normal references are irrelevant to positions and do not matter; bad texture
    // coordinate references are errors naming the face (tests/texcoords.rs).
    assert!(obj(&format!("{tri}vn 0 0 1\nf 1//9 2//0 3//-7\n")).is_ok());
    assert_parse_error(
        obj(&format!("{tri}vt 0 0\nf 1/0 2/0 3/-7\n")),
        5,
        "f 1/0 2/0 3/-7",
    );
    // Binary junk that is not valid UTF-8.
    let junk: Vec<u8> = (0..2000u32)
        .map(|i| (i.wrapping_mul(2654435761) >> 13) as u8)
        .collect();
    let path = common::out_dir("mesh_input").join("junk.obj");
    std::fs::write(&path, &junk).unwrap();
    let r = ControlMesh::from_obj_file(&path, &ObjOptions::default());
    std::fs::remove_file(&path).ok();
    assert!(
        matches!(r, Err(Error::Parse { .. } | Error::EmptyMesh(_))),
        "{r:?}"
    );
    assert!(matches!(
        ControlMesh::from_obj_file("/nonexistent/file.obj", &ObjOptions::default()),
        Err(Error::Io { .. })
    ));
}

#[test]
fn ignored_statements_warn() {
    let m = obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nl 1 2\nusemtl red\nmtllib x.mtl\n").unwrap();
    assert_eq!(
        m.warnings(),
        &[MeshWarning::IgnoredStatement {
            line: 5,
            keyword: "l".into()
        }]
    );
}

// ---------------------------------------------------------------------------------------------
// The OpenSubdiv regression corpus

/// Files refused, and why. Derived from the files themselves, independently of this crate:
/// SOURCE.md's non-manifold-edge column (edges used by > 2 faces), and a separate per-vertex
/// analysis of the OBJ text (faces around a vertex grouped by shared edges at that vertex).
/// `catmark_nonman_bareverts` is not refused: it is manifold, its 10 bare vertices are only a
/// warning. `catmark_gregory_test4` is refused: vertex 4 (0-based) is shared by faces 0 and 1
/// only through that vertex (a bow-tie).
const REFUSED: &[(&str, &str)] = &[
    ("catmark_fan", "4 non-manifold edges"),
    ("catmark_gregory_test4", "bow-tie at vertex 4"),
    ("catmark_nonman_edge100", "1 non-manifold edge (100 faces)"),
    ("catmark_nonman_edges", "11 non-manifold edges"),
    (
        "catmark_nonman_quadpole8",
        "non-manifold edge, degenerate faces",
    ),
    (
        "catmark_nonman_quadpole64",
        "non-manifold edge, degenerate faces",
    ),
    (
        "catmark_nonman_quadpole360",
        "non-manifold edge, degenerate faces",
    ),
    ("catmark_nonman_verts", "bow-ties at vertices 1, 10, 24, 35"),
    ("catmark_val2_nonman", "2 non-manifold edges"),
];

#[test]
fn osd_corpus_loads_exactly_the_manifold_files() {
    let names = osd_names();
    assert_eq!(names.len(), 82);
    let mut loaded = 0;
    for name in &names {
        let result = ControlMesh::from_obj_file(osd_path(name), &corpus_options(name));
        match REFUSED.iter().find(|r| r.0 == name) {
            Some((_, why)) => {
                let e = result.expect_err(name);
                let expected = match why.contains("bow-tie") {
                    true => matches!(e, Error::NonManifoldVertex { .. }),
                    false => matches!(
                        e,
                        Error::NonManifoldEdge { .. } | Error::RepeatedVertex { .. }
                    ),
                };
                assert!(expected, "{name}: {why}, got {e}");
            }
            None => {
                let m = result.unwrap_or_else(|e| panic!("{name}: {e}"));
                assert!(m.face_count() > 0);
                loaded += 1;
            }
        }
    }
    assert_eq!(loaded, 82 - REFUSED.len());
}

#[test]
fn osd_specific_files() {
    let load = |name: &str, left_handed: bool| {
        ControlMesh::from_obj_file(
            osd_path(name),
            &ObjOptions {
                left_handed,
                check_with_tobj: true,
            },
        )
        .unwrap()
    };
    // Counts from SOURCE.md.
    let car = load("catmark_car", false);
    assert_eq!(
        (car.vertex_count(), car.face_count(), car.creases().len()),
        (1642, 1575, 314)
    );
    let nonquads = load("catmark_nonquads", false);
    let sizes =
        |m: &ControlMesh, n: usize| (0..m.face_count()).filter(|&f| m.face_size(f) == n).count();
    assert_eq!((sizes(&nonquads, 3), sizes(&nonquads, 4)), (7, 7));
    // Bare vertices: a warning naming 10 vertices.
    let bare = load("catmark_nonman_bareverts", false);
    assert!(matches!(bare.warnings(), [MeshWarning::UnreferencedVertices(v)] if v.len() == 10));
    // The left-handed model encloses positive volume only with the flag; the
    // right-handed twin does without it.
    let lh = load("catmark_lefthanded", true);
    let lh_raw = load("catmark_lefthanded", false);
    let rh = load("catmark_righthanded", false);
    assert!(signed_volume6(&lh) > 0.0);
    assert!(signed_volume6(&lh_raw) < 0.0);
    assert!(signed_volume6(&rh) > 0.0);
    let hole = load("catmark_hole_test1", false);
    assert_eq!((0..6).filter(|&f| hole.is_hole(f)).count(), 1);
    let chaikin = load("catmark_chaikin1", false);
    assert_eq!(chaikin.options().crease_method, CreaseMethod::Chaikin);
    let edgenone = load("catmark_edgenone", false);
    assert_eq!(edgenone.options().boundary, BoundaryInterpolation::None);
    let smooth = load("catmark_smoothtris1", false);
    assert!(matches!(
        smooth.warnings(),
        [MeshWarning::SmoothTrianglesIgnored { .. }]
    ));
}

// ---------------------------------------------------------------------------------------------
// Embedded meshes

/// Per undirected edge, the number of faces using it (computed here with a map, independently
/// of the crate's validation).
fn edge_use(m: &ControlMesh) -> std::collections::HashMap<(u32, u32), u32> {
    let mut uses = std::collections::HashMap::new();
    for f in 0..m.face_count() {
        let face = m.face(f);
        for k in 0..face.len() {
            let (a, b) = (face[k], face[(k + 1) % face.len()]);
            *uses.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    uses
}

/// (valence, is boundary) of every vertex.
fn valences(m: &ControlMesh) -> Vec<(usize, bool)> {
    let mut out = vec![(0usize, false); m.vertex_count()];
    for (&(a, b), &n) in &edge_use(m) {
        for v in [a, b] {
            out[v as usize].0 += 1;
            out[v as usize].1 |= n == 1;
        }
    }
    out
}

fn face_size_counts(m: &ControlMesh) -> std::collections::BTreeMap<usize, usize> {
    let mut c = std::collections::BTreeMap::new();
    for f in 0..m.face_count() {
        *c.entry(m.face_size(f)).or_insert(0) += 1;
    }
    c
}

#[test]
fn embedded_mixed_is_closed_with_the_promised_features() {
    use tessera::assets::{default_mesh, EmbeddedMesh};
    let m = EmbeddedMesh::Mixed.load().unwrap();
    assert_eq!(default_mesh().face_count(), m.face_count());
    assert!(m.warnings().is_empty());
    assert!(edge_use(&m).values().all(|&n| n == 2), "closed");
    assert!(signed_volume6(&m) > 0.0, "counter-clockwise from outside");
    let sizes = face_size_counts(&m);
    assert!(sizes[&3] > 0 && sizes[&4] > 0 && sizes[&5] > 0, "{sizes:?}");
    assert!((20..=200).contains(&m.face_count()));
    let vals: Vec<usize> = valences(&m).iter().map(|v| v.0).collect();
    for n in [3, 5, 6] {
        assert!(vals.contains(&n), "valence {n} missing: {vals:?}");
    }
}

#[test]
fn embedded_open_has_boundary_corners_and_a_boundary_extraordinary_vertex() {
    use tessera::assets::EmbeddedMesh;
    let m = EmbeddedMesh::Open.load().unwrap();
    assert!(m.warnings().is_empty());
    assert!((20..=200).contains(&m.face_count()));
    let vals = valences(&m);
    // Boundary corner: boundary vertex with 2 edges. Regular boundary vertex: 3 edges.
    assert_eq!(vals.iter().filter(|v| **v == (2, true)).count(), 2);
    assert!(vals.iter().any(|v| v.1 && v.0 > 3));
    // Consistently oriented: seen from +z every face turns counter-clockwise (shoelace area).
    for f in 0..m.face_count() {
        let face = m.face(f);
        let p = |k: usize| m.positions()[face[k % face.len()] as usize];
        let area: f64 = (0..face.len())
            .map(|k| p(k).x * p(k + 1).y - p(k + 1).x * p(k).y)
            .sum();
        assert!(area > 0.0, "face {f}");
    }
}

#[test]
fn embedded_creased_has_semi_sharp_and_infinite_creases_and_a_corner() {
    use tessera::assets::EmbeddedMesh;
    use tessera::mesh::INFINITE_SHARPNESS;
    let m = EmbeddedMesh::Creased.load().unwrap();
    assert!(m.warnings().is_empty());
    assert!((20..=200).contains(&m.face_count()));
    assert!(edge_use(&m).values().all(|&n| n == 2), "closed");
    assert!(signed_volume6(&m) > 0.0);
    let s: Vec<f32> = m.creases().iter().map(|c| c.sharpness).collect();
    for want in [0.5, 1.0, 2.5] {
        assert!(s.contains(&want), "sharpness {want} missing");
    }
    assert!(s.iter().any(|&x| x >= INFINITE_SHARPNESS));
    assert!(m
        .corners()
        .iter()
        .any(|c| c.sharpness >= INFINITE_SHARPNESS));
    assert_eq!(
        face_size_counts(&m).keys().copied().collect::<Vec<_>>(),
        vec![4]
    );
}

#[test]
fn load_mesh_spec() {
    use tessera::assets::load_mesh;
    let o = ObjOptions::default();
    assert_eq!(load_mesh("embedded:open", &o).unwrap().face_count(), 21);
    assert!(matches!(
        load_mesh("embedded:teapot", &o),
        Err(Error::Invalid(_))
    ));
    let car = osd_path("catmark_cube");
    assert_eq!(
        load_mesh(car.to_str().unwrap(), &o).unwrap().face_count(),
        6
    );
}

// ---------------------------------------------------------------------------------------------
// `tessera info`

fn run_info(args: &[&str]) -> (bool, String, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_tessera"))
        .arg("info")
        .args(args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The value after `key: ` on the line starting with `key`.
fn info_field<'a>(report: &'a str, key: &str) -> &'a str {
    report
        .lines()
        .find_map(|l| l.strip_prefix(key)?.strip_prefix(": "))
        .unwrap_or_else(|| panic!("no `{key}` in\n{report}"))
}

#[test]
fn info_on_the_embedded_default_mesh() {
    let (ok, out, err) = run_info(&["embedded:mixed"]);
    assert!(ok, "{err}");
    // Counted by hand from the construction of assets/mixed.obj: 5 + 5 + 6 + 6 + 6 + 1
    // vertices; 1 pentagon, 22 quads (5 + 5 + 6 + 6), 7 triangles (1 + 6); Euler: V - E + F = 2.
    assert_eq!(info_field(&out, "faces"), "30 (by size: 3: 7, 4: 22, 5: 1)");
    assert!(info_field(&out, "vertices").starts_with("29 "));
    assert_eq!(info_field(&out, "edges"), "57 (boundary 0)");
    assert_eq!(
        info_field(&out, "extraordinary vertices, interior"),
        "7 (by valence: 3: 5, 5: 1, 6: 1)"
    );
    let (ok, out, _) = run_info(&["embedded:creased"]);
    assert!(ok);
    // 4 vertical chains of 3 edges (0.5, 1, 2.5, 10), the 12-edge top rim (10), one edge of 2.
    assert_eq!(
        info_field(&out, "creases"),
        "25 (by sharpness: 0.5: 3, 1: 3, 2: 1, 2.5: 3, inf: 15)"
    );
    assert_eq!(info_field(&out, "corners"), "1 (by sharpness: inf: 1)");
}

#[test]
fn info_refuses_bad_input_with_the_typed_error() {
    let fan = osd_path("catmark_fan");
    let (ok, out, err) = run_info(&[fan.to_str().unwrap()]);
    assert!(!ok);
    assert!(out.is_empty());
    assert!(err.contains("non-manifold edge 7-8"), "{err}");
    let path = common::out_dir("mesh_input").join("bad.obj");
    std::fs::write(&path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n").unwrap();
    let (ok, _, err) = run_info(&[path.to_str().unwrap()]);
    std::fs::remove_file(&path).ok();
    assert!(!ok);
    assert!(err.contains("line 4") && err.contains("f 1 2 0"), "{err}");
    let (ok, _, err) = run_info(&["embedded:nothing"]);
    assert!(!ok && err.contains("no embedded mesh"), "{err}");
}

/// `tessera info` against the counts SOURCE.md lists for every loadable OpenSubdiv file
/// (computed there from the OBJ text by a separate script).
#[test]
fn info_agrees_with_source_md() {
    let table = std::fs::read_to_string(osd_dir().join("SOURCE.md")).unwrap();
    let mut checked = 0;
    for row in table.lines().filter(|l| l.starts_with("| catmark_")) {
        let cols: Vec<&str> = row.split('|').map(str::trim).collect();
        let name = cols[1].trim_end_matches(".obj");
        if REFUSED.iter().any(|r| r.0 == name) {
            continue;
        }
        let n = |i: usize| cols[i].parse::<usize>().unwrap();
        let path = osd_dir().join(cols[1]);
        let mut args = vec![path.to_str().unwrap()];
        if name == "catmark_lefthanded" {
            args.push("--left-handed");
        }
        let (ok, out, err) = run_info(&args);
        assert!(ok, "{name}: {err}");
        assert!(
            info_field(&out, "vertices").starts_with(&format!("{} ", n(2))),
            "{name}"
        );
        let faces = info_field(&out, "faces");
        assert!(faces.starts_with(&format!("{} ", n(3))), "{name}");
        let size = |s: usize| {
            faces
                .split(&format!(" {s}: "))
                .nth(1)
                .map_or(0, |t| t.split([',', ')']).next().unwrap().parse().unwrap())
        };
        let other = n(3) - size(3) - size(4);
        assert_eq!((size(3), size(4), other), (n(4), n(5), n(6)), "{name}");
        let count = |key: &str| -> usize {
            info_field(&out, key)
                .split(' ')
                .next()
                .unwrap()
                .parse()
                .unwrap()
        };
        assert_eq!(count("creases"), n(7), "{name}");
        assert_eq!(count("corners"), n(8), "{name}");
        // SOURCE.md counts `t hole` lines; a line may list several faces: count them here.
        let hole_faces: usize = std::fs::read_to_string(&path)
            .unwrap()
            .lines()
            .filter_map(|l| l.strip_prefix("t hole "))
            .map(|l| l.split_whitespace().count() - 1)
            .sum();
        assert_eq!(n(9) > 0, hole_faces > 0, "{name}");
        assert_eq!(count("holes"), hole_faces, "{name}");
        let edges = info_field(&out, "edges");
        assert!(
            edges.ends_with(&format!("(boundary {})", n(11))),
            "{name}: {edges}"
        );
        assert_eq!(count("extraordinary vertices, interior"), n(13), "{name}");
        checked += 1;
    }
    assert_eq!(checked, 82 - REFUSED.len());
}
