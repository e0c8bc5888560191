//! [`Level`]: one level of a subdivision hierarchy (topology, sharpness, holes), and
//! extraction of sub-levels around a set of faces.

use crate::mesh::{ControlMesh, ControlMeshDesc, Corner, Crease};
use crate::topology::{self, Topology};
use crate::Result;
use glam::DVec3;
use std::ops::Range;

/// The unit of refinement: a [`Topology`] (which carries sharpness and holes) plus, for levels
/// extracted from a larger mesh, which edges are cut by the extraction and which vertices are
/// complete.
///
/// A vertex is *complete* when its position, one-ring and incident sharpness equal those of the
/// same vertex in the refinement of the whole mesh (conservative: some exact vertices next to
/// a cut are reported incomplete). Levels built from a whole mesh are complete everywhere.
#[derive(Debug, Clone)]
pub struct Level {
    pub(crate) topo: Topology,
    /// Per edge: boundary only because of an extraction (empty when there is none).
    pub(crate) cut: Vec<bool>,
    /// Per vertex: not complete (empty when all are complete).
    pub(crate) incomplete: Vec<bool>,
}

impl Level {
    /// The base level of a mesh.
    pub fn from_mesh(mesh: &ControlMesh) -> Result<Level> {
        Ok(Level::from_topology(Topology::new(mesh)?))
    }

    /// Wraps a complete topology.
    pub fn from_topology(topo: Topology) -> Level {
        Level {
            topo,
            cut: Vec::new(),
            incomplete: Vec::new(),
        }
    }

    /// `topo` with per-edge `cut` and per-vertex `incomplete` flags, each kept only if some
    /// flag is set.
    pub(crate) fn with_flags(topo: Topology, cut: Vec<bool>, incomplete: Vec<bool>) -> Level {
        let some = |x: Vec<bool>| if x.contains(&true) { x } else { Vec::new() };
        Level {
            topo,
            cut: some(cut),
            incomplete: some(incomplete),
        }
    }

    /// The topology (with sharpness and holes) of this level.
    pub fn topology(&self) -> &Topology {
        &self.topo
    }

    /// Consumes the level, returning its topology.
    pub fn into_topology(self) -> Topology {
        self.topo
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.topo.vertex_count()
    }

    /// Number of faces.
    pub fn face_count(&self) -> usize {
        self.topo.face_count()
    }

    /// The children of face `f` in the refined level: one quad per corner, in corner order.
    pub fn child_faces(&self, f: u32) -> Range<u32> {
        self.topo.face_offsets[f as usize]..self.topo.face_offsets[f as usize + 1]
    }

    /// Index of the face point of face `f` in the refined level.
    pub fn child_face_point(&self, f: u32) -> u32 {
        f
    }

    /// Index of the edge point of edge `e` in the refined level.
    pub fn child_edge_point(&self, e: u32) -> u32 {
        self.topo.face_count() as u32 + e
    }

    /// Index of the vertex point of vertex `v` in the refined level.
    pub fn child_vertex_point(&self, v: u32) -> u32 {
        (self.topo.face_count() + self.topo.edge_count()) as u32 + v
    }

    /// Whether edge `e` is a boundary only because of an extraction (not a real boundary: it
    /// keeps its real sharpness and nothing should be evaluated next to it).
    pub fn is_cut_edge(&self, e: u32) -> bool {
        !self.cut.is_empty() && self.cut[e as usize]
    }

    /// Whether edge `e` is a real boundary edge (one face in the whole mesh).
    pub fn is_real_boundary_edge(&self, e: u32) -> bool {
        self.topo.is_boundary_edge(e) && !self.is_cut_edge(e)
    }

    /// Whether vertex `v` is complete (see the type docs).
    pub fn is_complete_vertex(&self, v: u32) -> bool {
        self.incomplete.is_empty() || !self.incomplete[v as usize]
    }

    /// Whether every vertex of this level is complete.
    pub fn is_complete(&self) -> bool {
        self.incomplete.is_empty()
    }

    /// Whether `v` lies on a real boundary edge.
    pub fn is_real_boundary_vertex(&self, v: u32) -> bool {
        self.topo
            .vertex_edges(v)
            .iter()
            .any(|&e| self.is_real_boundary_edge(e))
    }

