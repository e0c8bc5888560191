//! Exact limit normal frames on a lattice near the irregular crease vertices, which the end
//! caps' normals interpolate there (the README's *Where the rise comes from*).
//!
//! Within the fillet width `h = 2^-floor(s)` (own parameter) of an end-cap corner at a promoted
//! vertex whose crease is not regular ([`vertex_fillet_sharpness`] is `None`) the limit is the
//! vertex's smoothed neighbourhood, a region of fixed size on the surface, while the end caps draw
//! the crease surface; the normal error there does not fall with the isolation level `L`. Here
//! every lattice point `(a, b) 2^-J` of such a region (`J` = [`LATTICE_STEPS`], the region's own
//! coordinates `(x, w)`: along the corner's edge `c` and away from it, as
//! `AdaptiveSurface`'s `edge_coordinates(c, ..)`) is a vertex of level `L + J` of a local
//! refinement, and its exact limit tangents ([`SharedVertexMasks::vertex_mask`] there) are rows
//! over the level-`L` points, pulled back through the `J` refinement matrices: the GPU computes
//! their normals every frame from the refined points (`glsl/adaptive/limit_frames.comp`), so they
//! follow an animation. A lattice point's frame is shared by every end cap holding it (one per
//! level-`(L + J)` vertex: the corner, the points on the edges from it, each face's own), so both
//! sides of a shared edge read the same frames. Nodes with `a` or `b` equal to the region's
//! width in cells are its border: they take the end cap's own drawn normal at the point
//! ([`lattice_normal`]), so there is no seam where the region ends.

mod frame_rows;
mod neighbourhood;
mod sector_grids;

use glam::DVec3;

use super::census_index::{is_quad_end_cap, EndCapTopologies};
use super::promoted::{
    corner_mask, corner_offset_code, fillet_sharpness, mask_row, promoted_vertex,
    vertex_fillet_sharpness,
};
use super::slots::NONE;
use crate::patch::gregory::word_hash::WordHashMap;
use crate::patch::gregory::Weights;
use crate::subdiv::adaptive::{AdaptiveLevel, AdaptiveRefinement, PatchCensus, PatchType};
use crate::subdiv::limit::SharedVertexMasks;
use neighbourhood::{Neighbourhood, PullBack};
use sector_grids::{GridShapes, SectorGrids};

pub use frame_rows::FrameRows;

/// Refinement steps `J` of the lattice: its spacing is `2^-J` of the end cap (README: `J = 4`
/// measured better in h83's prototype, at 4x the frames; not built).
pub const LATTICE_STEPS: u32 = 3;

/// One region of an end cap: the lattice at its corner `corner`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LatticeRegion {
    /// The end cap's census patch.
    pub patch: u32,
    /// The face corner at the irregular crease vertex.
    pub corner: u32,
    /// The lattice spacing is `2^-steps` of the end cap.
    pub steps: u32,
    /// Cells per side (at most 15): the region is `x, w < cells 2^-steps`.
    pub cells: u32,
    /// Per node `(a, b)`, `a, b < cells`, at `a + cells b`: its frame ([`NONE`] where the exact
    /// mask failed: the node takes the drawn normal).
    pub frames: Vec<u32>,
}

/// The lattice frames of a census and the regions of its end caps.
#[derive(Debug, Clone, Default)]
pub struct LatticeFrames {
    /// Per frame: its exact limit tangent rows (d1, d2) over global refined ids,
    /// `cross(d1, d2)` outward.
    pub rows: FrameRows,
    /// The end caps' regions in census order (of the few end caps with any: a table per
    /// census patch would cost more to make and drop than the regions).
    pub regions: Vec<LatticeRegion>,
}

/// Which lattice point on a region's edges a frame is: the region's vertex or a point on an
/// edge from it (the edge, cells from the vertex).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum Node {
    Vertex(u32),
    Edge(u32, u32, u32),
}

