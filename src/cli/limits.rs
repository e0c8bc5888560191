//! Resource limits of the command line, as data: the largest input each subcommand accepts by
//! default (each raised by its own flag), and the estimated GPU memory of a render checked
//! against the device's heap before anything is allocated.
//!
//! The defaults are generous for real models (a 1M-face mesh loads) and stop what would take
//! minutes or exhaust memory: a mesh with millions of faces, one polygon with thousands of
//! sides (its CPU path costs grow with its size), one vertex shared by thousands of faces.

use clap::Args;
use tessera::gpu::Context;
use tessera::render::SurfaceData;
use tessera::{ControlMesh, Error, Result};

/// Default maximum number of control vertices.
pub const MAX_VERTICES: u64 = 4_000_000;
/// Default maximum number of faces.
pub const MAX_FACES: u64 = 4_000_000;
/// Default maximum number of vertices of one face.
pub const MAX_FACE_SIZE: u64 = 1024;
/// Default maximum number of faces around one vertex.
pub const MAX_VALENCE: u64 = 1024;

/// The input limits (flattened into the subcommands' arguments).
#[derive(Args, Clone, Copy, Debug)]
pub struct InputLimits {
    /// Largest number of control vertices accepted.
    #[arg(long, default_value_t = MAX_VERTICES)]
    pub max_vertices: u64,
    /// Largest number of faces accepted.
    #[arg(long, default_value_t = MAX_FACES)]
    pub max_faces: u64,
    /// Largest number of vertices of one face accepted.
    #[arg(long, default_value_t = MAX_FACE_SIZE)]
    pub max_face_size: u64,
    /// Largest number of faces around one vertex (valence) accepted.
    #[arg(long, default_value_t = MAX_VALENCE)]
    pub max_valence: u64,
}

impl Default for InputLimits {
    fn default() -> Self {
        InputLimits {
            max_vertices: MAX_VERTICES,
            max_faces: MAX_FACES,
            max_face_size: MAX_FACE_SIZE,
            max_valence: MAX_VALENCE,
        }
    }
}

/// Refuses `mesh` if it exceeds one of `limits`, naming the limit, the element and the flag.
pub fn check_mesh(mesh: &ControlMesh, limits: &InputLimits) -> Result<()> {
    let over = |what: String, found: u64, limit: u64, flag: &'static str| {
        Err(Error::LimitExceeded {
            what,
            found,
            limit,
            flag,
        })
    };
    let nv = mesh.vertex_count() as u64;
    if nv > limits.max_vertices {
        return over(
            "control vertices".into(),
            nv,
            limits.max_vertices,
            "--max-vertices",
        );
    }
    let nf = mesh.face_count() as u64;
    if nf > limits.max_faces {
        return over("faces".into(), nf, limits.max_faces, "--max-faces");
    }
    if let Some((f, n)) = (0..mesh.face_count())
        .map(|f| (f, mesh.face_size(f) as u64))
        .find(|&(_, n)| n > limits.max_face_size)
    {
        return over(
            format!("face {f} size"),
            n,
            limits.max_face_size,
            "--max-face-size",
        );
    }
    let mut valence = vec![0u32; mesh.vertex_count()];
    for &v in mesh.face_vertices() {
        valence[v as usize] += 1;
    }
    if let Some((v, &n)) = valence
        .iter()
        .enumerate()
        .find(|&(_, &n)| u64::from(n) > limits.max_valence)
    {
        return over(
            format!("vertex {v} valence (faces around it)"),
            u64::from(n),
            limits.max_valence,
            "--max-valence",
        );
    }
    Ok(())
}

/// Bytes per GPU patch assumed by the estimate (control-point indices, per-patch records,
/// vertex frames; generous).
const BYTES_PER_PATCH: u64 = 1024;
/// Bytes per vertex of the CPU-evaluated triangles on the GPU (position, normal, class, domain
/// point) and per index.
const BYTES_PER_FALLBACK_VERTEX: u64 = 48;
/// Bytes per TES capture record.
const BYTES_PER_CAPTURE: u64 = 64;

/// The GPU memory a frame of `surface` needs at `width` x `height` with `msaa` samples and a
/// capture buffer of `capture` records: the targets (colour and depth per sample, the resolved
/// colour, the read-back buffer), the patch tables, the CPU-evaluated triangles.
pub fn estimate_gpu_bytes(
    surface: &SurfaceData,
    width: u32,
    height: u32,
    msaa: u32,
    capture: u64,
) -> u64 {
    let pixels = u64::from(width) * u64::from(height);
    let targets = pixels * (8 * u64::from(msaa.max(1)) + 4 + 4);
    let patches = surface.patch_count() as u64 * BYTES_PER_PATCH;
    let fallback = surface.fallback.positions.len() as u64 * BYTES_PER_FALLBACK_VERTEX
        + surface.fallback.indices.len() as u64 * 4;
    let vertices = surface.positions.len() as u64 * 64;
    targets + patches + fallback + vertices + capture * BYTES_PER_CAPTURE
}

/// Refuses a render whose estimated GPU memory `bytes` exceeds the device's largest heap,
/// instead of letting the allocation fail or the device be lost mid-frame.
pub fn check_gpu_memory(ctx: &Context, bytes: u64, what: &str) -> Result<()> {
    let heap = ctx.largest_heap_bytes();
    log::debug!(
        "estimated GPU memory {:.1} MiB of a {:.1} MiB heap",
        bytes as f64 / (1u64 << 20) as f64,
        heap as f64 / (1u64 << 20) as f64
    );
    if heap > 0 && bytes > heap {
        return Err(Error::Invalid(format!(
            "{what} needs about {:.2} GiB of GPU memory, more than the device's largest heap \
             ({:.2} GiB on {}): lower --size, --msaa, --tess or the mesh size",
            bytes as f64 / (1u64 << 30) as f64,
            heap as f64 / (1u64 << 30) as f64,
            ctx.info().name
        )));
    }
    Ok(())
}

/// Refuses a surface that would draw nothing (every face a hole, or no face with a limit
/// surface): an empty image with exit status 0 would hide the problem.
pub fn check_drawable(surface: &SurfaceData) -> Result<()> {
    if surface.patch_count() == 0 && surface.fallback_faces.is_empty() {
        return Err(Error::NothingToDraw(format!(
            "no face has a limit surface ({} face(s) are holes or touch an uninterpolated \
             boundary)",
            surface.skipped_faces
        )));
    }
    Ok(())
}

/// Largest coordinate magnitude the f32 GPU pipeline draws faithfully. Measured: the OpenSubdiv
/// cube scaled by up to 3e9 renders the same image as at scale 1; at 1e10 its normals (products
/// of coordinate differences, squared when normalised) overflow f32 and the shading breaks, and
/// at 1e30 the shape too. Refused, not rescaled: `sample` reports positions in the file's
/// coordinates, which a rescaled upload would no longer give.
pub const GPU_MAX_COORDINATE: f64 = 1e9;

/// Refuses a mesh with a coordinate beyond [`GPU_MAX_COORDINATE`], naming the vertex.
pub fn check_gpu_range(mesh: &ControlMesh) -> Result<()> {
    tessera::mesh::validate::check_magnitude(mesh.positions(), GPU_MAX_COORDINATE)
}