    /// False for holes and, with [`crate::mesh::BoundaryInterpolation::None`], for faces touching
    /// a boundary vertex of the base mesh and their descendants (see
    /// [`Topology::has_limit_surface`]).
    pub fn has_limit_surface(&self, f: u32) -> bool {
        self.topo.has_limit_surface(f)
    }

    /// A mesh description of this level with the given positions (one per vertex): faces,
    /// sharp non-boundary edges as creases, sharp vertices as corners, faces without limit
    /// surface as holes, and the options, so
    /// that `ControlMesh::new` rebuilds an equivalent base mesh (e.g. a refined mesh as a new
    /// control mesh for benchmarks).
    pub fn to_mesh_desc(&self, positions: Vec<DVec3>) -> ControlMeshDesc {
        let t = &self.topo;
        let face_sizes = (0..t.face_count() as u32)
            .map(|f| t.face_size(f) as u32)
            .collect();
        let creases = (0..t.edge_count() as u32)
            .filter(|&e| t.edge_sharpness(e) > 0.0 && !t.is_boundary_edge(e))
            .map(|e| {
                let [v0, v1] = t.edge_vertices(e);
                Crease {
                    v0,
                    v1,
                    sharpness: t.edge_sharpness(e),
                }
            })
            .collect();
        let corners = (0..t.vertex_count() as u32)
            .filter(|&v| t.vertex_sharpness(v) > 0.0)
            .map(|v| Corner {
                vertex: v,
                sharpness: t.vertex_sharpness(v),
            })
            .collect();
        ControlMeshDesc {
            positions,
            face_sizes,
            face_vertices: t.face_verts.clone(),
            creases,
            corners,
            holes: (0..t.face_count() as u32)
                .filter(|&f| t.is_hole(f))
                .collect(),
            options: t.options,
            left_handed: false,
        }
    }

    /// The sub-level made of `faces` (new face `i` is `faces[i]`), with the real sharpness and
    /// holes, and the map from new to old vertex indices. Edges that become boundaries only
    /// through the extraction keep their sharpness (0 unless tagged) and are reported by
    /// [`Self::is_cut_edge`]; vertices on them are incomplete.
    ///
    /// # Panics
    /// If `faces` is empty, holds an index out of range or a face twice (caller bugs).
    pub fn extract(&self, faces: &[u32]) -> (Level, Vec<u32>) {
        self.try_extract(faces)
            .unwrap_or_else(|e| panic!("Level::extract: {e}"))
    }

    /// [`Self::extract`] returning an error instead of panicking.
    pub fn try_extract(&self, faces: &[u32]) -> Result<(Level, Vec<u32>)> {
        let t = &self.topo;
        let mut offsets = Vec::with_capacity(faces.len() + 1);
        offsets.push(0u32);
        let mut old_verts = Vec::with_capacity(faces.len() * 4);
        for &f in faces {
            if f as usize >= t.face_count() {
                return Err(crate::Error::Invalid(format!(
                    "extract: face {f} out of range"
                )));
            }
            old_verts.extend_from_slice(t.face_vertices(f));
            offsets.push(old_verts.len() as u32);
        }
        let (map, local) = local_vertex_ids(&old_verts, t.vertex_count());
        let sub = topology::build(map.len(), offsets, local, false)?;
        // Each new edge's old edge: edge `k` of new face `i` is edge `k` of `faces[i]` (the same
        // corners; an edge is the only one joining its two ends).
        let mut old_edge = vec![u32::MAX; sub.edge_count()];
        for (i, &f) in faces.iter().enumerate() {
            for (&e, &pe) in sub.face_edges(i as u32).iter().zip(t.face_edges(f)) {
                old_edge[e as usize] = pe;
            }
        }
        let level = self.tag_extraction(sub, faces, &map, &old_edge);
        Ok((level, map))
    }

