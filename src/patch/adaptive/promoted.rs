//! Promoted creases: edges whose residual semi-sharpness the end caps treat as infinitely sharp
//! ([`EndCapSharpness::Crease`]) while the exact limit is smooth across them (it rounds the
//! crease within about `2^-s` of the patch, Nießner, Loop, Greiner 2012 §3).
//!
//! The end caps keep the crease for their positions, but their normals on it are shared, one
//! per point: on a promoted edge between two end caps, `cross(tangent, d_left - d_right)` of
//! both patches' cross-edge derivatives (the normal of `gregory_edge` in
//! `glsl/gregory/gregory.glsl` across a smooth edge), which weights each side by its
//! cross-edge derivative as the limit's tangent plane at a crease point does once the
//! sharpness has decayed (its cross tangent is the chord between the two sides); at a vertex
//! with promoted edges, the exact limit normal ([`vertex_mask`], the vertex's semi-sharp rules
//! applied until they decay).

use crate::mesh::INFINITE_SHARPNESS;
use crate::patch::gregory::Weights;
use crate::subdiv::adaptive::AdaptiveLevel;
#[cfg(doc)]
use crate::subdiv::adaptive::EndCapSharpness;
#[cfg(doc)]
use crate::subdiv::limit::vertex_mask;
use crate::subdiv::limit::SharedVertexMasks;
use crate::topology::Topology;
use glam::DVec3;

/// Whether edge `e` is a promoted crease: infinitely sharp in `caps` (the level's end-cap
/// topology) but not in `level` (its own), with a face on both sides.
pub fn promoted_edge(level: &Topology, caps: &Topology, e: u32) -> bool {
    !level.is_boundary_edge(e)
        && caps.edge_sharpness(e) >= INFINITE_SHARPNESS
        && level.edge_sharpness(e) < INFINITE_SHARPNESS
}

/// Whether vertex `v` touches a promoted crease, or is a corner only in `caps`.
pub fn promoted_vertex(level: &Topology, caps: &Topology, v: u32) -> bool {
    (caps.vertex_sharpness(v) >= INFINITE_SHARPNESS
        && level.vertex_sharpness(v) < INFINITE_SHARPNESS)
        || level
            .vertex_edges(v)
            .iter()
            .any(|&e| promoted_edge(level, caps, e))
}

/// Rows (d/du, d/dv) over global refined ids of the exact limit tangents at corner `k` of face
/// `f` of `lev`, in the face's frame (`u` towards corner `k + 1` at corner 0): the limit mask of
/// the corner's vertex ([`vertex_mask`], `LimitEvaluator`'s corner evaluation). `None` where
/// the mask fails (the caller keeps the end cap's own corner).
pub fn exact_corner_tangents(lev: &AdaptiveLevel, f: u32, k: usize) -> Option<[Weights; 2]> {
    exact_corner_tangents_shared(lev, f, k, &mut SharedVertexMasks::default())
}

/// [`exact_corner_tangents`] with the masks shared between corners whose rings are alike
/// ([`SharedVertexMasks`]; the same rows).
pub fn exact_corner_tangents_shared(
    lev: &AdaptiveLevel,
    f: u32,
    k: usize,
    masks: &mut SharedVertexMasks,
) -> Option<[Weights; 2]> {
    let v = lev.topology().face_vertices(f)[k];
    let mask = match masks.vertex_mask(&lev.level, v, f) {
        Ok(m) => m,
        Err(e) => {
            log::debug!("promoted corner {k} of face {f}: no exact limit mask ({e})");
            return None;
        }
    };
    let row = |w: &[f64], sign: f64| {
        Weights::from_terms(
            mask.indices
                .iter()
                .zip(w)
                .map(|(&i, &x)| (lev.global(i), sign * x)),
        )
    };
    // `tangent_u` points to corner k + 1, `tangent_v` to corner k - 1 (as
    // `subdiv::eval::corner_sample`): d/du and d/dv of the face.
    let (tu, tv) = (&mask.tangent_u, &mask.tangent_v);
    Some(match k {
        0 => [row(tu, 1.0), row(tv, 1.0)],
        1 => [row(tv, -1.0), row(tu, 1.0)],
        2 => [row(tu, -1.0), row(tv, -1.0)],
        _ => [row(tv, 1.0), row(tu, -1.0)],
    })
}

