//! The local refinement around one region vertex as sector grids ([`SectorGrids`]), without a
//! topology per step: the lattice nodes' limit tangent rows.

use super::frame_rows::FrameRows;
use super::NONE;
use crate::mesh::{CreaseMethod, SchemeOptions};
use crate::subdiv::adaptive::AdaptiveLevel;
use crate::subdiv::limit::SharedVertexMasks;
use crate::subdiv::points::{edge_point_weights, vertex_point_mask};
use crate::subdiv::rules::{child_sharpness, decrement, VertexMask};
use crate::subdiv::rules::{REGULAR_EDGE_WEIGHTS, REGULAR_VERTEX_WEIGHTS};
use crate::subdiv::sparse::merge_row_from;
use crate::subdiv::word_hash::WordHashMap;
use crate::subdiv::Level;

/// The points of one level near a region vertex `v` whose faces are all quads: per face `i`
/// of `v` (a sector, between `v`'s edges `i` and `i + 1`, the spokes) the grid points
/// `(x, y) 2^-l` of the face's own coordinates from `v` (`x` along spoke `i`, `y` along spoke
/// `i + 1`) with `x, y <= radius`. A point on spoke `j` (`y = 0` in sector `j`, `x = 0` in
/// sector `j - 1`) is numbered once: `v` is 0, then per spoke its points `1..=radius`, then per
/// sector its inner points, row by row.
#[derive(Debug, Clone, Copy)]
struct Grid {
    spokes: u32,
    sectors: u32,
    radius: u32,
}

impl Grid {
    /// Number of points.
    fn len(self) -> usize {
        (1 + self.spokes * self.radius + self.sectors * self.radius * self.radius) as usize
    }

    /// Point `x >= 1` of spoke `j`.
    fn spoke(self, j: u32, x: u32) -> u32 {
        1 + j * self.radius + x - 1
    }

    /// Point `(x, y)` of sector `i`.
    fn point(self, i: u32, x: u32, y: u32) -> u32 {
        match (x, y) {
            (0, 0) => 0,
            (_, 0) => self.spoke(i, x),
            (0, _) => self.spoke((i + 1) % self.spokes, y),
            _ => {
                let inner = 1 + self.spokes * self.radius + i * self.radius * self.radius;
                inner + (y - 1) * self.radius + x - 1
            }
        }
    }

    /// The corners of the cell `[x, x + 1] x [y, y + 1]` of sector `i`.
    fn cell(self, i: u32, x: u32, y: u32) -> [u32; 4] {
        [
            self.point(i, x, y),
            self.point(i, x + 1, y),
            self.point(i, x + 1, y + 1),
            self.point(i, x, y + 1),
        ]
    }

    /// The sectors beside spoke `j`: `j` (its `x` axis) and `j - 1` (its `y` axis), where
    /// they exist.
    fn beside(self, j: u32) -> (Option<u32>, Option<u32>) {
        let after = (j < self.sectors).then_some(j);
        let before = if self.sectors == self.spokes {
            Some((j + self.spokes - 1) % self.spokes)
        } else {
            j.checked_sub(1)
        };
        (after, before)
    }
}

/// One level's sharpness on the grid: the spokes' segments (`(x - 1, x)` of spoke `j` at
/// `j radius + x - 1`) and `v`'s vertex sharpness; every other edge and vertex is smooth.
#[derive(Debug, Clone)]
struct GridSharpness {
    segments: Vec<f32>,
    vertex: f32,
    method: CreaseMethod,
}

impl GridSharpness {
    /// Segment `x` of spoke `j` of `grid`.
    fn segment(&self, grid: Grid, j: u32, x: u32) -> f32 {
        self.segments[(j * grid.radius + x - 1) as usize]
    }
}

/// Rows of one level's points, `(column, weight)` (a column may repeat), per point in grid
/// order.
#[derive(Debug, Default, Clone)]
struct Rows {
    offsets: Vec<u32>,
    terms: Vec<(u32, f64)>,
}

impl Rows {
    /// Row `i`.
    fn row(&self, i: u32) -> &[(u32, f64)] {
        let (a, b) = (self.offsets[i as usize], self.offsets[i as usize + 1]);
        &self.terms[a as usize..b as usize]
    }

