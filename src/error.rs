//! The crate's error type. Every failure a user can trigger (bad input, missing device features)
//! is reported through [`enum@Error`]; nothing a user supplies may cause a panic.

use thiserror::Error;

mod device;

pub use device::{DeviceReport, GpuError, VkResultCode};

/// Longest quote of user text in a message ([`excerpt`]), in characters.
pub const EXCERPT_CHARS: usize = 80;

/// `text` trimmed, or its first [`EXCERPT_CHARS`] characters followed by `…` and the length
/// when longer: errors quote a short excerpt of what they refuse, never a whole multi-megabyte
/// line.
///
/// Control characters (NUL, escape sequences a terminal would act on, ...) are shown escaped.
pub fn excerpt(text: &str) -> String {
    let t = text.trim();
    let (head, cut) = match t.char_indices().nth(EXCERPT_CHARS) {
        None => (t, false),
        Some((at, _)) => (&t[..at], true),
    };
    let mut s = String::with_capacity(head.len() + 16);
    for c in head.chars() {
        if c.is_control() {
            s.extend(c.escape_default());
        } else {
            s.push(c);
        }
    }
    if cut {
        s += &format!("… ({} bytes)", t.len());
    }
    s
}

/// Result alias used throughout the crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Which kind of subdivision tag an error refers to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TagKind {
    /// A crease (sharp edge).
    Crease,
    /// A corner (sharp vertex).
    Corner,
    /// A hole face.
    Hole,
}

impl std::fmt::Display for TagKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            TagKind::Crease => "crease",
            TagKind::Corner => "corner",
            TagKind::Hole => "hole",
        })
    }
}

impl Error {
    /// [`Error::Parse`] of line `line` quoting an [`excerpt`] of `text`.
    pub fn parse(line: usize, text: &str, message: String) -> Error {
        Error::Parse {
            line,
            text: excerpt(text),
            message,
        }
    }
}

