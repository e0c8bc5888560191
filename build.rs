//! Build script: compiles the GLSL in `glsl/` to SPIR-V with the vendored glslang and embeds the
//! words through generated lookup tables in `$OUT_DIR`.
//!
//! Layout (walked recursively; only stage files and `variants.txt` are picked up):
//! * `glsl/common/`: includes shared by every scheme; `glsl/surface/`: the stages every scheme
//!   shares; one folder per patch scheme (`bspline/`, `gregory/`, `gregory_vs/`,
//!   `gregory_stencil/`) with its stages and includes.
//! * `glsl/tests/` and `glsl/examples/`: test-only and example shaders. They go to
//!   `test_shaders.rs` (`TEST_SHADERS`), which integration tests include and register with
//!   `Context::add_shaders` and examples include for their own pipelines; every other module goes
//!   to `shaders.rs` (`SHADERS`), embedded in the library by `src/gpu/shaders.rs`.
//!
//! Modules are named by file name alone (no folder), and a name two sources produce is an error:
//! * every `.vert`, `.tesc`, `.geom`, `.frag`, `.comp` is compiled without extra defines under its name;
//! * every `.tese` outside `glsl/tests/` (a scheme's evaluation shader) is compiled only as the six
//!   variants `{stem}_{equal|odd|even}[_capture].tese` (defines in `SPACINGS`, plus `CAPTURE`);
//!   a test `.tese` is compiled as is;
//! * a folder's `variants.txt` adds macro variants of that folder's shaders, one per line:
//!   `<output-name> <source-file> [NAME[=VALUE] ...]` (`#` starts a comment, bare `NAME` defines
//!   it as 1). The stage comes from the source file's extension. Defines follow `#version`.
//! * `#include "name.glsl"` is resolved here, first relative to the including file's folder, then
//!   in `glsl/common/`, then relative to `glsl/` (so `"gregory/gregory.glsl"` reaches another
//!   scheme's include). Each file is expanded at most once per shader, so shader authors need no
//!   GLSL extension or include guards. Errors are reported as `glsl/<folder>/<file>:<line>`.
//! * If `spirv-val` is on PATH, every module is also validated for Vulkan 1.2 (optional; set
//!   `TESSERA_SPIRV_VAL=0` to skip, `=1` to require the tool).

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Component, Path, PathBuf};

use glslang::{
    CompilerOptions, ShaderInput, ShaderSource, ShaderStage, SpirvVersion, Target, VulkanVersion,
};

/// Folders (under `glsl/`) of the shaders not embedded in the library: the tests' and the
/// examples' (`examples/engine.rs` draws its own ground with `glsl/examples/`).
const TEST_DIRS: [&str; 2] = ["tests", "examples"];

/// Spacing variants of every scheme's evaluation shader: name suffix and defines.
const SPACINGS: [(&str, &[&str]); 3] = [
    ("equal", &["SPACING=equal_spacing", "SPACING_EQUAL"]),
    ("odd", &["SPACING=fractional_odd_spacing"]),
    ("even", &["SPACING=fractional_even_spacing"]),
];

/// One SPIR-V module to produce.
struct Variant {
    name: String,
    /// Source path relative to `glsl/`, `/`-separated.
    source: String,
    defines: Vec<(String, Option<String>)>,
    /// Where the defines come from, for error messages.
    defined_in: String,
    /// From `glsl/tests/`: goes to the test table.
    test: bool,
}

/// Source text after include expansion, with a map from output line to (file, line).
struct Expanded {
    text: String,
    origin: Vec<(String, usize)>,
}