    /// [`Self::try_extract`] of increasing `faces`, with the extraction's edges taken from
    /// this level's instead of bucketed anew: the same level and map. An extracted edge keeps
    /// its ends and faces; `topology::build` numbers edges by smaller end vertex, then by first
    /// corner, and the extraction's vertex numbering increases with this level's, so each
    /// vertex's edges to larger vertices, in the order of their first extracted corner, are
    /// the next edges. Each vertex's one-ring is its ring here without the faces left out
    /// (`topology::RingBuilder`).
    pub fn extract_increasing(&self, faces: &[u32]) -> Result<(Level, Vec<u32>)> {
        let t = &self.topo;
        if faces.is_empty() {
            return Err(crate::Error::EmptyMesh(
                "topology needs vertices and faces".into(),
            ));
        }
        // Per face of this level: its index in the extraction, or `topology::NONE`.
        let mut sub_face = vec![topology::NONE; t.face_count()];
        let mut offsets = Vec::with_capacity(faces.len() + 1);
        offsets.push(0u32);
        let mut old_verts = Vec::with_capacity(faces.len() * 4);
        let mut corner_face = Vec::with_capacity(faces.len() * 4);
        let mut max_size = 0;
        for (i, &f) in faces.iter().enumerate() {
            if f as usize >= t.face_count() || (i > 0 && f <= faces[i - 1]) {
                return Err(crate::Error::Invalid(format!(
                    "extract: face {i} is {f}: faces must increase and be below {}",
                    t.face_count()
                )));
            }
            sub_face[f as usize] = i as u32;
            let fv = t.face_vertices(f);
            old_verts.extend_from_slice(fv);
            corner_face.extend(std::iter::repeat_n(i as u32, fv.len()));
            max_size = max_size.max(fv.len() as u32);
            offsets.push(old_verts.len() as u32);
        }
        let (map, local) = local_vertex_ids(&old_verts, t.vertex_count());
        drop(old_verts);
        let fvn = local.len();
        let mut face_edges = vec![topology::NONE; fvn];
        let mut edge_verts = Vec::with_capacity(fvn);
        let mut edge_faces = Vec::with_capacity(fvn);
        let mut edge_face_local = Vec::with_capacity(fvn);
        let mut old_edge = Vec::with_capacity(fvn);
        // Per vertex: (first extracted corner, edge) of its edges to larger vertices.
        let mut buf: Vec<(u32, u32)> = Vec::with_capacity(16);
        for &v in &map {
            buf.clear();
            for &e in t.vertex_edges(v) {
                if t.other_vertex(e, v) < v || buf.iter().any(|x| x.1 == e) {
                    continue;
                }
                let first = t
                    .edge_faces(e)
                    .iter()
                    .zip(t.edge_face_locals(e))
                    .filter(|(&g, _)| sub_face[g as usize] != topology::NONE)
                    .map(|(&g, &k)| offsets[sub_face[g as usize] as usize] + k as u32)
                    .min();
                if let Some(h) = first {
                    buf.push((h, e));
                }
            }
            buf.sort_unstable();
            for &(h, e) in &buf {
                let id = edge_verts.len() as u32;
                let i = corner_face[h as usize] as usize;
                let next = if h + 1 == offsets[i + 1] {
                    offsets[i]
                } else {
                    h + 1
                };
                edge_verts.push([local[h as usize], local[next as usize]]);
                face_edges[h as usize] = id;
                let mut ef = [i as u32, topology::NONE];
                let mut el = [(h - offsets[i]) as u16, 0];
                for (&g, &k) in t.edge_faces(e).iter().zip(t.edge_face_locals(e)) {
                    let j = sub_face[g as usize];
                    if j == topology::NONE {
                        continue;
                    }
                    let c = offsets[j as usize] + k as u32;
                    if c != h {
                        ef[1] = j;
                        el[1] = k;
                        face_edges[c as usize] = id;
                    }
                }
                edge_faces.push(ef);
                edge_face_local.push(el);
                old_edge.push(e);
            }
        }
        let connectivity = topology::Connectivity {
            face_offsets: offsets,
            face_verts: local,
            face_edges,
            edge_verts,
            edge_faces,
            edge_face_local,
        };
        drop(corner_face);
        // Each vertex's ring: its faces here that are extracted, fan by fan.
        let mut rings = topology::RingBuilder::new(
            &connectivity.face_offsets,
            &connectivity.face_edges,
            map.len(),
            fvn,
            connectivity.edge_verts.len(),
        );
        for &v in &map {
            rings.fans_of(t, v, |g, k| (sub_face[g as usize], k));
            rings.end_vertex();
        }
        let rings = rings.finish();
        // Zero here: `tag_extraction` copies the parent's sharpness and holes.
        let (ne, nf) = (
            connectivity.edge_verts.len(),
            connectivity.face_offsets.len() - 1,
        );
        let sub = topology::with_given_rings(
            map.len(),
            connectivity,
            rings,
            max_size,
            vec![0.0; ne],
            vec![false; nf],
        );
        let level = self.tag_extraction(sub, faces, &map, &old_edge);
        Ok((level, map))
    }

