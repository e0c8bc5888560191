//! Validation of a [`super::ControlMeshDesc`] before it becomes a [`super::ControlMesh`].
//!
//! Checks, in this order, each refused with its own [`Error`] variant naming the element:
//! empty mesh, size mismatch, face with < 3 vertices, out-of-range index, non-finite coordinate,
//! coordinate beyond [`MAX_COORDINATE`], repeated vertex in a face, non-manifold edge (3+ faces), inconsistent winding across an edge,
//! non-manifold vertex (more than one fan of faces), then the tags: crease/corner/hole index out
//! of range, negative or NaN sharpness, crease on a pair that is not an edge.
//! Unreferenced vertices are reported as a [`MeshWarning`].
//!
//! Everything runs on flat arrays: half-edges are bucketed by their smaller vertex (counting
//! sort) and sorted by the larger one inside each bucket, and the fans around each vertex are
//! found with a union-find over face corners, so the cost is O(n log n) in the worst bucket and
//! close to linear on ordinary meshes.

use super::{ControlMeshDesc, MeshWarning};
use crate::error::TagKind;
use crate::{Error, Result};

/// Checks a description; the first problem found is returned, otherwise the warnings.
pub fn validate(desc: &ControlMeshDesc) -> Result<Vec<MeshWarning>> {
    check_structure(desc)?;
    let offsets = face_offsets(&desc.face_sizes);
    check_faces(desc, &offsets)?;
    let edges = EdgeIndex::build(&desc.face_vertices, &offsets, desc.positions.len());
    let referenced = edges.check_manifold(&desc.face_vertices)?;
    check_tags(desc, &edges)?;
    let unreferenced: Vec<u32> = (0..desc.positions.len() as u32)
        .filter(|&v| !referenced[v as usize])
        .collect();
    let mut warnings = Vec::new();
    if !unreferenced.is_empty() {
        warnings.push(MeshWarning::UnreferencedVertices(unreferenced));
    }
    Ok(warnings)
}

/// Largest coordinate magnitude accepted. Limit evaluation works in f64 and its normals take
/// products of up to four coordinates (1e30^4 = 1e120, far from f64's 1.8e308); positions go
/// to the GPU as f32 (at most 3.4e38). Larger values would overflow to infinity there, so they
/// are refused rather than rescaled (a rescaled mesh would no longer evaluate, sample or
/// capture at the file's coordinates). The GPU pipeline has a narrower range of its own,
/// checked where it draws.
pub const MAX_COORDINATE: f64 = 1e30;

/// Refuses the first vertex with a coordinate of magnitude beyond `limit` (validation uses
/// [`MAX_COORDINATE`]; a consumer with a narrower range, such as the f32 GPU pipeline, its own).
pub fn check_magnitude(positions: &[glam::DVec3], limit: f64) -> Result<()> {
    if let Some(v) = positions.iter().position(|p| p.abs().max_element() > limit) {
        return Err(Error::CoordinateTooLarge {
            vertex: v as u32,
            value: positions[v].abs().max_element(),
            limit,
        });
    }
    Ok(())
}

/// Empty mesh, sizes that cannot be indexed with `u32`, face sizes that do not add up.
fn check_structure(desc: &ControlMeshDesc) -> Result<()> {
    if desc.positions.is_empty() {
        return Err(Error::EmptyMesh("no vertices".into()));
    }
    if desc.face_sizes.is_empty() {
        return Err(Error::EmptyMesh("no faces".into()));
    }
    if desc.positions.len() >= u32::MAX as usize || desc.face_sizes.len() >= u32::MAX as usize {
        return Err(Error::Invalid(
            "more than 2^32 - 1 vertices or faces".into(),
        ));
    }
    let total: u64 = desc.face_sizes.iter().map(|&n| n as u64).sum();
    if total != desc.face_vertices.len() as u64 {
        return Err(Error::SizeMismatch {
            what: "face_vertices length vs. sum of face_sizes",
            expected: total,
            found: desc.face_vertices.len() as u64,
        });
    }
    if total >= u32::MAX as u64 {
        return Err(Error::Invalid("more than 2^32 - 1 face vertices".into()));
    }
    Ok(())
}

/// Prefix sums of the face sizes (only called once the total fits in `u32`).
fn face_offsets(sizes: &[u32]) -> Vec<u32> {
    let mut offsets = Vec::with_capacity(sizes.len() + 1);
    let mut acc = 0u32;
    offsets.push(0);
    for &n in sizes {
        acc += n;
        offsets.push(acc);
    }
    offsets
}

