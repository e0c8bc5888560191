//! Per-patch data of Gregory patches that the shared TES reads (`glsl/gregory/`),
//! the same for both GPU construction variants: patch records (face, flags, corner ids), the
//! 12-point B-spline grids of edges shared with regular patches, and per-vertex limit positions
//! and normals for the patch corners (§4.5: watertight corners and edges).

use glam::DVec3;

use crate::patch::gregory::edge_flags::{edge_flags, Across, EdgeFlags, ManySectors};
pub use crate::patch::gregory::gregory_faces as irregular_faces;
use crate::patch::gregory::{check_face_level0, gregory_vertex, GregoryTangents};
use crate::patch::single_crease::SingleCreasePatch;
use crate::patch::RegularPatch;
use crate::topology::Topology;

/// Bytes of one `GregoryPatchInfo` record.
pub const GREGORY_PATCH_INFO_BYTES: usize = 32;
pub use crate::patch::gregory::edge_flags::GRID_IDS_PER_PATCH;

/// Why a face is not drawn as a GPU Gregory patch (the renderer keeps it on the CPU path):
/// the construction's own limits at level 0 ([`check_face_level0`]: polygons, darts, semi-sharp tags, cone
/// points, one-face crease sectors, wide corner sectors).
pub fn gregory_face_problem(topo: &Topology, f: u32) -> Option<String> {
    check_face_level0(topo, f).err().map(|e| e.to_string())
}

/// Shared TES data of a list of Gregory faces, in draw order: quads first, then triangles.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GregoryLayout {
    /// Face of each patch.
    pub faces: Vec<u32>,
    /// Number of quad patches (the first `quad_count` entries).
    pub quad_count: u32,
    /// Corner vertex ids (w repeats corner 0 for triangles).
    pub corners: Vec<[u32; 4]>,
    /// Index of the patch's face in each corner vertex's ring (paper Fig. 8).
    pub corner_ring: Vec<[u32; 4]>,
    /// Edge-tangent lengths of the construction the patches are built with.
    pub tangents: GregoryTangents,
    /// Bit k: edge k (corner k -> k+1) is shared with a regular B-spline patch; bit 4+k: that
    /// shared edge is a boundary or infinitely sharp edge (curve from the crease polygon); bit 8+k: the
    /// face across edge k is a triangle; bit 12+k: edge k is a boundary or infinitely sharp edge, or its other face is
    /// neither a Gregory patch of this layout nor a regular patch (one-sided normal);
    /// bit 16+k: corner k's vertex has two or more sectors; bits 20+2k / 21+2k: the first /
    /// last grid point of edge k is a mirrored phantom (`glsl/common/gregory.glsl`).
    pub flags: Vec<u32>,
    /// [`GRID_IDS_PER_PATCH`] ids per patch (zeros where the flag is off).
    pub grid_ids: Vec<u32>,
}

/// The 16-point grid of face `g` when it is drawn from one: a regular B-spline patch, or a
/// single-crease patch, whose edges a Gregory face can share are those away from its crease
/// (a Gregory corner has no semi-sharp edge), the B-spline grid curves of its unmodified points
/// (`glsl/single_crease/single_crease.tese`).
fn grid_neighbour(topo: &Topology, g: u32) -> Option<RegularPatch> {
    RegularPatch::gather(topo, g).or_else(|| {
        SingleCreasePatch::gather(topo, g).map(|p| RegularPatch {
            face: g,
            cvs: p.cvs,
            boundary_mask: 0,
        })
    })
}

