//! Which faces are single-crease patches (Nießner, Loop, Greiner 2012, §3): the topological
//! test shared by feature-adaptive refinement ([`super::adaptive`], which stops refining such a
//! face when asked to) and the patch's evaluation ([`crate::patch::single_crease`]).

use super::bspline::{interior_grid_lines, interior_grid_lines_at_grid_corners};
use crate::mesh::INFINITE_SHARPNESS;
use crate::topology::Topology;

/// The face edge the crease line runs along: `U0` the line `u = 0` (grid column 1), `U1`
/// `u = 1` (column 2), `V0` `v = 0` (row 1), `V1` `v = 1` (row 2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum CreaseSide {
    /// Crease along `u = 0`: cvs 1, 5, 9, 13.
    U0,
    /// Crease along `u = 1`: cvs 2, 6, 10, 14.
    U1,
    /// Crease along `v = 0`: cvs 4, 5, 6, 7.
    V0,
    /// Crease along `v = 1`: cvs 8, 9, 10, 11.
    V1,
}

impl CreaseSide {
    /// All four sides.
    pub const ALL: [CreaseSide; 4] = [
        CreaseSide::U0,
        CreaseSide::U1,
        CreaseSide::V0,
        CreaseSide::V1,
    ];

    /// The `cvs` slot of the paper's point `P_k` of curve `r` (`r` along the crease, `k` across
    /// it, the crease at `k = 2`): `U1` `4r + k`, `U0` `4r + 3 - k`, `V1` `4k + r`, `V0`
    /// `4(3 - k) + r`.
    pub fn slot(self, r: usize, k: usize) -> usize {
        match self {
            CreaseSide::U1 => 4 * r + k,
            CreaseSide::U0 => 4 * r + 3 - k,
            CreaseSide::V1 => 4 * k + r,
            CreaseSide::V0 => 4 * (3 - k) + r,
        }
    }

    /// The curve parameter `t` (0 away from the crease, 1 on it) at patch `(u, v)`.
    pub fn t(self, u: f64, v: f64) -> f64 {
        match self {
            CreaseSide::U1 => u,
            CreaseSide::U0 => 1.0 - u,
            CreaseSide::V1 => v,
            CreaseSide::V0 => 1.0 - v,
        }
    }

    /// The three grid edges of the crease line as `cvs` slot pairs.
    pub fn line(self) -> [(usize, usize); 3] {
        std::array::from_fn(|r| (self.slot(r, 2), self.slot(r + 1, 2)))
    }

    /// The face edge the line runs along (edge `k` from corner `k` to `k + 1`; corners at
    /// `cvs` 5, 6, 10, 9).
    pub fn face_edge(self) -> usize {
        match self {
            CreaseSide::V0 => 0,
            CreaseSide::U1 => 1,
            CreaseSide::V1 => 2,
            CreaseSide::U0 => 3,
        }
    }
}

/// The net and crease line of a single-crease face: what
/// [`SingleCreasePatch`](crate::patch::single_crease::SingleCreasePatch) evaluates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CreaseLine {
    /// Control vertices in [`RegularPatch`](super::bspline::RegularPatch) order (`cvs[4*j + i]`,
    /// `i` along u; corners 5, 6, 10, 9), indices in the topology given.
    pub cvs: [u32; 16],
    /// The face edge the crease line runs along.
    pub side: CreaseSide,
    /// Sharpness along the line, `0 < s < 10`.
    pub sharpness: f32,
}

/// The crease line of `face` if it is a single-crease patch: each corner an interior valence-4
/// vertex with only quads around it and no vertex sharpness, the 16-point net complete, and of
/// the 12 edges at the corners exactly the three of one [`CreaseSide`] line semi-sharp, all
/// with the same `s`, the other nine smooth (the rule
/// [`SingleCreasePatch`](crate::patch::single_crease::SingleCreasePatch) documents; OpenSubdiv's
/// `Level::isSingleCreasePatch` for semi-sharp creases).
pub fn single_crease_line(topo: &Topology, face: u32) -> Option<CreaseLine> {
    grid_crease_line(topo, interior_grid_lines(topo, face)?)
}

/// [`single_crease_line`] of a quad with a limit surface whose corners are known to pass
/// [`is_grid_corner`](super::bspline::is_grid_corner), given its corners and edges `quad`
/// ([`Topology::quad`]): the corners are not judged again.
pub(crate) fn single_crease_line_at_grid_corners(
    topo: &Topology,
    face: u32,
    quad: (&[u32; 4], &[u32; 4]),
) -> Option<CreaseLine> {
    grid_crease_line(topo, interior_grid_lines_at_grid_corners(topo, face, quad)?)
}

/// The single-crease line of the grid `cvs` with lines `lines` ([`interior_grid_lines`]).
fn grid_crease_line(
    topo: &Topology,
    (cvs, lines): ([u32; 16], [[u32; 3]; 4]),
) -> Option<CreaseLine> {
    crease_line(cvs, |side| {
        Some(lines[side.face_edge()].map(|e| topo.edge_sharpness(e)))
    })
}

