//! Per-patch data of Gregory patches that the shared TES reads (`glsl/gregory/`),
//! the same for both GPU construction variants: patch records (face, flags, corner ids), the
//! 12-point B-spline grids of edges shared with regular patches, and per-vertex limit positions
//! and normals for the patch corners (§4.5: watertight corners and edges).

use glam::DVec3;

pub use crate::patch::gregory::gregory_faces as irregular_faces;
use crate::patch::gregory::{check_face, gregory_vertex};
use crate::patch::single_crease::SingleCreasePatch;
use crate::patch::RegularPatch;
use crate::render::pass::frames::{is_sharp_edge, sector_count};
use crate::render::schemes::bspline::PATCH_EDGES;
use crate::topology::Topology;

/// Bytes of one `GregoryPatchInfo` record.
pub const GREGORY_PATCH_INFO_BYTES: usize = 32;
/// Grid vertex ids per patch (4 edges x 3 rows x 4).
pub const GRID_IDS_PER_PATCH: usize = 48;

/// Why a face is not drawn as a GPU Gregory patch (the renderer keeps it on the CPU path):
/// the construction's own limits ([`check_face`]: polygons, darts, semi-sharp tags, cone
/// points, one-face crease sectors, wide corner sectors).
pub fn gregory_face_problem(topo: &Topology, f: u32) -> Option<String> {
    check_face(topo, f).err().map(|e| e.to_string())
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
    /// Bit k: edge k (corner k -> k+1) is shared with a regular B-spline patch or a
    /// single-crease patch (edge away from its crease, [`grid_neighbour`]); bit 4+k: that
    /// shared edge is a boundary or infinitely sharp edge (curve from the crease polygon); bit 8+k: the
    /// face across edge k is a triangle; bit 12+k: edge k is a boundary or infinitely sharp edge, or its other face is
    /// neither a Gregory patch of this layout nor a regular patch (one-sided normal);
    /// bit 16+k: corner k's vertex has two or more sectors; bits 20+2k / 21+2k: the first /
    /// last grid point of edge k is a mirrored phantom (`glsl/common/gregory.glsl`).
    pub flags: Vec<u32>,
    /// [`GRID_IDS_PER_PATCH`] ids per patch (zeros where the flag is off).
    pub grid_ids: Vec<u32>,
}

/// The 12 grid ids of the edge `a -> b` of a Gregory face shared with regular patch `p`, in the
/// TES order (rows left / on / right of the direction from the smaller id, 4 along it), and
/// whether the first / last point along it is a phantom the TES mirrors (`2 x1 - x2`, as the
/// B-spline TCS does). `None` if a phantom would lie in the rows themselves (cannot happen for
/// an edge with a face on both sides).
fn grid_of(p: &RegularPatch, a: u32, b: u32) -> Option<([u32; 12], bool, bool)> {
    let c = [p.cvs[5], p.cvs[6], p.cvs[10], p.cvs[9]];
    let pe = PATCH_EDGES
        .iter()
        .position(|&(s, t)| (c[s] == a && c[t] == b) || (c[s] == b && c[t] == a))?;
    let along_u = pe == 0 || pe == 2;
    let off = usize::from(pe == 1 || pe == 2);
    let m = p.boundary_mask;
    // Boundary bits: 0 = v=0 (row 0), 1 = u=1 (column 3), 2 = v=1 (row 3), 3 = u=0 (column 0).
    let (near_first, near_last, along_first, along_last) =
        if along_u { (1, 4, 8, 2) } else { (8, 2, 1, 4) };
    if (off == 0 && m & near_first != 0) || (off == 1 && m & near_last != 0) {
        return None;
    }
    let (s, t) = PATCH_EDGES[pe];
    let reversed = c[s] > c[t];
    let lo = a.min(b);
    // The Gregory face runs a -> b, so it lies left of lo -> hi exactly when a is lo.
    let gregory_left = a == lo;
    let outer = if off == 0 { 0 } else { 2 };
    let rows = if gregory_left {
        [outer, 1, 2 - outer]
    } else {
        [2 - outer, 1, outer]
    };
    let mut out = [0u32; 12];
    for (r, &mm) in rows.iter().enumerate() {
        for k in 0..4 {
            let kk = if reversed { 3 - k } else { k };
            let idx = if along_u {
                (mm + off) * 4 + kk
            } else {
                kk * 4 + mm + off
            };
            out[r * 4 + k] = p.cvs[idx];
        }
    }
    let (pf, pl) = (m & along_first != 0, m & along_last != 0);
    Some(if reversed {
        (out, pl, pf)
    } else {
        (out, pf, pl)
    })
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
    pub fn new(topo: &Topology, faces: &[u32]) -> GregoryLayout {
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
        let mut out = GregoryLayout {
            quad_count,
            ..Default::default()
        };
        for &f in &quads {
            let fv = topo.face_vertices(f);
            let n = fv.len();
            let mut corners = [fv[0]; 4];
            let mut ring = [0u32; 4];
            let mut flags = 0u32;
            let mut grids = [0u32; GRID_IDS_PER_PATCH];
            for k in 0..n {
                corners[k] = fv[k];
                ring[k] = topo
                    .vertex_faces(fv[k])
                    .iter()
                    .position(|&g| g == f)
                    .unwrap_or(0) as u32;
                let (a, b) = (fv[k], fv[(k + 1) % n]);
                let across = topo
                    .find_edge(a, b)
                    .and_then(|e| topo.edge_faces(e).iter().copied().find(|&g| g != f));
                if across.is_some_and(|g| topo.face_size(g) == 3) {
                    flags |= 1 << (8 + k);
                }
                let sharp_edge = topo.find_edge(a, b).is_none_or(|e| is_sharp_edge(topo, e));
                // One-sided normal where nothing on the GPU shares the edge's normal: boundary,
                // sharp edge, or a neighbour drawn another way (CPU path).
                let neighbour = across.and_then(|g| grid_neighbour(topo, g));
                let gpu_neighbour =
                    across.is_some_and(|g| drawn.contains(&g)) || neighbour.is_some();
                if sharp_edge || !gpu_neighbour {
                    flags |= 1 << (12 + k);
                }
                if sector_count(topo, a) >= 2 {
                    flags |= 1 << (16 + k);
                }
                if let Some((grid, first, last)) = neighbour.as_ref().and_then(|p| grid_of(p, a, b))
                {
                    flags |= 1 << k;
                    if sharp_edge {
                        flags |= 1 << (4 + k);
                    }
                    flags |= u32::from(first) << (20 + 2 * k);
                    flags |= u32::from(last) << (21 + 2 * k);
                    grids[12 * k..12 * k + 12].copy_from_slice(&grid);
                }
            }
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
