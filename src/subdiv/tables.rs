//! Subdivision tables: one Catmull-Clark step as data for three compute kernels (face, edge and
//! vertex points), after Köbler 2013, section 4.2 (Fig. 4.2) and Nießner et al. 2012.
//!
//! Every index is into ONE vertex buffer holding every level: the parent level's vertices at
//! some offset, the children wherever a [`ChildPlacement`] puts them. A table is built for the
//! children a placement asks for, so a sparse (adaptive) child level uses the same tables as
//! uniform refinement.
//!
//! - Face point: centroid of `count` parent vertices listed at `offset` in the flat index list
//!   [`SubdivisionTables::indices`] (n-gons in the first step included).
//! - Edge point: `s * (a + b) / 2 + (1 - s) * (a + b + f0 + f1) / 4` with `a, b` the parent end
//!   vertices, `f0, f1` the two adjacent new face points and `s` the crease blend weight: the
//!   edge sharpness clamped to `[0, 1]`, `1` on boundaries (`f0, f1` then unused, `f1` is
//!   [`NO_POINT`]). Semi-sharp edges `0 < s < 1` blend exactly as `Level::refine`.
//! - Vertex point: the parent vertex, its `edge_count` ring neighbours (far ends of its edges,
//!   parent vertices) then its `face_count` new face points, listed at `offset`; the rule is data:
//!   `rules[0]` with weight `weight`, plus `rules[1]` with `1 - weight` when the rule changes
//!   between parent and child (the fractional blend of DeRose et al. 1998, weight from
//!   [`fractional_weight`]). Smooth and dart use the Catmull-Clark mask of [`VertexMask`]
//!   (renormalised on rings with `edge_count != face_count`, which only extraction cuts make);
//!   crease uses `3/4 v + 1/8 (c0 + c1)` with `crease` the ring positions of the two sharp edges;
//!   corner keeps the vertex. Rules come from [`vertex_rule`] on the parent and child
//!   sharpness, the child edge sharpness from [`child_edge_sharpness`], so integer, fractional
//!   and Chaikin decay, boundaries under every `interpolateboundary` mode (boundary edges are
//!   infinitely sharp, `edge-and-corner` corners infinitely sharp vertices) and holes (whose
//!   points are computed like any other: neighbours need them) are all expressed without
//!   per-vertex weight lists.
//!
//! [`SubdivisionTables::apply_cpu`] is the f64 reference of the kernels (`glsl/adaptive/`).

use super::adaptive::{AdaptiveRefinement, ChildOf};
use super::level::Level;
use super::rules::{
    child_edge_sharpness, decrement, fractional_weight, vertex_rule, VertexMask, VertexRule,
};
use crate::{Error, Result};
use glam::DVec3;

/// Marker for "no point" (the missing second face of a boundary edge, an unused crease slot).
pub const NO_POINT: u32 = u32::MAX;

/// One face point: centroid of `count` vertices at `offset` in the index list.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FaceEntry {
    /// Buffer index written.
    pub dst: u32,
    /// First vertex in [`SubdivisionTables::indices`].
    pub offset: u32,
    /// Number of face vertices.
    pub count: u32,
}

/// One edge point (see the module docs for the formula).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgeEntry {
    /// Buffer index written.
    pub dst: u32,
    /// Buffer indices of the two parent end vertices.
    pub ends: [u32; 2],
    /// Buffer indices of the two adjacent new face points ([`NO_POINT`] if absent; unused
    /// when `sharp == 1`).
    pub faces: [u32; 2],
    /// Crease blend weight in `[0, 1]`: 1 = midpoint (sharp or boundary), 0 = smooth.
    pub sharp: f64,
}

/// One vertex point (see the module docs for the formula).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VertexEntry {
    /// Buffer index written.
    pub dst: u32,
    /// Buffer index of the parent vertex.
    pub src: u32,
    /// Number of ring edges (valence).
    pub edge_count: u32,
    /// Number of ring faces.
    pub face_count: u32,
    /// First ring entry in [`SubdivisionTables::indices`]: `edge_count` edge neighbours, then
    /// `face_count` face points.
    pub offset: u32,
    /// The parent rule (weight `weight`) and the child rule (weight `1 - weight`).
    pub rules: [VertexRule; 2],
    /// Weight of `rules[0]`.
    pub weight: f64,
    /// Ring positions (`0..edge_count`) of the two crease edges when either rule is a crease,
    /// else [`NO_POINT`].
    pub crease: [u32; 2],
}