    /// Ends the row being pushed.
    fn close_row(&mut self) {
        self.offsets.push(self.terms.len() as u32);
    }
}

/// The refinement of a region vertex `v`'s faces, `steps` levels down from its level `L`
/// (whose point ids the first level's rows read), kept to the sector grids the lattice nodes
/// read: the nodes `(a, b)` with `a, b < cells` read their one-rings on the last level, so
/// radius `cells` there, and a point at `x` reads its parent element's one-ring, at most
/// `x / 2 + 1` (the bounds of [`super::neighbourhood::Neighbourhood`]). Inside `v`'s faces only
/// the spokes are sharp and every other point is a regular quad-grid point, so each step's
/// rows are the Catmull-Clark rules on the grid (`subdiv::points`' weights and
/// `subdiv::rules`' sharpness); the first step's are `Level::refine_matrix_row` of `v`'s
/// level. The first step is `v`'s own; what follows it depends only on the first level's
/// [`GridShape`], shared by every region vertex of that shape ([`GridShapes`]).
pub(super) struct SectorGrids {
    /// `v`'s faces, in ring order.
    faces: Vec<u32>,
    /// Whether face `i`'s corner after `v` is on spoke `i + 1` (the ring runs against the
    /// faces' orientation).
    flipped: bool,
    /// The first level's points' rows over local columns `columns`.
    first: Rows,
    /// The first level's columns: level `L`'s vertex ids, increasing.
    columns: Vec<u32>,
    /// Its shape in [`GridShapes`].
    shape: u32,
}