/// Whether the end caps at vertex `v` of `lev` interpolate lattice frames: a promoted vertex
/// whose crease is not regular and whose faces are all quad end caps of its level (`quad_cap`).
pub fn lattice_vertex(
    level: &crate::topology::Topology,
    caps: &crate::topology::Topology,
    v: u32,
    quad_cap: impl Fn(u32) -> bool,
) -> bool {
    promoted_vertex(level, caps, v)
        && vertex_fillet_sharpness(level, caps, v).is_none()
        && level.vertex_faces(v).iter().all(|&g| quad_cap(g))
}

/// Cells of the lattice beyond the fillet width `h` (measured: with none, the nodes at `h`
/// taking the drawn normal, the exact normal changes too fast between the last exact node and
/// the border, `catmark_cube_creases1` L3 max 0.17 rad against the end caps' 0.095).
pub const LATTICE_MARGIN: u32 = 1;

/// `floor(s)` for the sharpness `s` of [`corner_offset_code`] at vertex `v` (the mean residual
/// sharpness of its promoted edges, else its vertex sharpness): the fillet width there is
/// `h = 2^-floor(s)` of the end cap.
pub fn fillet_steps(
    level: &crate::topology::Topology,
    caps: &crate::topology::Topology,
    v: u32,
) -> u32 {
    fillet_sharpness(corner_offset_code(level, caps, v)).floor() as u32
}

/// `(steps, cells)` of the region at vertex `v`: spacing `2^-J` (`steps` = [`LATTICE_STEPS`]),
/// `h = 2^-`[`fillet_steps`] rounded up to a cell, plus [`LATTICE_MARGIN`] cells (at most the
/// end cap; at most half of it where two of its corners have regions, see
/// [`LatticeFrames::new`]). A region narrower than a cell is not refined deeper (measured: at
/// `h = 2^-4`, car isolation 2, four local steps cost 5.4x the build's instructions).
pub fn lattice_size(
    level: &crate::topology::Topology,
    caps: &crate::topology::Topology,
    v: u32,
) -> (u32, u32) {
    let floor = fillet_steps(level, caps, v);
    let steps = LATTICE_STEPS;
    let within = if floor >= steps {
        1
    } else {
        1 << (steps - floor)
    };
    (steps, (within + LATTICE_MARGIN).min(1 << steps))
}

/// The end caps [`LatticeFrames::new`] reads.
#[derive(Clone, Copy)]
struct EndCaps<'a> {
    /// The adaptive refinement whose end caps hold the regions.
    refinement: &'a AdaptiveRefinement,
    /// Its patches.
    census: &'a PatchCensus,
    /// Per level, its topology as its end caps see it.
    topologies: &'a EndCapTopologies<'a>,
    /// Per level, per face: its census patch (`super::census_index::patch_index`).
    at: &'a [Vec<u32>],
}

impl LatticeFrames {
    /// The lattice frames of the quad end caps' corners at [`lattice_vertex`]es, numbered from
    /// `first` in census order; `at` as `super::census_index::patch_index`; `masks` the build's exact
    /// limit masks.
    pub fn new(
        refinement: &AdaptiveRefinement,
        census: &PatchCensus,
        topologies: &EndCapTopologies,
        at: &[Vec<u32>],
        first: u32,
        masks: &SharedVertexMasks,
    ) -> LatticeFrames {
        let caps = EndCaps {
            refinement,
            census,
            topologies,
            at,
        };
        caps.frames(first, masks, Local::new)
    }

