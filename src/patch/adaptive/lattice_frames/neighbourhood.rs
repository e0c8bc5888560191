//! The local refinement around one region vertex ([`Neighbourhood`]) and its nodes' exact limit
//! tangent rows.

use super::NONE;
use crate::patch::gregory::Weights;
use crate::subdiv::adaptive::AdaptiveLevel;
use crate::subdiv::limit::SharedVertexMasks;
use crate::subdiv::Level;
use crate::topology::Topology;

/// The faces near a vertex, refined `steps` times keeping only what the lattice nodes of its
/// regions read (`Level::refine_kept`): every node is a vertex of the last level whose limit
/// mask reads only its one-ring there, and each kept vertex's refinement row reads only the
/// one-ring of its parent (face, edge or vertex) one level up.
///
/// Which children are kept follows a distance: per vertex of each level a label `d`, the
/// faces between it and the region's vertex (`0` there, `1` on its faces, `2` beyond: the
/// extraction is the faces touching its faces), and for the children of a step `2 d` at a
/// vertex point, `d_a + d_b` at an edge point, `min + max` of the face's at a face point (the
/// Chebyshev distance of the regular grid inside the vertex's faces, in units of the finer
/// level). The labels of a face's corners differ by at most one on every level, so a child
/// face whose smallest corner label is below `bound` has its parent corner `u` at
/// `2 d_u <= bound`, and every face at `u` has a corner label below `bound / 2 + 1`. The
/// bounds `k_l = k_(l + 1) / 2 + 1` from `k_steps = cells` (the nodes' one-rings) thus keep,
/// level by level, every face that a kept row reads (`k_0 = 2` for any `cells <= 2^steps`:
/// the extraction), so the rows and masks read are those of the whole refinement of the
/// extraction; the pull-back sums them in that refinement's vertex order ([`WholeIds`]), so
/// the frames are bit for bit those of refining the extraction as whole levels.
pub(super) struct Neighbourhood {
    /// Extracted faces, increasing (sub face `i` is `faces[i]`).
    faces: Vec<u32>,
    /// Extracted vertex -> level vertex.
    map: Vec<u32>,
    /// The extraction, then each kept refinement.
    levels: Vec<Level>,
    /// Per step `l`: per corner of `levels[l]`, its child face in `levels[l + 1]` ([`NONE`]
    /// where not kept).
    children: Vec<Vec<u32>>,
    /// Refinement rows: `steps[l]` gives `levels[l + 1]`'s points from `levels[l]`'s.
    steps: Vec<StepRows>,
    /// Per level: its vertices' ids in the whole refinement of the extraction.
    whole: Vec<Vec<u32>>,
    /// Per level: its vertices in increasing whole id.
    order: Vec<Vec<u32>>,
}

impl Neighbourhood {
    /// The neighbourhood of vertex `v` of `lev` for regions of at most `cells` cells of
    /// `2^-steps`.
    pub(super) fn new(lev: &AdaptiveLevel, v: u32, steps: u32, cells: u32) -> Option<Self> {
        let (mut out, centre) = Self::extraction(lev, v, steps)?;
        let mut labels = vec![2u32; out.map.len()];
        let t = out.levels[0].topology();
        for &f in t.vertex_faces(centre) {
            for &u in t.face_vertices(f) {
                labels[u as usize] = 1;
            }
        }
        labels[centre as usize] = 0;
        let mut bounds = vec![cells; steps as usize + 1];
        for l in (0..steps as usize).rev() {
            bounds[l] = bounds[l + 1] / 2 + 1;
        }
        let mut whole = WholeIds::extraction(t);
        for (l, &bound) in bounds[1..].iter().enumerate() {
            let parent = out.levels.last()?;
            let pt = parent.topology();
            let (keep, children) = kept_children(pt, &labels, bound);
            let (child, rows) = parent
                .refine_kept(&keep)
                .map_err(|e| log::debug!("lattice vertex {v}: no local refinement ({e})"))
                .ok()?;
            labels = child_labels(pt, &labels, &rows);
            // The last level's edges number no further step.
            let edges = (l + 1 < steps as usize).then(|| child.topology());
            whole = whole.child(pt, &keep, &rows, edges)?;
            out.steps.push(StepRows::new(rows));
            out.children.push(children);
            out.order.push(increasing(&whole.vertices));
            out.whole.push(whole.vertices.clone());
            out.levels.push(child);
        }
        Some(out)
    }