impl SectorGrids {
    /// The sector grids of vertex `v` of `lev` for regions of at most `cells` cells of
    /// `2^-steps` (their shape found or made in `shapes`); `None` where the grids do not hold
    /// the nodes (a wider region, whose reads leave `v`'s faces; `v`'s faces not all quads or
    /// not one fan).
    pub(super) fn new(
        lev: &AdaptiveLevel,
        v: u32,
        steps: u32,
        cells: u32,
        shapes: &mut GridShapes,
    ) -> Option<Self> {
        let t = lev.topology();
        let (ne, nf) = (
            t.vertex_edges(v).len() as u32,
            t.vertex_faces(v).len() as u32,
        );
        if nf == 0 || steps == 0 || !(nf == ne || nf + 1 == ne) {
            return None;
        }
        let radii = radii(steps, cells);
        // Level 1 reads level L's elements up to the far corners; level l >= 2 stays off the
        // far edges of v's faces (x = 2^l), whose sharpness and outer faces it does not hold.
        if radii[0] > 2 || (1..steps as usize).any(|l| radii[l] >= 1 << (l + 1)) {
            return None;
        }
        let mut edges = t.vertex_edges(v).to_vec();
        let mut faces = t.vertex_faces(v).to_vec();
        let mut ends: Vec<u32> = edges.iter().map(|&e| t.other_vertex(e, v)).collect();
        let method = t.options.crease_method;
        let mut sharp = GridSharpness {
            segments: Vec::with_capacity(2 * ne as usize),
            vertex: decrement(t.vertex_sharpness(v)),
            method,
        };
        for (&e, &end) in edges.iter().zip(&ends) {
            let others = |at: u32| {
                let s = t.vertex_edges(at).iter().filter(move |&&o| o != e);
                s.map(|&o| t.edge_sharpness(o))
            };
            let s = t.edge_sharpness(e);
            sharp.segments.push(child_sharpness(s, others(v), method));
            sharp.segments.push(child_sharpness(s, others(end), method));
        }
        // A closed ring starts from the spoke whose rotation of the segments is least, so the
        // rotations of one pattern of sharp spokes share a shape (a boundary fan's ring starts
        // at its boundary spoke).
        if nf == ne {
            let start = least_rotation(&sharp.segments);
            edges.rotate_left(start);
            faces.rotate_left(start);
            ends.rotate_left(start);
            sharp.segments.rotate_left(2 * start);
        }
        // Per sector: (its far corner, the face's edges from spoke i's end and spoke i + 1's
        // end to it); the orientation of the ring against the faces'.
        let mut far = Vec::with_capacity(nf as usize);
        let mut flipped = false;
        for (i, &f) in faces.iter().enumerate() {
            let (fv, fe) = (t.face_vertices(f), t.face_edges(f));
            // Quads of four distinct corners (their face points' rows below).
            if fv.len() != 4 || (1..4).any(|k| fv[k..].contains(&fv[k - 1])) {
                return None;
            }
            let k = fv.iter().position(|&u| u == v)?;
            let (next, opposite, prev) = (fv[(k + 1) % 4], fv[(k + 2) % 4], fv[(k + 3) % 4]);
            let (a, b) = (ends[i], ends[(i + 1) % ne as usize]);
            let flip = if (next, prev) == (a, b) {
                false
            } else if (next, prev) == (b, a) {
                true
            } else {
                return None;
            };
            if i > 0 && flip != flipped {
                return None;
            }
            flipped = flip;
            let (after, before) = (fe[(k + 1) % 4], fe[(k + 2) % 4]);
            let (from_a, from_b) = if flip {
                (before, after)
            } else {
                (after, before)
            };
            far.push((opposite, from_a, from_b));
        }
        let level = &lev.level;
        // Level 1: v's faces refined once, rows over level L (room for the rows of a smooth
        // neighbourhood: 9 terms for a regular vertex point, 4 for a face point, 6 for an edge
        // point, `2 n + 1` for v's).
        let points = (1 + 2 * ne + 4 * nf) as usize;
        let mut first = Rows {
            offsets: Vec::with_capacity(points + 1),
            terms: Vec::with_capacity(2 * ne as usize + 1 + 9 * (points - 1)),
        };
        let mut buf = Vec::with_capacity(32);
        let mut push = |r: u32, rows: &mut Rows| {
            level.refine_matrix_row(r as usize, &mut buf);
            rows.terms.extend_from_slice(&buf);
            rows.close_row();
        };
        first.offsets.push(0);
        push(level.child_vertex_point(v), &mut first);
        for (&e, &u) in edges.iter().zip(&ends) {
            push(level.child_edge_point(e), &mut first);
            push(level.child_vertex_point(u), &mut first);
        }
        for (&f, &(c, from_a, from_b)) in faces.iter().zip(&far) {
            // Row by row: (1, 1), (2, 1), (1, 2), (2, 2). The face point is the quad's
            // centroid: `refine_matrix_row`'s terms in the face's order rather than sorted, the
            // same bits (the pull-backs add a row's distinct columns to distinct sums).
            let quad = t.face_vertices(f);
            first.terms.extend(quad.iter().map(|&u| (u, 0.25)));
            first.close_row();
            push(level.child_edge_point(from_a), &mut first);
            push(level.child_edge_point(from_b), &mut first);
            push(level.child_vertex_point(c), &mut first);
        }
        let local = &mut shapes.columns;
        if local.len() < level.vertex_count() {
            local.resize(level.vertex_count(), NONE);
        }
        let columns = compact_columns(&mut first, local);
        let shape = GridShape {
            grid: Grid {
                spokes: ne,
                sectors: nf,
                radius: 2,
            },
            steps,
            cells,
            flipped,
            sharp,
            options: t.options,
        };
        let shape = shapes.find(shape)?;
        Some(SectorGrids {
            faces,
            flipped,
            first,
            columns,
            shape,
        })
    }
}

/// The spoke a closed ring of `segments` (two per spoke, [`GridSharpness::segments`]' order)
/// starts from: the first whose rotation of the words is least.
fn least_rotation(segments: &[f32]) -> usize {
    let n = segments.len();
    let words = |j: usize| (0..n).map(move |k| segments[(2 * j + k) % n].to_bits());
    (0..n / 2)
        .min_by(|&a, &b| words(a).cmp(words(b)))
        .unwrap_or(0)
}

/// Per level `1..=steps`: its grid's radius, for nodes `a, b < cells` on the last.
fn radii(steps: u32, cells: u32) -> Vec<u32> {
    let mut radii = vec![cells; steps as usize];
    for l in (0..steps as usize - 1).rev() {
        radii[l] = radii[l + 1] / 2 + 1;
    }
    radii
}

/// What the sector grids after the first level depend on: the first level's grid and
/// sharpness, the steps, the region's cells, the orientation and the scheme options.
#[derive(Debug, Clone)]
struct GridShape {
    grid: Grid,
    steps: u32,
    cells: u32,
    flipped: bool,
    sharp: GridSharpness,
    options: SchemeOptions,
}