/// Where the children of one refinement step of a parent [`Level`] go in the vertex buffer:
/// `(parent element, buffer index)` pairs for the face, edge and vertex points wanted, and the
/// buffer index of the parent's vertex 0 (`parent_offset + v` for vertex `v`). Edge points need
/// the face points of their faces (unless the edge is sharp), vertex points those of every
/// incident face: the tables refuse a placement that lacks them.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ChildPlacement {
    /// Buffer index of parent vertex 0.
    pub parent_offset: u32,
    /// `(parent face, buffer index of its face point)`.
    pub faces: Vec<(u32, u32)>,
    /// `(parent edge, buffer index of its edge point)`.
    pub edges: Vec<(u32, u32)>,
    /// `(parent vertex, buffer index of its vertex point)`.
    pub vertices: Vec<(u32, u32)>,
}

impl ChildPlacement {
    /// Every child of a uniform step, in [`Level::refine`]'s order (face, edge, vertex
    /// points) from `child_offset`.
    pub fn uniform(parent: &Level, parent_offset: u32, child_offset: u32) -> ChildPlacement {
        let place = |n: usize, first: u32| (0..n as u32).map(|i| (i, first + i)).collect();
        ChildPlacement {
            parent_offset,
            faces: place(
                parent.face_count(),
                child_offset + parent.child_face_point(0),
            ),
            edges: place(
                parent.topology().edge_count(),
                child_offset + parent.child_edge_point(0),
            ),
            vertices: place(
                parent.vertex_count(),
                child_offset + parent.child_vertex_point(0),
            ),
        }
    }
}

/// The three kernel tables of one refinement step (Köbler 2013, Fig. 4.2).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SubdivisionTables {
    /// Face-point kernel entries.
    pub faces: Vec<FaceEntry>,
    /// Edge-point kernel entries.
    pub edges: Vec<EdgeEntry>,
    /// Vertex-point kernel entries.
    pub vertices: Vec<VertexEntry>,
    /// Flat buffer-index list: face vertices and vertex rings.
    pub indices: Vec<u32>,
}

