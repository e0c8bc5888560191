//! Property tests of mesh input (issue 14): random descriptions, random OBJ text and mutations
//! of valid OBJ files (embedded meshes and OpenSubdiv shapes) with random tags. The property:
//! no panic; either a typed error, or a mesh that passes validation, has a limit evaluator and
//! evaluates to finite positions, partials and normals at a few points of a few faces.

mod common;

use glam::DVec3;
use proptest::prelude::*;
use tessera::mesh::{
    BoundaryInterpolation, ControlMeshDesc, Corner, Crease, ObjOptions, SchemeOptions,
};
use tessera::subdiv::eval::LimitEvaluator;
use tessera::{ControlMesh, Error};

/// The property on a construction result.
fn check(result: tessera::Result<ControlMesh>) -> Result<(), TestCaseError> {
    let mesh = match result {
        Err(e) => {
            // Typed and printable, of bounded length.
            let text = e.to_string();
            prop_assert!(!text.is_empty() && text.len() < 1000, "{text}");
            return Ok(());
        }
        Ok(mesh) => mesh,
    };
    let ev = LimitEvaluator::new(&mesh);
    prop_assert!(ev.is_ok(), "valid mesh without evaluator: {:?}", ev.err());
    let ev = ev.unwrap();
    let faces: Vec<usize> = (0..ev.face_count())
        .filter(|&f| ev.has_limit_surface(f))
        .take(6)
        .collect();
    for f in faces {
        let subs = ev.sub_face_count(f);
        for sub in [0, subs - 1] {
            let uv = [(0.0, 0.0), (0.5, 0.5), (1.0, 1.0), (0.3, 0.9)];
            let samples = ev.eval_points(f, sub, &uv);
            prop_assert!(samples.is_ok(), "face {f}: {:?}", samples.err());
            for (s, &(u, v)) in samples.unwrap().iter().zip(&uv) {
                prop_assert!(
                    s.position.is_finite()
                        && s.du.is_finite()
                        && s.dv.is_finite()
                        && s.normal.is_finite(),
                    "face {f} sub {sub} ({u}, {v}): {s:?}"
                );
            }
        }
    }
    Ok(())
}

/// Coordinates: mostly ordinary, sometimes extreme or non-finite.
fn coord() -> impl Strategy<Value = f64> {
    prop_oneof![
        8 => -10.0..10.0f64,
        1 => prop::sample::select(vec![
            0.0, -0.0, 1e-300, 1e29, -1e29, 1e30, 1e31, 1e308, f64::NAN, f64::INFINITY,
            f64::NEG_INFINITY, f64::MAX, f64::MIN_POSITIVE,
        ]),
    ]
}

fn sharpness() -> impl Strategy<Value = f32> {
    prop_oneof![
        6 => 0.0..12.0f32,
        1 => prop::sample::select(vec![-1.0, f32::NAN, f32::INFINITY, 1e30, 10.0, 0.0]),
    ]
}

prop_compose! {
    /// A random description: vertices, faces of 1..7 corners over (mostly) valid indices, tags.
    fn random_desc()(
        n in 1usize..14,
    )(
        positions in prop::collection::vec((coord(), coord(), coord()), n),
        faces in prop::collection::vec(prop::collection::vec(0u32..(n as u32 + 2), 1..7), 0..10),
        creases in prop::collection::vec((0u32..(n as u32 + 1), 0u32..(n as u32 + 1), sharpness()), 0..4),
        corners in prop::collection::vec((0u32..(n as u32 + 1), sharpness()), 0..3),
        holes in prop::collection::vec(0u32..12, 0..3),
        boundary in 0u8..3,
        left_handed in any::<bool>(),
    ) -> ControlMeshDesc {
        ControlMeshDesc {
            positions: positions.into_iter().map(|(x, y, z)| DVec3::new(x, y, z)).collect(),
            face_sizes: faces.iter().map(|f| f.len() as u32).collect(),
            face_vertices: faces.concat(),
            creases: creases.into_iter().map(|(v0, v1, sharpness)| Crease { v0, v1, sharpness }).collect(),
            corners: corners.into_iter().map(|(vertex, sharpness)| Corner { vertex, sharpness }).collect(),
            holes,
            options: SchemeOptions {
                boundary: match boundary {
                    0 => BoundaryInterpolation::None,
                    1 => BoundaryInterpolation::EdgeAndCorner,
                    _ => BoundaryInterpolation::EdgeOnly,
                },
                ..SchemeOptions::default()
            },
            left_handed,
        }
    }
}

/// Valid OBJ sources to mutate: the embedded meshes and a few small OpenSubdiv shapes.
fn sources() -> Vec<String> {
    let mut v: Vec<String> = tessera::assets::EmbeddedMesh::ALL
        .iter()
        .map(|m| m.obj_text().to_string())
        .collect();
    for name in [
        "catmark_cube",
        "catmark_cube_creases1",
        "catmark_pyramid_creases0",
        "catmark_nonquads",
        "catmark_square_hedit0",
        "catmark_torus_creases0",
    ] {
        if let Ok(text) = std::fs::read_to_string(common::meshes::osd_path(name)) {
            v.push(text);
        }
    }
    v
}

