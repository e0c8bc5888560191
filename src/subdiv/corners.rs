//! Face-corner arithmetic of one Catmull-Clark step, shared by the whole-level refinement
//! (`super::refine`) and the kept children of an adaptive step (`super::kept`,
//! `super::ring_step`): which child quad a parent corner makes, the next and previous corner.

use crate::topology::Topology;

/// The child quad of corner `h` (previous corner `hp`) of parent face `f`: (vertex point of the
/// corner, edge point of its edge, face point, edge point of the previous edge).
pub(super) fn child_face(t: &Topology, f: usize, h: usize, hp: usize) -> [u32; 4] {
    child_face_with(t, f, h, hp, t.edge_count() as u32, |e| e)
}

/// [`child_face`] in a child numbering of `ne` edge points, edge `e`'s at `edge_point(e)`.
#[inline]
pub(super) fn child_face_with(
    t: &Topology,
    f: usize,
    h: usize,
    hp: usize,
    ne: u32,
    edge_point: impl Fn(u32) -> u32,
) -> [u32; 4] {
    let nf = t.face_count() as u32;
    [
        nf + ne + t.face_verts[h],
        nf + edge_point(t.face_edges[h]),
        f as u32,
        nf + edge_point(t.face_edges[hp]),
    ]
}

/// `(k + 1) % n` for `k < n`, without a division.
#[inline]
pub(super) fn next_corner(k: u32, n: u32) -> u32 {
    if k + 1 == n {
        0
    } else {
        k + 1
    }
}

/// The corner before corner `h` of face `f`.
pub(super) fn prev_corner(t: &Topology, f: usize, h: u32) -> usize {
    if h == t.face_offsets[f] {
        t.face_offsets[f + 1] as usize - 1
    } else {
        h as usize - 1
    }
}
