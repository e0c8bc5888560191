//! `tessera render --animate FRAMES`: a twisting deformation over one period, rendered through
//! the same renderer with only the control positions updated per frame (topology tables, patch
//! records and stencils stay; both Gregory variants rebuild every patch on the GPU), written as
//! a contact sheet.

use std::path::Path;

use tessera::render::animate::{contact_sheet, twist};
use tessera::render::{OffscreenDesc, OffscreenSession, RenderDesc, SurfaceData};
use tessera::{ControlMesh, Result};

/// Renders `frames` frames of `mesh` twisting about the up axis and writes the contact sheet
/// to `out`. Faces drawn from the CPU reference are re-evaluated per frame. Prints the GPU time
/// of the tessellated pass per frame when `timings`.
#[allow(clippy::too_many_arguments)]
pub fn run(
    ctx: &tessera::gpu::Context,
    mesh: &ControlMesh,
    surface: &SurfaceData,
    level: u32,
    render: &RenderDesc,
    desc: &OffscreenDesc,
    frames: u32,
    out: &Path,
    timings: bool,
) -> Result<()> {
    let mut session = OffscreenSession::new(ctx, surface, render, desc, timings)?;
    let mut mesh = mesh.clone();
    let rest = mesh.positions().to_vec();
    let up = desc.up.vector();
    let mut images = Vec::with_capacity(frames as usize);
    let mut ms = Vec::new();
    for k in 0..frames {
        let moved = twist(&rest, up, 1.5, f64::from(k) / f64::from(frames));
        mesh.set_positions(&moved)?;
        let fallback = if surface.fallback_faces.is_empty() {
            None
        } else {
            Some(tessera::render::cpu_faces(
                &mesh,
                &surface.fallback_faces,
                level,
            )?)
        };
        session
            .renderer_mut()
            .update_positions(&moved, fallback.as_ref())?;
        if let Some(r) = session.frame()? {
            ms.push(r.patch_ms());
        }
        images.push(session.image()?);
    }
    let cols = (f64::from(frames).sqrt().ceil() as u32).max(1);
    super::image_out::save(&contact_sheet(&images, cols), out)?;
    eprintln!(
        "{frames} frame(s) written as a {cols}-column contact sheet to {}",
        out.display()
    );
    if !ms.is_empty() {
        let list: Vec<String> = ms.iter().map(|m| format!("{m:.2}")).collect();
        println!("GPU ms per frame (tessellated pass): {}", list.join(" "));
    }
    Ok(())
}