/// Every error tessera reports. Variants name the offending element (vertex, face, edge, line).
#[derive(Debug, Error, Clone, PartialEq)]
pub enum Error {
    /// The mesh has no vertices or no faces.
    #[error("empty mesh: {0}")]
    EmptyMesh(String),
    /// Generic invalid input that does not fit another variant.
    #[error("invalid input: {0}")]
    Invalid(String),
    /// Two arrays that must agree in length do not (e.g. the face sizes do not add up to the
    /// number of face-vertex indices).
    #[error("size mismatch: {what}: expected {expected}, found {found}")]
    SizeMismatch {
        /// What was compared.
        what: &'static str,
        /// The length implied by the other array.
        expected: u64,
        /// The length found.
        found: u64,
    },
    /// A face has fewer than 3 vertices.
    #[error("face {face} has {size} vertices (at least 3 needed)")]
    FaceTooSmall {
        /// The face (0-based).
        face: u32,
        /// Its number of vertices.
        size: u32,
    },
    /// A face refers to a vertex that does not exist.
    #[error("face {face}, corner {corner}: vertex index {index} out of range (mesh has {vertex_count} vertices)")]
    IndexOutOfRange {
        /// The face (0-based).
        face: u32,
        /// Position of the bad index within the face (0-based corner).
        corner: u32,
        /// The bad index.
        index: u32,
        /// Number of vertices of the mesh.
        vertex_count: u32,
    },
    /// A vertex coordinate is NaN or infinite.
    #[error("vertex {vertex} has a non-finite coordinate")]
    NonFiniteCoordinate {
        /// The vertex (0-based).
        vertex: u32,
    },
    /// A vertex coordinate is too large to evaluate or draw without overflow.
    #[error("vertex {vertex} has a coordinate of magnitude {value:e}, beyond the supported {limit:e} (it would overflow in evaluation or on the GPU); scale the model down")]
    CoordinateTooLarge {
        /// The vertex (0-based).
        vertex: u32,
        /// Its largest coordinate magnitude.
        value: f64,
        /// The largest magnitude accepted.
        limit: f64,
    },
    /// A face uses the same vertex twice.
    #[error("face {face} uses vertex {vertex} more than once")]
    RepeatedVertex {
        /// The face (0-based).
        face: u32,
        /// The repeated vertex.
        vertex: u32,
    },
    /// An edge is used by three or more faces.
    #[error("non-manifold edge {v0}-{v1}: used by {face_count} faces")]
    NonManifoldEdge {
        /// Smaller end vertex.
        v0: u32,
        /// Larger end vertex.
        v1: u32,
        /// How many faces use it.
        face_count: u32,
    },
    /// The faces around a vertex form more than one fan (a "bow-tie").
    #[error("non-manifold vertex {vertex}: its faces form {fans} separate fans")]
    NonManifoldVertex {
        /// The vertex.
        vertex: u32,
        /// Number of separate face fans around it (>= 2).
        fans: u32,
    },
    /// Two faces traverse a shared edge in the same direction: their windings disagree.
    #[error(
        "inconsistent winding: faces {face0} and {face1} both use the directed edge {v0}->{v1}"
    )]
    InconsistentWinding {
        /// First face.
        face0: u32,
        /// Second face.
        face1: u32,
        /// Start of the directed edge both faces use.
        v0: u32,
        /// End of the directed edge both faces use.
        v1: u32,
    },
    /// A crease tag names two vertices that are not joined by an edge of the mesh.
    #[error("crease {crease}: {v0}-{v1} is not an edge of the mesh")]
    CreaseNotAnEdge {
        /// Index of the crease in the crease list.
        crease: u32,
        /// First vertex of the tag.
        v0: u32,
        /// Second vertex of the tag.
        v1: u32,
    },
    /// A crease or corner sharpness is negative or NaN.
    #[error("{kind} {index}: invalid sharpness {sharpness} (must be >= 0)")]
    InvalidSharpness {
        /// Crease or corner.
        kind: TagKind,
        /// Index of the tag in its list.
        index: u32,
        /// The bad value.
        sharpness: f32,
    },
    /// A face corner's texture-coordinate index is out of range.
    #[error("face {face}, corner {corner}: texture coordinate {index} out of range (the mesh has {count})")]
    TexCoordOutOfRange {
        /// Face index.
        face: u32,
        /// Corner within the face.
        corner: u32,
        /// The bad texture-coordinate index (0-based).
        index: u32,
        /// Number of texture coordinates.
        count: u32,
    },
    /// A texture coordinate is NaN or infinite.
    #[error("texture coordinate {index} is not finite")]
    NonFiniteTexCoord {
        /// Texture-coordinate index (0-based).
        index: u32,
    },
    /// A crease/corner vertex or a hole face index is out of range.
    #[error("{kind} {index}: index {value} out of range (limit {limit})")]
    TagIndexOutOfRange {
        /// Crease, corner or hole.
        kind: TagKind,
        /// Index of the tag in its list.
        index: u32,
        /// The bad vertex or face index.
        value: u32,
        /// Number of vertices (crease, corner) or faces (hole).
        limit: u32,
    },
    /// A line of an OBJ file could not be understood.
    #[error("line {line}: {message}: `{text}`")]
    Parse {
        /// 1-based line number.
        line: usize,
        /// The line as written.
        text: String,
        /// What is wrong with it.
        message: String,
    },
    /// The OBJ reader (tobj) refused the file.
    #[error("OBJ error: {0}")]
    Obj(String),
    /// A file could not be read.
    #[error("cannot read {path}: {message}")]
    Io {
        /// The file.
        path: String,
        /// The operating system's message.
        message: String,
    },
    /// A file is not an image the reader can decode (corrupt, truncated, another format).
    #[error("cannot decode image {path}: {message}")]
    Image {
        /// The file.
        path: String,
        /// The decoder's message.
        message: String,
    },
    /// A displacement map was asked for a surface without face-varying texture coordinates to
    /// sample it by.
    #[error("displacement map {map}: the mesh has no texture coordinates (OBJ `vt` lines referenced by its faces as `f v/vt ...`) to sample it by")]
    MissingTexCoords {
        /// The map (its path, or "texels").
        map: String,
    },
    /// A file (or standard output) could not be written.
    #[error("cannot write {path}: {message}")]
    Write {
        /// The file.
        path: String,
        /// The operating system's (or encoder's) message.
        message: String,
    },
    /// A resource limit of the command line was exceeded; `flag` raises it.
    #[error("{what}: {found} exceeds the limit {limit} (raise it with {flag})")]
    LimitExceeded {
        /// What was counted (vertices, faces, face size, valence, ...), with the element.
        what: String,
        /// The count found.
        found: u64,
        /// The limit in force.
        limit: u64,
        /// The command-line flag that raises it.
        flag: &'static str,
    },
    /// The input would draw nothing (every face a hole, no face with a limit surface, ...).
    #[error("nothing to draw: {0}")]
    NothingToDraw(String),
    /// Vulkan / device failure (see [`GpuError`]).
    #[error(transparent)]
    Gpu(#[from] GpuError),
}