    /// The faces of vertex `v` extracted in a numbering that depends only on the ring's shape
    /// ([`RingCorners`]; for sharing limit masks between alike rings). Otherwise as
    /// [`Self::try_extract`] (sharpness, holes, cut edges, incomplete vertices); the map from
    /// new to old vertex ids does not increase.
    pub(crate) fn try_extract_ring(&self, mut ring: RingCorners) -> Result<(Level, Vec<u32>)> {
        let offsets = std::mem::take(&mut ring.offsets);
        let local = std::mem::take(&mut ring.local);
        let sub = topology::build(ring.map.len(), offsets, local, false)?;
        let mut old_edge = vec![u32::MAX; sub.edge_count()];
        for j in 0..ring.faces.len() {
            for (c, &e) in sub.face_edges(j as u32).iter().enumerate() {
                old_edge[e as usize] = ring.edge(&self.topo, j, c);
            }
        }
        let level = self.tag_extraction(sub, &ring.faces, &ring.map, &old_edge);
        Ok((level, ring.map))
    }

    /// An extraction's connectivity `sub` of `faces` (vertex map `map`, each edge's edge here
    /// `old_edge`) with this level's options, holes, no-limit faces and sharpness, and its cut
    /// edges and incomplete vertices.
    fn tag_extraction(
        &self,
        mut sub: Topology,
        faces: &[u32],
        map: &[u32],
        old_edge: &[u32],
    ) -> Level {
        let t = &self.topo;
        sub.options = t.options;
        for (i, &f) in faces.iter().enumerate() {
            sub.holes[i] = t.holes[f as usize];
        }
        if !t.no_limit.is_empty() {
            sub.no_limit = faces.iter().map(|&f| t.no_limit[f as usize]).collect();
        }
        let mut cut = vec![false; sub.edge_count()];
        for (e, c) in cut.iter_mut().enumerate() {
            let pe = old_edge[e];
            sub.edge_sharpness[e] = t.edge_sharpness[pe as usize];
            let opened = sub.edge_faces[e][1] == topology::NONE && !t.is_boundary_edge(pe);
            *c = opened || self.is_cut_edge(pe);
        }
        let mut incomplete = vec![false; sub.vertex_count()];
        for (v, &old) in map.iter().enumerate() {
            sub.vertex_sharpness[v] = t.vertex_sharpness[old as usize];
            incomplete[v] = !self.is_complete_vertex(old)
                || sub.vertex_faces(v as u32).len() != t.vertex_faces(old).len();
        }
        Level::with_flags(sub, cut, incomplete)
    }
}

/// The corners of a vertex's faces in a numbering that depends only on the ring's shape:
/// face `j` is the vertex's face `(first + j) % n` with its corners rotated to start at the
/// vertex, and vertices are numbered by first appearance in that corner list (the vertex is 0).
#[derive(Debug, Clone, Default)]
pub(crate) struct RingCorners {
    /// The level's faces, in ring order from the first.
    pub faces: Vec<u32>,
    /// Per face: the vertex's corner there (the face's corners start from it).
    pub rotation: Vec<u16>,
    /// Corner offsets per face (`faces.len() + 1`).
    pub offsets: Vec<u32>,
    /// New to old vertex ids.
    pub map: Vec<u32>,
    /// The corners, in new ids.
    pub local: Vec<u32>,
}

