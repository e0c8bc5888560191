//! Faces without a GPU patch scheme yet, drawn from the CPU reference: limit points on a grid
//! matching the tessellation level, as triangles.

use glam::DVec3;

use crate::subdiv::eval::LimitSample;
use crate::Result;

/// Colour class of a surface piece (`CLASS_*` in `glsl/common/frame.glsl`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PatchClass {
    /// Regular B-spline patch.
    Regular = 0,
    /// Quad or polygon with an extraordinary vertex, boundary or crease.
    Irregular = 1,
    /// Triangle.
    Triangle = 2,
}

/// A face to evaluate on the CPU.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FallbackFace {
    /// Base-mesh face.
    pub face: u32,
    /// Number of corners (4 = one quad domain; otherwise one quad sub-face per corner).
    pub corners: u32,
    /// Colour class.
    pub class: PatchClass,
}

impl FallbackFace {
    /// Face `face` with `corners` corners, coloured as a triangle or an irregular face.
    pub fn new(face: u32, corners: u32) -> FallbackFace {
        FallbackFace {
            face,
            corners,
            class: if corners == 3 {
                PatchClass::Triangle
            } else {
                PatchClass::Irregular
            },
        }
    }
}

/// Triangles evaluated on the CPU.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FallbackMesh {
    /// Limit positions.
    pub positions: Vec<DVec3>,
    /// Unit limit normals.
    pub normals: Vec<DVec3>,
    /// Colour class per vertex.
    pub classes: Vec<u32>,
    /// Counter-clockwise (seen from outside) triangles.
    pub indices: Vec<u32>,
    /// Per vertex, where it lies on the surface (the texture coordinates and a displacement
    /// map are looked up from it); may be shorter than `positions` for triangles that are not
    /// points of a face (e.g. error maps), whose vertices then have none.
    pub domain: Vec<DomainPoint>,
    /// Per vertex with a domain point, the limit surface's partials `[dP/du, dP/dv]` there (the
    /// displacement map's shading normal, `glsl/surface/mesh.vert`); may be shorter, as
    /// `domain`.
    pub tangents: Vec<[DVec3; 2]>,
}

/// A point of a face's domain, as the TES capture names it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DomainPoint {
    /// Base-mesh face.
    pub face: u32,
    /// Sub-face (`NO_SUB_FACE` = `u32::MAX`: a quad's own domain).
    pub sub_face: u32,
    /// Parameter in the (sub-)face's unit square.
    pub uv: [f32; 2],
}

/// Grid resolution per quad domain for tessellation level `level`: quads use the level itself;
/// the sub-faces of other faces (each about a quarter of the face) use half of it.
pub fn grid_resolution(level: u32, corners: u32) -> u32 {
    if corners == 4 {
        level.max(1)
    } else {
        level.div_ceil(2).max(1)
    }
}

/// Evaluates every face on an `(r+1) x (r+1)` grid per quad domain with
/// `eval(face, sub, &[(u, v)]) -> [LimitSample]` (position, partials, unit normal: the CPU limit
/// evaluator, called once per quad domain, in parallel over faces) and triangulates each grid
/// cell.
pub fn tessellate<F>(faces: &[FallbackFace], level: u32, eval: F) -> Result<FallbackMesh>
where
    F: Fn(u32, u32, &[(f64, f64)]) -> Result<Vec<LimitSample>> + Sync,
{
    use rayon::prelude::*;
    let pieces: Vec<FallbackMesh> = faces
        .par_iter()
        .map(|f| face_grid(f, level, &eval))
        .collect::<Result<_>>()?;
    let mut mesh = FallbackMesh::default();
    for p in pieces {
        let base = mesh.positions.len() as u32;
        mesh.positions.extend(p.positions);
        mesh.normals.extend(p.normals);
        mesh.classes.extend(p.classes);
        mesh.domain.extend(p.domain);
        mesh.tangents.extend(p.tangents);
        mesh.indices.extend(p.indices.iter().map(|i| i + base));
    }
    Ok(mesh)
}

