//! The 12 B-spline points of a regular patch along one of its edges in the canonical frame every
//! patch sharing that edge uses (Loop et al. 2009 §4.5; `grid_edge_rows` in
//! `glsl/common/watertight.glsl`): three rows (left of the direction from the smaller key, on the
//! edge, right), four points each from the smaller-key end.

use super::RegularPatch;

/// B-spline patch edges as (start corner, end corner) in the order of the boundary bits, with
/// corners indexed 0..3 = (0,0), (1,0), (1,1), (0,1); the edge parameter runs from start to
/// end. Edge `e` is face edge `e` (corner `e` -> `e + 1`), reversed for `e = 2, 3`.
pub const PATCH_EDGES: [(usize, usize); 4] = [(0, 1), (1, 2), (3, 2), (0, 3)];

/// The canonical grid of one patch edge.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EdgeGrid {
    /// B-spline edge of the patch ([`PATCH_EDGES`]).
    pub edge: usize,
    /// Rows left / on / right of the canonical direction, 4 ids each from its start.
    pub ids: [u32; 12],
    /// The first point along the canonical direction is a phantom (mirrored `2 x1 - x2`).
    pub first_phantom: bool,
    /// The last point is a phantom.
    pub last_phantom: bool,
    /// The outer row was a phantom (the edge is a boundary or infinitely sharp crease of the
    /// patch): it holds the edge row instead, so `outer - inner` keeps the patch's one-sided
    /// cross direction (half the mirrored row's difference).
    pub outer_phantom: bool,
}

/// The grid of the edge of `p` whose corners are `a` and `b`, in the frame of `key` (ids order
/// by `key(id)`), seen from the face across it running `a -> b` (so that face lies left of the
/// canonical direction exactly when `key(a) < key(b)`). `None` when `a`, `b` are not the ends of
/// one patch edge.
pub fn edge_grid(p: &RegularPatch, a: u32, b: u32, key: impl Fn(u32) -> u32) -> Option<EdgeGrid> {
    let c = p.corners();
    let pe = PATCH_EDGES
        .iter()
        .position(|&(s, t)| (c[s] == a && c[t] == b) || (c[s] == b && c[t] == a))?;
    let (s, t) = PATCH_EDGES[pe];
    let reversed = key(c[s]) > key(c[t]);
    let across_left = key(a) < key(b);
    let along_u = pe == 0 || pe == 2;
    let off = usize::from(pe == 1 || pe == 2);
    let m = p.boundary_mask;
    // Row (offset by `off`) outside the patch; the edge row is 1.
    let outer = if off == 0 { 0 } else { 2 };
    let outer_phantom = m & (1 << pe) != 0;
    let outer_row = if outer_phantom { 1 } else { outer };
    let rows = if across_left {
        [outer_row, 1, 2 - outer]
    } else {
        [2 - outer, 1, outer_row]
    };
    let mut ids = [0u32; 12];
    for (r, &mm) in rows.iter().enumerate() {
        for k in 0..4 {
            let kk = if reversed { 3 - k } else { k };
            let idx = if along_u {
                (mm + off) * 4 + kk
            } else {
                kk * 4 + mm + off
            };
            ids[r * 4 + k] = p.cvs[idx];
        }
    }
    // Boundary bits: 0 = v=0 (row 0), 1 = u=1 (column 3), 2 = v=1 (row 3), 3 = u=0 (column 0).
    let (along_first, along_last) = if along_u { (8, 2) } else { (1, 4) };
    let (pf, pl) = (m & along_first != 0, m & along_last != 0);
    let (first_phantom, last_phantom) = if reversed { (pl, pf) } else { (pf, pl) };
    Some(EdgeGrid {
        edge: pe,
        ids,
        first_phantom,
        last_phantom,
        outer_phantom,
    })
}