impl GridShape {
    /// The shape as words: equal words, equal shapes.
    fn key(&self) -> Vec<u32> {
        let (g, o) = (self.grid, self.options);
        let mut words = vec![
            g.spokes,
            g.sectors,
            self.steps,
            self.cells,
            u32::from(self.flipped),
            o.boundary as u32,
            o.crease_method as u32,
            self.sharp.vertex.to_bits(),
        ];
        words.extend(self.sharp.segments.iter().map(|s| s.to_bits()));
        words
    }
}

/// The sector grids after the first level of one [`GridShape`] and its nodes' tangent terms
/// over the first level's points, made when a node first reads them.
struct ShapeGrids {
    /// Per level `1..=steps`: its grid.
    grids: Vec<Grid>,
    /// Per level `2..=steps`: its points' rows over the level above.
    rows: Vec<Rows>,
    /// The last level's grid as a level (cells of each sector's grid, `v`'s ring order).
    last: Level,
    /// Per node `(i, x, y)` of the last level, at `(i cells + y) cells + x`: its terms.
    nodes: Vec<NodeTerms>,
    /// The nodes' terms (first-level point, tangent weights).
    terms: Vec<(u32, [f64; 2])>,
    /// Nodes per sector side.
    cells: u32,
}

/// A node's terms in [`ShapeGrids::terms`].
#[derive(Debug, Clone, Copy)]
enum NodeTerms {
    Unmade,
    /// The exact mask failed.
    Failed,
    Span(u32, u32),
}

impl ShapeGrids {
    /// The grids of `shape`; `None` where its last level cannot be built.
    fn new(shape: &GridShape) -> Option<Self> {
        let radii = radii(shape.steps, shape.cells);
        let grid = |radius| Grid {
            radius,
            ..shape.grid
        };
        let mut grids = vec![shape.grid];
        let mut rows = Vec::with_capacity(radii.len());
        let mut sharp = shape.sharp.clone();
        for &radius in &radii[1..] {
            let parent = *grids.last()?;
            let child = grid(radius);
            rows.push(step_rows(parent, &sharp, child));
            sharp = child_sharpness_of(parent, &sharp, child);
            grids.push(child);
        }
        let last = grid_level(*grids.last()?, &sharp, shape.flipped, shape.options)?;
        let nodes = (shape.grid.sectors * shape.cells * shape.cells) as usize;
        Some(ShapeGrids {
            grids,
            rows,
            last,
            nodes: vec![NodeTerms::Unmade; nodes],
            terms: Vec::new(),
            cells: shape.cells,
        })
    }

    /// The tangent terms over the first level's points of node `(x, y)` of sector `i`
    /// (`None`: no exact mask), pulled back with `sums`.
    fn node_terms(
        &mut self,
        (i, x, y): (u32, u32, u32),
        masks: &SharedVertexMasks,
        sums: &mut GridSums,
    ) -> Option<&[(u32, [f64; 2])]> {
        let k = ((i * self.cells + y) * self.cells + x) as usize;
        if let NodeTerms::Unmade = self.nodes[k] {
            self.nodes[k] = self.make_node(i, x, y, masks, sums);
        }
        match self.nodes[k] {
            NodeTerms::Span(a, b) => Some(&self.terms[a as usize..b as usize]),
            _ => None,
        }
    }

    /// [`Self::node_terms`] made: the last level's mask at the node pulled back to the first.
    fn make_node(
        &mut self,
        i: u32,
        x: u32,
        y: u32,
        masks: &SharedVertexMasks,
        sums: &mut GridSums,
    ) -> NodeTerms {
        let grid = self.grids[self.grids.len() - 1];
        let node = grid.point(i, x, y);
        // A cell of sector i at the node: the tangents are oriented by a face on the region's
        // side of a spoke.
        let cell =
            i * grid.radius * grid.radius + y.saturating_sub(1) * grid.radius + x.saturating_sub(1);
        let Ok(m) = masks
            .vertex_mask(&self.last, node, cell)
            .map_err(|e| log::debug!("lattice node ({x}, {y}) of sector {i}: no mask ({e})"))
        else {
            return NodeTerms::Failed;
        };
        sums.start(&m.indices, &m.tangent_u, &m.tangent_v);
        for (rows, parent) in self.rows.iter().zip(&self.grids).rev() {
            sums.pull_back(rows, parent.len());
        }
        let a = self.terms.len() as u32;
        self.terms.extend_from_slice(&sums.terms);
        NodeTerms::Span(a, self.terms.len() as u32)
    }
}