fn main() {
    let manifest = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("CARGO_MANIFEST_DIR"));
    let glsl = manifest.join("glsl");
    let out_dir = PathBuf::from(std::env::var("OUT_DIR").expect("OUT_DIR"));
    println!("cargo:rerun-if-changed=glsl");
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-env-changed=TESSERA_SPIRV_VAL");

    let mut variants = Vec::new();
    if let Err(e) = collect_variants(&glsl, "", &mut variants).and_then(|()| unique(&variants)) {
        fail(&e);
    }

    let mut errors = Vec::new();
    let mut shipped: BTreeMap<String, Vec<u32>> = BTreeMap::new();
    let mut tests: BTreeMap<String, Vec<u32>> = BTreeMap::new();
    for v in &variants {
        match compile_variant(&glsl, v) {
            Ok(words) => {
                let table = if v.test { &mut tests } else { &mut shipped };
                table.insert(v.name.clone(), words);
            }
            Err(e) => errors.push(e),
        }
    }
    if !errors.is_empty() {
        fail(&errors.join("\n"));
    }
    validate_spirv(&out_dir, shipped.iter().chain(&tests));

    write_table(
        &out_dir.join("shaders.rs"),
        "SHADERS",
        "Every embedded shader",
        &shipped,
    );
    write_table(
        &out_dir.join("test_shaders.rs"),
        "TEST_SHADERS",
        "Every test-only shader (glsl/tests/)",
        &tests,
    );
}

fn fail(msg: &str) -> ! {
    for line in msg.lines() {
        println!("cargo:warning={line}");
    }
    eprintln!("{msg}");
    std::process::exit(1);
}

/// Writes `pub static {table}: &[(&str, &[u32])]`, sorted by name, to `path`.
fn write_table(path: &Path, table: &str, doc: &str, modules: &BTreeMap<String, Vec<u32>>) {
    let mut rs = String::new();
    rs.push_str("// Generated by build.rs from glsl/. Do not edit.\n");
    for (i, (name, words)) in modules.iter().enumerate() {
        let _ = writeln!(rs, "// {name}");
        let _ = write!(rs, "static SPV_{i}: [u32; {}] = [", words.len());
        for (j, w) in words.iter().enumerate() {
            if j % 8 == 0 {
                rs.push_str("\n    ");
            }
            let _ = write!(rs, "0x{w:08x}, ");
        }
        rs.push_str("\n];\n");
    }
    let _ = writeln!(rs, "/// {doc}, sorted by name.");
    let _ = writeln!(rs, "pub static {table}: &[(&str, &[u32])] = &[");
    for (i, name) in modules.keys().enumerate() {
        let _ = writeln!(rs, "    ({name:?}, &SPV_{i}),");
    }
    rs.push_str("];\n");
    if let Err(e) = std::fs::write(path, rs) {
        fail(&format!("cannot write {}: {e}", path.display()));
    }
}

fn stage_of(file: &str) -> Option<ShaderStage> {
    let ext = Path::new(file).extension()?.to_str()?;
    Some(match ext {
        "vert" => ShaderStage::Vertex,
        "tesc" => ShaderStage::TesselationControl,
        "tese" => ShaderStage::TesselationEvaluation,
        "geom" => ShaderStage::Geometry,
        "frag" => ShaderStage::Fragment,
        "comp" => ShaderStage::Compute,
        _ => return None,
    })
}

/// `a/b` for a folder `a` ("" at the top) and a name `b`.
fn join_rel(dir: &str, name: &str) -> String {
    if dir.is_empty() {
        name.to_owned()
    } else {
        format!("{dir}/{name}")
    }
}

/// `NAME=VALUE` or `NAME` (defined as 1).
fn parse_define(d: &str) -> (String, Option<String>) {
    match d.split_once('=') {
        Some((k, v)) => (k.to_owned(), Some(v.to_owned())),
        None => (d.to_owned(), None),
    }
}