    /// The regions' side table of the end caps (`glsl/adaptive/endcap.glsl`'s `lattice`): word
    /// `e` per end cap (`end_caps` their census patches, draw order) the index of its block in
    /// the same table, [`NONE`] for none; a block is a head word (bits `8c..8c + 8` per corner
    /// `c`: bits 0-3 its region's steps, bits 4-7 its cells, 0 for none), then per
    /// corner the index of its node frames (`cells^2`, [`LatticeRegion::frames`]'s order; 0
    /// where none).
    pub fn table_words(&self, end_caps: impl ExactSizeIterator<Item = usize>) -> Vec<u32> {
        let mut words = vec![NONE; end_caps.len()];
        let mut from = 0;
        for (e, i) in end_caps.enumerate() {
            let regions = self.regions_of(i as u32, &mut from);
            if regions.is_empty() {
                continue;
            }
            words[e] = words.len() as u32;
            let block = words.len();
            words.extend([0u32; 5]);
            for r in regions {
                let c = r.corner as usize;
                words[block] |= (r.steps | (r.cells << 4)) << (8 * c);
                words[block + 1 + c] = words.len() as u32;
                words.extend(&r.frames);
            }
        }
        words
    }

    /// The regions of census patch `patch`, looked for from `regions[*from]` on (a patch
    /// before that one's starts over); `*from` is left after them, where the next patch in
    /// census order starts.
    fn regions_of(&self, patch: u32, from: &mut usize) -> &[LatticeRegion] {
        let r = &self.regions;
        let mut a = (*from).min(r.len());
        if a > 0 && r[a - 1].patch >= patch {
            a = r.partition_point(|x| x.patch < patch);
        }
        while a < r.len() && r[a].patch < patch {
            a += 1;
        }
        let mut b = a;
        while b < r.len() && r[b].patch == patch {
            b += 1;
        }
        *from = b;
        &r[a..b]
    }
}

/// A region found by [`EndCaps::regions`], before its frames are made.
struct RegionAt {
    /// The end cap's census patch.
    patch: u32,
    /// The face corner at the region vertex `v`.
    corner: usize,
    v: u32,
    /// [`lattice_size`] at `v`: its steps and widest region (the neighbourhood's).
    steps: u32,
    widest: u32,
    /// The region's own cells.
    cells: u32,
}

/// Room for the lattice frames' terms up front: per node (a frame at most), this many terms
/// (two rows; the car at isolation 2 averages 24 over its 698 frames), so a build's frame rows
/// are seldom moved as they grow.
const FRAME_TERMS: usize = 32;

