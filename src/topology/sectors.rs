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

/// Sharpness tags `tags` with the semi-sharp ones made smooth (0).
fn smooth(tags: &[f32]) -> Vec<f32> {
    tags.iter()
        .map(|&s| if is_semi(s) { 0.0 } else { s })
        .collect()
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
        let (edges, vertices) = (smooth(&self.edge_sharpness), smooth(&self.vertex_sharpness));
        Cow::Owned(self.with_tags(edges, vertices, self.promoted.clone()))
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
        let promote = |s: f32| is_semi(s) && s >= threshold;
        // Each edge's promoted flag from `self`'s (before the change); the tags written once
        // from `self`'s rather than cloned and then overwritten.
        let promoted: Vec<bool> = if self.promoted.is_empty() {
            if self.edge_sharpness.iter().any(|&s| promote(s)) {
                self.edge_sharpness.iter().map(|&s| promote(s)).collect()
            } else {
                Vec::new()
            }
        } else {
            let p: Vec<bool> = (self.promoted.iter().zip(&self.edge_sharpness))
                .map(|(&p, &s)| p || promote(s))
                .collect();
            if p.contains(&true) {
                p
            } else {
                Vec::new()
            }
        };
        let edge_sharpness = (self.edge_sharpness.iter())
            .map(|&s| match s {
                s if promote(s) => INFINITE_SHARPNESS,
                s if is_semi(s) => 0.0,
                s => s,
            })
            .collect();
        Cow::Owned(self.with_tags(edge_sharpness, smooth(&self.vertex_sharpness), promoted))
    }

    /// This topology's connectivity and other tags with edge and vertex sharpness `edge_sharpness`,
    /// `vertex_sharpness` and promoted edges `promoted` (per edge, or empty for none): a clone
    /// that does not copy the three arrays it replaces.
    fn with_tags(
        &self,
        edge_sharpness: Vec<f32>,
        vertex_sharpness: Vec<f32>,
        promoted: Vec<bool>,
    ) -> Topology {
        Topology {
            num_vertices: self.num_vertices,
            face_offsets: self.face_offsets.clone(),
            face_verts: self.face_verts.clone(),
            face_edges: self.face_edges.clone(),
            edge_verts: self.edge_verts.clone(),
            edge_faces: self.edge_faces.clone(),
            edge_face_local: self.edge_face_local.clone(),
            vert_face_offsets: self.vert_face_offsets.clone(),
            vert_faces: self.vert_faces.clone(),
            vert_face_local: self.vert_face_local.clone(),
            vert_edge_offsets: self.vert_edge_offsets.clone(),
            vert_edges: self.vert_edges.clone(),
            edge_sharpness,
            vertex_sharpness,
            promoted,
            decayed_corner: self.decayed_corner.clone(),
            crease_factors: self.crease_factors.clone(),
            holes: self.holes.clone(),
            no_limit: self.no_limit.clone(),
            options: self.options,
            max_face_size: self.max_face_size,
        }
    }
}