/// Adds the modules of folder `dir` (relative to `glsl/`) and its subfolders, in name order.
fn collect_variants(glsl: &Path, dir: &str, out: &mut Vec<Variant>) -> Result<(), String> {
    let abs = glsl.join(dir);
    let mut entries: Vec<(String, bool)> = std::fs::read_dir(&abs)
        .map_err(|e| format!("cannot list {}: {e}", abs.display()))?
        .filter_map(|e| e.ok())
        .filter_map(|e| {
            let is_dir = e.file_type().is_ok_and(|t| t.is_dir());
            e.file_name().to_str().map(|n| (n.to_owned(), is_dir))
        })
        .collect();
    entries.sort();
    let test = TEST_DIRS
        .iter()
        .any(|t| dir == *t || dir.starts_with(&format!("{t}/")));
    for (name, is_dir) in entries {
        let rel = join_rel(dir, &name);
        if is_dir {
            collect_variants(glsl, &rel, out)?;
        } else if name == "variants.txt" {
            read_variants_txt(glsl, dir, test, out)?;
        } else if let Some(stem) = name.strip_suffix(".tese").filter(|_| !test) {
            out.extend(spacing_variants(stem, &rel));
        } else if stage_of(&name).is_some() {
            out.push(Variant {
                name,
                source: rel,
                defines: Vec::new(),
                defined_in: String::new(),
                test,
            });
        }
    }
    Ok(())
}

/// The spacing x capture variants of the evaluation shader `source` (named `{stem}.tese`).
fn spacing_variants<'a>(stem: &'a str, source: &'a str) -> impl Iterator<Item = Variant> + 'a {
    SPACINGS.into_iter().flat_map(move |(spacing, defines)| {
        [false, true].map(|capture| {
            let mut defines: Vec<_> = defines.iter().map(|d| parse_define(d)).collect();
            let mut name = format!("{stem}_{spacing}");
            if capture {
                defines.push(("CAPTURE".to_owned(), None));
                name.push_str("_capture");
            }
            Variant {
                name: name + ".tese",
                source: source.to_owned(),
                defines,
                defined_in: "build.rs SPACINGS".to_owned(),
                test: false,
            }
        })
    })
}

/// Adds the macro variants listed in `glsl/{dir}/variants.txt` (format in the module docs).
fn read_variants_txt(
    glsl: &Path,
    dir: &str,
    test: bool,
    out: &mut Vec<Variant>,
) -> Result<(), String> {
    let manifest = join_rel(dir, "variants.txt");
    let text = std::fs::read_to_string(glsl.join(&manifest))
        .map_err(|e| format!("cannot read glsl/{manifest}: {e}"))?;
    for (i, raw) in text.lines().enumerate() {
        let at = format!("glsl/{manifest}:{}", i + 1);
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let mut parts = line.split_whitespace();
        let name = parts.next().unwrap_or_default().to_owned();
        let Some(source) = parts.next() else {
            return Err(format!(
                "{at}: expected `<output-name> <source-file> [DEFINE[=VALUE]...]`"
            ));
        };
        if stage_of(source).is_none() {
            return Err(format!(
                "{at}: source `{source}` has no shader-stage extension (.vert/.tesc/.tese/.frag/.comp)"
            ));
        }
        let source = join_rel(dir, source);
        if !glsl.join(&source).is_file() {
            return Err(format!("{at}: source file glsl/{source} does not exist"));
        }
        out.push(Variant {
            name,
            source,
            defines: parts.map(parse_define).collect(),
            defined_in: at,
            test,
        });
    }
    Ok(())
}

/// Fails when two variants (in either table) produce the same module name.
fn unique(variants: &[Variant]) -> Result<(), String> {
    let mut by_name: BTreeMap<&str, &Variant> = BTreeMap::new();
    for v in variants {
        if let Some(first) = by_name.insert(&v.name, v) {
            let from = |v: &Variant| match v.defined_in.as_str() {
                "" => format!("glsl/{}", v.source),
                d => format!("glsl/{} ({d})", v.source),
            };
            return Err(format!(
                "shader name `{}` is produced twice: by {} and by {} (module names carry no folder)",
                v.name,
                from(first),
                from(v)
            ));
        }
    }
    Ok(())
}