impl SubdivisionTables {
    /// The tables of the children `placement` asks for, from `parent`.
    pub fn new(parent: &Level, placement: &ChildPlacement) -> Result<SubdivisionTables> {
        let t = parent.topology();
        let base = placement.parent_offset;
        let mut face_point = vec![NO_POINT; t.face_count()];
        for &(f, dst) in &placement.faces {
            *face_point
                .get_mut(f as usize)
                .ok_or_else(|| range("face", f))? = dst;
        }
        // `what` and `i` name the element asking (formatted only on error).
        let needed = |f: u32, what: &str, i: u32| -> Result<u32> {
            match face_point[f as usize] {
                NO_POINT => Err(Error::Invalid(format!(
                    "subdivision tables: {what} {i} needs the face point of face {f}"
                ))),
                p => Ok(p),
            }
        };
        // Sized up front: one entry per child, the face corners and the rings in the indices.
        let ring_len: usize = placement
            .vertices
            .iter()
            .filter(|&&(v, _)| (v as usize) < t.vertex_count())
            .map(|&(v, _)| t.vertex_edges(v).len() + t.vertex_faces(v).len())
            .sum();
        let corners: usize = placement
            .faces
            .iter()
            .filter(|&&(f, _)| (f as usize) < t.face_count())
            .map(|&(f, _)| t.face_size(f))
            .sum();
        let mut out = SubdivisionTables {
            faces: Vec::with_capacity(placement.faces.len()),
            edges: Vec::with_capacity(placement.edges.len()),
            vertices: Vec::with_capacity(placement.vertices.len()),
            indices: Vec::with_capacity(corners + ring_len),
        };
        for &(f, dst) in &placement.faces {
            let verts = t.face_vertices(f);
            out.faces.push(FaceEntry {
                dst,
                offset: out.indices.len() as u32,
                count: verts.len() as u32,
            });
            // Pushed one by one: a few indices a face, where `extend`'s call costs more.
            for &v in verts {
                out.indices.push(base + v);
            }
        }
        for &(e, dst) in &placement.edges {
            if e as usize >= t.edge_count() {
                return Err(range("edge", e));
            }
            let [a, b] = t.edge_vertices(e);
            let s = t.edge_sharpness(e) as f64;
            let sharp = if t.is_boundary_edge(e) || s >= 1.0 {
                1.0
            } else {
                s.max(0.0)
            };
            let mut faces = [NO_POINT; 2];
            if sharp < 1.0 {
                for (slot, &f) in faces.iter_mut().zip(t.edge_faces(e)) {
                    *slot = needed(f, "edge", e)?;
                }
            }
            out.edges.push(EdgeEntry {
                dst,
                ends: [base + a, base + b],
                faces,
                sharp,
            });
        }
        let mut ring_sharpness = RingSharpness::default();
        for &(v, dst) in &placement.vertices {
            if v as usize >= t.vertex_count() {
                return Err(range("vertex", v));
            }
            let offset = out.indices.len() as u32;
            let edges = t.vertex_edges(v);
            let faces = t.vertex_faces(v);
            for &e in edges {
                out.indices.push(base + t.other_vertex(e, v));
            }
            for &f in faces {
                out.indices.push(needed(f, "vertex", v)?);
            }
            let (rules, weight, crease) = vertex_rules(parent, v, &mut ring_sharpness);
            out.vertices.push(VertexEntry {
                dst,
                src: base + v,
                edge_count: edges.len() as u32,
                face_count: faces.len() as u32,
                offset,
                rules,
                weight,
                crease,
            });
        }
        Ok(out)
    }

    /// Applies the three kernels in order (face, edge, vertex points) to `buffer` in f64: the
    /// reference of the GPU kernels.
    pub fn apply_cpu(&self, buffer: &mut [DVec3]) {
        for f in &self.faces {
            let idx = &self.indices[f.offset as usize..(f.offset + f.count) as usize];
            let sum: DVec3 = idx.iter().map(|&i| buffer[i as usize]).sum();
            buffer[f.dst as usize] = sum / f.count as f64;
        }
        for e in &self.edges {
            let [a, b] = e.ends.map(|i| buffer[i as usize]);
            let mid = 0.5 * (a + b);
            buffer[e.dst as usize] = if e.sharp >= 1.0 {
                mid
            } else {
                let [f0, f1] = e.faces.map(|i| buffer[i as usize]);
                e.sharp * mid + (1.0 - e.sharp) * 0.25 * (a + b + f0 + f1)
            };
        }
        let mut mask = VertexMask::default();
        for v in &self.vertices {
            let (ne, nf) = (v.edge_count as usize, v.face_count as usize);
            mask.reset(ne, nf);
            let crease: Vec<usize> = v
                .crease
                .iter()
                .filter(|&&c| c != NO_POINT)
                .map(|&c| c as usize)
                .collect();
            mask.add_rule(v.rules[0], &crease, v.weight);
            if v.weight < 1.0 {
                mask.add_rule(v.rules[1], &crease, 1.0 - v.weight);
            }
            let ring = &self.indices[v.offset as usize..v.offset as usize + ne + nf];
            let mut p = buffer[v.src as usize] * mask.vertex;
            for (w, &i) in mask.edges.iter().chain(&mask.faces).zip(ring) {
                p += buffer[i as usize] * *w;
            }
            buffer[v.dst as usize] = p;
        }
    }
}

fn range(what: &str, i: u32) -> Error {
    Error::Invalid(format!("subdivision tables: {what} {i} out of range"))
}