    /// The faces touching the faces at `v` extracted, no step yet (room for `steps`); `v`'s id
    /// there.
    fn extraction(lev: &AdaptiveLevel, v: u32, steps: u32) -> Option<(Self, u32)> {
        let t = lev.topology();
        let mut faces = Vec::with_capacity(64);
        for &f in t.vertex_faces(v) {
            for &u in t.face_vertices(f) {
                faces.extend_from_slice(t.vertex_faces(u));
            }
        }
        faces.sort_unstable();
        faces.dedup();
        let (sub, map) = lev
            .level
            .try_extract(&faces)
            .map_err(|e| log::debug!("lattice vertex {v}: no extraction ({e})"))
            .ok()?;
        let centre = map.binary_search(&v).ok()? as u32;
        let n = steps as usize;
        let mut whole = Vec::with_capacity(n + 1);
        whole.push((0..map.len() as u32).collect());
        let mut order = Vec::with_capacity(n + 1);
        order.push((0..map.len() as u32).collect());
        let mut levels = Vec::with_capacity(n + 1);
        levels.push(sub);
        let out = Neighbourhood {
            faces,
            map,
            levels,
            children: Vec::with_capacity(n),
            steps: Vec::with_capacity(n),
            whole,
            order,
        };
        Some((out, centre))
    }

    /// [`Self::new`] refining the extraction as whole levels (`Level::refine`): the former
    /// path, the test oracle of the kept refinements.
    #[cfg(test)]
    pub(super) fn whole(lev: &AdaptiveLevel, v: u32, steps: u32, _cells: u32) -> Option<Self> {
        let (mut out, _) = Self::extraction(lev, v, steps)?;
        for _ in 0..steps {
            let parent = out.levels.last()?;
            let child = parent.refine_topology();
            out.children
                .push((0..parent.topology().corner_count() as u32).collect());
            out.steps
                .push(StepRows::new((0..child.vertex_count() as u32).collect()));
            out.whole.push((0..child.vertex_count() as u32).collect());
            out.order.push((0..child.vertex_count() as u32).collect());
            out.levels.push(child);
        }
        Some(out)
    }