/// The sector grids' shapes of one build, each made once, and the pull-back's accumulators.
#[derive(Default)]
pub(super) struct GridShapes {
    /// Per shape's words ([`GridShape::key`]): its index in `shapes`.
    ids: WordHashMap<Vec<u32>, u32>,
    /// Per shape: its grids (`None` where they cannot be built).
    shapes: Vec<Option<ShapeGrids>>,
    sums: GridSums,
    /// Per vertex of a level: its first-step column ([`compact_columns`]' scratch).
    columns: Vec<u32>,
}

impl GridShapes {
    /// The index of `shape`, made if new; `None` where its grids cannot be built.
    fn find(&mut self, shape: GridShape) -> Option<u32> {
        let next = self.shapes.len() as u32;
        let id = *self.ids.entry(shape.key()).or_insert(next);
        if id == next {
            self.shapes.push(ShapeGrids::new(&shape));
        }
        self.shapes[id as usize].as_ref().map(|_| id)
    }

    /// The exact limit tangent rows (global ids of `lev`) at node `(a, b)` (not `(0, 0)`) of
    /// the region of `grids` in `face`, appended to `out` as a frame; false (none appended)
    /// where there is no exact mask.
    pub(super) fn node_rows(
        &mut self,
        grids: &SectorGrids,
        lev: &AdaptiveLevel,
        face: u32,
        (a, b): (u32, u32),
        masks: &SharedVertexMasks,
        out: &mut FrameRows,
    ) -> bool {
        let Some(i) = grids.faces.iter().position(|&f| f == face) else {
            return false;
        };
        // The region's `a` runs along the face's edge from `v` to its next corner: spoke `i`
        // (the sector's `x`) unless the ring is flipped.
        let (x, y) = if grids.flipped { (b, a) } else { (a, b) };
        let Some(shape) = self.shapes[grids.shape as usize].as_mut() else {
            return false;
        };
        let sums = &mut self.sums;
        let Some(terms) = shape.node_terms((i as u32, x, y), masks, sums) else {
            return false;
        };
        sums.pull_back_from(terms, &grids.first, grids.columns.len());
        // Each row in increasing point (so global id), zeros dropped.
        for d in 0..2 {
            for &(k, x) in &sums.terms {
                if x[d] != 0.0 {
                    out.push_term((lev.global(grids.columns[k as usize]), x[d]));
                }
            }
            out.end_row();
        }
        true
    }
}

/// The pull-back of [`GridShapes::node_rows`], its accumulators reused from node to node.
#[derive(Debug, Default)]
struct GridSums {
    /// Per point of the coarser level: its sums so far and whether it has any.
    sums: Vec<([f64; 2], bool)>,
    /// A node's terms (point, weights) as they are pulled back.
    terms: Vec<(u32, [f64; 2])>,
}

impl GridSums {
    /// A node's mask (`indices` with the tangent weights `u`, `v`) as its terms.
    fn start(&mut self, indices: &[u32], u: &[f64], v: &[f64]) {
        self.terms.clear();
        let it = indices.iter().enumerate();
        self.terms.extend(it.map(|(j, &i)| (i, [u[j], v[j]])));
    }

    /// The terms over a level's points as terms over its parent's (`width` points), through
    /// the level's rows, in increasing parent point.
    fn pull_back(&mut self, rows: &Rows, width: usize) {
        accumulate(&mut self.sums, &self.terms, rows, width);
        self.collect();
    }

    /// [`Self::pull_back`] of `terms` instead of the node's own.
    fn pull_back_from(&mut self, terms: &[(u32, [f64; 2])], rows: &Rows, width: usize) {
        accumulate(&mut self.sums, terms, rows, width);
        self.collect();
    }

    /// The sums made as the node's terms.
    fn collect(&mut self) {
        self.terms.clear();
        for (c, &(s, seen)) in self.sums.iter().enumerate() {
            if seen {
                self.terms.push((c as u32, s));
            }
        }
    }
}

