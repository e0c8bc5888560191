//! What a facet's patch reads from the vertex stage at each corner (the paper's per-facet input
//! `j_k`: the facet's slot in corner `k`'s ring selects `f_{j_k}` and the two tangent points).

use super::vertex::PmVertex;
use crate::patch::gregory::GregoryPoint;
use crate::topology::Topology;

/// The per-vertex data of a facet's corner `k`, oriented along the facet.
#[derive(Debug, Clone, PartialEq)]
pub struct FacetCorner<P> {
    /// The vertex point `v`.
    pub v: P,
    /// Tangent point towards corner `k + 1`.
    pub next: P,
    /// Tangent point towards corner `k - 1`.
    pub prev: P,
    /// The corner's face point in this facet.
    pub f_in: P,
    /// The corner's face point in the facet across edge `k` (to corner `k + 1`).
    pub f_next: P,
    /// The corner's face point in the facet across edge `k - 1` (to corner `k - 1`).
    pub f_prev: P,
    /// Valence of the corner vertex.
    pub valence: usize,
    /// Spoke index (in the vertex's ring) of edge `k`.
    pub next_spoke: usize,
    /// Spoke index of edge `k - 1`.
    pub prev_spoke: usize,
}

/// Where a facet's corner `k` reads its vertex's data: the paper's per-facet input `j_k` and
/// the spokes and slots next to it (indices into the vertex's ring).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CornerSlots {
    /// The facet's slot in the ring (facet `j` lies between spokes `j` and `j + 1`).
    pub slot: usize,
    /// Slot of the facet across edge `k` (to corner `k + 1`).
    pub f_next: usize,
    /// Slot of the facet across edge `k - 1`.
    pub f_prev: usize,
    /// Spoke of edge `k`.
    pub next_spoke: usize,
    /// Spoke of edge `k - 1`.
    pub prev_spoke: usize,
}

/// The ring indices corner `k` of facet `face` reads.
pub fn corner_slots(topo: &Topology, face: u32, k: usize) -> CornerSlots {
    let fv = topo.face_vertices(face);
    let s = fv.len();
    let w = fv[k];
    let edges = topo.vertex_edges(w);
    let n = edges.len();
    let spoke_to = |x: u32| {
        edges
            .iter()
            .position(|&e| topo.other_vertex(e, w) == x)
            .unwrap_or(0)
    };
    let next_spoke = spoke_to(fv[(k + 1) % s]);
    let prev_spoke = spoke_to(fv[(k + s - 1) % s]);
    // Facet j lies between spokes j and j + 1.
    let slot = if (prev_spoke + 1) % n == next_spoke {
        prev_spoke
    } else {
        next_spoke
    };
    let (f_next, f_prev) = if slot == prev_spoke {
        ((slot + 1) % n, (slot + n - 1) % n)
    } else {
        ((slot + n - 1) % n, (slot + 1) % n)
    };
    CornerSlots {
        slot,
        f_next,
        f_prev,
        next_spoke,
        prev_spoke,
    }
}

/// Corner `k` of facet `face` from the per-vertex data `vert` of its vertex.
pub fn facet_corner<P: GregoryPoint>(
    topo: &Topology,
    face: u32,
    k: usize,
    vert: &PmVertex<P>,
) -> FacetCorner<P> {
    let c = corner_slots(topo, face, k);
    FacetCorner {
        v: vert.v.clone(),
        next: vert.tangent(c.next_spoke),
        prev: vert.tangent(c.prev_spoke),
        f_in: vert.f[c.slot].clone(),
        f_next: vert.f[c.f_next].clone(),
        f_prev: vert.f[c.f_prev].clone(),
        valence: vert.valence(),
        next_spoke: c.next_spoke,
        prev_spoke: c.prev_spoke,
    }
}
