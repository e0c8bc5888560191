//! Control meshes embedded in the binary (`assets/*.obj`, OBJ with OpenSubdiv tags).
//!
//! Commands that take a mesh accept either a file path or `embedded:NAME`
//! (see [`load_mesh`]); [`default_mesh`] is the mesh `tessera render` shows by default.

use crate::mesh::{ControlMesh, ObjOptions};
use crate::{Error, Result};

/// A mesh shipped inside the crate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EmbeddedMesh {
    /// Closed twisted onion dome: a pentagon, quads and triangles; extraordinary vertices of
    /// valence 3, 5 and 6. The default mesh.
    Mixed,
    /// Open scallop shell: boundary corners (valence 2) and a boundary extraordinary vertex
    /// (3 faces); interior valence-3 vertices.
    Open,
    /// Closed box with semi-sharp creases (0.5, 1, 2, 2.5), infinitely sharp creases and an
    /// infinitely sharp corner at the bottom of its infinitely sharp vertical edge.
    Creased,
}

impl EmbeddedMesh {
    /// Every embedded mesh.
    pub const ALL: [EmbeddedMesh; 3] = [
        EmbeddedMesh::Mixed,
        EmbeddedMesh::Open,
        EmbeddedMesh::Creased,
    ];

    /// Short name, as used in `embedded:NAME`.
    pub fn name(self) -> &'static str {
        match self {
            EmbeddedMesh::Mixed => "mixed",
            EmbeddedMesh::Open => "open",
            EmbeddedMesh::Creased => "creased",
        }
    }

    /// The mesh called `name`, if any.
    pub fn from_name(name: &str) -> Option<EmbeddedMesh> {
        Self::ALL.into_iter().find(|m| m.name() == name)
    }

    /// The OBJ text.
    pub fn obj_text(self) -> &'static str {
        match self {
            EmbeddedMesh::Mixed => include_str!("../assets/mixed.obj"),
            EmbeddedMesh::Open => include_str!("../assets/open.obj"),
            EmbeddedMesh::Creased => include_str!("../assets/creased.obj"),
        }
    }

    /// Parses and validates the mesh.
    pub fn load(self) -> Result<ControlMesh> {
        ControlMesh::from_obj_str(
            self.obj_text(),
            &format!("embedded:{}", self.name()),
            &ObjOptions::default(),
        )
    }
}

/// The default mesh ([`EmbeddedMesh::Mixed`]).
pub fn default_mesh() -> ControlMesh {
    // The embedded text is fixed at build time and covered by tests, so this cannot fail.
    EmbeddedMesh::Mixed
        .load()
        .expect("the embedded default mesh is valid")
}

/// Loads `spec`: `embedded:NAME` for an embedded mesh, otherwise an OBJ file path.
pub fn load_mesh(spec: &str, options: &ObjOptions) -> Result<ControlMesh> {
    match spec.strip_prefix("embedded:") {
        Some(name) => {
            let mesh = EmbeddedMesh::from_name(name).ok_or_else(|| {
                let known: Vec<&str> = EmbeddedMesh::ALL.iter().map(|m| m.name()).collect();
                Error::Invalid(format!(
                    "no embedded mesh `{name}` (known: {})",
                    known.join(", ")
                ))
            })?;
            ControlMesh::from_obj_str(mesh.obj_text(), spec, options)
        }
        None => ControlMesh::from_obj_file(spec, options),
    }
}
