//! Catmull-Clark rules with semi-sharp creases (DeRose, Kass, Truong 1998; the RenderMan /
//! OpenSubdiv semantics, listed in Köbler 2013 section 3.1-3.2 and Nießner et al. 2012).
//!
//! Masks are expressed on a vertex's one-ring (see [`crate::topology`] for the ring order):
//! a weight for the vertex itself, one per incident edge (applied to the edge's other end) and
//! one per incident face (applied to the face centroid).

use crate::mesh::{CreaseMethod, INFINITE_SHARPNESS};
use crate::topology::Topology;

/// Catmull-Clark weights of a smooth edge point between two quads: each end, each of the two
/// quads' far corners (3/8 and 1/16).
pub const REGULAR_EDGE_WEIGHTS: [f64; 2] = [0.375, 0.0625];

/// Catmull-Clark weights of the vertex point of a smooth valence-4 vertex among four quads: the
/// vertex, each edge neighbour, each diagonal (9/16, 3/32 and 1/64).
pub const REGULAR_VERTEX_WEIGHTS: [f64; 3] = [0.5625, 0.09375, 0.015625];

/// Whether a sharpness value is infinitely sharp.
pub fn is_infinite(s: f32) -> bool {
    s >= INFINITE_SHARPNESS
}

/// Sharpness of a child edge or vertex under the normal rule: `max(s - 1, 0)`; infinite stays
/// infinite (DeRose et al. 1998, section 3).
pub fn decrement(s: f32) -> f32 {
    if is_infinite(s) {
        INFINITE_SHARPNESS
    } else if s > 1.0 {
        s - 1.0
    } else {
        0.0
    }
}

/// The vertex rule chosen by the number of incident sharp edges and the vertex sharpness.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum VertexRule {
    /// No sharp edge: the smooth Catmull-Clark rule.
    Smooth,
    /// One sharp edge: the smooth rule.
    Dart,
    /// Two sharp edges: the crease rule `1/8, 3/4, 1/8`.
    Crease,
    /// More than two sharp edges or a sharp vertex: the vertex stays.
    Corner,
}

/// Rule for a vertex with sharpness `vertex_sharpness` and `sharp_edges` incident edges of
/// sharpness `> 0` (DeRose et al. 1998, section 3; Köbler 2013, section 3.2).
pub fn vertex_rule(vertex_sharpness: f32, sharp_edges: usize) -> VertexRule {
    if vertex_sharpness > 0.0 {
        return VertexRule::Corner;
    }
    match sharp_edges {
        0 => VertexRule::Smooth,
        1 => VertexRule::Dart,
        2 => VertexRule::Crease,
        _ => VertexRule::Corner,
    }
}

/// Sharpness of the child (half) edge of `e` that ends at `v`.
///
/// Normal: [`decrement`]. Chaikin: `max(0.75 s + 0.25 avg - 1, 0)` where `avg` is the mean
/// sharpness of the other semi-sharp edges at `v`; plain `s - 1` when there are none; smooth
/// stays smooth and infinite stays infinite (OpenSubdiv's Chaikin creasing).
pub fn child_edge_sharpness(topo: &Topology, e: u32, v: u32) -> f32 {
    let others = topo.vertex_edges(v).iter().filter(|&&o| o != e);
    let others = others.map(|&o| topo.edge_sharpness[o as usize]);
    child_sharpness(
        topo.edge_sharpness[e as usize],
        others,
        topo.options.crease_method,
    )
}

/// [`child_edge_sharpness`] of an edge of sharpness `s` whose end `v` has the other edges of
/// sharpness `others`, under `method`.
pub fn child_sharpness(s: f32, others: impl IntoIterator<Item = f32>, method: CreaseMethod) -> f32 {
    if s <= 0.0 || is_infinite(s) || method == CreaseMethod::Normal {
        return decrement(s);
    }
    let mut sum = 0.0f32;
    let mut count = 0u32;
    for so in others {
        if so > 0.0 && !is_infinite(so) {
            sum += so;
            count += 1;
        }
    }
    if count == 0 {
        decrement(s)
    } else {
        decrement(0.75 * s + 0.25 * sum / count as f32)
    }
}

/// Weight of the parent rule when the rule changes between parent and child: the mean parent
/// sharpness of the vertex and edges that are sharp in the parent and smooth in the child,
/// clamped to `[0, 1]` (DeRose et al. 1998, section 3, fractional sharpness).
pub fn fractional_weight(
    parent_vertex: f32,
    child_vertex: f32,
    parent_edges: &[f32],
    child_edges: &[f32],
) -> f64 {
    let mut sum = 0.0f64;
    let mut count = 0u32;
    if parent_vertex > 0.0 && child_vertex <= 0.0 {
        sum += parent_vertex as f64;
        count += 1;
    }
    for (&p, &c) in parent_edges.iter().zip(child_edges) {
        if p > 0.0 && c <= 0.0 {
            sum += p as f64;
            count += 1;
        }
    }
    if count == 0 {
        0.0
    } else {
        (sum / count as f64).clamp(0.0, 1.0)
    }
}