/// The vertex rule of parent vertex `v` as `Level::refine` applies it: `([parent, child],
/// weight of the parent rule, ring positions of the crease edges)`.
fn vertex_rules(
    level: &Level,
    v: u32,
    scratch: &mut RingSharpness,
) -> ([VertexRule; 2], f64, [u32; 2]) {
    let t = level.topology();
    let edges = t.vertex_edges(v);
    let pv = t.vertex_sharpness(v);
    // The parent rule from a count of the sharp edges first: most vertices are smooth or darts,
    // whose rule needs no sharpness lists.
    let sharp_edges = edges.iter().filter(|&&e| t.edge_sharpness(e) > 0.0).count();
    let prule = vertex_rule(pv, sharp_edges);
    if matches!(prule, VertexRule::Smooth | VertexRule::Dart) {
        return ([prule, prule], 1.0, [NO_POINT; 2]);
    }
    let RingSharpness {
        parent: ps,
        child: cs,
    } = scratch;
    ps.clear();
    ps.extend(edges.iter().map(|&e| t.edge_sharpness(e)));
    cs.clear();
    cs.extend(edges.iter().map(|&e| child_edge_sharpness(t, e, v)));
    let cv = decrement(pv);
    let crule = vertex_rule(cv, cs.iter().filter(|&&s| s > 0.0).count());
    if crule == prule {
        let crease = if prule == VertexRule::Crease {
            crease_of(ps)
        } else {
            [NO_POINT; 2]
        };
        return ([prule, prule], 1.0, crease);
    }
    // The child's sharp edges are a subset of the parent's: only one rule can be a crease.
    let crease = if prule == VertexRule::Crease {
        crease_of(ps)
    } else if crule == VertexRule::Crease {
        crease_of(cs)
    } else {
        [NO_POINT; 2]
    };
    let w = fractional_weight(pv, cv, ps, cs);
    ([prule, crule], w, crease)
}

/// [`vertex_rules`]' sharpness of a ring's edges, parent's and child's, in ring order: buffers
/// reused from vertex to vertex rather than allocated per crease or corner vertex.
#[derive(Default)]
struct RingSharpness {
    parent: Vec<f32>,
    child: Vec<f32>,
}

/// The ring positions of the first two sharp edges of `sharpness` (a crease rule's two).
fn crease_of(sharpness: &[f32]) -> [u32; 2] {
    let mut sharp = (0..sharpness.len() as u32).filter(|&i| sharpness[i as usize] > 0.0);
    [sharp.next(), sharp.next()].map(|i| i.expect("a crease rule has two sharp edges"))
}

/// Tables of several refinement steps stacked in one vertex buffer: level `l`'s vertices start
/// at `level_offsets[l]`; `levels[l]` refines level `l` into level `l + 1`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RefinementTables {
    /// One table per step.
    pub levels: Vec<SubdivisionTables>,
    /// First buffer index of each level (`levels.len() + 1` entries).
    pub level_offsets: Vec<u32>,
    /// Vertices in the buffer (all levels).
    pub total_vertices: u32,
}

impl RefinementTables {
    /// Uniform refinement of `base` by `depth` steps; level `l` is ordered as `Level::refine`
    /// orders it.
    pub fn uniform(base: &Level, depth: u32) -> Result<RefinementTables> {
        let mut out = RefinementTables {
            level_offsets: vec![0],
            total_vertices: base.vertex_count() as u32,
            ..Default::default()
        };
        let mut current = base.clone();
        for d in 0..depth {
            let child_offset = out.total_vertices;
            let placement =
                ChildPlacement::uniform(&current, out.level_offsets[d as usize], child_offset);
            out.levels
                .push(SubdivisionTables::new(&current, &placement)?);
            let t = current.topology();
            out.total_vertices += (t.face_count() + t.edge_count() + t.vertex_count()) as u32;
            out.level_offsets.push(child_offset);
            if d + 1 < depth {
                current = current.refine_topology();
            }
        }
        Ok(out)
    }

