//! The per-patch flags and shared-edge grids the Gregory TES reads (`glsl/gregory/gregory.glsl`,
//! §4.5 watertight edges and corners), from topology alone, for any set of neighbouring patches.

use super::super::edge_grid::edge_grid;
use super::super::RegularPatch;
use crate::topology::{is_sharp_edge, sector_count, Topology};

/// Grid vertex ids per patch (4 edges x 3 rows x 4).
pub const GRID_IDS_PER_PATCH: usize = 48;

/// What is drawn across one edge of a Gregory patch.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Across {
    /// Nothing on the GPU (boundary, hole, a face left to another path): one-sided normal.
    Nothing,
    /// A patch sharing the edge's normal without a B-spline grid (another Gregory patch, or a
    /// coarser patch whose own record replaces the grid).
    Patch,
    /// A regular B-spline patch (control vertex ids in the id space of the flags' ids).
    BSpline(RegularPatch),
}

/// Flags and grids of one Gregory patch.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EdgeFlags {
    /// Bit k: edge k (corner k -> k+1) is shared with a regular B-spline patch, whose grid gives
    /// its points; bit 4+k: that shared edge is a boundary or infinitely sharp edge (the grid
    /// gives the position, the patch keeps its own normal); bit 8+k: the face across edge k is a
    /// triangle; bit 12+k: edge k is a boundary or infinitely sharp edge, or nothing on the GPU
    /// lies across it (one-sided normal); bit 16+k: corner k's vertex has two or more sectors;
    /// bits 20+2k / 21+2k: the first / last grid point of edge k is a mirrored phantom.
    pub flags: u32,
    /// [`GRID_IDS_PER_PATCH`] ids (zeros where bit k is off).
    pub grids: [u32; GRID_IDS_PER_PATCH],
}

/// Whether each vertex of one topology has two or more sectors ([`sector_count`]), each vertex
/// counted on its first ask: neighbouring patches share corners (a vertex of a refined level
/// serves up to four end caps), so [`edge_flags`] over many faces asks most vertices often.
#[derive(Debug, Default)]
pub struct ManySectors {
    /// Per vertex: 0 not asked yet, 1 fewer than two sectors, 2 two or more (empty: nothing
    /// asked yet).
    known: Vec<u8>,
}

impl ManySectors {
    /// Whether vertex `v` of `topo` (the same topology on every call) has two or more sectors.
    pub fn get(&mut self, topo: &Topology, v: u32) -> bool {
        if self.known.is_empty() {
            self.known.resize(topo.vertex_count(), 0);
        }
        let known = &mut self.known[v as usize];
        if *known == 0 {
            *known = 1 + u8::from(sector_count(topo, v) >= 2);
        }
        *known == 2
    }
}

/// The flags of face `f` of `topo`: `across(k, g)` classifies the face `g` across edge `k`
/// (`None` on a boundary); `id` maps a vertex of `topo` to the id space of the B-spline
/// patches' control vertices and `key` orders those ids for the canonical edge direction;
/// `sectors` says which vertices of `topo` have two or more sectors.
pub fn edge_flags(
    topo: &Topology,
    f: u32,
    across: impl Fn(usize, Option<u32>) -> Across,
    id: impl Fn(u32) -> u32,
    key: impl Fn(u32) -> u32,
    sectors: &mut ManySectors,
) -> EdgeFlags {
    let fv = topo.face_vertices(f);
    let n = fv.len();
    let mut flags = 0u32;
    let mut grids = [0u32; GRID_IDS_PER_PATCH];
    // Edge `k` of the face joins corners `k` and `k + 1` (`Topology::face_edges`).
    for (k, &e) in topo.face_edges(f).iter().enumerate() {
        let (a, b) = (fv[k], fv[(k + 1) % n]);
        let g = topo.edge_faces(e).iter().copied().find(|&g| g != f);
        if g.is_some_and(|g| topo.face_size(g) == 3) {
            flags |= 1 << (8 + k);
        }
        let sharp = is_sharp_edge(topo, e);
        let other = across(k, g);
        if sharp || other == Across::Nothing {
            flags |= 1 << (12 + k);
        }
        if sectors.get(topo, a) {
            flags |= 1 << (16 + k);
        }
        let Across::BSpline(p) = other else { continue };
        // Across a boundary or sharp edge the B-spline patch mirrors its own rows (its outer
        // row is a phantom): the two sides share only the edge row, the crease polygon, whose
        // curve both take from the grid; the normal stays each side's own (bit 4+k).
        let Some(grid) = edge_grid(&p, id(a), id(b), &key).filter(|g| sharp || !g.outer_phantom)
        else {
            continue;
        };
        flags |= 1 << k;
        if sharp {
            flags |= 1 << (4 + k);
        }
        flags |= u32::from(grid.first_phantom) << (20 + 2 * k);
        flags |= u32::from(grid.last_phantom) << (21 + 2 * k);
        grids[12 * k..12 * k + 12].copy_from_slice(&grid.ids);
    }
    EdgeFlags { flags, grids }
}
