//! The OBJ + OpenSubdiv tag parser and mesh validation on arbitrary bytes: no panic, no hang,
//! no unbounded allocation; a mesh that loads has a limit evaluator whose samples are finite.
#![no_main]

use libfuzzer_sys::fuzz_target;
use tessera::mesh::ObjOptions;
use tessera::subdiv::eval::LimitEvaluator;
use tessera::ControlMesh;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let left_handed = data.first().is_some_and(|b| b & 1 == 1);
    let Ok(mesh) = ControlMesh::from_obj_str(&text, "fuzz", &ObjOptions { left_handed }) else {
        return;
    };
    // Bounded work per input: evaluate only small meshes.
    if mesh.face_count() > 64 || mesh.vertex_count() > 256 {
        return;
    }
    let Ok(ev) = LimitEvaluator::new(&mesh) else {
        return;
    };
    for f in (0..ev.face_count())
        .filter(|&f| ev.has_limit_surface(f))
        .take(8)
    {
        for &(u, v) in &[(0.0, 0.0), (0.5, 0.5), (1.0, 0.25)] {
            let s = ev
                .eval(f, 0, u, v)
                .expect("face with a limit surface evaluates");
            assert!(
                s.position.is_finite()
                    && s.du.is_finite()
                    && s.dv.is_finite()
                    && s.normal.is_finite(),
                "face {f} ({u}, {v}): {s:?}"
            );
        }
    }
});
