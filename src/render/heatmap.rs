//! Error maps like Fig. 11 of the Gregory-patch paper: every Gregory face drawn from its CPU
//! samples, coloured by the distance to the exact Catmull-Clark limit surface (blue = exact,
//! red = the map's scale or more); regular faces are exact B-spline patches (blue); faces
//! without a Gregory patch are drawn exactly from the CPU reference in neutral grey.

use glam::DVec3;

use super::fallback::{FallbackMesh, PatchClass};
use super::plan::{cpu_faces, plan_for_scheme};
use super::schemes::{Scheme, SchemeLimits};
use super::surface::SurfaceData;
use crate::patch::gregory::accuracy::{heat_samples, AccuracyOptions, FaceHeat};
use crate::topology::Topology;
use crate::{ControlMesh, Result};

/// Colour classes at or above this value carry an error: `HEAT_CLASS_BASE + e`, with `e` in
/// `0..=HEAT_STEPS` the error relative to the map's scale (`CLASS_HEAT_BASE` in
/// `glsl/common/frame.glsl`).
pub const HEAT_CLASS_BASE: u32 = 16;
/// Quantisation steps of the error colour ramp.
pub const HEAT_STEPS: u32 = 1023;

/// An error-map surface and the distance (model units) that maps to full red.
#[derive(Debug, Clone)]
pub struct HeatSurface {
    /// The surface to draw with [`super::ColorBy::Error`].
    pub surface: SurfaceData,
    /// Distance shown as full red.
    pub scale: f64,
    /// Largest measured distance.
    pub max_distance: f64,
}

/// The colour class of an error `distance` on a map whose full scale is `scale`.
pub fn heat_class(distance: f64, scale: f64) -> u32 {
    let t = if scale > 0.0 {
        (distance / scale).clamp(0.0, 1.0)
    } else {
        0.0
    };
    HEAT_CLASS_BASE + (t * f64::from(HEAT_STEPS)).round() as u32
}

/// Builds the error map of `mesh`'s Gregory faces sampled on a `grid`; `scale` is the distance
/// shown as full red (default: the largest measured distance). Other faces are drawn at
/// tessellation `level`.
pub fn heat_surface(
    mesh: &ControlMesh,
    grid: usize,
    level: u32,
    scale: Option<f64>,
) -> Result<HeatSurface> {
    let heat = heat_samples(
        mesh,
        &AccuracyOptions {
            grid,
            include_regular: false,
        },
    )?;
    heat_surface_from_samples(mesh, &heat, level, scale)
}

/// [`heat_surface`] from samples already measured (e.g. by
/// [`crate::patch::gregory::accuracy::measure_with_samples`]).
pub fn heat_surface_from_samples(
    mesh: &ControlMesh,
    heat: &[FaceHeat],
    level: u32,
    scale: Option<f64>,
) -> Result<HeatSurface> {
    let max_distance = heat
        .iter()
        .flat_map(|f| f.samples.iter().map(|s| s.distance))
        .fold(0.0f64, f64::max);
    let scale = scale.unwrap_or(max_distance);
    let topo = Topology::new(mesh)?;
    let mut plan = surface_from_mesh_plan(mesh)?;
    let mut is_heat = vec![false; topo.face_count()];
    for f in heat {
        is_heat[f.face as usize] = true;
    }
    plan.fallback_faces.retain(|f| !is_heat[f.face as usize]);
    for f in &mut plan.fallback_faces {
        // Grey in the error colouring.
        f.class = PatchClass::Irregular;
    }
    let mut fallback = cpu_faces(mesh, &plan.fallback_faces, level)?;
    for f in heat {
        append_face(&mut fallback, f, scale);
    }
    plan.fallback = fallback;
    Ok(HeatSurface {
        surface: plan,
        scale,
        max_distance,
    })
}

