//! The GPU tables of the Pm pass (stencil variant): every Bézier coefficient the shaders read
//! is a sparse stencil row over the control vertices, produced by the CPU construction of
//! [`crate::patch::pm`] run on unit [`Weights`] (so CPU and GPU evaluate the same
//! construction), and the GPU sums `weight × control position` (set 0 binding 8) per row.
//! Animation therefore only re-uploads the control positions.
//!
//! One word buffer (set 0 binding 4, `glsl/pm/pm.glsl` mirrors it):
//! - header ([`HEADER_WORDS`]): word offsets of the patch records, edge records, centre records,
//!   rows and terms;
//! - patch records ([`RECORD_WORDS`] each, draw order: bicubic, polar, then one per Pm sector):
//!   face, kind word (`kind | sector << 8 | m << 16 | pole << 24`), flags (bit `k`: domain edge
//!   `k` starts at its canonical start), centre record, four corner vertex ids (domain order),
//!   four edge record ids (domain edges), sixteen coefficient rows (bicubic `b[i + 4j]`; polar
//!   the same with row 3 the pole; sector the 15 quartic coefficients, `quartic_index` order);
//! - edge records ([`EDGE_WORDS`] each), one per mesh edge between drawn facets and one per
//!   inner spoke of a Pm-patch: degree (3 outer, 4 spoke), the edge curve's Bézier rows in the
//!   canonical direction (from the smaller vertex id; a spoke from its corner to the centre),
//!   then the inward cross-derivative rows (degree 3) of the patch on the left and on the
//!   right of that direction (empty rows where no drawn patch is);
//! - centre records ([`CENTRE_WORDS`]): rows of `b_004`, `b^0_103`, `b^1_103` of a Pm-patch;
//! - rows (first term, term count) and terms (vertex id, `f32` weight bits), terms sorted by
//!   vertex id, zero weights dropped, identical rows stored once (row 0 is empty: zero).
//!
//! The shaders sum a row relative to an origin vertex `o` (`Σ w_i (p_i - o)`, then `+ o` for a
//! position): patch coefficients relative to the patch's corner 0, an edge record's relative to
//! its canonical start (word 14), a centre record's relative to the facet's corner 0 (word 3).
//! Derivatives then come from small differences, not from cancelling large `f32` coordinates.
//!
//! Both patches of an edge evaluate the same edge record with the same canonical parameter, so
//! positions and normals there are bitwise equal (`glsl/pm/pm.glsl`, `pm_edge`).

use std::collections::HashMap;

use glam::DVec3;

use crate::patch::gregory::{combine, Weights};
use crate::patch::pm::construct::{quartic_index, sector_quartic, SECTOR_POINTS};
use crate::patch::pm::{
    classify, facet_corner, pm_patch, pm_vertex, pm_vertices, FacetClass, NotPm, PmOptions, PmPatch,
};
use crate::topology::Topology;

/// Words of the buffer header.
pub const HEADER_WORDS: usize = 8;
/// Words per patch record (`PmRecord` in `glsl/pm/pm.glsl`).
pub const RECORD_WORDS: usize = 32;
/// Words per edge record.
pub const EDGE_WORDS: usize = 16;
/// Words per centre record.
pub const CENTRE_WORDS: usize = 4;

/// Patch kinds (low byte of the record's kind word).
pub const KIND_BICUBIC: u32 = 0;
/// Polar (singular bicubic on a triangle domain).
pub const KIND_POLAR: u32 = 1;
/// One quartic sector of a Pm-patch.
pub const KIND_SECTOR: u32 = 2;

/// The patch-type code a facet class gets in captures and colours: ordinary 0, polar 1, Pm
/// `m = 3, 4, 5` as 2, 3, 4.
pub fn class_code(class: FacetClass) -> u32 {
    match class {
        FacetClass::Ordinary => 0,
        FacetClass::Polar { .. } => 1,
        FacetClass::Pm { m } => m as u32 - 1,
    }
}

/// Sparse rows, stored once each.
#[derive(Default)]
struct Rows {
    ids: HashMap<Vec<(u32, u32)>, u32>,
    rows: Vec<[u32; 2]>,
    terms: Vec<u32>,
}

impl Rows {
    fn new() -> Rows {
        let mut r = Rows::default();
        r.id(&Weights::default());
        r
    }