/// The grid triangles of one face (indices local to the face).
fn face_grid<F>(f: &FallbackFace, level: u32, eval: &F) -> Result<FallbackMesh>
where
    F: Fn(u32, u32, &[(f64, f64)]) -> Result<Vec<LimitSample>>,
{
    let mut mesh = FallbackMesh::default();
    let r = grid_resolution(level, f.corners);
    let subs = if f.corners == 4 { 1 } else { f.corners };
    let mut uv = Vec::with_capacity(((r + 1) * (r + 1)) as usize);
    for j in 0..=r {
        for i in 0..=r {
            uv.push((f64::from(i) / f64::from(r), f64::from(j) / f64::from(r)));
        }
    }
    for sub in 0..subs {
        let base = mesh.positions.len() as u32;
        let pts = eval(f.face, sub, &uv)?;
        if pts.len() != uv.len() {
            return Err(crate::Error::Invalid(format!(
                "limit evaluation of face {} returned {} points for {} parameters",
                f.face,
                pts.len(),
                uv.len()
            )));
        }
        let sub_face = if f.corners == 4 { u32::MAX } else { sub };
        for (s, &(u, v)) in pts.into_iter().zip(&uv) {
            mesh.positions.push(s.position);
            mesh.normals.push(s.normal);
            mesh.tangents.push([s.du, s.dv]);
            mesh.classes.push(f.class as u32);
            mesh.domain.push(DomainPoint {
                face: f.face,
                sub_face,
                uv: [u as f32, v as f32],
            });
        }
        let row = r + 1;
        for j in 0..r {
            for i in 0..r {
                let a = base + j * row + i;
                let (b, c, d) = (a + 1, a + row + 1, a + row);
                // (u, v) counter-clockwise = outward for counter-clockwise faces.
                mesh.indices.extend_from_slice(&[a, b, c, a, c, d]);
            }
        }
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_counts_and_orientation() {
        let faces = [
            FallbackFace {
                face: 3,
                corners: 4,
                class: PatchClass::Irregular,
            },
            FallbackFace {
                face: 5,
                corners: 3,
                class: PatchClass::Triangle,
            },
        ];
        let calls = std::sync::Mutex::new(Vec::new());
        let mesh = tessellate(&faces, 4, |f, s, uv| {
            calls.lock().unwrap().push((f, s, uv.len()));
            Ok(uv
                .iter()
                .map(|&(u, v)| LimitSample::new(DVec3::new(u, v, f64::from(f)), DVec3::X, DVec3::Y))
                .collect())
        })
        .unwrap();
        let calls = calls.into_inner().unwrap();
        // Quad: 5x5 points, 32 triangles. Triangle: 3 sub-faces of 3x3 points, 8 triangles each.
        assert_eq!(mesh.positions.len(), 25 + 3 * 9);
        assert_eq!(mesh.indices.len(), 3 * (32 + 3 * 8));
        assert_eq!(
            calls
                .iter()
                .filter(|c| c.0 == 5)
                .map(|c| c.2)
                .sum::<usize>(),
            27
        );
        assert_eq!(calls.len(), 4);
        assert_eq!(mesh.classes[25], PatchClass::Triangle as u32);
        // First triangle of the quad: (0,0) (1/4,0) (1/4,1/4): counter-clockwise in (u, v).
        let t: Vec<DVec3> = mesh.indices[..3]
            .iter()
            .map(|&i| mesh.positions[i as usize])
            .collect();
        assert!((t[1] - t[0]).cross(t[2] - t[0]).z > 0.0);
    }

    #[test]
    fn evaluator_errors_propagate() {
        let faces = [FallbackFace {
            face: 0,
            corners: 4,
            class: PatchClass::Irregular,
        }];
        let r = tessellate(&faces, 2, |_, _, _| {
            Err(crate::Error::Invalid("no limit".into()))
        });
        assert!(r.is_err());
    }
}