/// Resolves `#include "name"` in `from` (both relative to `glsl/`): the including file's folder,
/// then `common/`, then `glsl/` itself.
fn resolve_include(glsl: &Path, from: &str, name: &str) -> Result<String, String> {
    if !Path::new(name)
        .components()
        .all(|c| matches!(c, Component::Normal(_)))
    {
        return Err(format!(
            "#include \"{name}\": use a name or folder/name below glsl/ (no `..`, no absolute path)"
        ));
    }
    let dir = from.rsplit_once('/').map_or("", |(d, _)| d);
    [
        join_rel(dir, name),
        join_rel("common", name),
        name.to_owned(),
    ]
    .into_iter()
    .find(|c| glsl.join(c).is_file())
    .ok_or_else(|| format!("#include \"{name}\" not found in glsl/{dir}/, glsl/common/ or glsl/"))
}

/// Expands `#include "x"` recursively; each file is included at most once per shader.
fn expand(
    glsl: &Path,
    file: &str,
    seen: &mut Vec<String>,
    out: &mut Expanded,
    depth: usize,
) -> Result<(), String> {
    if depth > 32 {
        return Err(format!("glsl/{file}: #include nesting deeper than 32"));
    }
    let path = glsl.join(file);
    let text = std::fs::read_to_string(&path).map_err(|e| format!("glsl/{file}: {e}"))?;
    for (i, line) in text.lines().enumerate() {
        let t = line.trim_start();
        if let Some(rest) = t.strip_prefix("#include") {
            let at = format!("glsl/{file}:{}", i + 1);
            let rest = rest.trim();
            let inner = rest
                .strip_prefix('"')
                .and_then(|r| r.strip_suffix('"'))
                .ok_or_else(|| {
                    format!("{at}: malformed #include (expected #include \"name.glsl\")")
                })?;
            let resolved = resolve_include(glsl, file, inner).map_err(|e| format!("{at}: {e}"))?;
            if !seen.contains(&resolved) {
                seen.push(resolved.clone());
                expand(glsl, &resolved, seen, out, depth + 1)
                    .map_err(|e| format!("{e}\n  included from {at}"))?;
            }
            // Keep line numbering stable with an empty line.
            out.text.push('\n');
            out.origin.push((file.to_owned(), i + 1));
        } else {
            out.text.push_str(line);
            out.text.push('\n');
            out.origin.push((file.to_owned(), i + 1));
        }
    }
    Ok(())
}

/// Builds the full source: `#version` line first, then the variant's defines, then the rest.
fn build_source(glsl: &Path, v: &Variant) -> Result<Expanded, String> {
    let mut body = Expanded {
        text: String::new(),
        origin: Vec::new(),
    };
    let mut seen = vec![v.source.clone()];
    expand(glsl, &v.source, &mut seen, &mut body, 0)?;
    let lines: Vec<&str> = body.text.lines().collect();
    let version_at = lines
        .iter()
        .position(|l| l.trim_start().starts_with("#version"))
        .ok_or_else(|| format!("glsl/{}: no #version line", v.source))?;
    let mut out = Expanded {
        text: String::new(),
        origin: Vec::new(),
    };
    for (i, l) in lines.iter().enumerate().take(version_at + 1) {
        out.text.push_str(l);
        out.text.push('\n');
        out.origin.push(body.origin[i].clone());
    }
    for (k, val) in &v.defines {
        let _ = writeln!(out.text, "#define {k} {}", val.as_deref().unwrap_or("1"));
        out.origin.push((v.defined_in.clone(), 0));
    }
    for (i, l) in lines.iter().enumerate().skip(version_at + 1) {
        out.text.push_str(l);
        out.text.push('\n');
        out.origin.push(body.origin[i].clone());
    }
    Ok(out)
}