    /// The tables of exactly the sparse levels of a feature-adaptive refinement (Köbler 2013
    /// §3.3 levels, §4.2 tables), in its global vertex numbering: vertex `i` of level `l` is
    /// buffer index `levels[l].first_vertex + i`, so [`Self::refine_cpu`] gives
    /// [`AdaptiveRefinement::refine_positions`].
    ///
    /// Each step is built on the whole sparse level `l` (contiguous at `first_vertex`), placing
    /// every vertex of level `l + 1` by [`AdaptiveLevel::child_of`](super::adaptive::AdaptiveLevel::child_of):
    /// a kept child lies around a vertex of a refined face, whose ring is complete in level
    /// `l`, so its face, edge and vertex points see the same neighbourhood as in the refined
    /// sub-level.
    pub fn adaptive(refinement: &AdaptiveRefinement) -> Result<RefinementTables> {
        let mut out = RefinementTables {
            level_offsets: refinement.levels.iter().map(|l| l.first_vertex).collect(),
            total_vertices: refinement.vertex_count() as u32,
            ..Default::default()
        };
        for (lev, next) in refinement.levels.iter().zip(&refinement.levels[1..]) {
            let n = next.level.vertex_count();
            let mut placement = ChildPlacement {
                parent_offset: lev.first_vertex,
                faces: Vec::with_capacity(n),
                edges: Vec::with_capacity(n),
                vertices: Vec::with_capacity(n),
            };
            for (dst, &child_of) in (next.first_vertex..).zip(lev.children_of()) {
                match child_of {
                    ChildOf::Face(f) => placement.faces.push((f, dst)),
                    ChildOf::Edge(e) => placement.edges.push((e, dst)),
                    ChildOf::Vertex(v) => placement.vertices.push((v, dst)),
                }
            }
            out.levels
                .push(SubdivisionTables::new(&lev.level, &placement)?);
        }
        log::debug!(
            "adaptive tables: {} steps, {} vertices",
            out.levels.len(),
            out.total_vertices
        );
        Ok(out)
    }

    /// Number of vertices of level `l`.
    pub fn level_len(&self, l: usize) -> u32 {
        let end = self
            .level_offsets
            .get(l + 1)
            .copied()
            .unwrap_or(self.total_vertices);
        end - self.level_offsets[l]
    }

    /// The whole buffer from the control points (level 0), refined on the CPU in f64.
    pub fn refine_cpu(&self, control: &[DVec3]) -> Vec<DVec3> {
        let mut buffer = vec![DVec3::ZERO; self.total_vertices as usize];
        buffer[..control.len()].copy_from_slice(control);
        for level in &self.levels {
            level.apply_cpu(&mut buffer);
        }
        buffer
    }
}

/// Words per face record in the GPU layout: `dst, offset, count`.
pub const FACE_WORDS: u32 = 3;
/// Words per edge record: `dst, a, b, f0, f1, sharp (f32 bits)`.
pub const EDGE_WORDS: u32 = 6;
/// Words per vertex record: `dst, src, edge_count, face_count, offset, rules (rule0 | rule1 <<
/// 8), weight (f32 bits), crease0, crease1`.
pub const VERTEX_WORDS: u32 = 9;

/// GPU code of a vertex rule: 0 smooth (and dart), 1 crease, 2 corner.
pub fn rule_code(rule: VertexRule) -> u32 {
    match rule {
        VertexRule::Smooth | VertexRule::Dart => 0,
        VertexRule::Crease => 1,
        VertexRule::Corner => 2,
    }
}

/// The records of one kernel dispatch: `count` records from word `first`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct KernelRange {
    /// Word index of the first record.
    pub first: u32,
    /// Number of records (threads).
    pub count: u32,
}

/// Every level's tables packed into one `uint[]` storage buffer (`glsl/adaptive/refine.glsl`):
/// per level the index list, then the face, edge and vertex records, whose offsets are
/// absolute word indices.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GpuTables {
    /// The buffer contents.
    pub words: Vec<u32>,
    /// Per level: the face, edge and vertex kernel ranges.
    pub steps: Vec<[KernelRange; 3]>,
}

impl GpuTables {
    /// Size of the table buffer in bytes.
    pub fn bytes(&self) -> usize {
        self.words.len() * std::mem::size_of::<u32>()
    }
}