    /// The id of row `w` (its weights rounded to `f32`, zeros dropped).
    fn id(&mut self, w: &Weights) -> u32 {
        let key: Vec<(u32, u32)> =
            w.0.iter()
                .map(|&(v, x)| (v, x as f32))
                .filter(|&(_, x)| x != 0.0)
                .map(|(v, x)| (v, x.to_bits()))
                .collect();
        if let Some(&id) = self.ids.get(&key) {
            return id;
        }
        let id = self.rows.len() as u32;
        self.rows
            .push([(self.terms.len() / 2) as u32, key.len() as u32]);
        for &(v, b) in &key {
            self.terms.extend([v, b]);
        }
        self.ids.insert(key, id);
        id
    }
}

/// Which edge record a domain edge uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum EdgeKey {
    Mesh(u32),
    /// Spoke `i` (corner `i` to the centre) of a Pm facet.
    Spoke(u32, usize),
}

/// One edge record: degree, curve rows, left and right cross-derivative rows.
#[derive(Debug, Clone, Copy, Default)]
struct EdgeRecord {
    degree: u32,
    origin: u32,
    curve: [u32; 5],
    left: [u32; 4],
    right: [u32; 4],
}

/// A domain edge of a patch, in the patch's direction (its start corner to its end corner).
struct DomainEdge {
    key: EdgeKey,
    /// The vertex whose control position the record's rows are summed relative to (the
    /// canonical start: the smaller vertex id, or the spoke's corner).
    origin: u32,
    /// Whether the patch's start is the canonical start (then the patch is left of it).
    start_is_canonical: bool,
    /// Bézier points of the edge curve.
    curve: Vec<Weights>,
    /// Inward cross-edge derivative, Bézier coefficients of degree 3.
    cross: [Weights; 4],
}

fn scaled_diff(k: f64, a: &Weights, b: &Weights) -> Weights {
    combine(&[(k, a), (-k, b)])
}

/// `(on, inner)` index pairs of bicubic edge `k` (`b[i + 4j]`), in the edge's direction.
fn bicubic_edge_pairs(k: usize) -> [(usize, usize); 4] {
    std::array::from_fn(|i| match k {
        0 => (i, i + 4),
        1 => (3 + 4 * i, 2 + 4 * i),
        2 => ((3 - i) + 12, (3 - i) + 8),
        _ => (4 * (3 - i), 1 + 4 * (3 - i)),
    })
}

fn bicubic_edge(b: &[Weights; 16], k: usize, key: EdgeKey, ends: [u32; 2]) -> DomainEdge {
    let pairs = bicubic_edge_pairs(k);
    let start_is_canonical = ends[0] < ends[1];
    DomainEdge {
        key,
        origin: ends[0].min(ends[1]),
        start_is_canonical,
        curve: pairs.iter().map(|&(on, _)| b[on].clone()).collect(),
        cross: pairs.map(|(on, inner)| scaled_diff(3.0, &b[inner], &b[on])),
    }
}

/// One drawn patch before it becomes a record.
struct Patch {
    face: u32,
    kind: u32,
    sector: u32,
    m: u32,
    pole: u32,
    corners: [u32; 4],
    rows: Vec<Weights>,
    edges: Vec<DomainEdge>,
    centre: Option<[Weights; 3]>,
    /// Facet corner 0 (the origin of its centre record's rows).
    corners_0: u32,
}

/// The CPU side of the Pm pass of one surface: which faces it draws and the word buffer.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PmGpuTables {
    /// Faces drawn, in draw order (bicubic, polar, Pm).
    pub faces: Vec<u32>,
    /// Class of each drawn face (parallel to `faces`).
    pub classes: Vec<FacetClass>,
    /// Patches per draw group: bicubic, polar, Pm sectors.
    pub counts: [u32; 3],
    /// The word buffer (module docs).
    pub words: Vec<u32>,
    /// Corner vertices of the drawn patches (limit frames), each once, with a facet and its
    /// corner index there.
    pub corners: Vec<(u32, u32, usize)>,
}