/// A vertex-point mask on a one-ring: `vertex` weight, `edges[i]` for the far end of ring edge
/// `i`, `faces[i]` for the centroid of ring face `i`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct VertexMask {
    /// Weight of the vertex itself.
    pub vertex: f64,
    /// Weights of the far ends of the ring edges.
    pub edges: Vec<f64>,
    /// Weights of the centroids of the ring faces.
    pub faces: Vec<f64>,
}

impl VertexMask {
    /// Resets to the zero mask of a ring with `ne` edges and `nf` faces.
    pub fn reset(&mut self, ne: usize, nf: usize) {
        self.vertex = 0.0;
        self.edges.clear();
        self.edges.resize(ne, 0.0);
        self.faces.clear();
        self.faces.resize(nf, 0.0);
    }

    /// Adds `w` times the mask of `rule`. `sharp` lists the ring edges that are sharp for the
    /// rule (used by the crease rule, which needs exactly two).
    ///
    /// Smooth (Catmull-Clark 1978, general valence `n` = number of ring edges):
    /// `(n-2)/n v + 1/n^2 sum(edge ends) + 1/n^2 sum(face centroids)`; on an incomplete ring
    /// (only possible on extraction cuts) the weights are renormalised to sum to one.
    /// Crease: `3/4 v + 1/8 (a + b)`. Corner: `v`.
    pub fn add_rule(&mut self, rule: VertexRule, sharp: &[usize], w: f64) {
        let ne = self.edges.len();
        let nf = self.faces.len();
        let rule = if rule == VertexRule::Crease && sharp.len() != 2 {
            VertexRule::Corner
        } else {
            rule
        };
        match rule {
            VertexRule::Smooth | VertexRule::Dart => {
                if ne < 2 || nf == 0 {
                    self.vertex += w;
                    return;
                }
                let n = ne as f64;
                let inv = 1.0 / (n * n);
                let scale = if ne == nf {
                    w
                } else {
                    w / ((n - 2.0) / n + inv * (ne + nf) as f64)
                };
                self.vertex += scale * (n - 2.0) / n;
                for x in &mut self.edges {
                    *x += scale * inv;
                }
                for x in &mut self.faces {
                    *x += scale * inv;
                }
            }
            VertexRule::Crease => {
                self.vertex += 0.75 * w;
                self.edges[sharp[0]] += 0.125 * w;
                self.edges[sharp[1]] += 0.125 * w;
            }
            VertexRule::Corner => self.vertex += w,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sharpness_decay_and_rules() {
        assert_eq!(decrement(2.5), 1.5);
        assert_eq!(decrement(0.7), 0.0);
        assert_eq!(decrement(INFINITE_SHARPNESS), INFINITE_SHARPNESS);
        assert_eq!(decrement(25.0), INFINITE_SHARPNESS);
        assert_eq!(vertex_rule(0.0, 0), VertexRule::Smooth);
        assert_eq!(vertex_rule(0.0, 1), VertexRule::Dart);
        assert_eq!(vertex_rule(0.0, 2), VertexRule::Crease);
        assert_eq!(vertex_rule(0.0, 3), VertexRule::Corner);
        assert_eq!(vertex_rule(0.5, 0), VertexRule::Corner);
    }

    #[test]
    fn fractional_weight_averages_the_transitions() {
        // Edges 0.4 and 0.6 become smooth, the 10 stays: (0.4 + 0.6) / 2.
        let w = fractional_weight(0.0, 0.0, &[0.4, 0.6, 10.0, 0.0], &[0.0, 0.0, 10.0, 0.0]);
        assert!((w - 0.5).abs() < 1e-7);
        // A vertex sharpness 0.25 turning smooth together with an edge 1.0 -> 0.
        let w = fractional_weight(0.25, 0.0, &[1.0], &[0.0]);
        assert!((w - 0.625).abs() < 1e-7);
        // Clamped to 1 and 0 without transitions.
        assert_eq!(fractional_weight(0.0, 0.0, &[3.0, 2.0], &[2.0, 1.0]), 0.0);
    }

    #[test]
    fn masks_sum_to_one() {
        let mut m = VertexMask::default();
        m.reset(5, 5);
        m.add_rule(VertexRule::Smooth, &[], 0.3);
        m.add_rule(VertexRule::Crease, &[1, 3], 0.7);
        let total = m.vertex + m.edges.iter().sum::<f64>() + m.faces.iter().sum::<f64>();
        assert!((total - 1.0).abs() < 1e-15);
        assert!((m.edges[1] - (0.3 / 25.0 + 0.7 / 8.0)).abs() < 1e-15);
        assert!((m.vertex - (0.3 * 3.0 / 5.0 + 0.7 * 0.75)).abs() < 1e-15);
    }
}
