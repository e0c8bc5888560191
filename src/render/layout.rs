//! GPU data layout of the surface: regular B-spline patches (index buffer of 16 control vertices
//! per patch + a per-patch info record), vertex positions and vertex limit positions. The byte
//! layouts mirror `glsl/common/frame.glsl`.

use glam::DVec3;

use crate::patch::RegularPatch;

/// A regular bicubic B-spline patch as the GPU consumes it: the layout of api.md's
/// `patch::regular::RegularPatch` (`cvs[4*j + i]`, i along u; face corners 0..3 are cvs 5, 6, 10,
/// 9; boundary bit e: 0 = v=0 side, 1 = u=1, 2 = v=1, 3 = u=0, phantoms mirrored columns first).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BSplinePatch {
    /// Base-mesh face.
    pub face: u32,
    /// Control vertices (phantom slots hold any valid vertex index).
    pub cvs: [u32; 16],
    /// Boundary / infinitely-sharp sides whose outer row or column is a mirrored phantom.
    pub boundary_mask: u8,
}

/// Bytes of one `PatchInfo` record (`glsl/common/frame.glsl`).
pub const PATCH_INFO_BYTES: usize = 32;

/// Patch edges as (start corner, end corner) in the order of the boundary bits, with corners
/// indexed 0..3 = (0,0), (1,0), (1,1), (0,1); the edge parameter runs from start to end.
pub const PATCH_EDGES: [(usize, usize); 4] = [(0, 1), (1, 2), (3, 2), (0, 3)];

impl BSplinePatch {
    /// Vertex ids of the face corners (u,v) = (0,0), (1,0), (1,1), (0,1).
    pub fn corners(&self) -> [u32; 4] {
        [self.cvs[5], self.cvs[6], self.cvs[10], self.cvs[9]]
    }

    /// The `flags` word of the GPU record: bits 0-3 boundary mask, bit 4+e set when edge e
    /// (see [`PATCH_EDGES`]) runs from the larger to the smaller vertex id.
    pub fn gpu_flags(&self) -> u32 {
        let c = self.corners();
        let mut flags = u32::from(self.boundary_mask & 0xf);
        for (e, &(a, b)) in PATCH_EDGES.iter().enumerate() {
            if c[a] > c[b] {
                flags |= 1 << (4 + e);
            }
        }
        flags
    }

    /// Limit positions of the four face corners, from the CPU reference patch
    /// ([`RegularPatch::eval`] at the domain corners).
    pub fn corner_limits(&self, positions: &[DVec3]) -> [DVec3; 4] {
        let p = RegularPatch {
            face: self.face,
            cvs: self.cvs,
            boundary_mask: self.boundary_mask,
        };
        [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
            .map(|(u, v)| p.eval(positions, u, v).position)
    }
}

/// Per-patch GPU records (`PatchInfo`): face, flags, two pad words, corner vertex ids.
pub fn patch_info_bytes(patches: &[BSplinePatch]) -> Vec<u8> {
    let mut out = Vec::with_capacity(patches.len() * PATCH_INFO_BYTES);
    for p in patches {
        let c = p.corners();
        for w in [p.face, p.gpu_flags(), 0, 0, c[0], c[1], c[2], c[3]] {
            out.extend_from_slice(&w.to_le_bytes());
        }
    }
    out
}

/// The index buffer of the patch draw: 16 vertex ids per patch.
pub fn patch_index_bytes(patches: &[BSplinePatch]) -> Vec<u8> {
    let mut out = Vec::with_capacity(patches.len() * 64);
    for p in patches {
        for v in p.cvs {
            out.extend_from_slice(&v.to_le_bytes());
        }
    }
    out
}

/// Points as tightly packed f32 triples (vertex buffers).
pub fn vec3_bytes(points: &[DVec3]) -> Vec<u8> {
    let mut out = Vec::with_capacity(points.len() * 12);
    for p in points {
        for c in p.as_vec3().to_array() {
            out.extend_from_slice(&c.to_le_bytes());
        }
    }
    out
}

/// Points as f32 quadruples with w = 1 (std430 `vec4[]`).
pub fn vec4_bytes(points: &[DVec3]) -> Vec<u8> {
    let mut out = Vec::with_capacity(points.len() * 16);
    for p in points {
        for c in p.as_vec3().extend(1.0).to_array() {
            out.extend_from_slice(&c.to_le_bytes());
        }
    }
    out
}

/// Limit positions of every vertex that is a corner of some patch (others stay at the control
/// position; no shader reads them). Each vertex is written once, by the first patch that has it.
pub fn vertex_limits(patches: &[BSplinePatch], positions: &[DVec3]) -> Vec<DVec3> {
    let mut out = positions.to_vec();
    let mut done = vec![false; positions.len()];
    for p in patches {
        let lim = p.corner_limits(positions);
        for (k, v) in p.corners().iter().enumerate() {
            let v = *v as usize;
            if !done[v] {
                done[v] = true;
                out[v] = lim[k];
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 4x4 grid patch with ids 0..15 in cvs order.
    fn grid_patch(mask: u8) -> BSplinePatch {
        let mut cvs = [0u32; 16];
        for (k, c) in cvs.iter_mut().enumerate() {
            *c = k as u32;
        }
        BSplinePatch {
            face: 7,
            cvs,
            boundary_mask: mask,
        }
    }

    #[test]
    fn flags_encode_mask_and_edge_direction() {
        let p = grid_patch(0b0101);
        // corners 5, 6, 10, 9: edges (5,6) (6,10) (9,10) (5,9) all increasing.
        assert_eq!(p.gpu_flags(), 0b0101);
        let mut q = p;
        q.cvs.swap(5, 10); // corners 10, 6, 5, 9: every edge runs downwards
        assert_eq!(q.gpu_flags() >> 4, 0b1111);
        let mut r = p;
        r.cvs.swap(5, 6); // corners 6, 5, 10, 9: only edge 0 (6 -> 5) runs downwards
        assert_eq!(r.gpu_flags() >> 4, 0b0001);
    }

    #[test]
    fn planar_grid_corner_limits_are_the_vertices() {
        // On an affine grid the B-spline reproduces the affine map: limit of vertex = vertex.
        let pos: Vec<DVec3> = (0..16)
            .map(|k| DVec3::new((k % 4) as f64, (k / 4) as f64 * 2.0, 0.5))
            .collect();
        let lim = grid_patch(0).corner_limits(&pos);
        for (k, v) in grid_patch(0).corners().iter().enumerate() {
            assert!((lim[k] - pos[*v as usize]).length() < 1e-12);
        }
    }

    #[test]
    fn byte_layouts() {
        let p = grid_patch(0);
        let info = patch_info_bytes(&[p]);
        assert_eq!(info.len(), PATCH_INFO_BYTES);
        assert_eq!(u32::from_le_bytes(info[0..4].try_into().unwrap()), 7);
        assert_eq!(u32::from_le_bytes(info[16..20].try_into().unwrap()), 5);
        assert_eq!(u32::from_le_bytes(info[28..32].try_into().unwrap()), 9);
        assert_eq!(patch_index_bytes(&[p]).len(), 64);
        let v = vec4_bytes(&[DVec3::new(1.0, 2.0, 3.0)]);
        assert_eq!(f32::from_le_bytes(v[12..16].try_into().unwrap()), 1.0);
        assert_eq!(f32::from_le_bytes(v[4..8].try_into().unwrap()), 2.0);
    }
}
