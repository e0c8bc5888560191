//! Wavefront OBJ input with OpenSubdiv-style tags.
//!
//! Faces of any size are kept as polygons. Tags address the file's `v` list by 0-based index and
//! may name vertices no face uses, and positions are read in `f64`, so this reader parses the
//! file itself in one pass: every `v` line in `f64` (vertex `i` of the mesh is the file's `i`-th
//! `v`), the `t` tag lines, face indices (1-based or negative relative) resolved and checked with
//! line numbers; objects (`o` / `g`) are concatenated in file order. `tobj` (which renumbers
//! vertices per object and stores them as `f32`) reads the same faces as an independent check
//! when [`ObjOptions::check_with_tobj`] asks for it, as the tests do; on every load it doubled
//! the time of large files (a 1M-face grid: 2.8 s for `tessera info`, most of it in the two
//! parses).
//!
//! Texture coordinates (`vt`, referenced as `f v/vt ...`) become the mesh's face-varying
//! [`FaceUvs`] when every face has them (when only some have, a warning names the first face
//! without and the mesh has none); bad references are errors naming the face. Normals,
//! materials and smoothing groups are not used.

use glam::DVec3;

use super::tags::Tags;
use super::uv::FaceUvs;
use super::{ControlMesh, ControlMeshDesc, MeshWarning};
use crate::error::excerpt;
use crate::{Error, Result};

/// Options of the OBJ reader.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ObjOptions {
    /// The file's faces are wound clockwise seen from outside (e.g. OpenSubdiv's
    /// `catmark_lefthanded`): reverse them on load.
    pub left_handed: bool,
    /// Also read the faces with `tobj` and error if its faces differ from this reader's (an
    /// independent check the tests turn on; it doubles the load time of large files).
    pub check_with_tobj: bool,
}

/// OBJ statements that mean nothing for a subdivision control mesh and are skipped silently.
const SILENT: &[&str] = &["vn", "vp", "s", "mtllib", "usemtl", "o", "g"];

/// OBJ statements that are valid OBJ but not used here; skipped with a warning.
const IGNORED: &[&str] = &[
    "l",
    "p",
    "cstype",
    "deg",
    "bmat",
    "step",
    "curv",
    "curv2",
    "surf",
    "parm",
    "trim",
    "hole",
    "scrv",
    "sp",
    "end",
    "con",
    "mg",
    "lod",
    "maplib",
    "usemap",
    "bevel",
    "c_interp",
    "d_interp",
    "shadow_obj",
    "trace_obj",
    "ctech",
    "stech",
    "call",
    "csh",
];