    /// The exact limit tangent rows (global ids of `lev`) at node `(a, b)` of the region at
    /// corner `c` of `face`.
    pub(super) fn node_rows(
        &mut self,
        lev: &AdaptiveLevel,
        face: u32,
        c: usize,
        (a, b): (u32, u32),
        masks: &SharedVertexMasks,
        sums: &mut PullBack,
    ) -> Option<[Weights; 2]> {
        let steps = self.steps.len();
        let n = 1u32 << steps;
        // The region's (x, w) = (a, b) as the face's own (s, t), in 2^-steps.
        let (mut s, mut t) = match c {
            0 => (a, b),
            1 => (n - b, a),
            2 => (n - a, n - b),
            _ => (b, n - a),
        };
        let mut f = self.faces.binary_search(&face).ok()? as u32;
        let mut half = n / 2;
        for l in 0..steps {
            // The child at the corner whose quadrant holds the point: (x, w) from that corner.
            let (j, x, w) = if s <= half && t <= half {
                (0, s, t)
            } else if s >= half && t <= half {
                (1, t, 2 * half - s)
            } else if s >= half && t >= half {
                (2, 2 * half - s, 2 * half - t)
            } else {
                (3, 2 * half - t, s)
            };
            let corner = self.levels[l].topology().face_offsets[f as usize] + j;
            f = self.children[l][corner as usize];
            if f == NONE {
                log::debug!("lattice node ({a}, {b}) of face {face}: not kept");
                return None;
            }
            (s, t) = (x, w);
            half /= 2;
        }
        let last = &self.levels[steps];
        let k = match (s, t) {
            (0, 0) => 0,
            (1, 0) => 1,
            (1, 1) => 2,
            _ => 3,
        };
        let vertex = last.topology().face_vertices(f)[k];
        let m = masks
            .vertex_mask(last, vertex, f)
            .map_err(|e| log::debug!("lattice node ({a}, {b}) of face {face}: no mask ({e})"))
            .ok()?;
        // Pulled back level by level: weights over each level's points (whole refinement's id,
        // own id, weights), in increasing whole id, the order the sums take.
        let ids = &self.whole[steps];
        let mut terms = std::mem::take(&mut sums.terms);
        terms.clear();
        terms.extend(
            m.indices
                .iter()
                .enumerate()
                .map(|(j, &i)| (ids[i as usize], i, [m.tangent_u[j], m.tangent_v[j]])),
        );
        terms.sort_unstable_by_key(|x| x.0);
        for l in (0..steps).rev() {
            let rows = &mut self.steps[l];
            let (ids, order) = (&self.whole[l], &self.order[l]);
            sums.pull_back(&mut terms, &self.levels[l], rows, ids, order);
        }
        // The extraction's whole ids are its own, which increase with the level's ids: the
        // terms are in increasing global id, one per id, what `Weights::from_terms` makes of
        // them.
        let row = |d: usize| {
            let mut w = Vec::with_capacity(terms.len());
            w.extend(
                terms
                    .iter()
                    .filter(|t| t.2[d] != 0.0)
                    .map(|&(_, i, w)| (lev.global(self.map[i as usize]), w[d])),
            );
            Weights(w)
        };
        let out = [row(0), row(1)];
        sums.terms = terms;
        Some(out)
    }
}

/// The accumulators of [`Neighbourhood::node_rows`]' pull-back, reused from node to node.
#[derive(Debug, Default)]
pub(super) struct PullBack {
    /// Per point of the coarser level: its sum so far.
    sums: Vec<[f64; 2]>,
    /// Per point: whether it has a sum.
    seen: Vec<bool>,
    /// A node's terms (whole id, own id, weights) as they are pulled back.
    terms: Vec<(u32, u32, [f64; 2])>,
}

impl PullBack {
    /// `terms` (whole id, own id, weights; increasing whole id) of a finer level as terms of
    /// the coarser level `parent` through its refinement rows `rows` (`ids` the coarser
    /// points' whole ids, `order` its points in increasing whole id): each sum adds its
    /// products term by term, in the order of `terms`.
    fn pull_back(
        &mut self,
        terms: &mut Vec<(u32, u32, [f64; 2])>,
        parent: &Level,
        rows: &mut StepRows,
        ids: &[u32],
        order: &[u32],
    ) {
        self.sums.resize(parent.vertex_count(), [0.0; 2]);
        self.seen.resize(parent.vertex_count(), false);
        for &(_, i, w) in terms.iter() {
            for &(col, x) in rows.row(parent, i) {
                let c = col as usize;
                self.seen[c] = true;
                self.sums[c][0] += w[0] * x;
                self.sums[c][1] += w[1] * x;
            }
        }
        terms.clear();
        for &col in order {
            let c = col as usize;
            if self.seen[c] {
                self.seen[c] = false;
                terms.push((ids[c], col, std::mem::take(&mut self.sums[c])));
            }
        }
    }
}

/// The vertices `0..ids.len()` in increasing `ids`.
fn increasing(ids: &[u32]) -> Vec<u32> {
    let mut order: Vec<u32> = (0..ids.len() as u32).collect();
    order.sort_unstable_by_key(|&i| ids[i as usize]);
    order
}

/// The refinement rows of one kept step (`Level::refine_matrix_row`), each made when a node
/// first reads it: the nodes read a part of the kept vertices' rows.
struct StepRows {
    /// Per vertex of the finer level: its id in the coarser level's child numbering.
    ids: Vec<u32>,
    /// Per vertex of the finer level: its row's range in `terms` ([`NONE`] before it is made).
    spans: Vec<[u32; 2]>,
    /// The rows made so far, `(column, weight)`.
    terms: Vec<(u32, f64)>,
    /// One row as it is made.
    scratch: Vec<(u32, f64)>,
}

