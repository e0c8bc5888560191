//! Sharp edges and sectors around a vertex (pure topology): how many limit normals meet at a
//! vertex, and the smooth stand-in of a level with residual semi-sharp tags.

use std::borrow::Cow;

use super::{Topology, NONE};
use crate::mesh::INFINITE_SHARPNESS;

/// Boundary or infinitely sharp edge.
pub fn is_sharp_edge(topo: &Topology, e: u32) -> bool {
    topo.is_boundary_edge(e) || topo.edge_sharpness(e) >= INFINITE_SHARPNESS
}

/// Number of sectors the sharp edges split vertex `v`'s ring into (0 for a smooth vertex).
pub fn sector_count(topo: &Topology, v: u32) -> usize {
    let sharp = topo
        .vertex_edges(v)
        .iter()
        .filter(|&&e| is_sharp_edge(topo, e))
        .count();
    // The boundary test only where it can matter: without a sharp edge the count is 0 either
    // way (most vertices; `edge_flags` asks it per corner of every end cap).
    if sharp > 0 && topo.is_boundary_vertex(v) {
        sharp - 1
    } else {
        sharp
    }
}

/// [`sector_count`] of every vertex, from one pass over the edges (each sharp edge, as
/// [`is_sharp_edge`] says, counted at both its ends) and one over the ring offsets (a vertex
/// with no face or fewer faces than edges is a boundary vertex, as
/// [`Topology::is_boundary_vertex`] says) instead of one ring walk per vertex.
pub fn sector_counts(topo: &Topology) -> Vec<u32> {
    let mut counts = vec![0u32; topo.vertex_count()];
    let edges = topo.edge_verts.iter().zip(&topo.edge_faces);
    for ((&[a, b], &[_, f1]), &s) in edges.zip(&topo.edge_sharpness) {
        if f1 == NONE || s >= INFINITE_SHARPNESS {
            counts[a as usize] += 1;
            counts[b as usize] += 1;
        }
    }
    let rings = topo
        .vert_face_offsets
        .windows(2)
        .zip(topo.vert_edge_offsets.windows(2));
    for (c, (f, e)) in counts.iter_mut().zip(rings) {
        let faces = f[1] - f[0];
        if *c > 0 && (faces == 0 || e[1] - e[0] != faces) {
            *c -= 1;
        }
    }
    counts
}

/// Face slots (indices into `vertex_faces(v)`) of `v`'s sector containing face slot `i`
/// (between infinitely sharp edges, boundary edges included by the boundary rule), in
/// counter-clockwise order; every slot when no sharp edge splits the ring.
pub fn sector_slots(topo: &Topology, v: u32, i: usize) -> Vec<usize> {
    let nf = topo.vertex_faces(v).len();
    let edges = topo.vertex_edges(v);
    let ne = edges.len();
    let sharp = |k: usize| topo.edge_sharpness(edges[k % ne]) >= INFINITE_SHARPNESS;
    let mut lo = i;
    let mut count = 1;
    while !sharp(lo) && count < nf {
        lo = (lo + nf - 1) % nf;
        count += 1;
    }
    let mut out = vec![lo];
    let mut j = lo;
    while out.len() < nf && !sharp(j + 1) {
        j = (j + 1) % nf;
        out.push(j);
    }
    out
}

/// The faces of the sector of face `f` around vertex `v` ([`sector_slots`]; `f` alone if it is
/// not one of `v`'s faces).
pub fn sector_faces(topo: &Topology, v: u32, f: u32) -> Vec<u32> {
    let faces = topo.vertex_faces(v);
    match faces.iter().position(|&g| g == f) {
        Some(i) => sector_slots(topo, v, i)
            .into_iter()
            .map(|k| faces[k])
            .collect(),
        None => vec![f],
    }
}

/// Whether every patch at vertex `v` has the same limit normal there (one sector: smooth
/// interior or a boundary/crease vertex whose sharp edges do not split its faces; not a cone).
pub fn single_normal_vertex(topo: &Topology, v: u32) -> bool {
    sector_count(topo, v) <= 1
        && (topo.is_boundary_vertex(v) || topo.vertex_sharpness(v) < INFINITE_SHARPNESS)
}

fn is_semi(s: f32) -> bool {
    s > 0.0 && s < INFINITE_SHARPNESS
}

impl Topology {
    /// Whether any edge or vertex carries a finite non-zero (semi-sharp) sharpness.
    pub fn has_semi_sharpness(&self) -> bool {
        self.edge_sharpness.iter().any(|&s| is_semi(s))
            || self.vertex_sharpness.iter().any(|&s| is_semi(s))
    }

    /// This topology with every semi-sharp edge and vertex made smooth (sharpness 0), infinitely
    /// sharp tags and boundaries kept; borrowed when there is nothing to clear. The last level
    /// of a feature-adaptive refinement treats its residual semi-sharpness this way, as
    /// OpenSubdiv's irregular (end-cap) patches do: `Far::PatchBuilder::
    /// GetIrregularPatchCornerSpans` sharpens corner spans from the infinitely sharp tags only.
    pub fn without_semi_sharpness(&self) -> Cow<'_, Topology> {
        if !self.has_semi_sharpness() {
            return Cow::Borrowed(self);
        }
        let mut t = self.clone();
        for s in t
            .edge_sharpness
            .iter_mut()
            .chain(t.vertex_sharpness.iter_mut())
        {
            if is_semi(*s) {
                *s = 0.0;
            }
        }
        Cow::Owned(t)
    }

    /// This topology with every semi-sharp edge of sharpness at least `threshold` made
    /// infinitely sharp, the other semi-sharp edges and every semi-sharp vertex smooth,
    /// boundaries and infinitely sharp tags kept; borrowed when there is nothing to change. The
    /// end caps of a feature-adaptive refinement see their level's residual semi-sharpness this
    /// way by default ([`crate::subdiv::adaptive::EndCapSharpness::Crease`]). The edges made
    /// infinitely sharp are marked promoted ([`Topology::is_promoted_edge`]).
    pub fn with_semi_sharpness_as_crease(&self, threshold: f32) -> Cow<'_, Topology> {
        if !self.has_semi_sharpness() {
            return Cow::Borrowed(self);
        }
        let mut t = self.clone();
        // One pass over the edges: each one's promoted flag from `self`'s (before the
        // change), then the change.
        let mut any = false;
        let promoted: Vec<bool> = t
            .edge_sharpness
            .iter_mut()
            .enumerate()
            .map(|(e, s)| {
                let semi = is_semi(*s);
                let p = self.is_promoted_edge(e as u32) || (semi && *s >= threshold);
                if semi {
                    *s = if *s >= threshold {
                        INFINITE_SHARPNESS
                    } else {
                        0.0
                    };
                }
                any |= p;
                p
            })
            .collect();
        t.promoted = if any { promoted } else { Vec::new() };
        for s in t.vertex_sharpness.iter_mut() {
            if is_semi(*s) {
                *s = 0.0;
            }
        }
        Cow::Owned(t)
    }
}