/// Corner `k` of face `face` of `lev` on a promoted crease: its end-cap `rows` with the
/// tangents replaced by the exact limit's ([`exact_corner_tangents`]), the position kept (the
/// end caps' crease position); empty tangent rows where the exact mask fails. `masks` shares
/// the limit masks between calls ([`exact_corner_tangents_shared`]).
pub fn exact_frame(
    lev: &AdaptiveLevel,
    face: u32,
    k: usize,
    rows: [Weights; 3],
    masks: &mut SharedVertexMasks,
) -> [Weights; 3] {
    let [p, ..] = rows;
    match exact_corner_tangents_shared(lev, face, k, masks) {
        Some([du, dv]) => [p, du, dv],
        None => [p, Weights::default(), Weights::default()],
    }
}

/// The change of the cross-edge derivative `d` (into the end cap) at distance `w` (own
/// parameter) from a promoted edge of residual sharpness `sharpness`, where the limit's fillet
/// replaces the crease: `d_sum` is the sum of both sides' cross-edge derivatives at the edge
/// point (each into its own end cap).
///
/// After `n` more crease steps the limit is the B-spline over the refined points, whose
/// segment next to the crease (width `h = 2^-n` of the end cap) has the far side's point where
/// the crease had its phantom `2c - a`: the crease surface plus `h d_sum (1 - w/h)^3 / 6`
/// (B-spline basis `B0`), so `d` gains `-d_sum (1 - w/h)^2 / 2` there, zero beyond `h` (C2).
/// A fractional sharpness `n + f` blends the limits of `n` and `n + 1` steps by `f`, as its
/// rule blends the points (Nießner, Loop, Greiner 2012 §3; DeRose et al. 1998 §3).
pub fn fillet_cross_derivative(sharpness: f64, w: f64, d_sum: DVec3) -> DVec3 {
    let n = sharpness.floor();
    let f = sharpness - n;
    let step = |steps: f64| {
        let r = (1.0 - w * steps.exp2()).max(0.0);
        -0.5 * r * r
    };
    d_sum * ((1.0 - f) * step(n) + f * step(n + 1.0))
}

/// The band offset's factor on a promoted edge of residual sharpness `sharpness`: the fillet
/// of [`fillet_cross_derivative`] moves the edge point by `h d_sum / 6` (`B0(0) = 1/6` of the
/// segment of width `h = 2^-n`; a fractional `n + f` blends `h` and `h / 2` by `f`), so the
/// limit's tangent along the edge is the crease's plus this factor times the derivative of
/// `d_sum` along the edge, while its cross-edge direction stays `d_own - d_across` (the fillet's
/// cross derivative there is `(d_own - d_across) / 2`).
pub fn band_offset_factor(sharpness: f64) -> f64 {
    let n = sharpness.floor();
    let f = sharpness - n;
    ((1.0 - f) * (-n).exp2() + f * (-n - 1.0).exp2()) / 6.0
}

/// The residual sharpness `s` of a promoted crease as the GPU reads it (`PatchRecord::fillet`):
/// `16 s` rounded, in 16..=255 (`s` from 1 to 15.9; the fillet of a sharper edge is narrower
/// than 2^-15 of the end cap).
pub fn fillet_code(sharpness: f32) -> u32 {
    (sharpness * 16.0).round().clamp(16.0, 255.0) as u32
}

/// The sharpness of [`fillet_code`] `code`.
pub fn fillet_sharpness(code: u32) -> f64 {
    f64::from(code) / 16.0
}

/// The residual sharpness of the fillet at vertex `v` of `level` (its topology as `caps` sees it
/// for the end caps) where the crease through it is regular (valence 4, two opposite promoted
/// edges ([`promoted_edge`]) and no other sharp one, so its other edges cross the crease): the
/// mean of the two, as the crease vertex rule averages its edges' sharpness (DeRose et al. 1998
/// §3);
/// `None` elsewhere (at an extraordinary crease vertex the other edges are no cross-section of
/// the fillet: measured worse with the bend, bishop L5 max 2.08 rad against 1.82 without).
pub fn vertex_fillet_sharpness(level: &Topology, caps: &Topology, v: u32) -> Option<f32> {
    let (promoted, sharp) = crease_edges_at(level, caps, v);
    // The two promoted edges opposite (no face between them): every other edge lies between two
    // faces beside the crease, whose continuations beyond it are the same edge.
    let opposite = promoted.len() == 2
        && !level
            .edge_faces(promoted[0])
            .iter()
            .any(|f| level.edge_faces(promoted[1]).contains(f));
    (level.vertex_edges(v).len() == 4 && sharp == 2 && opposite)
        .then(|| mean_sharpness(level, &promoted))
}

