//! Promoted creases: edges whose residual semi-sharpness the end caps treat as infinitely sharp
//! ([`EndCapSharpness::Crease`]) while the exact limit is smooth across them (it rounds the
//! crease within about `2^-s` of the patch, Nießner, Loop, Greiner 2012 §3).
//!
//! The end caps keep the crease for their positions, plus the limit's fillet beside it where
//! it is known ([`fillet_offset_factor`], faded towards irregular crease vertices,
//! [`positional_fillet_end`]), and their normals on it are shared, one
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
use crate::subdiv::limit::{SharedVertexMasks, VertexMask};
use crate::topology::Topology;
use glam::DVec3;
use std::sync::Arc;

/// Whether vertex `v` touches a promoted crease, or is a corner only in `caps`.
pub fn promoted_vertex(level: &Topology, caps: &Topology, v: u32) -> bool {
    (caps.vertex_sharpness(v) >= INFINITE_SHARPNESS
        && level.vertex_sharpness(v) < INFINITE_SHARPNESS)
        || level
            .vertex_edges(v)
            .iter()
            .any(|&e| caps.is_promoted_edge(e))
}

/// Rows (d/du, d/dv) over global refined ids of the exact limit tangents at corner `k` of face
/// `f` of `lev`, in the face's frame (`u` towards corner `k + 1` at corner 0): the limit mask of
/// the corner's vertex ([`vertex_mask`], `LimitEvaluator`'s corner evaluation). `None` where
/// the mask fails (the caller keeps the end cap's own corner). `masks` are shared between
/// corners whose rings are alike ([`SharedVertexMasks`]; the same rows).
pub fn exact_corner_tangents_shared(
    lev: &AdaptiveLevel,
    f: u32,
    k: usize,
    masks: &SharedVertexMasks,
) -> Option<[Weights; 2]> {
    let v = lev.topology().face_vertices(f)[k];
    let mask = match corner_mask(lev, v, f, masks) {
        Ok(m) => m,
        Err(e) => {
            log::debug!("promoted corner {k} of face {f}: no exact limit mask ({e})");
            return None;
        }
    };
    let row = |w: &[f64], sign: f64| mask_row(lev, &mask.indices, w, sign);
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

/// The row over global refined ids of the exact limit position at corner `k` of face `f` of
/// `lev` (the position weights of [`vertex_mask`]); `None` where the mask fails.
pub fn exact_corner_position(
    lev: &AdaptiveLevel,
    f: u32,
    k: usize,
    masks: &SharedVertexMasks,
) -> Option<Weights> {
    let v = lev.topology().face_vertices(f)[k];
    let mask = corner_mask(lev, v, f, masks)
        .map_err(|e| log::debug!("corner {k} of face {f}: no exact limit mask ({e})"))
        .ok()?;
    Some(mask_row(lev, &mask.indices, &mask.position, 1.0))
}

/// The limit mask of vertex `v` of `lev` in face `f`, kept in `masks` under `v`'s global id
/// and `f` ([`SharedVertexMasks::corner_mask`]): the slot, sector, exact-position and lattice
/// frames of one build read the same promoted corners.
pub(super) fn corner_mask(
    lev: &AdaptiveLevel,
    v: u32,
    f: u32,
    masks: &SharedVertexMasks,
) -> crate::Result<Arc<VertexMask>> {
    masks.corner_mask((lev.global(v), f), &lev.level, v, f)
}

/// Weights `w` of a limit mask over vertices `indices` of `lev`, times `sign`, as a row over
/// global refined ids (`sign` 1 leaves them as they are, bit for bit). A mask's indices
/// increase ([`VertexMask`]) and global ids keep their order, so the terms are taken as they
/// come, zeros dropped: what [`Weights::from_terms`], which any other order goes through,
/// makes of them.
pub(super) fn mask_row(lev: &AdaptiveLevel, indices: &[u32], w: &[f64], sign: f64) -> Weights {
    let terms = indices
        .iter()
        .zip(w)
        .map(|(&i, &x)| (lev.global(i), sign * x));
    if !indices.windows(2).all(|p| p[0] < p[1]) {
        return Weights::from_terms(terms);
    }
    // Room for every term up front (a filtered `collect` would grow from nothing).
    let mut row = Vec::with_capacity(indices.len());
    row.extend(terms.filter(|&(_, x)| x != 0.0));
    Weights(row)
}

/// Whether the end caps at vertex `v` add its corner offset ([`corner_offset_share`]): a
/// promoted vertex the positional fillet does not reach whole ([`positional_fillet_end`]) whose
/// faces are all quad end caps of its level (`quad_cap`), so every patch there adds the same.
pub fn corner_offset_vertex(
    level: &Topology,
    caps: &Topology,
    v: u32,
    quad_cap: impl Fn(u32) -> bool,
) -> bool {
    promoted_vertex(level, caps, v)
        && level.vertex_faces(v).iter().all(|&g| quad_cap(g))
        && !positional_fillet_end(level, caps, v, quad_cap)
}

/// The width code ([`fillet_code`]) of the corner offset at promoted vertex `v`
/// ([`corner_offset_share`]): the mean residual sharpness of its promoted edges (as the vertex
/// rule averages them), else its own vertex sharpness.
pub fn corner_offset_code(level: &Topology, caps: &Topology, v: u32) -> u32 {
    let creases = CreaseEdges::at(level, caps, v);
    fillet_code(if creases.promoted().is_empty() {
        level.vertex_sharpness(v)
    } else {
        mean_sharpness(level, creases.promoted())
    })
}

/// The share of a corner offset (exact limit position minus the end caps' corner) kept at own
/// distances `x`, `w` from the corner along its two edges: `(1 - x/h)^2 (1 - w/h)^2`, `h = 2^-s`
/// for the sharpness `s` of [`corner_offset_code`], blended by its fraction as
/// [`fillet_cross_derivative`] (the complement of [`fillet_end_fade`] on a crease).
pub fn corner_offset_share(sharpness: f64, x: f64, w: f64) -> f64 {
    fillet_fade(sharpness, x, 2) * fillet_fade(sharpness, w, 2)
}

/// Corner `k` of face `face` of `lev` on a promoted crease: its end-cap position row `p` (the
/// end caps' crease position) with the exact limit's tangents
/// ([`exact_corner_tangents_shared`]); empty tangent rows where the exact mask fails. `masks`
/// shares the limit masks between calls ([`exact_corner_tangents_shared`]).
pub fn exact_frame(
    lev: &AdaptiveLevel,
    face: u32,
    k: usize,
    p: Weights,
    masks: &SharedVertexMasks,
) -> [Weights; 3] {
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
    d_sum
        * blend_steps(sharpness, |steps| {
            let r = (1.0 - w * steps.exp2()).max(0.0);
            -0.5 * r * r
        })
}

/// `step(n)` after `n = floor(s)` crease steps, blended with `step(n + 1)` by the fraction of
/// `s` (a fractional sharpness blends the limits of its two integer steps as its rule blends
/// the points): the fillets' one treatment of fractional sharpness.
fn blend_steps(sharpness: f64, step: impl Fn(f64) -> f64) -> f64 {
    let n = sharpness.floor();
    let f = sharpness - n;
    (1.0 - f) * step(n) + f * step(n + 1.0)
}

/// The band offset's factor on a promoted edge of residual sharpness `sharpness`: the fillet
/// of [`fillet_cross_derivative`] moves the edge point by `h d_sum / 6` (`B0(0) = 1/6` of the
/// segment of width `h = 2^-n`; a fractional `n + f` blends `h` and `h / 2` by `f`), so the
/// limit's tangent along the edge is the crease's plus this factor times the derivative of
/// `d_sum` along the edge, while its cross-edge direction stays `d_own - d_across` (the fillet's
/// cross derivative there is `(d_own - d_across) / 2`).
pub fn band_offset_factor(sharpness: f64) -> f64 {
    fillet_offset_factor(sharpness, 0.0)
}

/// The fillet's offset `h (1 - w/h)^3 / 6` at distance `w` (own parameter) from a promoted edge
/// of residual sharpness `sharpness` (`h = 2^-n` after `n` steps, zero beyond `h`; a fractional
/// `n + f` blends `n` and `n + 1` steps by `f`), as a factor of `d_sum`, the sum of both sides'
/// cross-edge derivatives at the edge point ([`fillet_cross_derivative`] is minus its
/// derivative by `w`). Exact where the crease and its neighbourhood are regular: the crease
/// surface's segment beside the edge has the phantom row `2c - a` where the smooth limit has the
/// far side's `b`, and `a + b - 2c` is `h d_sum` row by row, so the smooth limit is the crease
/// surface plus this factor times `d_sum(x)` (B-spline basis `B0(w/h) = (1 - w/h)^3 / 6`), and
/// its derivative along the edge gains this factor times `d_sum`'s: [`band_offset_factor`] on the
/// edge, fading to zero across the band.
pub fn fillet_offset_factor(sharpness: f64, w: f64) -> f64 {
    blend_steps(sharpness, |steps| {
        let r = (1.0 - w * steps.exp2()).max(0.0);
        (-steps).exp2() * (r * r * r)
    }) / 6.0
}

/// Whether the positional fillet ([`fillet_offset_factor`]) of the promoted crease through vertex `v`
/// reaches `v` whole: its crease is regular ([`vertex_fillet_sharpness`]: valence 4, the two
/// promoted edges opposite, no other sharp edge), of one residual sharpness as the GPU reads it
/// ([`fillet_fine_code`]: each end cap's crossing edge takes its own crease's), `v` carries no vertex sharpness, and every face at `v` is a quad end cap
/// (`quad_cap`). There the limit is locally the crease curve swept by the fillet's
/// cross-section, so the offset holds at `v` and on the edges crossing the crease (the sum of
/// the edge's derivative and its continuation's beyond the crease). Elsewhere the offset fades
/// to zero at `v` ([`fillet_end_fade`]), keeping the end caps' position there, which every patch
/// at `v` shares.
pub fn positional_fillet_end(
    level: &Topology,
    caps: &Topology,
    v: u32,
    quad_cap: impl Fn(u32) -> bool,
) -> bool {
    let creases = CreaseEdges::at(level, caps, v);
    creases.regular_sharpness(level, v).is_some()
        && fillet_fine_code(level.edge_sharpness(creases.promoted()[0]))
            == fillet_fine_code(level.edge_sharpness(creases.promoted()[1]))
        && level.vertex_sharpness(v) == 0.0
        && caps.vertex_sharpness(v) == 0.0
        && level.vertex_faces(v).iter().all(|&f| quad_cap(f))
}

/// Whether distance `w` (own parameter) from a promoted edge of residual sharpness `sharpness`
/// lies within its fillet, `w < h` with `h = 2^-floor(s)` (the wider of the two integer steps a
/// fractional sharpness blends, [`fillet_cross_derivative`]): beyond it the fillet changes
/// neither position nor derivative.
pub fn within_fillet(sharpness: f64, w: f64) -> bool {
    w < sharpness.floor().exp2().recip()
}

/// The share of the positional fillet ([`fillet_offset_factor`]) kept at distance `x` (own parameter)
/// along a promoted edge of residual sharpness `sharpness` from an end that is no
/// [`positional_fillet_end`]: `1 - (1 - x/h)^2` within `h` (blended by the fraction of the
/// sharpness as [`fillet_cross_derivative`]), 1 beyond, so the offset is zero at that end and
/// on the edges from it. A choice, not derived: within `h` of such a vertex the limit is the
/// vertex's smooth neighbourhood, not the band's ([`crease_turn_share`]).
pub fn fillet_end_fade(sharpness: f64, x: f64) -> f64 {
    1.0 - fillet_fade(sharpness, x, 2)
}

/// A residual sharpness `s` in 16ths, as the corner offsets' widths read it
/// (`PatchRecord::corner_fade`, [`corner_offset_code`]): `16 s` rounded, in 16..=255 (`s` from 1 to 15.9; the fillet of a sharper edge is narrower
/// than 2^-15 of the end cap).
pub fn fillet_code(sharpness: f32) -> u32 {
    (sharpness * 16.0).round().clamp(16.0, 255.0) as u32
}

/// The sharpness of [`fillet_code`] `code`.
pub fn fillet_sharpness(code: u32) -> f64 {
    f64::from(code) / 16.0
}

/// The scale of [`fillet_fine_code`]: 2^20 per unit of sharpness, the resolution of an `f32`
/// sharpness in 8..16 (finer ones round to within 2^-21).
const FILLET_FINE_SCALE: f32 = 1_048_576.0;

/// The residual sharpness `s` of a promoted crease as its fillet reads it
/// (`PatchRecord::fillet_fine`): `2^20 s` rounded, in 2^20..2^24 (`s` from 1 to just under 16,
/// as [`fillet_code`]'s range), 24 bits per edge so that a fractional `s` such as 1.7 is read
/// to within 5e-7 rather than [`fillet_code`]'s 1/32
/// (`catmark_torus_creases0`'s 1.7 read as 1.6875 bent its regular bands by 1.7e-3 rad RMS).
pub fn fillet_fine_code(sharpness: f32) -> u32 {
    (sharpness * FILLET_FINE_SCALE)
        .round()
        .clamp(FILLET_FINE_SCALE, 16_777_215.0) as u32
}

/// The sharpness of [`fillet_fine_code`] `code` (exact: the code has 24 bits).
pub fn fillet_fine_sharpness(code: u32) -> f64 {
    f64::from(code) / f64::from(FILLET_FINE_SCALE)
}

/// The three record words holding [`fillet_fine_code`]s `codes` (per face edge `k`, 0: none):
/// bits `16 (k mod 2)..+16` of word `k / 2` hold a code's upper 16 bits, bits `8k..8k + 8` of
/// word 2 its lower 8 (`glsl/adaptive/patch_adaptive_endcap.tese`'s `fillet_fine_sharpness`).
pub fn fillet_fine_words(codes: [u32; 4]) -> [u32; 3] {
    let mut w = [0u32; 3];
    for (k, &c) in codes.iter().enumerate() {
        w[k / 2] |= (c >> 8) << (16 * (k % 2));
        w[2] |= (c & 0xff) << (8 * k);
    }
    w
}

/// Edge `k`'s code in [`fillet_fine_words`] `words`.
pub fn fillet_fine_code_of(words: [u32; 3], k: usize) -> u32 {
    (((words[k / 2] >> (16 * (k % 2))) & 0xffff) << 8) | ((words[2] >> (8 * k)) & 0xff)
}

/// The residual sharpness of the fillet at vertex `v` of `level` (its topology as `caps` sees it
/// for the end caps) where the crease through it is regular (valence 4, two opposite promoted
/// edges ([`Topology::is_promoted_edge`]) and no other sharp one, so its other edges cross the crease): the
/// mean of the two, as the crease vertex rule averages its edges' sharpness (DeRose et al. 1998
/// §3);
/// `None` elsewhere (at an extraordinary crease vertex the other edges are no cross-section of
/// the fillet: measured worse with the bend, bishop L5 max 2.08 rad against 1.82 without).
pub fn vertex_fillet_sharpness(level: &Topology, caps: &Topology, v: u32) -> Option<f32> {
    CreaseEdges::at(level, caps, v).regular_sharpness(level, v)
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
    /// Three or more promoted creases meet at `v`: the edge's normal turns towards the limit
    /// normal there by [`fillet_many_share`] ([`turn_towards`]).
    TurnMany(f32),
}

impl FilletEnd {
    /// The fillet's residual sharpness at that end.
    pub fn sharpness(self) -> f32 {
        match self {
            FilletEnd::Bend(s) | FilletEnd::Turn(s) | FilletEnd::TurnMany(s) => s,
        }
    }
}

/// [`FilletEnd`] at the end `v` of edge `e`, `None` where no fillet reaches it.
///
/// A turn: where a promoted crease ([`Topology::is_promoted_edge`]) runs through `v` but not regularly
/// ([`vertex_fillet_sharpness`] is `None`: valence other than 4, or the two edges not opposite):
/// exactly two sharp edges there, both promoted; the mean of theirs, as the crease vertex rule
/// averages its edges' sharpness (DeRose et al. 1998 §3). Its other edges are no cross-section
/// of the fillet (no edge continues them beyond the crease), so their normals turn by
/// [`fillet_rotation`] instead of a bent tangent, where `e` is at most
/// [`FILLET_ROTATION_REACH`] steps around `v` (faces) from a promoted crease: edges farther
/// round a wide sector stay outside the fillet (bishop L4, points 1/16-3/16 from the vertex: 3 or
/// more steps away the one-sided normal is within 0.01 rad RMS of the limit's, the turned one
/// 0.02-0.06 off). No turn at the end of a crease (a dart for the end caps: the limit is smooth
/// already).
///
/// Where three or more promoted creases meet (and no other sharp edge), [`FilletEnd::TurnMany`]
/// with the mean sharpness of all of them, on edges as far round as the turn's: the end caps'
/// normal there is a corner sector's, the limit's the vertex's single normal (the creases
/// decay, so the vertex rule ends smooth). [`fillet_rotation`]'s turn from the one-sided normal
/// measured worse there (`catmark_torus_creases1` L3, a valence-4 vertex with three: 1.67 rad
/// against 0.40 without; the bishop's of valence 16: 0.92 against 0.65), hence the turn from
/// the normal at the point ([`turn_towards`]).
pub fn fillet_end(level: &Topology, caps: &Topology, v: u32, e: u32) -> Option<FilletEnd> {
    let creases = CreaseEdges::at(level, caps, v);
    if let Some(s) = creases.regular_sharpness(level, v) {
        return Some(FilletEnd::Bend(s));
    }
    let promoted = creases.irregular(level, caps, v)?;
    let ring = level.vertex_edges(v);
    let n = ring.len();
    let at = ring.iter().position(|&x| x == e)?;
    let near = ring.iter().enumerate().any(|(j, x)| {
        let d = (at + n - j) % n;
        promoted.contains(x) && d.min(n - d) <= FILLET_ROTATION_REACH
    });
    let s = mean_sharpness(level, promoted);
    near.then_some(if promoted.len() == 2 {
        FilletEnd::Turn(s)
    } else {
        FilletEnd::TurnMany(s)
    })
}

/// [`fillet_end`] of the edge ends around the end caps of a refinement, with whether any
/// fillet reaches a vertex (its promoted edges, `CreaseEdges`) found once per vertex: each
/// vertex is asked from every edge and end cap around it, and most are reached by none.
#[derive(Debug, Default)]
pub struct FilletEnds {
    /// Per level, per vertex: whether a fillet may reach it (1) or not (0), `UNASKED`
    /// before; a level's table is made when first asked.
    reached: Vec<Vec<u8>>,
}

/// [`FilletEnds`]' mark of a vertex not asked yet.
const UNASKED: u8 = 2;

impl FilletEnds {
    /// [`fillet_end`] at the end `v` of edge `e` of level `l` (`level`, seen by the end caps
    /// as `caps`).
    pub fn at(
        &mut self,
        l: u32,
        level: &Topology,
        caps: &Topology,
        v: u32,
        e: u32,
    ) -> Option<FilletEnd> {
        let l = l as usize;
        if self.reached.len() <= l {
            self.reached.resize(l + 1, Vec::new());
        }
        let known = &mut self.reached[l];
        if known.is_empty() {
            known.resize(level.vertex_count(), UNASKED);
        }
        let reached = &mut known[v as usize];
        if *reached == UNASKED {
            let creases = CreaseEdges::at(level, caps, v);
            *reached = u8::from(
                creases.regular_sharpness(level, v).is_some()
                    || creases.irregular(level, caps, v).is_some(),
            );
        }
        if *reached == 0 {
            return None;
        }
        fillet_end(level, caps, v, e)
    }
}

/// Whether promoted creases meet irregularly at `v`: two or more promoted edges, every sharp
/// edge there one of them, `v` no corner for the end caps alone and not the regular crease of
/// [`vertex_fillet_sharpness`]; where only two meet, of valence 4 or more. The promoted edges
/// from such a vertex turn their shared normal towards its limit normal
/// ([`crease_turn_share`]). Not at valence 3 with two creases (a sector of one face): there the
/// exact normal's share of the angle falls faster (`catmark_pyramid_creases0` L2 and
/// `cube_creases1` L4, 0.5-0.6 at `w = h/4`, 0-0.15 at `h/2`) and the turn measured worse
/// (pyramid_creases0 L2 2.06e-2 -> 2.40e-2 rad RMS, pyramid_creases1 L1 0.125 -> 0.131).
pub fn irregular_crease_vertex(level: &Topology, caps: &Topology, v: u32) -> bool {
    let creases = CreaseEdges::at(level, caps, v);
    creases.regular_sharpness(level, v).is_none()
        && creases
            .irregular(level, caps, v)
            .is_some_and(|p| p.len() >= 3 || level.valence(v) >= 4)
}

/// The creases at a vertex `v`, what [`vertex_fillet_sharpness`], [`fillet_end`] and
/// [`irregular_crease_vertex`] classify it by: its promoted edges ([`Topology::is_promoted_edge`]) in ring
/// order, and how many of its edges are sharp for the end caps (`caps`), counted only where two
/// or more are promoted (both classes need two; most vertices have none).
struct CreaseEdges {
    /// The first promoted edges ([`Self::promoted`]; asked per end-cap corner, so not
    /// allocated for the few a vertex has).
    first: [u32; CREASE_EDGES_INLINE],
    /// All promoted edges where there are more than `first` holds, else empty.
    more: Vec<u32>,
    count: usize,
    sharp: usize,
}

/// Promoted edges [`CreaseEdges`] holds without allocating.
const CREASE_EDGES_INLINE: usize = 8;

impl CreaseEdges {
    fn at(level: &Topology, caps: &Topology, v: u32) -> Self {
        let edges = level.vertex_edges(v);
        let mut out = CreaseEdges {
            first: [0; CREASE_EDGES_INLINE],
            more: Vec::new(),
            count: 0,
            sharp: 0,
        };
        for &e in edges.iter().filter(|&&e| caps.is_promoted_edge(e)) {
            if out.count < CREASE_EDGES_INLINE {
                out.first[out.count] = e;
            } else {
                if out.more.is_empty() {
                    out.more.extend_from_slice(&out.first);
                }
                out.more.push(e);
            }
            out.count += 1;
        }
        if out.count >= 2 {
            out.sharp = edges
                .iter()
                .filter(|&&e| caps.edge_sharpness(e) > 0.0)
                .count();
        }
        out
    }

    /// The promoted edges at the vertex, in ring order.
    fn promoted(&self) -> &[u32] {
        if self.count <= CREASE_EDGES_INLINE {
            &self.first[..self.count]
        } else {
            &self.more
        }
    }

    /// [`vertex_fillet_sharpness`]: valence 4, the two promoted edges opposite (no face between
    /// them: every other edge lies between two faces beside the crease, whose continuations
    /// beyond it are the same edge) and no other sharp edge.
    fn regular_sharpness(&self, level: &Topology, v: u32) -> Option<f32> {
        let p = self.promoted();
        // The faces' test last: most vertices have fewer than two promoted edges.
        let opposite =
            || !(level.edge_faces(p[0]).iter()).any(|f| level.edge_faces(p[1]).contains(f));
        (p.len() == 2 && self.sharp == 2 && level.vertex_edges(v).len() == 4 && opposite())
            .then(|| mean_sharpness(level, p))
    }

    /// The promoted edges where two or more meet, every sharp edge at `v` is one and `v` is no
    /// corner for the end caps alone; `None` elsewhere.
    fn irregular(&self, level: &Topology, caps: &Topology, v: u32) -> Option<&[u32]> {
        let p = self.promoted();
        (caps.vertex_sharpness(v) <= level.vertex_sharpness(v)
            && p.len() >= 2
            && self.sharp == p.len())
        .then_some(p)
    }
}

/// The mean sharpness of promoted edges `edges` (as the vertex rule averages them).
fn mean_sharpness(level: &Topology, edges: &[u32]) -> f32 {
    edges.iter().map(|&e| level.edge_sharpness(e)).sum::<f32>() / edges.len() as f32
}

/// How many steps around a crease vertex (faces) the fillet's turn reaches ([`fillet_end`]).
pub const FILLET_ROTATION_REACH: usize = 2;

/// The share of its angle the fillet's turn ([`fillet_rotation`]) keeps at distance `w` (own
/// parameter) from the crease vertex: linear, `1 - w/h` with `h = 2^-n` after `n` steps, zero
/// beyond `h`, blended between `floor(s)` and `floor(s) + 1` steps by the fraction of `s` (as
/// [`fillet_cross_derivative`]); `fillet_fade(sharp, w, false)` in `glsl/gregory/gregory.glsl`.
pub fn fillet_turn_weight(sharpness: f64, w: f64) -> f64 {
    fillet_fade(sharpness, w, 1)
}

/// `(1 - w/h)^p` with `h = 2^-n` after `n` steps, zero beyond `h`, blended between `floor(s)`
/// and `floor(s) + 1` steps by the fraction of `s` (as [`fillet_cross_derivative`]).
fn fillet_fade(sharpness: f64, w: f64, p: i32) -> f64 {
    blend_steps(sharpness, |steps| (1.0 - w * steps.exp2()).max(0.0).powi(p))
}

/// The share of the angle to the vertex's limit normal that [`turn_towards`] keeps at the
/// vertex for the turns of [`fillet_many_share`] and [`crease_turn_share`]: fitted, not derived
/// (bishop L4-L5 and `catmark_torus_creases1` L2-L3; the exact normal's share of the angle
/// from the end caps' one-sided normal to the vertex's, bishop L5, is 0.5-0.7 at `w = h/8` on
/// both kinds of edge, falling to 0.05-0.15 at `3h/4`; as the crease turn's gain 0.5 / 0.75 / 1
/// measured bishop L5 6.50e-3 / 6.51e-3 / 6.68e-3 rad RMS, L4 5.35e-3 / 5.33e-3 / 5.43e-3,
/// torus_creases1 L3 1.34e-2 / 1.29e-2 / 1.29e-2).
pub const FILLET_TURN_GAIN: f64 = 0.75;

/// The share of the angle to the limit normal an edge from a vertex where three or more
/// promoted creases meet ([`FilletEnd::TurnMany`]) turns by at distance `w` from it
/// ([`turn_towards`]): [`FILLET_TURN_GAIN`] `(1 - w/h)^2` (fitted: the exact normal's share on
/// the bishop's valence-7, -16 and -20 vertices at L5, edges beside a crease, 0.52-0.68 /
/// 0.39-0.48 / 0.15-0.19 / 0.05 at `w/h` = 1/8, 1/4, 1/2, 3/4; with a reach of one face, the
/// linear weight measured 7.30e-3 rad RMS on the bishop L5 against 7.14e-3, the cube 7.21e-3).
pub fn fillet_many_share(sharpness: f64, w: f64) -> f64 {
    FILLET_TURN_GAIN * fillet_fade(sharpness, w, 2)
}

/// The share of the angle to the vertex's limit normal by which the shared normal of a promoted
/// crease turns at distance `w` from an [`irregular_crease_vertex`] ([`turn_towards`]):
/// [`FILLET_TURN_GAIN`] `(1 - w/h)`, `h` the edge's fillet width. Within `h` of such a vertex
/// the limit is the vertex's smooth neighbourhood, not the band's (Nießner, Loop, Greiner 2012
/// §3: after `s` steps the smooth rules apply; the band offset, [`band_offset_factor`], models
/// only the band), and its normal tends to the vertex's single limit normal, while the end caps'
/// shared normal stays the crease's chord normal.
pub fn crease_turn_share(sharpness: f64, w: f64) -> f64 {
    FILLET_TURN_GAIN * fillet_fade(sharpness, w, 1)
}

/// `n` turned towards `limit` by `share` of the angle between them, about `n x limit` (the
/// turns of [`FilletEnd::TurnMany`] and [`crease_turn_share`], from the normal drawn at the
/// point rather than from the vertex's one-sided normal as [`fillet_rotation`]: at a vertex
/// with three creases, `catmark_torus_creases1` L3, the one-sided normal of the single edge
/// between two of them lies 2 rad from the limit's and [`fillet_rotation`]'s turn measured
/// 2.28e-2 rad RMS against 1.65e-2 without, this one 1.56e-2).
pub fn turn_towards(n: DVec3, limit: DVec3, share: f64) -> DVec3 {
    let limit = limit.normalize_or_zero();
    let axis = n.cross(limit);
    let sin = axis.length();
    if sin <= 1e-12 || !sin.is_finite() || share == 0.0 {
        return n;
    }
    rotate(n, axis / sin, sin.atan2(n.dot(limit)) * share)
}

/// Rodrigues' rotation of `n` about the unit `axis` by `angle`.
fn rotate(n: DVec3, axis: DVec3, angle: f64) -> DVec3 {
    let (s, c) = angle.sin_cos();
    n * c + axis.cross(n) * s + axis * (axis.dot(n) * (1.0 - c))
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
    rotate(
        n,
        axis,
        sin.atan2(own.dot(limit)) * fillet_turn_weight(sharpness, w),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every f32 residual sharpness that is a multiple of 2^-20 in 1..16 reads back exactly
    /// through the packed record words, each edge's code apart from the others'; 4.7 - 3 (an
    /// f32 with 2^-21 steps) to within 2^-21, where `fillet_code` reads 1.6875.
    #[test]
    fn fillet_fine_codes_read_back_exact() {
        let s: [f32; 4] = [1.0, 4.7 - 3.0, 15.999_999, 9.0 + 3.0 / 1_048_576.0];
        let codes = s.map(fillet_fine_code);
        let words = fillet_fine_words(codes);
        for k in 0..4 {
            assert_eq!(fillet_fine_code_of(words, k), codes[k], "edge {k}");
            let back = fillet_fine_sharpness(codes[k]);
            assert!(
                (back - f64::from(s[k])).abs() <= 0.5 / 1_048_576.0,
                "edge {k}: {back}"
            );
        }
        assert_eq!(fillet_fine_sharpness(codes[0]), 1.0);
        assert_eq!(fillet_fine_sharpness(codes[3]), f64::from(s[3]));
        assert_eq!(fillet_sharpness(fillet_code(s[1])), 1.6875);
        // Out of range: clamped as fillet_code.
        assert_eq!(fillet_fine_sharpness(fillet_fine_code(0.5)), 1.0);
        assert!(fillet_fine_sharpness(fillet_fine_code(40.0)) < 16.0);
        // Alone in its bits: edge 2's code does not reach edge 3's.
        let only = fillet_fine_words([0, 0, codes[2], 0]);
        assert_eq!(fillet_fine_code_of(only, 3), 0);
        assert_eq!(fillet_fine_code_of(only, 1), 0);
    }

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

    /// The positional fillet's derivative by `w` is the normal fillet's cross-derivative factor
    /// (central differences), its value on the edge the band offset's factor, and it ends with
    /// the fillet (`h = 2^-floor(s)`); the end fade runs from 0 to 1 over `h`.
    #[test]
    fn fillet_offset_integrates_the_cross_derivative() {
        for s in [1.0, 1.5, 2.0, 2.25, 3.75] {
            for w in [0.01, 0.05, 0.1, 0.2, 0.3, 0.45] {
                let e = 1e-6;
                let slope =
                    (fillet_offset_factor(s, w + e) - fillet_offset_factor(s, w - e)) / (2.0 * e);
                let expected = fillet_cross_derivative(s, w, DVec3::X).x;
                assert!(
                    (slope - expected).abs() < 1e-8,
                    "s {s} w {w}: {slope} vs {expected}"
                );
            }
            assert!((fillet_offset_factor(s, 0.0) - band_offset_factor(s)).abs() < 1e-16);
            let h = s.floor().exp2().recip();
            assert_eq!(fillet_offset_factor(s, h), 0.0);
            // The fillet ends at `h`: nothing beyond, something just inside.
            assert!(!within_fillet(s, h) && within_fillet(s, 0.999 * h));
            assert!(fillet_offset_factor(s, 0.999 * h) > 0.0);
            assert_eq!(fillet_end_fade(s, 0.0), 0.0);
            assert_eq!(fillet_end_fade(s, h), 1.0);
        }
        // s = 1: h = 1/2, a quarter of the way: (3/4)^3 / 12, fade 1 - (3/4)^2.
        assert_eq!(fillet_offset_factor(1.0, 0.125), 0.75f64.powi(3) / 12.0);
        assert_eq!(fillet_end_fade(1.0, 0.125), 1.0 - 0.5625);
    }

    /// The turn towards an irregular crease vertex's normal: the given share of the angle from
    /// the point's normal (closed form in the xz plane), none beyond the fillet; the shares
    /// `0.75 (1 - w/h)` and `0.75 (1 - w/h)^2`.
    #[test]
    fn turn_towards_keeps_its_share_of_the_angle() {
        let n = DVec3::Z;
        let limit = DVec3::new(0.6, 0.0, 0.8) * 2.0;
        let angle = 0.3 * 0.6f64.atan2(0.8);
        let turned = turn_towards(n, limit, 0.3);
        assert!(
            turned.distance(DVec3::new(angle.sin(), 0.0, angle.cos())) < 1e-15,
            "{turned}"
        );
        assert_eq!(turn_towards(n, limit, 0.0), n);
        // h = 1/2 at s = 1: w = 1/8 is a quarter of the way.
        assert_eq!(crease_turn_share(1.0, 0.125), 0.75 * 0.75);
        assert_eq!(fillet_many_share(1.0, 0.125), 0.75 * 0.75 * 0.75);
        assert_eq!(crease_turn_share(1.0, 0.5), 0.0);
        // s = 1.5 blends h = 1/2 and 1/4 halfway.
        assert_eq!(
            crease_turn_share(1.5, 0.125),
            0.75 * (0.5 * 0.75 + 0.5 * 0.5)
        );
    }
}