/// Sums `terms` through `rows` into `sums` (`width` points, cleared first), term by term.
fn accumulate(
    sums: &mut Vec<([f64; 2], bool)>,
    terms: &[(u32, [f64; 2])],
    rows: &Rows,
    width: usize,
) {
    sums.clear();
    sums.resize(width, ([0.0; 2], false));
    for &(i, w) in terms {
        for &(col, x) in rows.row(i) {
            let (s, seen) = &mut sums[col as usize];
            *seen = true;
            s[0] += w[0] * x;
            s[1] += w[1] * x;
        }
    }
}

/// The distinct columns of `rows` (increasing) and `rows` renumbered over them; `local` a
/// scratch table per column, [`NONE`] before and after.
fn compact_columns(rows: &mut Rows, local: &mut [u32]) -> Vec<u32> {
    let mut columns = Vec::with_capacity(rows.terms.len() / 2);
    for t in &rows.terms {
        let at = &mut local[t.0 as usize];
        if *at == NONE {
            *at = 0;
            columns.push(t.0);
        }
    }
    columns.sort_unstable();
    for (k, &c) in columns.iter().enumerate() {
        local[c as usize] = k as u32;
    }
    for t in &mut rows.terms {
        t.0 = local[t.0 as usize];
    }
    for &c in &columns {
        local[c as usize] = NONE;
    }
    columns
}

/// The rows of grid `child`'s points over grid `parent`'s (sharpness `sharp`): the
/// Catmull-Clark rules (`subdiv::points`) on the grid.
fn step_rows(parent: Grid, sharp: &GridSharpness, child: Grid) -> Rows {
    let mut rows = Rows {
        offsets: Vec::with_capacity(child.len() + 1),
        terms: Vec::with_capacity(9 * child.len()),
    };
    rows.offsets.push(0);
    let mut ring = Ring::default();
    // v's vertex point.
    vertex_point(parent, sharp, 0, None, &mut ring, &mut rows.terms);
    rows.close_row();
    for j in 0..child.spokes {
        for x in 1..=child.radius {
            if x % 2 == 0 {
                vertex_point(parent, sharp, j, Some(x / 2), &mut ring, &mut rows.terms);
            } else {
                spoke_edge_point(parent, sharp, j, x.div_ceil(2), &mut rows.terms);
            }
            rows.close_row();
        }
    }
    for i in 0..child.sectors {
        for y in 1..=child.radius {
            for x in 1..=child.radius {
                inner_point(parent, i, x, y, &mut rows.terms);
                rows.close_row();
            }
        }
    }
    rows
}

/// A vertex's one-ring as [`vertex_point`] gathers it, reused from vertex to vertex.
#[derive(Default)]
struct Ring {
    /// Per edge: its far end, its sharpness and its half's at the vertex after the step.
    ends: Vec<(u32, f32, f32)>,
    /// Per face: its corners.
    cells: Vec<[u32; 4]>,
    /// The edges' sharpness, before and after the step.
    before: Vec<f32>,
    after: Vec<f32>,
    mask: VertexMask,
}