impl GregoryLayout {
    /// Tables for `faces` (each a triangle or quad with interior smooth vertices: check with
    /// [`gregory_face_problem`] first; others are skipped).
    pub fn new(topo: &Topology, faces: &[u32], tangents: GregoryTangents) -> GregoryLayout {
        let mut quads: Vec<u32> = faces
            .iter()
            .copied()
            .filter(|&f| topo.face_size(f) == 4)
            .collect();
        let tris: Vec<u32> = faces
            .iter()
            .copied()
            .filter(|&f| topo.face_size(f) == 3)
            .collect();
        let quad_count = quads.len() as u32;
        quads.extend(tris);
        let drawn: std::collections::HashSet<u32> = quads.iter().copied().collect();
        let mut sectors = ManySectors::default();
        let mut out = GregoryLayout {
            quad_count,
            tangents,
            ..Default::default()
        };
        for &f in &quads {
            let fv = topo.face_vertices(f);
            let n = fv.len();
            let mut corners = [fv[0]; 4];
            let mut ring = [0u32; 4];
            for (k, r) in ring.iter_mut().enumerate().take(n) {
                corners[k] = fv[k];
                *r = topo
                    .vertex_faces(fv[k])
                    .iter()
                    .position(|&g| g == f)
                    .unwrap_or(0) as u32;
            }
            // A neighbour drawn another way (CPU path) shares nothing on the GPU.
            let across = |_, g: Option<u32>| match g {
                Some(g) => match grid_neighbour(topo, g) {
                    Some(p) => Across::BSpline(p),
                    None if drawn.contains(&g) => Across::Patch,
                    None => Across::Nothing,
                },
                None => Across::Nothing,
            };
            let EdgeFlags { flags, grids } =
                edge_flags(topo, f, across, |v| v, |v| v, &mut sectors);
            out.faces.push(f);
            out.corners.push(corners);
            out.corner_ring.push(ring);
            out.flags.push(flags);
            out.grid_ids.extend_from_slice(&grids);
        }
        out
    }

    /// Number of patches.
    pub fn patch_count(&self) -> u32 {
        self.faces.len() as u32
    }

    /// `GregoryPatchInfo` records (binding 6).
    pub fn patch_info_bytes(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(self.faces.len() * GREGORY_PATCH_INFO_BYTES);
        for i in 0..self.faces.len() {
            let c = self.corners[i];
            for w in [self.faces[i], self.flags[i], 0, 0, c[0], c[1], c[2], c[3]] {
                out.extend_from_slice(&w.to_le_bytes());
            }
        }
        out
    }

    /// Grid ids (binding 7).
    pub fn grid_bytes(&self) -> Vec<u8> {
        self.grid_ids.iter().flat_map(|w| w.to_le_bytes()).collect()
    }

    /// Ring offsets, 4 words per patch (two-stage variant, binding 5).
    pub fn corner_ring_bytes(&self) -> Vec<u8> {
        self.corner_ring
            .iter()
            .flatten()
            .flat_map(|w| w.to_le_bytes())
            .collect()
    }

    /// Index buffer of the two-stage draw: the face's corners (4 per quad, then 3 per triangle).
    pub fn corner_index_bytes(&self) -> Vec<u8> {
        let mut out = Vec::new();
        for (i, c) in self.corners.iter().enumerate() {
            let n = if (i as u32) < self.quad_count { 4 } else { 3 };
            for v in &c[..n] {
                out.extend_from_slice(&v.to_le_bytes());
            }
        }
        out
    }
}

/// Limit position and unit limit normal of a vertex the Gregory construction covers (§3.2-3.3,
/// §4.6: the plane of the limit tangents along ring edges 0 and 1, outward for counter-clockwise
/// faces; a boundary ring starts at a boundary edge). Vertices with several sectors have no
/// single normal: patch corners there keep their own (flags bit 16+k). Uncovered vertices give
/// the control position and +z.
pub fn gregory_vertex_frame(topo: &Topology, positions: &[DVec3], v: u32) -> (DVec3, DVec3) {
    let point = |i: u32| positions[i as usize];
    match gregory_vertex(topo, v, &point) {
        Some(g) if g.e.len() >= 2 => {
            let n = (g.e[0] - g.p).cross(g.e[1] - g.p).normalize_or_zero();
            (g.p, n)
        }
        _ => (positions[v as usize], DVec3::Z),
    }
}