impl PmGpuTables {
    /// Tables of the faces among `candidates` the construction takes, and the refusals.
    pub fn build(
        topo: &Topology,
        candidates: &[u32],
        options: &PmOptions,
    ) -> (PmGpuTables, Vec<NotPm>) {
        let mut refused = Vec::new();
        let mut groups: [Vec<(u32, FacetClass)>; 3] = Default::default();
        for &f in candidates {
            match classify(topo, f) {
                Ok(c @ FacetClass::Ordinary) => groups[0].push((f, c)),
                Ok(c @ FacetClass::Polar { .. }) => groups[1].push((f, c)),
                Ok(c @ FacetClass::Pm { .. }) => groups[2].push((f, c)),
                Err(e) => refused.push(e),
            }
        }
        // Pm facets by side count, so each m is one contiguous run (the vertex-stage variant
        // draws each m with its own patch size).
        groups[2].sort_by_key(|&(_, c)| match c {
            FacetClass::Pm { m } => m,
            _ => 0,
        });
        let verts = pm_vertices(topo, &Weights::unit, options);
        let mut patches: Vec<Patch> = Vec::new();
        let mut counts = [0u32; 3];
        let mut out = PmGpuTables::default();
        for (g, group) in groups.iter().enumerate() {
            for &(f, class) in group {
                let patch = match pm_patch(topo, f, &verts, options) {
                    Ok(p) => p,
                    Err(e) => {
                        refused.push(e);
                        continue;
                    }
                };
                let before = patches.len();
                face_patches(topo, f, &patch, &mut patches);
                counts[g] += (patches.len() - before) as u32;
                out.faces.push(f);
                out.classes.push(class);
            }
        }
        out.counts = counts;
        out.words = words(&patches);
        let mut seen = std::collections::HashSet::new();
        for &f in &out.faces {
            for (k, &v) in topo.face_vertices(f).iter().enumerate() {
                if seen.insert(v) {
                    out.corners.push((v, f, k));
                }
            }
        }
        (out, refused)
    }

    /// Total patches drawn (a Pm facet draws one per sector).
    pub fn patch_count(&self) -> usize {
        self.counts.iter().map(|&c| c as usize).sum()
    }

    /// Limit position (the vertex point `v`) and unit normal of every patch corner vertex.
    pub fn corner_frames(
        &self,
        topo: &Topology,
        positions: &[DVec3],
        options: &PmOptions,
    ) -> Vec<(u32, DVec3, DVec3)> {
        let point = |v: u32| positions[v as usize];
        self.corners
            .iter()
            .map(|&(v, f, k)| {
                let vert = pm_vertex(topo, v, &point, options);
                let c = facet_corner(topo, f, k, &vert);
                let n = (c.next - c.v).cross(c.prev - c.v).normalize_or_zero();
                (v, vert.v, n)
            })
            .collect()
    }
}

/// The patches drawn for facet `f` (one, or one per sector).
fn face_patches(topo: &Topology, f: u32, patch: &PmPatch<Weights>, out: &mut Vec<Patch>) {
    let fv = topo.face_vertices(f);
    let fe = topo.face_edges(f);
    let n = fv.len();
    // Facet edge e (corner e to corner e + 1) and its end vertices.
    let mesh_edge = |e: usize| (EdgeKey::Mesh(fe[e]), [fv[e], fv[(e + 1) % n]]);
    match patch {
        PmPatch::Bicubic(b) => {
            let edges = (0..4)
                .map(|k| {
                    let (key, ends) = mesh_edge(k);
                    bicubic_edge(b, k, key, ends)
                })
                .collect();
            out.push(Patch {
                face: f,
                kind: KIND_BICUBIC,
                sector: 0,
                m: 4,
                pole: 0,
                corners: [fv[0], fv[1], fv[2], fv[3]],
                rows: b.to_vec(),
                edges,
                centre: None,
                corners_0: fv[0],
            });
        }
        PmPatch::Polar { h, pole } => {
            let b: [Weights; 16] = std::array::from_fn(|k| h[k.min(12)].clone());
            let (a, bb) = ((pole + 1) % 3, (pole + 2) % 3);
            // Domain edges: a -> b (facet edge a), b -> pole (facet edge b), pole -> a (facet
            // edge pole): bicubic edges 0, 1, 3.
            let edges = [(0, a), (1, bb), (3, *pole)]
                .into_iter()
                .map(|(k, e)| {
                    let (key, ends) = mesh_edge(e);
                    bicubic_edge(&b, k, key, ends)
                })
                .collect();
            out.push(Patch {
                face: f,
                kind: KIND_POLAR,
                sector: 0,
                m: 3,
                pole: *pole as u32,
                corners: [fv[a], fv[bb], fv[*pole], 0],
                rows: b.to_vec(),
                edges,
                centre: None,
                corners_0: fv[0],
            });
        }
        PmPatch::Pm(pts) => {
            let m = (pts.len() - 1) / SECTOR_POINTS;
            let quartics: Vec<[Weights; 15]> = (0..m).map(|i| sector_quartic(pts, i)).collect();
            let q = |i: usize, a: usize, b: usize| &quartics[i][quartic_index(a, b)];
            let centre = [q(0, 0, 0).clone(), q(0, 1, 0).clone(), q(1, 1, 0).clone()];
            for i in 0..m {
                let j = (i + 1) % m;
                let (key0, ends) = mesh_edge(i);
                let outer = DomainEdge {
                    key: key0,
                    origin: ends[0].min(ends[1]),
                    start_is_canonical: ends[0] < ends[1],
                    curve: patch.edge_cubic(i).to_vec(),
                    cross: std::array::from_fn(|k| {
                        scaled_diff(4.0, q(i, 3 - k, k), q(i, 4 - k, k))
                    }),
                };
                // v^{i+1} -> centre: spoke j in its canonical direction, this sector on the left.
                let to_centre = DomainEdge {
                    key: EdgeKey::Spoke(f, j),
                    origin: fv[j],
                    start_is_canonical: true,
                    curve: (0..5).map(|l| q(i, 0, 4 - l).clone()).collect(),
                    cross: std::array::from_fn(|k| {
                        scaled_diff(4.0, q(i, 1, 3 - k), q(i, 0, 4 - k))
                    }),
                };
                // centre -> v^i: spoke i reversed, this sector on the right.
                let from_centre = DomainEdge {
                    key: EdgeKey::Spoke(f, i),
                    origin: fv[i],
                    start_is_canonical: false,
                    curve: (0..5).map(|l| q(i, l, 0).clone()).collect(),
                    cross: std::array::from_fn(|k| {
                        let c = 3 - k;
                        scaled_diff(4.0, q(i, 3 - c, 1), q(i, 4 - c, 0))
                    }),
                };
                out.push(Patch {
                    face: f,
                    kind: KIND_SECTOR,
                    sector: i as u32,
                    m: m as u32,
                    pole: 0,
                    corners: [fv[i], fv[j], 0, 0],
                    rows: quartics[i].to_vec(),
                    edges: vec![outer, to_centre, from_centre],
                    centre: Some(centre.clone()),
                    corners_0: fv[0],
                });
            }
        }
    }
}