/// The single-crease line of the net `cvs` whose lines have the sharpness `line_sharpness`
/// (`None`: a line edge is missing): exactly one side with any sharpness, the same `0 < s < 10`
/// along its three edges.
fn crease_line(
    cvs: [u32; 16],
    line_sharpness: impl Fn(CreaseSide) -> Option<[f32; 3]>,
) -> Option<CreaseLine> {
    let mut found = None;
    for side in CreaseSide::ALL {
        let s = line_sharpness(side)?;
        if s.iter().all(|&x| x == 0.0) {
            continue;
        }
        if found.is_some() || s.iter().any(|&x| x != s[0]) || s[0] >= INFINITE_SHARPNESS {
            return None;
        }
        found = Some((side, s[0]));
    }
    let (side, sharpness) = found?;
    (sharpness > 0.0).then_some(CreaseLine {
        cvs,
        side,
        sharpness,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::subdiv::bspline::{interior_grid, is_grid_corner};

    /// The test as it was before the grid walk gave the lines' edges: each line's edges
    /// looked up by their ends (`find_edge` between the slots of [`CreaseSide::line`]).
    fn single_crease_line_by_find_edge(topo: &Topology, face: u32) -> Option<CreaseLine> {
        let cvs = interior_grid(topo, face)?;
        crease_line(cvs, |side| {
            let s = side
                .line()
                .map(|(a, b)| Some(topo.edge_sharpness(topo.find_edge(cvs[a], cvs[b])?)));
            Some([s[0]?, s[1]?, s[2]?])
        })
    }

    /// `single_crease_line` gives what the edge look-ups gave on every face of levels 0-3 of
    /// meshes with semi-sharp creases (single-crease faces on each side, and faces with two
    /// lines, uneven sharpness or infinitely sharp lines, which are not).
    #[test]
    fn single_crease_lines_equal_the_edge_lookups() {
        let (mut sides, mut grid_corners) = ([0; 4], 0);
        let levels = crate::subdiv::corpus_levels(
            &[
                "catmark_car",
                "catmark_single_crease",
                "catmark_cubes_semisharp",
                "catmark_cube_creases1",
                "catmark_cube_creases2",
                "catmark_torus_creases1",
            ],
            3,
        );
        for (name, depth, level) in &levels {
            let t = level.topology();
            for f in 0..t.face_count() as u32 {
                let line = single_crease_line(t, f);
                assert_eq!(
                    line,
                    single_crease_line_by_find_edge(t, f),
                    "{name} level {depth} face {f}"
                );
                // The census's path: the corners judged apart, once per vertex.
                let quad = t.quad(f).filter(|_| t.has_limit_surface(f));
                let grid_corner = |v| is_grid_corner(t, v, t.quads_only());
                if let Some(quad) = quad.filter(|q| q.0.iter().all(|&v| grid_corner(v))) {
                    assert_eq!(
                        single_crease_line_at_grid_corners(t, f, quad),
                        line,
                        "{name} level {depth} face {f}"
                    );
                    grid_corners += 1;
                }
                if let Some(line) = line {
                    sides[line.side.face_edge()] += 1;
                }
            }
        }
        assert!(sides.iter().all(|&n| n > 0), "{sides:?}");
        assert!(grid_corners > 1000, "{grid_corners}");
    }

    /// The grid lines `interior_grid_lines` reads from the walk are the edges `find_edge`
    /// finds between the lines' `cvs` (each [`CreaseSide`]'s slot pairs, as a set: the lines run
    /// along their face edge, the slots in grid order), on every face of levels 0-2 of meshes
    /// with semi-sharp and infinitely sharp creases, boundaries and extraordinary vertices.
    #[test]
    fn interior_grid_lines_are_the_edges_between_their_cvs() {
        let mut grids = 0;
        let levels = crate::subdiv::corpus_levels(
            &[
                "catmark_car",
                "catmark_single_crease",
                "catmark_cubes_semisharp",
                "catmark_cube_creases2",
                "catmark_torus_creases1",
                "catmark_hole_test1",
            ],
            2,
        );
        for (name, _, level) in &levels {
            let t = level.topology();
            for f in 0..t.face_count() as u32 {
                let Some((cvs, lines)) = interior_grid_lines(t, f) else {
                    continue;
                };
                for side in CreaseSide::ALL {
                    let mut found = side
                        .line()
                        .map(|(a, b)| t.find_edge(cvs[a], cvs[b]).unwrap());
                    let mut line = lines[side.face_edge()];
                    found.sort_unstable();
                    line.sort_unstable();
                    assert_eq!(line, found, "{name} face {f} {side:?}");
                }
                grids += 1;
            }
        }
        assert!(grids > 1000, "{grids}");
    }
}