impl StepRows {
    /// No row made yet of the vertices `ids` (child numbering).
    fn new(ids: Vec<u32>) -> Self {
        StepRows {
            spans: vec![[NONE; 2]; ids.len()],
            // Room for most rows (a quad mesh's rows hold 4, 6 or 9 terms).
            terms: Vec::with_capacity(8 * ids.len()),
            ids,
            scratch: Vec::with_capacity(32),
        }
    }

    /// Row `i` (a finer vertex) over the points of `parent`, the coarser level.
    fn row(&mut self, parent: &Level, i: u32) -> &[(u32, f64)] {
        let [mut a, mut b] = self.spans[i as usize];
        if a == NONE {
            parent.refine_matrix_row(self.ids[i as usize] as usize, &mut self.scratch);
            a = self.terms.len() as u32;
            self.terms.extend_from_slice(&self.scratch);
            b = self.terms.len() as u32;
            self.spans[i as usize] = [a, b];
        }
        &self.terms[a as usize..b as usize]
    }
}

/// The corners of `t` whose children a step keeps ([`Neighbourhood`]): those whose child
/// face's smallest corner label is below `bound` (`labels` per vertex of `t`), increasing,
/// and per corner its index among them ([`NONE`] where not kept).
fn kept_children(t: &Topology, labels: &[u32], bound: u32) -> (Vec<u32>, Vec<u32>) {
    let mut keep = Vec::with_capacity(t.corner_count());
    let mut children = vec![NONE; t.corner_count()];
    for f in 0..t.face_count() as u32 {
        let fv = t.face_vertices(f);
        let n = fv.len();
        let d = |k: usize| labels[fv[k] as usize];
        let (lo, hi) = fv.iter().fold((u32::MAX, 0), |(lo, hi), &u| {
            let x = labels[u as usize];
            (lo.min(x), hi.max(x))
        });
        let off = t.face_offsets[f as usize];
        for k in 0..n {
            let du = d(k);
            let next = d(if k + 1 == n { 0 } else { k + 1 });
            let prev = d(if k == 0 { n - 1 } else { k - 1 });
            let least = (2 * du).min(du + next).min(du + prev).min(lo + hi);
            if least < bound {
                children[(off + k as u32) as usize] = keep.len() as u32;
                keep.push(off + k as u32);
            }
        }
    }
    (keep, children)
}

/// The labels ([`Neighbourhood`]) of a kept refinement's vertices, `rows` their ids in the
/// child numbering `[face points | edge points | vertex points]` of `t` (labels `labels`).
fn child_labels(t: &Topology, labels: &[u32], rows: &[u32]) -> Vec<u32> {
    let (nf, ne) = (t.face_count() as u32, t.edge_count() as u32);
    let d = |u: u32| labels[u as usize];
    rows.iter()
        .map(|&r| {
            if r < nf {
                let fv = t.face_vertices(r).iter().map(|&u| d(u));
                fv.clone().min().unwrap_or(0) + fv.max().unwrap_or(0)
            } else if r < nf + ne {
                let [a, b] = t.edge_vertices(r - nf);
                d(a) + d(b)
            } else {
                2 * d(r - nf - ne)
            }
        })
        .collect()
}

/// A kept level's faces, edges and vertices numbered as in the whole refinement of the
/// extraction (`Level::refine_topology`: child face `h` per parent corner `h`; edges the spoke
/// `h` per corner, from the edge point to the face point, then the halves `2 e`, `2 e + 1` of
/// each parent edge `e` from its first end and to its second; vertices
/// `[face points | edge points | vertex points]`), where the kept level numbers its edges as
/// `topology::build` does.
struct WholeIds {
    /// Whether this is the extraction itself (its ids its own).
    extraction: bool,
    faces: Vec<u32>,
    edges: Vec<u32>,
    /// Per edge: whether its first end is the whole edge's.
    same_first: Vec<bool>,
    vertices: Vec<u32>,
    /// The whole level's face, edge and corner counts.
    counts: [u32; 3],
}