/// [`vertex_fillet_sharpness`] as the GPU reads it at an end of an edge that is no promoted
/// crease (`PatchRecord::fillet`, 4 bits): `2 s` rounded, in 2..=15.
pub fn fillet_end_code(sharpness: f32) -> u32 {
    (sharpness * 2.0).round().clamp(2.0, 15.0) as u32
}

/// The sharpness of [`fillet_end_code`] `code`.
pub fn fillet_end_sharpness(code: u32) -> f64 {
    f64::from(code) / 2.0
}

/// The change of the derivative `along` (into an edge that is no promoted crease, from its end
/// on one, which has the limit normal `normal`) at distance `w` from that end: the fillet of
/// [`fillet_cross_derivative`] across the crease, with the two sides' cross-crease derivatives'
/// sum taken as `2 (along . normal) normal` (its normal part, exact where the limit's tangent
/// at the crease is the chord between the sides). Only where the continuation beyond the crease
/// is unknown: where the two sides' derivatives differ in length (faces of different size) the
/// sum's tangential part dominates the fillet (bishop L4, an edge 1/8 from such a vertex: 1.1
/// rad off with this sum, 1e-4 with the real one).
pub fn fillet_bend(sharpness: f64, w: f64, along: DVec3, normal: DVec3) -> DVec3 {
    fillet_cross_derivative(sharpness, w, 2.0 * along.dot(normal) * normal)
}

/// How the fillet of a promoted crease reaches the end `v` of an edge `e` between two end caps
/// that is no promoted crease ([`fillet_end`]), with the fillet's residual sharpness there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FilletEnd {
    /// The crease through `v` is regular ([`vertex_fillet_sharpness`]): the edge's tangent
    /// bends ([`fillet_cross_derivative`]).
    Bend(f32),
    /// The crease through `v` is not regular: the edge's normal turns ([`fillet_rotation`]).
    Turn(f32),
}

/// [`FilletEnd`] at the end `v` of edge `e`, `None` where no fillet reaches it.
///
/// A turn: where a promoted crease ([`promoted_edge`]) runs through `v` but not regularly
/// ([`vertex_fillet_sharpness`] is `None`: valence other than 4, or the two edges not opposite):
/// exactly two sharp edges there, both promoted; the mean of theirs, as the crease vertex rule
/// averages its edges' sharpness (DeRose et al. 1998 §3). Its other edges are no cross-section
/// of the fillet (no edge continues them beyond the crease), so their normals turn by
/// [`fillet_rotation`] instead of a bent tangent, where `e` is at most
/// [`FILLET_ROTATION_REACH`] steps around `v` (faces) from a promoted crease: edges farther
/// round a wide sector stay outside the fillet (bishop L4, points 1/16-3/16 from the vertex: 3 or
/// more steps away the one-sided normal is within 0.01 rad RMS of the limit's, the turned one
/// 0.02-0.06 off). No turn where three or more promoted creases meet (measured worse:
/// `catmark_torus_creases1` L3, a valence-4 vertex with three: 1.67 rad against 0.40 without;
/// the bishop's of valence 16: 0.92 against 0.65), nor at the end of one (a dart for the end
/// caps: the limit is smooth already).
pub fn fillet_end(level: &Topology, caps: &Topology, v: u32, e: u32) -> Option<FilletEnd> {
    if let Some(s) = vertex_fillet_sharpness(level, caps, v) {
        return Some(FilletEnd::Bend(s));
    }
    if caps.vertex_sharpness(v) > level.vertex_sharpness(v) {
        return None;
    }
    let (promoted, sharp) = crease_edges_at(level, caps, v);
    if promoted.len() != 2 || sharp != 2 {
        return None;
    }
    let ring = level.vertex_edges(v);
    let n = ring.len();
    let at = ring.iter().position(|&x| x == e)?;
    let near = ring.iter().enumerate().any(|(j, x)| {
        let d = (at + n - j) % n;
        promoted.contains(x) && d.min(n - d) <= FILLET_ROTATION_REACH
    });
    near.then(|| FilletEnd::Turn(mean_sharpness(level, &promoted)))
}