impl ControlMesh {
    /// Reads an OBJ file with OpenSubdiv tags. Errors name the file, line or element at fault.
    pub fn from_obj_file(path: impl AsRef<std::path::Path>, options: &ObjOptions) -> Result<Self> {
        let path = path.as_ref();
        let bytes = std::fs::read(path).map_err(|e| Error::Io {
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
        let text = String::from_utf8_lossy(&bytes);
        Self::from_obj_str(&text, &path.display().to_string(), options)
    }

    /// Parses OBJ text with OpenSubdiv tags; `name` identifies the source in messages.
    pub fn from_obj_str(text: &str, name: &str, options: &ObjOptions) -> Result<Self> {
        let mut scan = Scan::run(text)?;
        if options.check_with_tobj {
            check_with_tobj(&scan, name)?;
        }
        let (uvs, partial) = scan.face_uvs(options);
        let face_sizes = std::mem::take(&mut scan.face_sizes);
        let face_vertices = std::mem::take(&mut scan.face_vertices);
        let Tags {
            creases,
            corners,
            holes,
            options: scheme,
            warnings: tag_warnings,
        } = scan.tags;
        let mut mesh = ControlMesh::new(ControlMeshDesc {
            positions: scan.positions,
            face_sizes,
            face_vertices,
            creases,
            corners,
            holes,
            options: scheme,
            left_handed: options.left_handed,
        })?;
        let mut warnings = scan.warnings;
        warnings.extend(partial);
        warnings.extend(tag_warnings);
        warnings.append(&mut mesh.warnings);
        mesh.warnings = warnings;
        match uvs {
            Some(uvs) => mesh.with_uvs(uvs),
            None => Ok(mesh),
        }
    }
}

/// What the reader finds.
struct Scan {
    positions: Vec<DVec3>,
    /// Corners of each face, in file order.
    face_sizes: Vec<u32>,
    /// 0-based file vertex indices of the faces' corners, face after face.
    face_vertices: Vec<u32>,
    /// The `vt` lines (s, t).
    texcoords: Vec<[f32; 2]>,
    /// 0-based `vt` indices of each face's corners, when its face line has them.
    face_texcoords: Vec<Option<Vec<u32>>>,
    tags: Tags,
    warnings: Vec<MeshWarning>,
}

impl Scan {
    fn run(text: &str) -> Result<Scan> {
        let mut scan = Scan {
            positions: Vec::new(),
            face_sizes: Vec::new(),
            face_vertices: Vec::new(),
            texcoords: Vec::new(),
            face_texcoords: Vec::new(),
            tags: Tags::default(),
            warnings: Vec::new(),
        };
        // The words of the current line (one buffer for the whole file).
        let mut words: Vec<&str> = Vec::new();
        let mut texcoords: Vec<u32> = Vec::new();
        // (index, line, text) of face references beyond the vertices read so far (allowed if
        // the vertex comes later in the file).
        let mut forward: Vec<(u32, usize, &str)> = Vec::new();
        // (face, index, line, text) of `vt` references beyond the `vt` lines read so far.
        let mut forward_vt: Vec<(usize, u32, usize, &str)> = Vec::new();
        // A UTF-8 byte-order mark (as some Windows editors write) is not content.
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        for (i, raw) in obj_lines(text).enumerate() {
            let line = i + 1;
            let content = raw.split('#').next().unwrap_or("");
            words.clear();
            words.extend(content.split_whitespace());
            let Some((&key, args)) = words.split_first() else {
                continue;
            };
            let err = |message: String| Error::parse(line, raw, message);
            match key {
                "v" => {
                    let p = parse_position(args).map_err(err)?;
                    let index = scan.positions.len() as u64;
                    if index >= u32::MAX as u64 {
                        return Err(err("too many vertices".into()));
                    }
                    scan.positions.push(p);
                }
                "vt" => {
                    let st = parse_texcoord(args).map_err(err)?;
                    scan.texcoords.push(st);
                }
                "f" => {
                    let nv = scan.positions.len() as i64;
                    let nt = scan.texcoords.len() as i64;
                    let f = scan.face_sizes.len();
                    texcoords.clear();
                    for w in args {
                        let v = resolve_index(w, nv).map_err(err)?;
                        if v as i64 >= nv {
                            forward.push((v, line, raw));
                        }
                        scan.face_vertices.push(v);
                        if let Some(t) = resolve_texcoord(w, nt)
                            .map_err(|m| Error::parse(line, raw, format!("face {f}: {m}")))?
                        {
                            if t as i64 >= nt {
                                forward_vt.push((f, t, line, raw));
                            }
                            texcoords.push(t);
                        }
                    }
                    let with_uv = match texcoords.len() {
                        0 => None,
                        n if n == args.len() => Some(texcoords.clone()),
                        _ => {
                            return Err(err(format!(
                                "face {f}: texture coordinates on some corners only"
                            )))
                        }
                    };
                    scan.face_sizes.push(args.len() as u32);
                    scan.face_texcoords.push(with_uv);
                }
                "t" => scan.tags.parse_line(args, line, raw)?,
                k if SILENT.contains(&k) => {}
                k if IGNORED.contains(&k) => scan.warnings.push(MeshWarning::IgnoredStatement {
                    line,
                    keyword: k.to_string(),
                }),
                k => return Err(err(format!("unknown OBJ statement `{}`", excerpt(k)))),
            }
        }
        let nv = scan.positions.len();
        if let Some(&(v, line, raw)) = forward.iter().find(|f| f.0 as usize >= nv) {
            return Err(Error::parse(
                line,
                raw,
                format!("vertex {} does not exist (the file has {nv})", v as u64 + 1),
            ));
        }
        let nt = scan.texcoords.len();
        if let Some(&(f, t, line, raw)) = forward_vt.iter().find(|f| f.1 as usize >= nt) {
            return Err(Error::parse(
                line,
                raw,
                format!(
                    "face {f}: texture coordinate {} does not exist (the file has {nt})",
                    t as u64 + 1
                ),
            ));
        }
        Ok(scan)
    }

    /// The faces' texture coordinates when every face has them, in the corner order
    /// [`ControlMesh::new`] gives the faces (reversed after corner 0 when left-handed); when only
    /// some have, none and a warning naming the first face without.
    fn face_uvs(&self, options: &ObjOptions) -> (Option<FaceUvs>, Option<MeshWarning>) {
        if self.face_texcoords.iter().all(Option::is_none) {
            return (None, None);
        }
        let mut indices = Vec::with_capacity(self.face_vertices.len());
        for (f, t) in self.face_texcoords.iter().enumerate() {
            let Some(t) = t else {
                let face = f as u32;
                return (None, Some(MeshWarning::PartialTexCoords { face }));
            };
            let start = indices.len();
            indices.extend_from_slice(t);
            if options.left_handed && t.len() > 1 {
                indices[start + 1..].reverse();
            }
        }
        (
            Some(FaceUvs {
                values: self.texcoords.clone(),
                indices,
            }),
            None,
        )
    }
}

/// The lines of `text`, ended by `\n`, `\r\n` or a lone `\r` (classic Mac OS), without their
/// terminators.
fn obj_lines(text: &str) -> impl Iterator<Item = &str> {
    let mut rest = Some(text);
    std::iter::from_fn(move || {
        let t = rest?;
        match t.find(['\n', '\r']) {
            Some(i) => {
                let skip = if t[i..].starts_with("\r\n") { 2 } else { 1 };
                rest = Some(&t[i + skip..]);
                Some(&t[..i])
            }
            None => {
                rest = None;
                (!t.is_empty()).then_some(t)
            }
        }
    })
}

/// `x y z`, `x y z w` (divided by `w`) or `x y z r g b` (colour ignored).
fn parse_position(args: &[&str]) -> std::result::Result<DVec3, String> {
    let num = |s: &str| {
        s.parse::<f64>()
            .map_err(|_| format!("`{}` is not a number", excerpt(s)))
    };
    match args.len() {
        3 | 4 | 6 => {
            let p = DVec3::new(num(args[0])?, num(args[1])?, num(args[2])?);
            if args.len() == 4 {
                let w = num(args[3])?;
                if w == 0.0 || !w.is_finite() {
                    return Err(format!("homogeneous coordinate w = {w}"));
                }
                return Ok(p / w);
            }
            Ok(p)
        }
        n => Err(format!(
            "a vertex needs 3 coordinates (optionally w, or r g b), found {n} values"
        )),
    }
}

/// `s [t [w]]` (t defaults to 0, w is ignored), finite.
fn parse_texcoord(args: &[&str]) -> std::result::Result<[f32; 2], String> {
    let num = |s: &str| {
        s.parse::<f64>()
            .ok()
            .filter(|x| x.is_finite() && x.abs() <= f64::from(f32::MAX))
            .map(|x| x as f32)
            .ok_or_else(|| format!("`{}` is not a finite number", excerpt(s)))
    };
    match args.len() {
        1..=3 => Ok([num(args[0])?, args.get(1).map_or(Ok(0.0), |s| num(s))?]),
        n => Err(format!(
            "a texture coordinate needs 1 to 3 values (s [t [w]]), found {n}"
        )),
    }
}

/// The words an OBJ reference's errors name it by.
struct Reference {
    /// What a malformed word is not, e.g. "vertex reference".
    kind: &'static str,
    /// How an index is named, e.g. "vertex index".
    index: &'static str,
    /// How a relative index is named, e.g. "relative index".
    relative: &'static str,
    /// What a relative index reaches before, e.g. "the first vertex".
    first: &'static str,
}

const VERTEX_REFERENCE: Reference = Reference {
    kind: "vertex reference",
    index: "vertex index",
    relative: "relative index",
    first: "the first vertex",
};

const TEXCOORD_REFERENCE: Reference = Reference {
    kind: "texture-coordinate reference",
    index: "texture coordinate index",
    relative: "relative texture coordinate",
    first: "the first `vt`",
};

/// The 0-based index of reference `part` of face word `word` (1-based, or negative = relative to
/// the `n` elements read so far).
fn resolve_reference(
    part: &str,
    word: &str,
    n: i64,
    what: &Reference,
) -> std::result::Result<u32, String> {
    let k: i64 = part
        .parse()
        .map_err(|_| format!("`{}` is not a {}", excerpt(word), what.kind))?;
    let i = match k {
        0 => return Err(format!("{} 0 (OBJ indices start at 1)", what.index)),
        k if k > 0 => k - 1,
        k => n + k,
    };
    if i < 0 {
        return Err(format!(
            "{} {k} reaches before {}",
            what.relative, what.first
        ));
    }
    u32::try_from(i)
        .ok()
        .filter(|&i| i < u32::MAX)
        .ok_or_else(|| format!("{} {k} is too large", what.index))
}

/// The 0-based texture-coordinate index of a face word `v/vt` or `v/vt/vn` (1-based, or
/// negative = relative to the `nt` coordinates read so far); `None` for `v` and `v//vn`.
fn resolve_texcoord(word: &str, nt: i64) -> std::result::Result<Option<u32>, String> {
    let Some(part) = word.split('/').nth(1).filter(|p| !p.is_empty()) else {
        return Ok(None);
    };
    resolve_reference(part, word, nt, &TEXCOORD_REFERENCE).map(Some)
}

/// The 0-based vertex index of a face word `v`, `v/vt`, `v//vn` or `v/vt/vn` (1-based, or
/// negative = relative to the `nv` vertices read so far).
fn resolve_index(word: &str, nv: i64) -> std::result::Result<u32, String> {
    let first = word.split('/').next().unwrap_or("");
    resolve_reference(first, word, nv, &VERTEX_REFERENCE)
}

/// The independent check of [`ObjOptions::check_with_tobj`]: tobj reads a clean copy of the
/// file's vertices and faces (`v` lines encoding their own index as two f32-exact halves, since
/// tobj renumbers the vertices of each object by first use and stores them as f32; `f` lines
/// with absolute indices), its output is decoded back to file indices and must equal this
/// reader's faces, face by face.
fn check_with_tobj(scan: &Scan, name: &str) -> Result<()> {
    use std::fmt::Write as _;
    let mut clean = String::new();
    for index in 0..scan.positions.len() {
        let _ = writeln!(clean, "v {} {} 0", index >> 16, index & 0xffff);
    }
    let mut at = 0usize;
    for &n in &scan.face_sizes {
        clean.push('f');
        for &v in &scan.face_vertices[at..at + n as usize] {
            let _ = write!(clean, " {}", u64::from(v) + 1);
        }
        clean.push('\n');
        at += n as usize;
    }
    let load = tobj::LoadOptions {
        triangulate: false,
        single_index: false,
        ignore_points: false,
        ignore_lines: false,
    };
    let mut reader = std::io::Cursor::new(clean.as_bytes());
    let (models, _) =
        tobj::load_obj_buf(&mut reader, &load, |_| Err(tobj::LoadError::GenericFailure))
            .map_err(|e| Error::Obj(format!("{name}: {e}")))?;
    let inconsistent = || Error::Obj(format!("{name}: tobj output is inconsistent"));
    let mut sizes = Vec::with_capacity(scan.face_sizes.len());
    let mut vertices = Vec::with_capacity(scan.face_vertices.len());
    for model in &models {
        let m = &model.mesh;
        let decode = |i: u32| -> Option<u32> {
            let i = i as usize * 3;
            let (hi, lo) = (*m.positions.get(i)?, *m.positions.get(i + 1)?);
            Some(((hi as u32) << 16) | lo as u32)
        };
        let arities: Vec<u32> = if m.face_arities.is_empty() {
            vec![3; m.indices.len() / 3]
        } else {
            m.face_arities.clone()
        };
        let mut at = 0usize;
        for n in arities {
            let end = at + n as usize;
            if end > m.indices.len() {
                return Err(inconsistent());
            }
            for &i in &m.indices[at..end] {
                vertices.push(decode(i).ok_or_else(inconsistent)?);
            }
            sizes.push(n);
            at = end;
        }
    }
    if sizes != scan.face_sizes || vertices != scan.face_vertices {
        return Err(Error::Obj(format!(
            "{name}: tobj's faces disagree with the file's face lines"
        )));
    }
    Ok(())
}