impl RefinementTables {
    /// The GPU layout of every level (weights rounded to f32).
    pub fn gpu_tables(&self) -> GpuTables {
        let mut out = GpuTables::default();
        for level in &self.levels {
            let w = &mut out.words;
            let base = w.len() as u32;
            w.extend_from_slice(&level.indices);
            let faces = KernelRange {
                first: w.len() as u32,
                count: level.faces.len() as u32,
            };
            for f in &level.faces {
                w.extend([f.dst, base + f.offset, f.count]);
            }
            let edges = KernelRange {
                first: w.len() as u32,
                count: level.edges.len() as u32,
            };
            for e in &level.edges {
                let [a, b] = e.ends;
                let [f0, f1] = e.faces;
                w.extend([e.dst, a, b, f0, f1, (e.sharp as f32).to_bits()]);
            }
            let vertices = KernelRange {
                first: w.len() as u32,
                count: level.vertices.len() as u32,
            };
            for v in &level.vertices {
                w.extend([
                    v.dst,
                    v.src,
                    v.edge_count,
                    v.face_count,
                    base + v.offset,
                    rule_code(v.rules[0]) | rule_code(v.rules[1]) << 8,
                    (v.weight as f32).to_bits(),
                    v.crease[0],
                    v.crease[1],
                ]);
            }
            out.steps.push([faces, edges, vertices]);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{ControlMesh, ControlMeshDesc};

    /// A sparse placement (the children around one vertex only, packed after the parent)
    /// gives the same points as the uniform refinement.
    #[test]
    fn sparse_placement_matches_uniform_refinement() {
        let mesh = crate::assets::EmbeddedMesh::from_name("creased")
            .unwrap()
            .load()
            .unwrap();
        let level = Level::from_mesh(&mesh).unwrap();
        let t = level.topology();
        let uniform = level.refine_positions(mesh.positions());
        let nv = level.vertex_count() as u32;
        for v in 0..nv {
            let mut next = nv;
            let mut place = |items: &[u32]| -> Vec<(u32, u32)> {
                items
                    .iter()
                    .map(|&i| {
                        next += 1;
                        (i, next - 1)
                    })
                    .collect()
            };
            let placement = ChildPlacement {
                parent_offset: 0,
                faces: place(t.vertex_faces(v)),
                edges: place(t.vertex_edges(v)),
                vertices: place(&[v]),
            };
            let tables = SubdivisionTables::new(&level, &placement).unwrap();
            let mut buffer = mesh.positions().to_vec();
            buffer.resize(next as usize, DVec3::ZERO);
            tables.apply_cpu(&mut buffer);
            let child = |(what, (i, dst)): (usize, &(u32, u32))| {
                let expect = match what {
                    0 => level.child_face_point(*i),
                    1 => level.child_edge_point(*i),
                    _ => level.child_vertex_point(*i),
                };
                (buffer[*dst as usize], uniform[expect as usize])
            };
            let lists = [&placement.faces, &placement.edges, &placement.vertices];
            for (a, b) in lists
                .iter()
                .enumerate()
                .flat_map(|(k, l)| l.iter().map(move |x| (k, x)))
                .map(child)
            {
                assert!(a.distance(b) < 1e-12, "vertex {v}: {a} != {b}");
            }
        }
    }

    #[test]
    fn placement_missing_face_point_is_an_error() {
        let d = ControlMeshDesc {
            positions: vec![
                DVec3::ZERO,
                DVec3::X,
                DVec3::new(1.0, 1.0, 0.0),
                DVec3::Y,
                DVec3::new(2.0, 0.0, 0.0),
                DVec3::new(2.0, 1.0, 0.0),
            ],
            face_sizes: vec![4, 4],
            face_vertices: vec![0, 1, 2, 3, 1, 4, 5, 2],
            ..Default::default()
        };
        let level = Level::from_mesh(&ControlMesh::new(d).unwrap()).unwrap();
        let e = level.topology().find_edge(1, 2).unwrap();
        let placement = ChildPlacement {
            parent_offset: 0,
            faces: vec![(0, 6)],
            edges: vec![(e, 7)],
            vertices: vec![],
        };
        assert!(SubdivisionTables::new(&level, &placement).is_err());
    }
}