impl WholeIds {
    /// The extraction's own ids.
    fn extraction(t: &Topology) -> WholeIds {
        let ne = t.edge_count() as u32;
        WholeIds {
            extraction: true,
            faces: (0..t.face_count() as u32).collect(),
            edges: (0..ne).collect(),
            same_first: vec![true; ne as usize],
            vertices: (0..t.vertex_count() as u32).collect(),
            counts: [t.face_count() as u32, ne, t.corner_count() as u32],
        }
    }

    /// The whole id of corner `k` of face `f` (this level's), its child face's.
    fn corner(&self, t: &Topology, f: u32, k: u32) -> u32 {
        if self.extraction {
            t.face_offsets[f as usize] + k
        } else {
            4 * self.faces[f as usize] + k
        }
    }

    /// The ids of the kept refinement `child` of this level (`t`): its faces the children of
    /// corners `keep`, its vertices `rows` in the child numbering of `t`; its edges' only when
    /// `child` is given (a level that is refined further).
    fn child(
        &self,
        t: &Topology,
        keep: &[u32],
        rows: &[u32],
        child: Option<&Topology>,
    ) -> Option<Self> {
        let [nf, ne, fv] = self.counts;
        let (tf, te) = (t.face_count() as u32, t.edge_count() as u32);
        let mut f = 0u32;
        let faces = keep
            .iter()
            .map(|&h| {
                while t.face_offsets[f as usize + 1] <= h {
                    f += 1;
                }
                self.corner(t, f, h - t.face_offsets[f as usize])
            })
            .collect();
        let vertices = rows
            .iter()
            .map(|&r| {
                if r < tf {
                    self.faces[r as usize]
                } else if r < tf + te {
                    nf + self.edges[(r - tf) as usize]
                } else {
                    nf + ne + self.vertices[(r - tf - te) as usize]
                }
            })
            .collect();
        let (edges, same_first) = match child {
            Some(c) => self.child_edges(t, rows, c)?,
            None => Default::default(),
        };
        Some(WholeIds {
            extraction: false,
            faces,
            edges,
            same_first,
            vertices,
            counts: [fv, fv + 2 * ne, 4 * fv],
        })
    }

    /// The whole ids of the edges of the kept refinement `child` of this level (`t`, its
    /// vertices `rows` in the child numbering of `t`) and per edge whether its first end is the
    /// whole edge's.
    fn child_edges(
        &self,
        t: &Topology,
        rows: &[u32],
        child: &Topology,
    ) -> Option<(Vec<u32>, Vec<bool>)> {
        let fv = self.counts[2];
        let (tf, te) = (t.face_count() as u32, t.edge_count() as u32);
        let mut edges = Vec::with_capacity(child.edge_count());
        let mut same_first = Vec::with_capacity(child.edge_count());
        for e in 0..child.edge_count() as u32 {
            let [x, y] = child.edge_vertices(e).map(|u| rows[u as usize]);
            // The edge point end first.
            let edge_point = |r: u32| (tf..tf + te).contains(&r);
            let (p, q, flipped) = match (edge_point(x), edge_point(y)) {
                (true, false) => (x - tf, y, false),
                (false, true) => (y - tf, x, true),
                _ => {
                    log::debug!("lattice neighbourhood: child edge {e} is no spoke or half");
                    return None;
                }
            };
            let (id, ep_first) = if q < tf {
                // The spoke of the corner of face q at edge p: edge point first.
                let k = t.face_edges(q).iter().position(|&g| g == p)? as u32;
                (self.corner(t, q, k), true)
            } else {
                // The half of edge p at vertex u: `2 e` from the whole edge's first end (the
                // vertex point first), `2 e + 1` to its second (the edge point first).
                let u = q - tf - te;
                let [a, b] = t.edge_vertices(p);
                let first = if self.same_first[p as usize] { a } else { b };
                let second = u32::from(u != first);
                (fv + 2 * self.edges[p as usize] + second, second == 1)
            };
            edges.push(id);
            same_first.push(ep_first != flipped);
        }
        Some((edges, same_first))
    }
}