/// Rewrites glslang's `ERROR: 0:LINE:` locations into `glsl/file:line:` (a define line: where
/// the variant's defines come from).
fn map_log(log: &str, src: &Expanded, variant: &str) -> String {
    let mut out = String::new();
    for line in log.lines() {
        let mut mapped = line.to_owned();
        for tag in ["ERROR: ", "WARNING: "] {
            if let Some(rest) = line.strip_prefix(tag) {
                let mut it = rest.splitn(3, ':');
                let (a, b, c) = (it.next(), it.next(), it.next());
                if let (Some(_), Some(ln), Some(msg)) = (a, b, c) {
                    if let Ok(n) = ln.trim().parse::<usize>() {
                        if let Some((f, l)) = n.checked_sub(1).and_then(|k| src.origin.get(k)) {
                            let loc = if *l == 0 {
                                format!("{f} (defines of {variant})")
                            } else {
                                format!("glsl/{f}:{l}")
                            };
                            mapped = format!("{tag}{loc}:{msg}");
                        }
                    }
                }
            }
        }
        out.push_str(&mapped);
        out.push('\n');
    }
    out
}

fn compile_variant(glsl: &Path, v: &Variant) -> Result<Vec<u32>, String> {
    let stage = stage_of(&v.source).ok_or_else(|| format!("{}: unknown stage", v.source))?;
    let src = build_source(glsl, v)?;
    let compiler = glslang::Compiler::acquire().ok_or("glslang failed to initialise")?;
    let source = ShaderSource::from(src.text.clone());
    let options = CompilerOptions {
        target: Target::Vulkan {
            version: VulkanVersion::Vulkan1_2,
            spirv_version: SpirvVersion::SPIRV1_5,
        },
        ..CompilerOptions::default()
    };
    let input = ShaderInput::new(
        &source,
        stage,
        &options,
        None::<&[(&str, Option<&str>)]>,
        None,
    )
    .map_err(|e| format!("shader {} (glsl/{}): {e}", v.name, v.source))?;
    let shader = compiler.create_shader(input).map_err(|e| {
        format!(
            "shader {} (glsl/{}) failed to compile:\n{}",
            v.name,
            v.source,
            map_log(&error_log(&e), &src, &v.name)
        )
    })?;
    shader.compile().map_err(|e| {
        format!(
            "shader {} (glsl/{}) failed to link:\n{}",
            v.name,
            v.source,
            map_log(&error_log(&e), &src, &v.name)
        )
    })
}

fn error_log(e: &glslang::error::GlslangError) -> String {
    use glslang::error::GlslangError as G;
    match e {
        G::PreprocessError(l) | G::ParseError(l) | G::MapIoError(l) | G::LinkError(l) => {
            format!("{}{}", l.log, l.debug_log)
        }
        other => other.to_string(),
    }
}

/// Runs `spirv-val` on every module when the tool exists (see the module docs).
fn validate_spirv<'a>(out_dir: &Path, compiled: impl Iterator<Item = (&'a String, &'a Vec<u32>)>) {
    let mode = std::env::var("TESSERA_SPIRV_VAL").unwrap_or_default();
    if mode == "0" {
        return;
    }
    let probe = std::process::Command::new("spirv-val")
        .arg("--version")
        .output();
    if probe.is_err() {
        if mode == "1" {
            fail("TESSERA_SPIRV_VAL=1 but spirv-val is not on PATH (Debian: spirv-tools)");
        }
        return;
    }
    let dir = out_dir.join("spv");
    if let Err(e) = std::fs::create_dir_all(&dir) {
        fail(&format!("cannot create {}: {e}", dir.display()));
    }
    let mut errors = Vec::new();
    for (name, words) in compiled {
        let path = dir.join(format!("{name}.spv"));
        let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
        if let Err(e) = std::fs::write(&path, bytes) {
            fail(&format!("cannot write {}: {e}", path.display()));
        }
        match std::process::Command::new("spirv-val")
            .args(["--target-env", "vulkan1.2"])
            .arg(&path)
            .output()
        {
            Ok(o) if o.status.success() => {}
            Ok(o) => errors.push(format!(
                "spirv-val rejected shader {name}:\n{}{}",
                String::from_utf8_lossy(&o.stdout),
                String::from_utf8_lossy(&o.stderr)
            )),
            Err(e) => errors.push(format!("cannot run spirv-val on {name}: {e}")),
        }
    }
    if !errors.is_empty() {
        fail(&errors.join("\n"));
    }
}
