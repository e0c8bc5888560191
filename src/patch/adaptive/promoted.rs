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
use crate::subdiv::limit::vertex_mask;
use crate::topology::Topology;

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
    let v = lev.topology().face_vertices(f)[k];
    let mask = match vertex_mask(&lev.level, v, f) {
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
/// end caps' crease position); empty tangent rows where the exact mask fails.
pub fn exact_frame(lev: &AdaptiveLevel, face: u32, k: usize, rows: [Weights; 3]) -> [Weights; 3] {
    let [p, ..] = rows;
    match exact_corner_tangents(lev, face, k) {
        Some([du, dv]) => [p, du, dv],
        None => [p, Weights::default(), Weights::default()],
    }
}