impl EndCaps<'_> {
    /// The regions of the quad end caps' corners at [`lattice_vertex`]es, in census order.
    fn regions(self) -> Vec<RegionAt> {
        let (refinement, census) = (self.refinement, self.census);
        let mut out = Vec::new();
        // Per level, per vertex: whether it is a `lattice_vertex` (1) or not (0), a property of
        // the vertex asked by each of its quad end caps (`UNASKED` before; a level's table is
        // made when first asked).
        const UNASKED: u8 = 2;
        let mut lattice: Vec<Vec<u8>> = vec![Vec::new(); refinement.levels.len()];
        for (i, p) in census.patches.iter().enumerate() {
            let lev = &refinement.levels[p.level as usize];
            let t = lev.topology();
            if p.kind != PatchType::EndCap || t.face_size(p.face) != 4 {
                continue;
            }
            let caps = self.topologies.get(p.level);
            let quad_cap = |g: u32| is_quad_end_cap(lev, census, &self.at[p.level as usize], g);
            let fv = t.face_vertices(p.face);
            let known = &mut lattice[p.level as usize];
            if known.is_empty() {
                known.resize(t.vertex_count(), UNASKED);
            }
            let mut corners = [0usize; 4];
            let mut count = 0;
            for (c, &v) in fv.iter().enumerate().take(4) {
                let at = &mut known[v as usize];
                if *at == UNASKED {
                    *at = u8::from(lattice_vertex(t, caps, v, quad_cap));
                }
                if *at == 1 {
                    corners[count] = c;
                    count += 1;
                }
            }
            for &c in &corners[..count] {
                let v = fv[c];
                // The vertex's neighbourhood serves its widest region.
                let (steps, widest) = lattice_size(t, caps, v);
                let mut cells = widest;
                if count > 1 {
                    // Two regions in one end cap (isolation 0 only: at a finer level only the
                    // vertex point corner of a quad can be such a vertex) stay apart.
                    cells = cells.min(1 << (steps - 1));
                }
                out.push(RegionAt {
                    patch: i as u32,
                    corner: c,
                    v,
                    steps,
                    widest,
                    cells,
                });
            }
        }
        out
    }

    /// [`LatticeFrames::new`] with each region vertex's neighbourhood made by `make(lev, v,
    /// steps, cells, shapes)`.
    fn frames(
        self,
        first: u32,
        masks: &SharedVertexMasks,
        make: fn(&AdaptiveLevel, u32, u32, u32, &mut GridShapes) -> Option<Local>,
    ) -> LatticeFrames {
        let mut out = LatticeFrames::default();
        if !self.refinement.lattice_normals {
            return out;
        }
        let regions = self.regions();
        let nodes: usize = regions.iter().map(|r| (r.cells * r.cells) as usize).sum();
        out.rows.reserve(nodes, FRAME_TERMS * nodes);
        out.regions.reserve_exact(regions.len());
        // The frames of the nodes on a region's edges, which the end caps there share (a node
        // inside a face is in one region only).
        let mut ids: WordHashMap<(u32, Node), u32> = WordHashMap::default();
        // Per (level, vertex): its refined neighbourhood, built once.
        let mut local: WordHashMap<(u32, u32), Option<Local>> = WordHashMap::default();
        let mut sums = Sums::default();
        for r in regions {
            let p = &self.census.patches[r.patch as usize];
            let lev = &self.refinement.levels[p.level as usize];
            let fe = lev.topology().face_edges(p.face);
            let (v, c, cells) = (r.v, r.corner, r.cells);
            let mut frames = Vec::with_capacity((cells * cells) as usize);
            for b in 0..cells {
                for a in 0..cells {
                    let node = match (a, b) {
                        (0, 0) => Some(Node::Vertex(v)),
                        (a, 0) => Some(Node::Edge(v, fe[c], a)),
                        (0, b) => Some(Node::Edge(v, fe[(c + 3) % 4], b)),
                        _ => None,
                    };
                    let key = node.map(|n| (p.level, n));
                    if let Some(&f) = key.and_then(|k| ids.get(&k)) {
                        frames.push(f);
                        continue;
                    }
                    let made = if (a, b) == (0, 0) {
                        corner_rows(lev, v, p.face, masks)
                            .map(|[d1, d2]| out.rows.push([&d1.0, &d2.0]))
                            .is_some()
                    } else {
                        let hood = local
                            .entry((p.level, v))
                            .or_insert_with(|| make(lev, v, r.steps, r.widest, &mut sums.grids));
                        let rows = &mut out.rows;
                        hood.as_mut().is_some_and(|h| {
                            h.node_rows(lev, (p.face, c), (a, b), masks, &mut sums, rows)
                        })
                    };
                    let f = if made {
                        first + out.rows.len() as u32 - 1
                    } else {
                        NONE
                    };
                    if let Some(k) = key {
                        ids.insert(k, f);
                    }
                    frames.push(f);
                }
            }
            out.regions.push(LatticeRegion {
                patch: r.patch,
                corner: c as u32,
                steps: r.steps,
                cells,
                frames,
            });
        }
        out
    }
}

/// The local refinement around one region vertex.
enum Local {
    /// Its sector grids (most region vertices).
    Grids(SectorGrids),
    /// Its kept refinement as levels (the regions wider than the sector grids hold).
    Kept(Neighbourhood),
}

/// The sector grids' shapes and the pull-backs' accumulators, reused from node to node.
#[derive(Default)]
struct Sums {
    grids: GridShapes,
    kept: PullBack,
}

