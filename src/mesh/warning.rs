//! Non-fatal findings about a control mesh or its file.

use std::fmt;

/// Something about the input that is accepted but worth telling the user.
#[derive(Debug, Clone, PartialEq)]
pub enum MeshWarning {
    /// Vertices that no face uses (0-based). They stay in the mesh (tags keep their indices)
    /// but take no part in the surface.
    UnreferencedVertices(Vec<u32>),
    /// A tag this reader does not know; it was ignored.
    UnknownTag {
        /// 1-based line number.
        line: usize,
        /// The tag name.
        name: String,
    },
    /// `t smoothtriangles 0/0/1 smooth` asks for the Loop-like triangle rule, which is not
    /// implemented: triangles use the Catmull-Clark rule.
    SmoothTrianglesIgnored {
        /// 1-based line number.
        line: usize,
    },
    /// An OBJ statement that carries nothing for a subdivision control mesh (`l`, `p`, curves...).
    IgnoredStatement {
        /// 1-based line number.
        line: usize,
        /// The statement keyword.
        keyword: String,
    },
    /// Some faces reference texture coordinates (`f v/vt`) and this one (the first) does not:
    /// the mesh is read without texture coordinates.
    PartialTexCoords {
        /// The first face without them.
        face: u32,
    },
}

impl fmt::Display for MeshWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MeshWarning::UnreferencedVertices(v) => {
                const SHOWN: usize = 20;
                write!(f, "{} unreferenced vertices:", v.len())?;
                for i in v.iter().take(SHOWN) {
                    write!(f, " {i}")?;
                }
                if v.len() > SHOWN {
                    write!(f, " ...")?;
                }
                Ok(())
            }
            MeshWarning::UnknownTag { line, name } => {
                write!(f, "line {line}: unknown tag `{name}` ignored")
            }
            MeshWarning::SmoothTrianglesIgnored { line } => write!(
                f,
                "line {line}: smoothtriangles=smooth is not implemented; triangles use the Catmull-Clark rule"
            ),
            MeshWarning::IgnoredStatement { line, keyword } => {
                write!(f, "line {line}: OBJ statement `{keyword}` ignored")
            }
            MeshWarning::PartialTexCoords { face } => write!(
                f,
                "face {face} has no texture coordinates while other faces have them: texture \
                 coordinates ignored"
            ),
        }
    }
}