/// Tokens a mutation writes into a line.
const TOKENS: &[&str] = &[
    "0",
    "1",
    "2",
    "-1",
    "-3",
    "4294967295",
    "99999999999",
    "1e308",
    "-1e31",
    "nan",
    "inf",
    "x",
    "",
    "/",
    "1/2/3",
    "//",
    "v",
    "f",
    "t",
    "0.5",
    "10",
    "crease",
    "corner",
    "hole",
    "2/1",
    "1/0",
    "0/1",
    "3/0/1",
    "\u{feff}",
    "\r",
];

/// Tag lines a mutation inserts.
const TAGS: &[&str] = &[
    "t crease 2/1 0 1 2.5",
    "t crease 2/1 0 2 1",
    "t crease 4/2 0 1 1 2 3 -1",
    "t corner 1/1 0 10",
    "t corner 1/1 3 nan",
    "t hole 1/0 0",
    "t hole 2/0 0 1",
    "t interpolateboundary 1/0 0",
    "t interpolateboundary 1/0 2",
    "t creasemethod 0/0/1 chaikin",
    "t smoothtriangles 0/0/1 smooth",
    "t crease 2/1 0 1 1e30",
];

#[derive(Debug, Clone)]
enum Mutation {
    DeleteLine(usize),
    DuplicateLine(usize),
    SwapLines(usize, usize),
    ReplaceToken(usize, usize, usize),
    InsertTag(usize, usize),
    Truncate(usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (0usize..1000).prop_map(Mutation::DeleteLine),
        (0usize..1000).prop_map(Mutation::DuplicateLine),
        (0usize..1000, 0usize..1000).prop_map(|(a, b)| Mutation::SwapLines(a, b)),
        (0usize..1000, 0usize..8, 0..TOKENS.len())
            .prop_map(|(l, w, t)| Mutation::ReplaceToken(l, w, t)),
        (0usize..1000, 0..TAGS.len()).prop_map(|(l, t)| Mutation::InsertTag(l, t)),
        (0usize..100_000).prop_map(Mutation::Truncate),
    ]
}

fn apply(text: &str, muts: &[Mutation]) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    for m in muts {
        if lines.is_empty() {
            break;
        }
        let n = lines.len();
        match *m {
            Mutation::DeleteLine(l) => {
                lines.remove(l % n);
            }
            Mutation::DuplicateLine(l) => {
                let line = lines[l % n].clone();
                lines.insert(l % n, line);
            }
            Mutation::SwapLines(a, b) => lines.swap(a % n, b % n),
            Mutation::ReplaceToken(l, w, t) => {
                let mut words: Vec<String> = lines[l % n].split(' ').map(str::to_string).collect();
                let k = w % words.len();
                words[k] = TOKENS[t].to_string();
                lines[l % n] = words.join(" ");
            }
            Mutation::InsertTag(l, t) => lines.insert(l % (n + 1), TAGS[t].to_string()),
            Mutation::Truncate(at) => {
                let joined = lines.join("\n");
                let mut cut = at % (joined.len() + 1);
                while !joined.is_char_boundary(cut) {
                    cut -= 1;
                }
                lines = joined[..cut].lines().map(str::to_string).collect();
            }
        }
    }
    lines.join("\n")
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn random_descriptions_give_a_typed_error_or_a_finite_surface(desc in random_desc()) {
        check(ControlMesh::new(desc))?;
    }

    #[test]
    fn random_obj_text_gives_a_typed_error_or_a_finite_surface(
        lines in prop::collection::vec(
            (prop::sample::select(vec!["v", "f", "t", "vt", "o", "#", "l", "q", ""]),
             prop::collection::vec(prop::sample::select(TOKENS.to_vec()), 0..7)),
            0..24),
    ) {
        let text: String = lines
            .iter()
            .map(|(k, w)| format!("{k} {}\n", w.join(" ")))
            .collect();
        check(ControlMesh::from_obj_str(&text, "random", &ObjOptions::default()))?;
    }

    #[test]
    fn mutated_obj_files_give_a_typed_error_or_a_finite_surface(
        source in 0usize..9,
        muts in prop::collection::vec(mutation(), 1..6),
        left_handed in any::<bool>(),
    ) {
        let sources = sources();
        let text = apply(&sources[source % sources.len()], &muts);
        check(ControlMesh::from_obj_str(&text, "mutated", &ObjOptions {
            left_handed,
            check_with_tobj: true,
        }))?;
    }
}

/// The mutations reach both outcomes: the test is not vacuous.
#[test]
fn mutations_reach_errors_and_valid_meshes() {
    let cube = &sources()[0];
    assert!(ControlMesh::from_obj_str(cube, "m", &ObjOptions::default()).is_ok());
    let broken = apply(cube, &[Mutation::ReplaceToken(3, 1, 7)]);
    let e = ControlMesh::from_obj_str(&broken, "m", &ObjOptions::default());
    assert!(
        matches!(
            e,
            Err(Error::Parse { .. } | Error::CoordinateTooLarge { .. })
        ),
        "{e:?}"
    );
}