impl RingCorners {
    /// Makes this the ring of vertex `v` of `topo` from its face `first`, reusing the buffers
    /// (a caller that looks many rings up keeps one); `false`, leaving it empty, if `v` has no
    /// such face.
    pub fn fill(&mut self, topo: &Topology, v: u32, first: usize) -> bool {
        let ring = topo.vertex_faces(v);
        let locals = topo.vertex_face_locals(v);
        let n = ring.len();
        self.faces.clear();
        self.rotation.clear();
        self.offsets.clear();
        self.map.clear();
        self.local.clear();
        if first >= n {
            return false;
        }
        self.offsets.push(0);
        for j in 0..n {
            let k = (first + j) % n;
            let fv = topo.face_vertices(ring[k]);
            let r = usize::from(locals[k]);
            for c in 0..fv.len() {
                let old = fv[(r + c) % fv.len()];
                let id = match self.map.iter().position(|&x| x == old) {
                    Some(p) => p,
                    None => {
                        self.map.push(old);
                        self.map.len() - 1
                    }
                };
                self.local.push(id as u32);
            }
            self.faces.push(ring[k]);
            self.rotation.push(locals[k]);
            self.offsets.push(self.local.len() as u32);
        }
        true
    }

    /// Edge `c` of face `j` (joining its corners `c` and `c + 1`) in `topo`.
    #[inline]
    pub fn edge(&self, topo: &Topology, j: usize, c: usize) -> u32 {
        let fe = topo.face_edges(self.faces[j]);
        fe[(usize::from(self.rotation[j]) + c) % fe.len()]
    }
}

/// New vertex ids of an extraction in increasing old id: `map` new to old, and `old_verts`
/// (old ids of the extracted faces' corners, of a level of `vertex_count` vertices) renumbered.
/// A few faces of a large level (a vertex's ring, `subdiv::limit`) sort their corners instead
/// of marking them in an array of the level's size: the same ids either way.
pub(super) fn local_vertex_ids(old_verts: &[u32], vertex_count: usize) -> (Vec<u32>, Vec<u32>) {
    if old_verts.len() * 16 < vertex_count {
        sorted_vertex_ids(old_verts)
    } else {
        marked_vertex_ids(old_verts, vertex_count)
    }
}

/// `local_vertex_ids` by sorting the corners.
fn sorted_vertex_ids(old_verts: &[u32]) -> (Vec<u32>, Vec<u32>) {
    let mut map = old_verts.to_vec();
    map.sort_unstable();
    map.dedup();
    let local = old_verts
        .iter()
        .map(|&v| map.partition_point(|&x| x < v) as u32)
        .collect();
    (map, local)
}

/// `local_vertex_ids` by marking the corners in an array of the level's size.
fn marked_vertex_ids(old_verts: &[u32], vertex_count: usize) -> (Vec<u32>, Vec<u32>) {
    let mut local_of = vec![u32::MAX; vertex_count];
    for &v in old_verts {
        local_of[v as usize] = 0;
    }
    // At most one vertex a corner (no growth).
    let mut map = Vec::with_capacity(old_verts.len().min(vertex_count));
    for (v, l) in local_of.iter_mut().enumerate() {
        if *l == 0 {
            *l = map.len() as u32;
            map.push(v as u32);
        }
    }
    let local = old_verts.iter().map(|&v| local_of[v as usize]).collect();
    (map, local)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sorting path numbers vertices as the marking path does (increasing old id, each
    /// once), on corner lists with repeats, gaps and unsorted order.
    #[test]
    fn sorted_and_marked_vertex_ids_agree() {
        let lists: [&[u32]; 4] = [
            &[7, 3, 9, 3, 7, 12, 0, 9],
            &[5],
            &[40, 2, 2, 2, 39, 1, 40, 17, 16, 15],
            &[11, 10, 9, 8, 7, 6, 5, 4, 3, 2, 1, 0, 0, 1],
        ];
        for old in lists {
            let marked = marked_vertex_ids(old, 64);
            assert_eq!(sorted_vertex_ids(old), marked, "{old:?}");
            for (&o, &l) in old.iter().zip(&marked.1) {
                assert_eq!(marked.0[l as usize], o);
            }
        }
    }
}