impl Local {
    /// The local refinement of vertex `v` of `lev` for regions of at most `cells` cells of
    /// `2^-steps`: its sector grids (their shape in `shapes`) where they hold the nodes, else
    /// its kept levels.
    fn new(
        lev: &AdaptiveLevel,
        v: u32,
        steps: u32,
        cells: u32,
        shapes: &mut GridShapes,
    ) -> Option<Local> {
        match SectorGrids::new(lev, v, steps, cells, shapes) {
            Some(g) => Some(Local::Grids(g)),
            None => Neighbourhood::new(lev, v, steps, cells).map(Local::Kept),
        }
    }

    /// The exact limit tangent rows (global ids of `lev`) at node `(a, b)` of the region at
    /// corner `c` of `face`, appended to `out` as a frame; false (none appended) where the
    /// exact mask fails.
    fn node_rows(
        &mut self,
        lev: &AdaptiveLevel,
        (face, c): (u32, usize),
        node: (u32, u32),
        masks: &SharedVertexMasks,
        sums: &mut Sums,
        out: &mut FrameRows,
    ) -> bool {
        match self {
            Local::Grids(g) => sums.grids.node_rows(g, lev, face, node, masks, out),
            Local::Kept(k) => (k.node_rows(lev, face, c, node, masks, &mut sums.kept))
                .map(|[d1, d2]| out.push([&d1.0, &d2.0]))
                .is_some(),
        }
    }
}

/// Exact limit tangent rows at vertex `v` of `lev` in face `face`'s sector (global ids).
fn corner_rows(
    lev: &AdaptiveLevel,
    v: u32,
    face: u32,
    masks: &SharedVertexMasks,
) -> Option<[Weights; 2]> {
    let m = corner_mask(lev, v, face, masks)
        .map_err(|e| log::debug!("lattice vertex {v}: no exact limit mask ({e})"))
        .ok()?;
    let row = |w: &[f64]| mask_row(lev, &m.indices, w, 1.0);
    Some([row(&m.tangent_u), row(&m.tangent_v)])
}