/// At vertex `v`: its promoted edges ([`promoted_edge`]) in ring order, and how many of its
/// edges are sharp for the end caps (`caps`).
fn crease_edges_at(level: &Topology, caps: &Topology, v: u32) -> (Vec<u32>, usize) {
    let edges = level.vertex_edges(v);
    let promoted = edges
        .iter()
        .copied()
        .filter(|&e| promoted_edge(level, caps, e))
        .collect();
    let sharp = edges
        .iter()
        .filter(|&&e| caps.edge_sharpness(e) > 0.0)
        .count();
    (promoted, sharp)
}

/// The mean sharpness of two promoted edges `[a, b]`.
fn mean_sharpness(level: &Topology, edges: &[u32]) -> f32 {
    (level.edge_sharpness(edges[0]) + level.edge_sharpness(edges[1])) / 2.0
}

/// How many steps around a crease vertex (faces) the fillet's turn reaches ([`fillet_end`]).
pub const FILLET_ROTATION_REACH: usize = 2;

/// The exponent `p` of the turn's weight `(1 - w/h)^p` ([`fillet_rotation`]).
pub const FILLET_TURN_EXPONENT: i32 = 1;

/// The share of its angle the fillet's turn ([`fillet_rotation`]) keeps at distance `w` (own
/// parameter) from the crease vertex: `(1 - w/h)^p`, `p` = [`FILLET_TURN_EXPONENT`], `h = 2^-n`
/// after `n` steps, zero beyond `h`, blended between `floor(s)` and `floor(s) + 1` steps by the
/// fraction of `s` (as [`fillet_cross_derivative`]).
pub fn fillet_turn_weight(sharpness: f64, w: f64) -> f64 {
    let n = sharpness.floor();
    let f = sharpness - n;
    let step = |steps: f64| (1.0 - w * steps.exp2()).max(0.0).powi(FILLET_TURN_EXPONENT);
    (1.0 - f) * step(n) + f * step(n + 1.0)
}

/// The normal `n` at distance `w` (own parameter) along an edge from a crease vertex whose
/// crease is not regular ([`FilletEnd::Turn`] `sharpness`): turned about
/// `own x limit` by [`fillet_turn_weight`] times the angle between `own`, the end caps'
/// one-sided normal at the vertex (the edge's own, from its tangent and cross-edge derivative
/// there), and `limit`, the exact limit normal there. At the vertex it is the limit normal,
/// beyond the fillet `n`. There is no edge beyond the crease whose derivative the fillet
/// would average with this one's (`fillet_bend`'s sum), so the turn is the vertex's, fading
/// over the fillet's width `h` (Nießner, Loop, Greiner 2012 §3: the sharpness decays after
/// `s` steps, the smooth rules round the crease within the level-`(L + s)` ring).
pub fn fillet_rotation(sharpness: f64, w: f64, own: DVec3, limit: DVec3, n: DVec3) -> DVec3 {
    let (own, limit) = (own.normalize_or_zero(), limit.normalize_or_zero());
    let axis = own.cross(limit);
    let sin = axis.length();
    if sin <= 1e-12 || !sin.is_finite() {
        return n;
    }
    let axis = axis / sin;
    let angle = sin.atan2(own.dot(limit)) * fillet_turn_weight(sharpness, w);
    let (s, c) = angle.sin_cos();
    // Rodrigues' rotation of n about the unit axis.
    n * c + axis.cross(n) * s + axis * (axis.dot(n) * (1.0 - c))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The turn ends at the limit normal on the vertex and leaves `n` alone beyond the fillet;
    /// in between it is the rotation by the weighted angle (closed form: a turn in the xz plane).
    #[test]
    fn fillet_rotation_runs_from_the_limit_normal_to_the_own() {
        let own = DVec3::Z;
        let limit = DVec3::new(0.6, 0.0, 0.8);
        let at_vertex = fillet_rotation(2.0, 0.0, own, limit, own);
        assert!(at_vertex.distance(limit) < 1e-15, "{at_vertex}");
        let beyond = fillet_rotation(2.0, 0.25, own, limit, own);
        assert_eq!(beyond, own);
        // Halfway through the fillet (h = 1/4): half the angle with the linear weight.
        let half = fillet_rotation(2.0, 0.125, own, limit, own);
        let angle = 0.5 * 0.6f64.atan2(0.8);
        let expected = DVec3::new(angle.sin(), 0.0, angle.cos());
        assert!(half.distance(expected) < 1e-15, "{half} vs {expected}");
        assert_eq!(fillet_turn_weight(2.5, 0.125), 0.25);
    }
}