/// The vertex point of `v` (`at` `None`) or of point `at` of spoke `j` of `parent`, merged.
fn vertex_point(
    parent: Grid,
    sharp: &GridSharpness,
    j: u32,
    at: Option<u32>,
    ring: &mut Ring,
    out: &mut Vec<(u32, f64)>,
) {
    let seg = |j: u32, x: u32| sharp.segment(parent, j, x);
    let m = sharp.method;
    let Ring {
        ends,
        cells,
        before,
        after,
        mask,
    } = ring;
    ends.clear();
    cells.clear();
    let (centre, pv) = match at {
        None => {
            for k in 0..parent.spokes {
                let s = seg(k, 1);
                let others = (0..parent.spokes).filter(|&o| o != k).map(|o| seg(o, 1));
                ends.push((parent.spoke(k, 1), s, child_sharpness(s, others, m)));
            }
            for i in 0..parent.sectors {
                cells.push(parent.cell(i, 0, 0));
            }
            (0, sharp.vertex)
        }
        Some(p) => {
            let (below, above) = (seg(j, p), seg(j, p + 1));
            let inner = parent.point(j, p - 1, 0);
            let outer = parent.spoke(j, p + 1);
            ends.push((inner, below, child_sharpness(below, [above], m)));
            ends.push((outer, above, child_sharpness(above, [below], m)));
            let (next, previous) = parent.beside(j);
            if let Some(i) = next {
                ends.push((parent.point(i, p, 1), 0.0, 0.0));
                cells.push(parent.cell(i, p - 1, 0));
                cells.push(parent.cell(i, p, 0));
            }
            if let Some(i) = previous {
                ends.push((parent.point(i, 1, p), 0.0, 0.0));
                cells.push(parent.cell(i, 0, p - 1));
                cells.push(parent.cell(i, 0, p));
            }
            (parent.spoke(j, p), 0.0)
        }
    };
    before.clear();
    before.extend(ends.iter().map(|e| e.1));
    after.clear();
    after.extend(ends.iter().map(|e| e.2));
    vertex_point_mask(mask, pv, before, after, cells.len());
    let start = out.len();
    out.push((centre, mask.vertex));
    for (k, e) in ends.iter().enumerate() {
        if mask.edges[k] != 0.0 {
            out.push((e.0, mask.edges[k]));
        }
    }
    for (k, cell) in cells.iter().enumerate() {
        if mask.faces[k] != 0.0 {
            let w = mask.faces[k] / 4.0;
            out.extend(cell.iter().map(|&u| (u, w)));
        }
    }
    merge_row_from(out, start);
}

/// The edge point of segment `x` (from `x - 1` to `x`) of spoke `j` of `parent`, merged.
fn spoke_edge_point(
    parent: Grid,
    sharp: &GridSharpness,
    j: u32,
    x: u32,
    out: &mut Vec<(u32, f64)>,
) {
    let s = sharp.segment(parent, j, x);
    let (after, before) = parent.beside(j);
    let boundary = after.is_none() || before.is_none();
    let (ends, faces) = edge_point_weights(s, boundary);
    let start = out.len();
    out.push((parent.point(j, x - 1, 0), ends));
    out.push((parent.spoke(j, x), ends));
    if faces != 0.0 {
        let w = faces / 4.0;
        for cell in after
            .map(|i| parent.cell(i, x - 1, 0))
            .into_iter()
            .chain(before.map(|i| parent.cell(i, 0, x - 1)))
        {
            out.extend(cell.iter().map(|&u| (u, w)));
        }
    }
    merge_row_from(out, start);
}

/// Child point `(x, y)` (`x, y >= 1`) of sector `i`: a face point, the edge point of a smooth
/// edge between two quads or the vertex point of a smooth valence-4 point of `parent`.
fn inner_point(parent: Grid, i: u32, x: u32, y: u32, out: &mut Vec<(u32, f64)>) {
    let p = |a: u32, b: u32| parent.point(i, a, b);
    let (hx, hy) = (x / 2, y / 2);
    let [end, far] = REGULAR_EDGE_WEIGHTS;
    let [centre, side, diagonal] = REGULAR_VERTEX_WEIGHTS;
    match (x % 2, y % 2) {
        (1, 1) => out.extend(parent.cell(i, hx, hy).map(|u| (u, 0.25))),
        (1, 0) => out.extend([
            (p(hx, hy), end),
            (p(hx + 1, hy), end),
            (p(hx, hy - 1), far),
            (p(hx + 1, hy - 1), far),
            (p(hx, hy + 1), far),
            (p(hx + 1, hy + 1), far),
        ]),
        (0, 1) => out.extend([
            (p(hx, hy), end),
            (p(hx, hy + 1), end),
            (p(hx - 1, hy), far),
            (p(hx - 1, hy + 1), far),
            (p(hx + 1, hy), far),
            (p(hx + 1, hy + 1), far),
        ]),
        _ => out.extend([
            (p(hx, hy), centre),
            (p(hx - 1, hy), side),
            (p(hx + 1, hy), side),
            (p(hx, hy - 1), side),
            (p(hx, hy + 1), side),
            (p(hx - 1, hy - 1), diagonal),
            (p(hx + 1, hy - 1), diagonal),
            (p(hx - 1, hy + 1), diagonal),
            (p(hx + 1, hy + 1), diagonal),
        ]),
    }
}