/// An error map drawn from `heat` alone (no GPU pass: every face of `mesh` must be in `heat`
/// or is not drawn), coloured on the given `scale` (model units shown as full red): for maps of
/// schemes whose regular faces carry error too.
pub fn heat_only_surface(mesh: &ControlMesh, heat: &[FaceHeat], scale: f64) -> Result<HeatSurface> {
    let mut surface = surface_from_mesh_plan(mesh)?;
    surface.parts.clear();
    surface.fallback_faces.clear();
    surface.fallback = FallbackMesh::default();
    for f in heat {
        append_face(&mut surface.fallback, f, scale);
    }
    let max_distance = heat
        .iter()
        .flat_map(|f| f.samples.iter().map(|s| s.distance))
        .fold(0.0f64, f64::max);
    Ok(HeatSurface {
        surface,
        scale,
        max_distance,
    })
}

/// The B-spline-only plan of `mesh` (no CPU evaluation; needs no device).
fn surface_from_mesh_plan(mesh: &ControlMesh) -> Result<SurfaceData> {
    plan_for_scheme(mesh, Scheme::BsplineOnly, &SchemeLimits::NO_DEVICE)
}

/// Appends the triangulated sample grid of one face, counter-clockwise in the face's
/// parameters (so outward for counter-clockwise faces).
fn append_face(mesh: &mut FallbackMesh, f: &FaceHeat, scale: f64) {
    let base = mesh.positions.len() as u32;
    let n = f.grid as u32;
    for s in &f.samples {
        mesh.positions.push(s.position);
        mesh.normals.push(if s.normal == DVec3::ZERO {
            DVec3::Z
        } else {
            s.normal
        });
        mesh.classes.push(heat_class(s.distance, scale));
    }
    if f.triangle {
        // Row j holds n + 1 - j samples and starts after the rows before it.
        let start = |j: u32| (0..j).map(|k| n + 1 - k).sum::<u32>();
        for j in 0..n {
            let (r0, r1) = (start(j), start(j + 1));
            for i in 0..(n - j) {
                let a = base + r0 + i;
                let b = base + r0 + i + 1;
                let c = base + r1 + i;
                mesh.indices.extend([a, b, c]);
                if i + 1 < n - j {
                    let d = base + r1 + i + 1;
                    mesh.indices.extend([b, d, c]);
                }
            }
        }
    } else {
        let w = n + 1;
        for j in 0..n {
            for i in 0..n {
                let a = base + j * w + i;
                let (b, c, d) = (a + 1, a + w + 1, a + w);
                mesh.indices.extend([a, b, c, a, c, d]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn classes_span_the_ramp() {
        assert_eq!(heat_class(0.0, 1.0), HEAT_CLASS_BASE);
        assert_eq!(heat_class(2.0, 1.0), HEAT_CLASS_BASE + HEAT_STEPS);
        assert_eq!(heat_class(0.5, 1.0), HEAT_CLASS_BASE + 512);
        assert_eq!(heat_class(1.0, 0.0), HEAT_CLASS_BASE);
    }

    #[test]
    fn heat_surface_covers_every_gregory_face_once() {
        let mesh = crate::assets::EmbeddedMesh::Mixed.load().unwrap();
        let h = heat_surface(&mesh, 4, 4, None).unwrap();
        let m = &h.surface.fallback;
        assert!(h.max_distance > 0.0 && h.scale == h.max_distance);
        assert_eq!(m.positions.len(), m.classes.len());
        assert!(m.indices.iter().all(|&i| (i as usize) < m.positions.len()));
        let hot = m.classes.iter().filter(|&&c| c >= HEAT_CLASS_BASE).count();
        // 23 Gregory faces of the mixed mesh: 16 quads (25 samples) and 7 triangles (15).
        assert_eq!(hot, 16 * 25 + 7 * 15);
        assert!(m.classes.contains(&(HEAT_CLASS_BASE + HEAT_STEPS)));
        // Triangles face the same way as the face's normal.
        for t in m.indices.chunks(3) {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| m.positions[i as usize]);
            let n = m.normals[t[0] as usize];
            assert!((b - a).cross(c - a).dot(n) > -1e-12);
        }
    }
}