/// The word buffer of `patches` (module docs).
fn words(patches: &[Patch]) -> Vec<u32> {
    let mut rows = Rows::new();
    let mut edge_ids: HashMap<EdgeKey, u32> = HashMap::new();
    let mut edges: Vec<EdgeRecord> = Vec::new();
    let mut centres: Vec<[u32; 4]> = Vec::new();
    let mut centre_of: HashMap<u32, u32> = HashMap::new();
    let mut records: Vec<u32> = Vec::with_capacity(patches.len() * RECORD_WORDS);
    for p in patches {
        let mut flags = 0u32;
        let mut edge_rec = [0u32; 4];
        for (k, e) in p.edges.iter().enumerate() {
            let id = *edge_ids.entry(e.key).or_insert_with(|| {
                edges.push(EdgeRecord::default());
                (edges.len() - 1) as u32
            });
            edge_rec[k] = id;
            let rec = &mut edges[id as usize];
            rec.degree = (e.curve.len() - 1) as u32;
            rec.origin = e.origin;
            let curve: Vec<u32> = e.curve.iter().map(|w| rows.id(w)).collect();
            let cross: Vec<u32> = e.cross.iter().map(|w| rows.id(w)).collect();
            if e.start_is_canonical {
                flags |= 1 << k;
                rec.curve[..curve.len()].copy_from_slice(&curve);
                rec.left.copy_from_slice(&cross);
            } else {
                for (i, &c) in curve.iter().rev().enumerate() {
                    rec.curve[i] = c;
                }
                for (i, &c) in cross.iter().rev().enumerate() {
                    rec.right[i] = c;
                }
            }
        }
        let centre = match &p.centre {
            Some(c) => *centre_of.entry(p.face).or_insert_with(|| {
                // Summed relative to the facet's corner 0 (patch records do the same).
                centres.push([rows.id(&c[0]), rows.id(&c[1]), rows.id(&c[2]), p.corners_0]);
                (centres.len() - 1) as u32
            }),
            None => 0,
        };
        records.extend([
            p.face,
            p.kind | p.sector << 8 | p.m << 16 | p.pole << 24,
            flags,
            centre,
        ]);
        records.extend(p.corners);
        records.extend(edge_rec);
        let mut coeff = [0u32; 16];
        for (k, w) in p.rows.iter().enumerate() {
            coeff[k] = rows.id(w);
        }
        records.extend(coeff);
        records.extend([0u32; 4]);
    }
    let mut out = vec![0u32; HEADER_WORDS];
    out[0] = out.len() as u32;
    out.extend(records);
    out[1] = out.len() as u32;
    for e in &edges {
        out.push(e.degree);
        out.extend(e.curve);
        out.extend(e.left);
        out.extend(e.right);
        out.extend([e.origin, 0]);
    }
    out[2] = out.len() as u32;
    for c in &centres {
        out.extend(c);
    }
    out[3] = out.len() as u32;
    out.extend(rows.rows.iter().flatten());
    out[4] = out.len() as u32;
    out.extend(rows.terms);
    out
}