/// Face sizes, index ranges, coordinates, repeated vertices.
fn check_faces(desc: &ControlMeshDesc, offsets: &[u32]) -> Result<()> {
    if let Some(f) = desc.face_sizes.iter().position(|&n| n < 3) {
        return Err(Error::FaceTooSmall {
            face: f as u32,
            size: desc.face_sizes[f],
        });
    }
    let nv = desc.positions.len() as u32;
    if let Some(i) = desc.face_vertices.iter().position(|&v| v >= nv) {
        // The face containing corner i: the last offset <= i.
        let f = offsets.partition_point(|&o| o as usize <= i) - 1;
        return Err(Error::IndexOutOfRange {
            face: f as u32,
            corner: (i - offsets[f] as usize) as u32,
            index: desc.face_vertices[i],
            vertex_count: nv,
        });
    }
    if let Some(v) = desc.positions.iter().position(|p| !p.is_finite()) {
        return Err(Error::NonFiniteCoordinate { vertex: v as u32 });
    }
    check_magnitude(&desc.positions, MAX_COORDINATE)?;
    let mut scratch = Vec::new();
    for f in 0..desc.face_sizes.len() {
        let face = &desc.face_vertices[offsets[f] as usize..offsets[f + 1] as usize];
        if let Some(vertex) = repeated_vertex(face, &mut scratch) {
            return Err(Error::RepeatedVertex {
                face: f as u32,
                vertex,
            });
        }
    }
    Ok(())
}

/// A vertex that occurs twice in `face`, if any.
fn repeated_vertex(face: &[u32], scratch: &mut Vec<u32>) -> Option<u32> {
    if face.len() <= 8 {
        for i in 1..face.len() {
            if face[..i].contains(&face[i]) {
                return Some(face[i]);
            }
        }
        return None;
    }
    scratch.clear();
    scratch.extend_from_slice(face);
    scratch.sort_unstable();
    scratch.windows(2).find(|w| w[0] == w[1]).map(|w| w[0])
}

/// Undirected edges found by grouping half-edges.
///
/// Half-edge `h` is the corner `h` of `face_vertices` together with the next corner of its
/// face. `sorted` holds `(hi, h)` for every half-edge, bucketed by the smaller end vertex `lo`
/// (`lo_start[lo]..lo_start[lo + 1]`, a counting sort) and sorted by the larger end `hi`
/// inside each bucket.
struct EdgeIndex<'a> {
    next: Vec<u32>,
    offsets: &'a [u32],
    lo_start: Vec<u32>,
    sorted: Vec<(u32, u32)>,
}

impl<'a> EdgeIndex<'a> {
    fn build(fv: &[u32], offsets: &'a [u32], nv: usize) -> EdgeIndex<'a> {
        let nh = fv.len();
        let mut next = vec![0u32; nh];
        let mut lo_start = vec![0u32; nv + 1];
        for w in offsets.windows(2) {
            let (s, e) = (w[0] as usize, w[1] as usize);
            let face = &fv[s..e];
            for (k, n) in next[s..e].iter_mut().enumerate() {
                *n = (s + k + 1) as u32;
                let lo = face[k].min(face[(k + 1) % face.len()]);
                lo_start[lo as usize + 1] += 1;
            }
            next[e - 1] = s as u32;
        }
        for v in 0..nv {
            lo_start[v + 1] += lo_start[v];
        }
        let mut fill = lo_start.clone();
        let mut sorted = vec![(0u32, 0u32); nh];
        for (h, (&a, &n)) in fv.iter().zip(&next).enumerate() {
            let b = fv[n as usize];
            let lo = a.min(b) as usize;
            sorted[fill[lo] as usize] = (a.max(b), h as u32);
            fill[lo] += 1;
        }
        for v in 0..nv {
            let bucket = &mut sorted[lo_start[v] as usize..lo_start[v + 1] as usize];
            if bucket.len() <= 16 {
                // Insertion sort: buckets hold a handful of half-edges on ordinary meshes.
                for i in 1..bucket.len() {
                    let mut j = i;
                    while j > 0 && bucket[j - 1].0 > bucket[j].0 {
                        bucket.swap(j - 1, j);
                        j -= 1;
                    }
                }
            } else {
                bucket.sort_unstable_by_key(|e| e.0);
            }
        }
        EdgeIndex {
            next,
            offsets,
            lo_start,
            sorted,
        }
    }

    /// The face that corner `c` belongs to.
    fn face_of(&self, c: usize) -> u32 {
        (self.offsets.partition_point(|&o| o as usize <= c) - 1) as u32
    }

    /// Whether `a`-`b` is an edge of the mesh.
    fn contains(&self, a: u32, b: u32) -> bool {
        let (lo, hi) = (a.min(b) as usize, a.max(b));
        if a == b || lo + 1 >= self.lo_start.len() {
            return false;
        }
        let range = self.lo_start[lo] as usize..self.lo_start[lo + 1] as usize;
        self.sorted[range]
            .binary_search_by_key(&hi, |e| e.0)
            .is_ok()
    }

    /// Non-manifold edges, inconsistent winding, bow-tie vertices. Returns, per vertex, whether
    /// any face uses it.
    fn check_manifold(&self, fv: &[u32]) -> Result<Vec<bool>> {
        let nh = self.sorted.len();
        let mut fans = UnionFind::new(nh);
        let mut winding: Option<Error> = None;
        for lo in 0..self.lo_start.len() - 1 {
            let end = self.lo_start[lo + 1] as usize;
            let mut i = self.lo_start[lo] as usize;
            while i < end {
                let mut j = i + 1;
                let hi = self.sorted[i].0;
                while j < end && self.sorted[j].0 == hi {
                    j += 1;
                }
                if j - i > 2 {
                    return Err(Error::NonManifoldEdge {
                        v0: lo as u32,
                        v1: hi,
                        face_count: (j - i) as u32,
                    });
                }
                if j - i == 2 {
                    let (h1, h2) = (self.sorted[i].1, self.sorted[i + 1].1);
                    let (h1, h2) = (h1 as usize, h2 as usize);
                    let (n1, n2) = (self.next[h1], self.next[h2]);
                    if fv[h1] == fv[h2] {
                        if winding.is_none() {
                            let (f1, f2) = (self.face_of(h1), self.face_of(h2));
                            winding = Some(Error::InconsistentWinding {
                                face0: f1.min(f2),
                                face1: f1.max(f2),
                                v0: fv[h1],
                                v1: fv[n1 as usize],
                            });
                        }
                    } else {
                        // h1 runs a->b, h2 runs b->a: the corners at a (start of h1, end of
                        // h2) are neighbours in a's fan, and likewise at b.
                        fans.union(h1 as u32, n2);
                        fans.union(n1, h2 as u32);
                    }
                }
                i = j;
            }
        }
        if let Some(e) = winding {
            return Err(e);
        }
        let nv = self.lo_start.len() - 1;
        let mut root_of_vertex = vec![u32::MAX; nv];
        for c in 0..nh {
            let r = fans.find(c as u32);
            let v = fv[c] as usize;
            if root_of_vertex[v] == u32::MAX {
                root_of_vertex[v] = r;
            } else if root_of_vertex[v] != r {
                let mut roots: Vec<u32> = (0..nh as u32)
                    .filter(|&k| fv[k as usize] as usize == v)
                    .map(|k| fans.find(k))
                    .collect();
                roots.sort_unstable();
                roots.dedup();
                return Err(Error::NonManifoldVertex {
                    vertex: v as u32,
                    fans: roots.len() as u32,
                });
            }
        }
        Ok(root_of_vertex.iter().map(|&r| r != u32::MAX).collect())
    }
}

/// Disjoint sets over face corners (path halving, union by index).
struct UnionFind {
    parent: Vec<u32>,
}

impl UnionFind {
    fn new(n: usize) -> UnionFind {
        UnionFind {
            parent: (0..n as u32).collect(),
        }
    }

