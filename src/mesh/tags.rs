//! OpenSubdiv-style subdivision tags in OBJ files:
//! `t NAME nint/nfloat[/nstring] ints... floats... strings...`.
//!
//! Supported: `crease` (pairs of 0-based vertices, one sharpness shared by all pairs or one per
//! pair), `corner` (vertices, one shared sharpness or one each), `hole` (0-based faces),
//! `interpolateboundary` (0 none, 1 edge-and-corner, 2 edge-only), `creasemethod`
//! (`normal` | `chaikin`), `smoothtriangles` (`catmark`; `smooth` is accepted with a warning and
//! the Catmull-Clark rule kept). `facevaryinginterpolateboundary` and
//! `facevaryingpropagatecorners` concern UVs only and are ignored; any other tag is ignored
//! with a warning.

use super::{BoundaryInterpolation, Corner, Crease, CreaseMethod, MeshWarning, SchemeOptions};
use crate::error::excerpt;
use crate::{Error, Result};

/// Tags collected from a file.
#[derive(Debug, Default)]
pub(crate) struct Tags {
    pub creases: Vec<Crease>,
    pub corners: Vec<Corner>,
    pub holes: Vec<u32>,
    pub options: SchemeOptions,
    pub warnings: Vec<MeshWarning>,
}

/// The arguments of one tag line, split by the counts it declares.
struct TagArgs<'a> {
    ints: Vec<u32>,
    floats: Vec<f32>,
    strings: Vec<&'a str>,
}

impl Tags {
    /// Parses the words after `t` on line `line` (1-based); `text` is the whole line for errors.
    pub fn parse_line(&mut self, words: &[&str], line: usize, text: &str) -> Result<()> {
        let err = |message: String| Error::parse(line, text, message);
        let [name, counts, rest @ ..] = words else {
            return Err(err(
                "a tag needs a name and nint/nfloat[/nstring] counts".into()
            ));
        };
        let args = split_args(counts, rest).map_err(err)?;
        let shape = |ni: Option<usize>, nf: Option<usize>, ns: usize| -> Result<()> {
            let ok = ni.is_none_or(|n| n == args.ints.len())
                && nf.is_none_or(|n| n == args.floats.len())
                && ns == args.strings.len();
            if ok {
                Ok(())
            } else {
                Err(err(format!(
                    "tag `{}` expects {}/{}/{ns} arguments",
                    excerpt(name),
                    ni.map_or("n".into(), |n| n.to_string()),
                    nf.map_or("n".into(), |n| n.to_string()),
                )))
            }
        };
        match *name {
            "crease" => {
                shape(None, None, 0)?;
                let pairs = args.ints.len() / 2;
                let nf = args.floats.len();
                if args.ints.is_empty() || args.ints.len() % 2 != 0 || !(nf == 1 || nf == pairs) {
                    return Err(err(
                        "crease expects 2k vertex indices and 1 or k sharpness values".into(),
                    ));
                }
                for (k, pair) in args.ints.chunks_exact(2).enumerate() {
                    self.creases.push(Crease {
                        v0: pair[0],
                        v1: pair[1],
                        sharpness: args.floats[k.min(nf - 1)],
                    });
                }
            }
            "corner" => {
                shape(None, None, 0)?;
                let nf = args.floats.len();
                if args.ints.is_empty() || !(nf == 1 || nf == args.ints.len()) {
                    return Err(err(
                        "corner expects k vertex indices and 1 or k sharpness values".into(),
                    ));
                }
                for (k, &v) in args.ints.iter().enumerate() {
                    self.corners.push(Corner {
                        vertex: v,
                        sharpness: args.floats[k.min(nf - 1)],
                    });
                }
            }
            "hole" => {
                shape(None, Some(0), 0)?;
                self.holes.extend_from_slice(&args.ints);
            }
            "interpolateboundary" => {
                shape(Some(1), Some(0), 0)?;
                self.options.boundary = match args.ints[0] {
                    0 => BoundaryInterpolation::None,
                    1 => BoundaryInterpolation::EdgeAndCorner,
                    2 => BoundaryInterpolation::EdgeOnly,
                    m => {
                        return Err(err(format!(
                            "interpolateboundary mode {m} (expected 0, 1 or 2)"
                        )))
                    }
                };
            }
            "creasemethod" => {
                shape(Some(0), Some(0), 1)?;
                self.options.crease_method = match args.strings[0] {
                    "normal" => CreaseMethod::Normal,
                    "chaikin" => CreaseMethod::Chaikin,
                    s => {
                        return Err(err(format!(
                            "creasemethod `{}` (expected normal or chaikin)",
                            excerpt(s)
                        )))
                    }
                };
            }
            "smoothtriangles" => {
                shape(Some(0), Some(0), 1)?;
                match args.strings[0] {
                    "catmark" => {}
                    "smooth" => self
                        .warnings
                        .push(MeshWarning::SmoothTrianglesIgnored { line }),
                    s => {
                        return Err(err(format!(
                            "smoothtriangles `{}` (expected catmark or smooth)",
                            excerpt(s)
                        )))
                    }
                }
            }
            "facevaryinginterpolateboundary" | "facevaryingpropagatecorners" => {}
            other => self.warnings.push(MeshWarning::UnknownTag {
                line,
                name: excerpt(other),
            }),
        }
        Ok(())
    }
}

/// Splits `rest` into the ints, floats and strings that `counts` (`a/b` or `a/b/c`) declares.
fn split_args<'a>(counts: &str, rest: &[&'a str]) -> std::result::Result<TagArgs<'a>, String> {
    let parts: Vec<&str> = counts.split('/').collect();
    if parts.is_empty() || parts.len() > 3 {
        return Err(format!(
            "bad argument counts `{}` (expected nint/nfloat[/nstring])",
            excerpt(counts)
        ));
    }
    let mut n = [0usize; 3];
    for (k, p) in parts.iter().enumerate() {
        n[k] = p.parse().map_err(|_| {
            format!(
                "bad argument counts `{}` (expected nint/nfloat[/nstring])",
                excerpt(counts)
            )
        })?;
    }
    if n.iter().sum::<usize>() != rest.len() {
        return Err(format!(
            "counts `{}` announce {} arguments, the line has {}",
            excerpt(counts),
            n.iter().sum::<usize>(),
            rest.len()
        ));
    }
    let (ints, rest) = rest.split_at(n[0]);
    let (floats, strings) = rest.split_at(n[1]);
    let ints = ints
        .iter()
        .map(|s| {
            s.parse::<u32>()
                .map_err(|_| format!("`{}` is not a non-negative integer index", excerpt(s)))
        })
        .collect::<std::result::Result<Vec<_>, _>>()?;
    let floats = floats
        .iter()
        .map(|s| {
            s.parse::<f32>()
                .map_err(|_| format!("`{}` is not a number", excerpt(s)))
        })
        .collect::<std::result::Result<Vec<_>, _>>()?;
    let strings = strings.iter().map(|s| s.trim_matches('"')).collect();
    Ok(TagArgs {
        ints,
        floats,
        strings,
    })
}