/// The normal at own `(x, w)` of a region (its corner's edge coordinates) of `cells` cells of
/// width `2^-steps`, `None` outside it: bilinear in the lattice cell over the node normals
/// `node(a, b)` (`None`: a border node or a failed mask, which takes `drawn`, the end cap's own
/// normal at the point); on the region's edges (`w = 0` or `x = 0`) linear along the edge from
/// the vertex, nearer node first, so both end caps there add the same terms in the same order.
/// Unnormalized.
pub fn lattice_normal(
    steps: u32,
    cells: u32,
    x: f64,
    w: f64,
    drawn: DVec3,
    node: impl Fn(u32, u32) -> Option<DVec3>,
) -> Option<DVec3> {
    let scale = f64::from(steps).exp2();
    let (fx, fw) = (x * scale, w * scale);
    let n = f64::from(cells);
    if fx >= n || fw >= n {
        return None;
    }
    let value = |a: u32, b: u32| {
        if a < cells && b < cells {
            node(a, b).unwrap_or(drawn)
        } else {
            drawn
        }
    };
    let along = |d: f64, at: &dyn Fn(u32) -> DVec3| {
        let a0 = d.floor();
        let ta = d - a0;
        let a0 = a0 as u32;
        at(a0) * (1.0 - ta) + at(a0 + 1) * ta
    };
    if fw == 0.0 {
        return Some(along(fx, &|a| value(a, 0)));
    }
    if fx == 0.0 {
        return Some(along(fw, &|b| value(0, b)));
    }
    let (a0, b0) = (fx.floor(), fw.floor());
    let (ta, tb) = (fx - a0, fw - b0);
    let (a0, b0) = (a0 as u32, b0 as u32);
    Some(
        value(a0, b0) * ((1.0 - ta) * (1.0 - tb))
            + value(a0 + 1, b0) * (ta * (1.0 - tb))
            + value(a0, b0 + 1) * ((1.0 - ta) * tb)
            + value(a0 + 1, b0 + 1) * (ta * tb),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::ControlMesh;
    use crate::subdiv::Level;

    /// At a node the node's normal, on the border the drawn one, between them the bilinear
    /// blend (closed form); on the region's edges linear along them; outside the region `None`.
    #[test]
    fn lattice_normal_interpolates_nodes_and_border() {
        let node = |a: u32, b: u32| Some(DVec3::new(f64::from(a), f64::from(b), 1.0));
        let drawn = DVec3::new(0.0, 0.0, -1.0);
        // Two cells of 1/8: the region is x, w < 1/4, nodes 0 and 1 exact, 2 the border.
        let at = |x: f64, w: f64| lattice_normal(3, 2, x, w, drawn, node);
        assert_eq!(at(0.125, 0.125), Some(DVec3::new(1.0, 1.0, 1.0)));
        assert_eq!(at(0.25, 0.1), None);
        assert_eq!(at(0.1, 0.25), None);
        // Halfway between node (1, 1) and the border node (2, 1) at w = 1/8.
        let mid = at(0.1875, 0.125).unwrap();
        assert_eq!(mid, 0.5 * DVec3::new(1.0, 1.0, 1.0) + 0.5 * drawn);
        // A quarter into cell (0, 0): weights 9/16, 3/16, 3/16, 1/16.
        let q = at(1.0 / 32.0, 1.0 / 32.0).unwrap();
        let expected = DVec3::new(0.0, 0.0, 1.0) * (9.0 / 16.0)
            + DVec3::new(1.0, 0.0, 1.0) * (3.0 / 16.0)
            + DVec3::new(0.0, 1.0, 1.0) * (3.0 / 16.0)
            + DVec3::new(1.0, 1.0, 1.0) * (1.0 / 16.0);
        assert!(q.distance(expected) < 1e-15, "{q}");
        // On the edge w = 0, three quarters of the way to the border.
        let e = at(0.25 - 1.0 / 32.0, 0.0).unwrap();
        assert_eq!(e, DVec3::new(1.0, 0.0, 1.0) * 0.25 + drawn * 0.75);
    }

    /// Mesh `name` of the corpus, its adaptive refinement at `isolation` and the end caps
    /// [`LatticeFrames::new`] reads, handed to `f`.
    fn with_end_caps(name: &str, isolation: u32, f: impl FnOnce(&ControlMesh, EndCaps)) {
        use crate::patch::adaptive::census_index::patch_index;
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/meshes/osd/");
        let path = format!("{dir}{name}.obj");
        let mesh = ControlMesh::from_obj_file(&path, &Default::default()).unwrap();
        let level = Level::from_mesh(&mesh).unwrap();
        let refinement = AdaptiveRefinement::new(&level, isolation).unwrap();
        let census = PatchCensus::new(&refinement);
        let topologies = EndCapTopologies::new(&refinement, &census);
        let at = patch_index(&refinement, &census);
        let caps = EndCaps {
            refinement: &refinement,
            census: &census,
            topologies: &topologies,
            at: &at,
        };
        f(&mesh, caps);
    }

    /// Meshes and isolation levels with lattice regions (promoted creases).
    const FRAME_MESHES: [(&str, u32); 5] = [
        ("catmark_car", 2),
        ("catmark_cube_creases1", 3),
        ("catmark_cubes_semisharp", 3),
        ("catmark_single_crease", 4),
        ("catmark_bishop", 2),
    ];

    /// The frames of `caps` on the kept levels (`Neighbourhood`) at every region vertex.
    fn kept_frames(caps: EndCaps, masks: &SharedVertexMasks) -> LatticeFrames {
        caps.frames(0, masks, |lev, v, steps, cells, _| {
            Neighbourhood::new(lev, v, steps, cells).map(Local::Kept)
        })
    }

    /// The kept refinements give every lattice frame's rows bit for bit as refining the
    /// extraction as whole levels does (`Neighbourhood::whole`).
    #[test]
    fn kept_neighbourhoods_are_whole_refinements() {
        for &(name, isolation) in &FRAME_MESHES {
            with_end_caps(name, isolation, |_, caps| {
                let masks = SharedVertexMasks::default();
                let build = |hood| caps.frames(0, &masks, hood);
                let kept = kept_frames(caps, &masks);
                let whole = build(|lev, v, steps, cells, _| {
                    Neighbourhood::whole(lev, v, steps, cells).map(Local::Kept)
                });
                assert_eq!(kept.regions, whole.regions, "{name}");
                assert_eq!(kept.rows.len(), whole.rows.len(), "{name}");
                let bits = |w: &[(u32, f64)]| -> Vec<(u32, u64)> {
                    w.iter().map(|&(i, x)| (i, x.to_bits())).collect()
                };
                for (f, (a, b)) in kept.rows.iter().zip(whole.rows.iter()).enumerate() {
                    for d in 0..2 {
                        assert_eq!(bits(a[d]), bits(b[d]), "{name} frame {f} row {d}");
                    }
                }
                assert!(!kept.rows.is_empty(), "{name}: no lattice frames");
            });
        }
    }

    /// The sector grids give every lattice frame the kept refinement's normal: for any points
    /// (a hash of the id), `cross(d1, d2)` of the two frames' rows point the same way within
    /// rounding (the tangents may be taken along another face's edges). Fails on a wrong step
    /// rule, sharpness, orientation or node.
    #[test]
    fn sector_grids_give_the_kept_refinements_normals() {
        let mut grids = 0;
        for &(name, isolation) in FRAME_MESHES.iter().chain(&[("catmark_car", 4)]) {
            with_end_caps(name, isolation, |_, caps| {
                let masks = SharedVertexMasks::default();
                let fast = caps.frames(0, &masks, Local::new);
                let kept = kept_frames(caps, &masks);
                assert_eq!(fast.regions, kept.regions, "{name}");
                assert_eq!(fast.rows.len(), kept.rows.len(), "{name}");
                let point = |i: u32| {
                    let h = |k: u32| {
                        let x = (i
                            .wrapping_mul(2654435761)
                            .wrapping_add(k.wrapping_mul(40503)))
                            >> 8;
                        f64::from(x % 1000) / 1000.0 - 0.5
                    };
                    DVec3::new(h(1), h(2), h(3))
                };
                let apply = |w: &[(u32, f64)]| w.iter().map(|&(i, x)| point(i) * x).sum::<DVec3>();
                let normal = |r: [&[(u32, f64)]; 2]| apply(r[0]).cross(apply(r[1])).normalize();
                for (f, (a, b)) in fast.rows.iter().zip(kept.rows.iter()).enumerate() {
                    let (na, nb) = (normal(a), normal(b));
                    assert!(na.dot(nb) > 1.0 - 1e-12, "{name} frame {f}: {na} {nb}");
                }
                // The frames the sector grids alone give (the others: corners, wide regions).
                let only = caps.frames(0, &masks, |lev, v, steps, cells, shapes| {
                    SectorGrids::new(lev, v, steps, cells, shapes).map(Local::Grids)
                });
                let corners: usize = (fast.regions.iter())
                    .filter(|r| r.frames[0] != NONE)
                    .count();
                assert_eq!(
                    only.rows.len(),
                    fast.rows.len(),
                    "{name}: {corners} corners"
                );
                grids += only.rows.len();
            });
        }
        assert!(grids > 100, "{grids} frames");
    }

    /// Every lattice frame is the exact limit normal at its node: `cross(d1, d2)` of its rows
    /// over the refined points, against `LimitEvaluator` at the node's (u, v) (the node
    /// `(a, b) 2^-steps` from the region's corner along its two edges). Fails on a wrong step
    /// rule, sharpness, orientation or node of the sector grids (or the kept levels).
    #[test]
    fn lattice_frames_are_the_limit_normals() {
        use crate::subdiv::eval::LimitEvaluator;
        for (name, isolation) in [
            ("catmark_car", 2),
            ("catmark_cube_creases1", 3),
            ("catmark_bishop", 2),
        ] {
            with_end_caps(name, isolation, |mesh, caps| {
                let (refinement, census) = (caps.refinement, caps.census);
                let masks = SharedVertexMasks::default();
                let frames = caps.frames(0, &masks, Local::new);
                let points = refinement.refine_positions(mesh.positions());
                let ev = LimitEvaluator::new(mesh).unwrap();
                let apply = |w: &[(u32, f64)]| {
                    w.iter()
                        .map(|&(i, x)| points[i as usize] * x)
                        .sum::<DVec3>()
                };
                let (mut checked, mut worst) = (0, 0.0f64);
                for r in &frames.regions {
                    let p = &census.patches[r.patch as usize];
                    let d = refinement.levels[p.level as usize].domains[p.face as usize];
                    let n = 1u32 << r.steps;
                    for (k, &f) in r.frames.iter().enumerate() {
                        if f == NONE {
                            continue;
                        }
                        let (a, b) = (k as u32 % r.cells, k as u32 / r.cells);
                        let (s, t) = match r.corner {
                            0 => (a, b),
                            1 => (n - b, a),
                            2 => (n - a, n - b),
                            _ => (b, n - a),
                        };
                        let (s, t) = (f64::from(s) / f64::from(n), f64::from(t) / f64::from(n));
                        let uv = d.origin + s * d.u + t * d.v;
                        let sub = d.sub_face.unwrap_or(0) as usize;
                        let x = ev
                            .eval_points(d.base_face as usize, sub, &[(uv.x, uv.y)])
                            .unwrap();
                        let [d1, d2] = frames.rows.get(f as usize).unwrap();
                        let normal = apply(d1).cross(apply(d2)).normalize();
                        let angle = normal.angle_between(x[0].normal);
                        worst = worst.max(angle);
                        assert!(
                            angle < 1e-7,
                            "{name} frame {f} node ({a}, {b}): {angle:e} rad"
                        );
                        checked += 1;
                    }
                }

                assert!(checked > 50, "{name}: {checked} nodes, max {worst:e} rad");
            });
        }
    }

    /// The side table: one word per end cap, a block per end cap with regions holding the head
    /// (steps, cells per corner) and each region's frames.
    #[test]
    fn table_words_address_each_region() {
        let region = |patch, corner, cells: u32, first: u32| LatticeRegion {
            patch,
            corner,
            steps: 3,
            cells,
            frames: (first..first + cells * cells).collect(),
        };
        let frames = LatticeFrames {
            rows: FrameRows::default(),
            regions: vec![region(1, 2, 2, 10), region(3, 0, 1, 7), region(3, 3, 4, 20)],
        };
        // End caps are census patches 1 and 3.
        let w = frames.table_words([1usize, 3].into_iter());
        assert_eq!(&w[..2], &[2, 2 + 5 + 4]);
        assert_eq!(w[2], (3 | (2 << 4)) << 16);
        assert_eq!(w[3 + 2], 7);
        assert_eq!(&w[7..11], &[10, 11, 12, 13]);
        let b = w[1] as usize;
        assert_eq!(w[b], (3 | (1 << 4)) | ((3 | (4 << 4)) << 24));
        assert_eq!(w[w[b + 1] as usize], 7);
        let fourth = w[b + 4] as usize;
        assert_eq!(&w[fourth..fourth + 16], &(20..36).collect::<Vec<u32>>()[..]);
        assert_eq!(w.len(), fourth + 16);
        // End caps in another order, and one (patch 2) without regions: the same blocks.
        let v = frames.table_words([3usize, 2, 1].into_iter());
        assert_eq!(v[1], NONE);
        assert_eq!(v[v[0] as usize], w[b]);
        assert_eq!(v[v[2] as usize], w[2]);
        assert_eq!(v[v[v[2] as usize + 3] as usize], 10);
    }
}