    fn find(&mut self, mut x: u32) -> u32 {
        while self.parent[x as usize] != x {
            let grand = self.parent[self.parent[x as usize] as usize];
            self.parent[x as usize] = grand;
            x = grand;
        }
        x
    }

    fn union(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            let (lo, hi) = (ra.min(rb), ra.max(rb));
            self.parent[hi as usize] = lo;
        }
    }
}

/// Tag indices in range, sharpness >= 0 and not NaN, creases on existing edges.
fn check_tags(desc: &ControlMeshDesc, edges: &EdgeIndex<'_>) -> Result<()> {
    let nv = desc.positions.len() as u32;
    let nf = desc.face_sizes.len() as u32;
    let bad_sharpness = |s: f32| s.is_nan() || s < 0.0;
    for (i, c) in desc.creases.iter().enumerate() {
        for v in [c.v0, c.v1] {
            if v >= nv {
                return Err(Error::TagIndexOutOfRange {
                    kind: TagKind::Crease,
                    index: i as u32,
                    value: v,
                    limit: nv,
                });
            }
        }
        if bad_sharpness(c.sharpness) {
            return Err(Error::InvalidSharpness {
                kind: TagKind::Crease,
                index: i as u32,
                sharpness: c.sharpness,
            });
        }
        if !edges.contains(c.v0, c.v1) {
            return Err(Error::CreaseNotAnEdge {
                crease: i as u32,
                v0: c.v0,
                v1: c.v1,
            });
        }
    }
    for (i, c) in desc.corners.iter().enumerate() {
        if c.vertex >= nv {
            return Err(Error::TagIndexOutOfRange {
                kind: TagKind::Corner,
                index: i as u32,
                value: c.vertex,
                limit: nv,
            });
        }
        if bad_sharpness(c.sharpness) {
            return Err(Error::InvalidSharpness {
                kind: TagKind::Corner,
                index: i as u32,
                sharpness: c.sharpness,
            });
        }
    }
    for (i, &h) in desc.holes.iter().enumerate() {
        if h >= nf {
            return Err(Error::TagIndexOutOfRange {
                kind: TagKind::Hole,
                index: i as u32,
                value: h,
                limit: nf,
            });
        }
    }
    Ok(())
}
