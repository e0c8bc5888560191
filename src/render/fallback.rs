//! Faces without a GPU patch scheme yet, drawn from the CPU reference: limit points on a grid
//! matching the tessellation level, as triangles.

use glam::DVec3;

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

/// Evaluates every face on an `(r+1) x (r+1)` grid per quad domain with `eval(face, sub, u, v)
/// -> (position, normal)` (the CPU limit evaluator) and triangulates each grid cell.
pub fn tessellate<F>(faces: &[FallbackFace], level: u32, mut eval: F) -> Result<FallbackMesh>
where
    F: FnMut(u32, u32, f64, f64) -> Result<(DVec3, DVec3)>,
{
    let mut mesh = FallbackMesh::default();
    for f in faces {
        let r = grid_resolution(level, f.corners);
        let subs = if f.corners == 4 { 1 } else { f.corners };
        for sub in 0..subs {
            let base = mesh.positions.len() as u32;
            for j in 0..=r {
                for i in 0..=r {
                    let (u, v) = (f64::from(i) / f64::from(r), f64::from(j) / f64::from(r));
                    let (p, n) = eval(f.face, sub, u, v)?;
                    mesh.positions.push(p);
                    mesh.normals.push(n);
                    mesh.classes.push(f.class as u32);
                }
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
        let mut calls = Vec::new();
        let mesh = tessellate(&faces, 4, |f, s, u, v| {
            calls.push((f, s));
            Ok((DVec3::new(u, v, f64::from(f)), DVec3::Z))
        })
        .unwrap();
        // Quad: 5x5 points, 32 triangles. Triangle: 3 sub-faces of 3x3 points, 8 triangles each.
        assert_eq!(mesh.positions.len(), 25 + 3 * 9);
        assert_eq!(mesh.indices.len(), 3 * (32 + 3 * 8));
        assert_eq!(calls.iter().filter(|c| c.0 == 5).count(), 27);
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
        let r = tessellate(&faces, 2, |_, _, _, _| {
            Err(crate::Error::Invalid("no limit".into()))
        });
        assert!(r.is_err());
    }
}