/// The sharpness of grid `child`'s spoke segments and vertex after a step from `parent`
/// (`sharp`): segment `x` is the half of parent segment `ceil(x / 2)` at its end `x / 2`
/// rounded down, beside the other spoke segments there (`subdiv::rules::child_sharpness`).
fn child_sharpness_of(parent: Grid, sharp: &GridSharpness, child: Grid) -> GridSharpness {
    let seg = |j: u32, x: u32| sharp.segment(parent, j, x);
    let mut segments = Vec::with_capacity((child.spokes * child.radius) as usize);
    for j in 0..child.spokes {
        for x in 1..=child.radius {
            let p = x.div_ceil(2);
            let s = seg(j, p);
            let at = x / 2;
            let half = if at == 0 {
                let others = (0..parent.spokes).filter(|&o| o != j).map(|o| seg(o, 1));
                child_sharpness(s, others, sharp.method)
            } else {
                // The other segment at point `at`: below it (x odd) or above it (x even).
                let other = if at < p { seg(j, at) } else { seg(j, at + 1) };
                child_sharpness(s, [other], sharp.method)
            };
            segments.push(half);
        }
    }
    GridSharpness {
        segments,
        vertex: decrement(sharp.vertex),
        method: sharp.method,
    }
}

/// `grid`'s cells as a level (sharpness `sharp`, scheme `options`; cell `(x, y)` of sector `i`
/// is face `(i radius + y) radius + x`, oriented as `v`'s faces: against the ring when
/// `flipped`): the edges on its border other than a boundary spoke's are cut, their ends
/// incomplete.
fn grid_level(
    grid: Grid,
    sharp: &GridSharpness,
    flipped: bool,
    options: SchemeOptions,
) -> Option<Level> {
    let r = grid.radius;
    let cells = (grid.sectors * r * r) as usize;
    let mut offsets = Vec::with_capacity(cells + 1);
    let mut corners = Vec::with_capacity(4 * cells);
    offsets.push(0);
    for i in 0..grid.sectors {
        for y in 0..r {
            for x in 0..r {
                let [a, b, c, d] = grid.cell(i, x, y);
                corners.extend(if flipped { [a, d, c, b] } else { [a, b, c, d] });
                offsets.push(corners.len() as u32);
            }
        }
    }
    let mut topo = crate::topology::build(grid.len(), offsets, corners, false)
        .map_err(|e| log::debug!("lattice sector grids: no level ({e})"))
        .ok()?;
    topo.options = options;
    let mut boundary = vec![false; topo.edge_count()];
    for j in 0..grid.spokes {
        let (after, before) = grid.beside(j);
        for x in 1..=r {
            let e = topo.find_edge(grid.point(j, x - 1, 0), grid.spoke(j, x))?;
            topo.edge_sharpness[e as usize] = sharp.segment(grid, j, x);
            boundary[e as usize] = after.is_none() || before.is_none();
        }
    }
    topo.vertex_sharpness[0] = sharp.vertex;
    let mut cut = vec![false; topo.edge_count()];
    let mut incomplete = vec![false; topo.vertex_count()];
    for e in 0..topo.edge_count() {
        if topo.is_boundary_edge(e as u32) && !boundary[e] {
            cut[e] = true;
            for u in topo.edge_vertices(e as u32) {
                incomplete[u as usize] = true;
            }
        }
    }
    Some(Level::with_flags(topo, cut, incomplete))
}

#[cfg(test)]
mod tests {
    use super::least_rotation;

    /// Every rotation of a ring of spokes starts from the same spoke of the pattern: the one
    /// after which the words read least (here the smooth spoke before the two sharp ones).
    #[test]
    fn rotations_of_a_ring_start_alike() {
        // Spokes 0..5 as (segment at v, segment at the far end); spokes 1 and 3 sharp.
        let ring = [0.0, 0.0, 2.0, 1.0, 0.0, 0.0, 2.0, 2.0, 0.0, 0.0];
        let least = [0.0, 0.0, 0.0, 0.0, 2.0, 1.0, 0.0, 0.0, 2.0, 2.0];
        for r in 0..5 {
            let mut rotated = ring;
            rotated.rotate_left(2 * r);
            let start = least_rotation(&rotated);
            rotated.rotate_left(2 * start);
            assert_eq!(rotated, least, "rotation {r}");
        }
    }
}
