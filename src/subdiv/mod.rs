//! Catmull-Clark subdivision: rules, refinement, limit masks, regular B-spline patches, exact
//! evaluation, stencil tables.
//!
//! [`Level`] is the unit of refinement; [`Level::refine`] performs one uniform step and returns
//! the child level with its [`SparseMatrix`]; [`StencilTable`] composes those matrices.

pub mod adaptive;
pub mod bspline;
mod corners;
pub mod eval;
mod kept;
mod level;
pub mod limit;
pub(crate) mod points;
mod refine;
mod ring_step;
pub mod rules;
pub mod single_crease;
pub mod sparse;
mod stencil;
pub mod tables;
pub(crate) mod word_hash;

pub use level::Level;
pub use sparse::SparseMatrix;
pub use stencil::StencilTable;

/// Levels `0..=depth` (uniform refinement) of each corpus mesh `names`
/// (`../shared/meshes/osd/NAME.obj`), as `(name, level index, level)`: unit tests' inputs.
#[cfg(test)]
pub(crate) fn corpus_levels(names: &[&str], depth: u32) -> Vec<(String, u32, Level)> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/meshes/osd/");
    let mut out = Vec::new();
    for name in names {
        let path = format!("{dir}{name}.obj");
        let mesh = crate::ControlMesh::from_obj_file(&path, &Default::default()).unwrap();
        let mut level = Level::from_mesh(&mesh).unwrap();
        for d in 0..=depth {
            let next = (d < depth).then(|| level.refine_topology());
            out.push((name.to_string(), d, level));
            match next {
                Some(n) => level = n,
                None => break,
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::topology::{sector_count, sector_counts};

    /// `topology::sector_counts` (here, where refined levels are at hand: `topology` must not
    /// use `subdiv`): the counts of one pass over the edges are the per-vertex ring counts, on every vertex of
    /// levels 0-2 of meshes with boundaries, corners, infinitely sharp creases, darts and holes
    /// (fails if a boundary vertex's first sharp edge is not discounted, or an edge is counted
    /// at one end only).
    #[test]
    fn sector_counts_are_per_vertex_counts() {
        let levels = corpus_levels(
            &[
                "catmark_car",
                "catmark_cubes_infsharp",
                "catmark_dart_edgecorner",
                "catmark_edgecorner",
                "catmark_hole_test1",
                "catmark_inf_crease1",
            ],
            2,
        );
        let mut split = 0;
        for (name, _, level) in &levels {
            let t = level.topology();
            let counts = sector_counts(t);
            for v in 0..t.vertex_count() as u32 {
                assert_eq!(
                    counts[v as usize] as usize,
                    sector_count(t, v),
                    "{name} vertex {v}"
                );
                split += usize::from(counts[v as usize] >= 2);
            }
        }
        assert!(split > 100, "{split} vertices of two or more sectors");
    }

    /// `bspline`'s grid read from the corners' rings is the grid walked across edges on the
    /// sparse levels of adaptive refinements too (rings built by the adaptive step; here, where
    /// `adaptive` may be used: `bspline` must not).
    #[test]
    fn adaptive_levels_grids_from_rings_are_grids_across_edges() {
        let mut same = 0;
        for name in ["catmark_car", "catmark_pole64", "catmark_hole_test1"] {
            let base = &corpus_levels(&[name], 0)[0].2;
            let refinement = adaptive::AdaptiveRefinement::new(base, 3).unwrap();
            for (l, level) in refinement.levels.iter().enumerate() {
                let (s, _) = bspline::grids_from_rings_checked(level.level.topology());
                assert!(s.is_ok(), "{name} level {l}: face {s:?}");
                same += s.unwrap_or(0);
            }
        }
        assert!(same > 10_000, "{same} grids");
    }
}
