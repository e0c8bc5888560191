//! Construction of the connectivity (edges, edge-face and ordered vertex one-rings) from flat
//! face arrays, without hashing: half-edges are bucketed by their smaller end vertex; and of the
//! topology of a mesh, with its tags and boundary rule ([`Topology::new`]).

use super::connectivity::{Topology, NONE};
use super::par::{try_for_chunks, Shared};
use crate::mesh::{BoundaryInterpolation, ControlMesh, Crease, SchemeOptions, INFINITE_SHARPNESS};
use crate::{Error, Result};

/// Clamps a tag sharpness to `[0, INFINITE_SHARPNESS]`.
fn clamp_sharpness(s: f32) -> f32 {
    s.clamp(0.0, INFINITE_SHARPNESS)
}

impl Topology {
    /// Builds the topology of a validated mesh and applies its tags and boundary rule.
    ///
    /// Errors (never panics) on non-manifold edges or vertices, inconsistent winding, creases on
    /// missing edges and invalid sharpness, naming the element.
    pub fn new(mesh: &ControlMesh) -> Result<Topology> {
        let mut t = build(
            mesh.vertex_count(),
            mesh.face_offsets().to_vec(),
            mesh.face_vertices().to_vec(),
            true,
        )?;
        t.options = mesh.options();
        for c in mesh.creases() {
            t.set_crease(c)?;
        }
        for c in mesh.corners() {
            if c.sharpness.is_nan() || c.sharpness < 0.0 || c.vertex >= t.num_vertices {
                return Err(Error::Invalid(format!(
                    "corner {}: invalid vertex or sharpness {}",
                    c.vertex, c.sharpness
                )));
            }
            t.vertex_sharpness[c.vertex as usize] = clamp_sharpness(c.sharpness);
        }
        for f in 0..t.face_count() {
            t.holes[f] = mesh.is_hole(f);
        }
        t.apply_boundary_rule();
        if t.options.boundary == BoundaryInterpolation::None {
            let no_limit: Vec<bool> = (0..t.face_count() as u32)
                .map(|f| t.face_vertices(f).iter().any(|&v| t.is_boundary_vertex(v)))
                .collect();
            if no_limit.iter().any(|&x| x) {
                t.no_limit = no_limit;
            }
        }
        Ok(t)
    }

    /// This topology with the sharpness of each edge (`v0`, `v1`) of `creases` replaced by its
    /// `sharpness` (run-time creases). Errors naming the crease on a missing edge, an invalid
    /// sharpness or a boundary edge (infinitely sharp by the boundary rule).
    pub fn with_creases(&self, creases: &[Crease]) -> Result<Topology> {
        let mut t = self.clone();
        for c in creases {
            let e = t.set_crease(c)?;
            if t.edge_faces[e as usize][1] == NONE {
                return Err(Error::Invalid(format!(
                    "crease {}-{}: a boundary edge, infinitely sharp by the boundary rule",
                    c.v0, c.v1
                )));
            }
        }
        Ok(t)
    }

    /// Sets the sharpness of the edge of crease `c` (clamped to infinitely sharp) and returns
    /// the edge, naming the crease when its sharpness is invalid or it is no edge.
    fn set_crease(&mut self, c: &Crease) -> Result<u32> {
        if c.sharpness.is_nan() || c.sharpness < 0.0 {
            return Err(Error::Invalid(format!(
                "crease {}-{}: invalid sharpness {}",
                c.v0, c.v1, c.sharpness
            )));
        }
        let e = self
            .find_edge(c.v0, c.v1)
            .ok_or_else(|| Error::Invalid(format!("crease {}-{}: no such edge", c.v0, c.v1)))?;
        self.edge_sharpness[e as usize] = clamp_sharpness(c.sharpness);
        Ok(e)
    }

    /// Boundary edges become infinitely sharp; with `EdgeAndCorner`, boundary vertices with a
    /// single face become infinitely sharp corners.
    fn apply_boundary_rule(&mut self) {
        for e in 0..self.edge_count() {
            if self.edge_faces[e][1] == NONE {
                self.edge_sharpness[e] = INFINITE_SHARPNESS;
            }
        }
        if self.options.boundary == BoundaryInterpolation::EdgeAndCorner {
            for v in 0..self.vertex_count() {
                if self.vertex_faces(v as u32).len() == 1 {
                    self.vertex_sharpness[v] = INFINITE_SHARPNESS;
                }
            }
        }
    }
}

/// Builds the connectivity of `nv` vertices and the faces `face_offsets` / `face_verts`.
///
/// `strict`: a vertex whose faces form more than one fan is an error (non-manifold vertex).
/// Without it (extracted sub-meshes) the fans are listed one after the other, each starting
/// at its boundary edge. Sharpness is zero, no face is a hole.
pub(crate) fn build(
    nv: usize,
    face_offsets: Vec<u32>,
    face_verts: Vec<u32>,
    strict: bool,
) -> Result<Topology> {
    let nf = face_offsets.len().saturating_sub(1);
    let fv = face_verts.len();
    if nf == 0 || nv == 0 {
        return Err(Error::EmptyMesh("topology needs vertices and faces".into()));
    }
    if face_offsets[0] != 0 || face_offsets[nf] as usize != fv {
        return Err(Error::Invalid(
            "face offsets do not match the face-vertex array".into(),
        ));
    }
    let mut corner_face = vec![0u32; fv];
    let mut max_size = 0usize;
    for f in 0..nf {
        let (a, b) = (face_offsets[f] as usize, face_offsets[f + 1] as usize);
        if b < a + 3 {
            return Err(Error::Invalid(format!(
                "face {f} has fewer than 3 vertices"
            )));
        }
        if b - a > u16::MAX as usize {
            return Err(Error::Invalid(format!(
                "face {f} has {} vertices (at most {} supported)",
                b - a,
                u16::MAX
            )));
        }
        max_size = max_size.max(b - a);
        for (h, cf) in corner_face.iter_mut().enumerate().take(b).skip(a) {
            if face_verts[h] as usize >= nv {
                return Err(Error::Invalid(format!(
                    "face {f}: vertex index {} out of range",
                    face_verts[h]
                )));
            }
            *cf = f as u32;
        }
    }
    let next = |h: usize| -> usize {
        let f = corner_face[h] as usize;
        if h + 1 == face_offsets[f + 1] as usize {
            face_offsets[f] as usize
        } else {
            h + 1
        }
    };
    // Bucket half-edges by their smaller end vertex (counting sort).
    let mut bstart = vec![0u32; nv + 1];
    for h in 0..fv {
        let (a, b) = (face_verts[h], face_verts[next(h)]);
        if a == b {
            return Err(Error::Invalid(format!(
                "face {}: vertex {a} repeated",
                corner_face[h]
            )));
        }
        bstart[a.min(b) as usize + 1] += 1;
    }
    for v in 0..nv {
        bstart[v + 1] += bstart[v];
    }
    let mut cursor = bstart.clone();
    let mut entries = vec![(0u32, 0u32); fv];
    for h in 0..fv {
        let (a, b) = (face_verts[h], face_verts[next(h)]);
        let slot = &mut cursor[a.min(b) as usize];
        entries[*slot as usize] = (a.max(b), h as u32);
        *slot += 1;
    }
    drop(cursor);

    // Assign edge ids; an edge's orientation is that of its first face.
    let mut face_edges = vec![0u32; fv];
    let mut edge_verts: Vec<[u32; 2]> = Vec::with_capacity(fv / 2 + 16);
    let mut edge_faces: Vec<[u32; 2]> = Vec::with_capacity(fv / 2 + 16);
    let mut edge_face_local: Vec<[u16; 2]> = Vec::with_capacity(fv / 2 + 16);
    for v in 0..nv {
        let (lo, hi) = (bstart[v] as usize, bstart[v + 1] as usize);
        for i in lo..hi {
            let (other, h) = entries[i];
            let h = h as usize;
            let f = corner_face[h];
            let k = (h - face_offsets[f as usize] as usize) as u16;
            let found = entries[lo..i].iter().find(|x| x.0 == other);
            match found {
                Some(&(_, h0)) => {
                    let e = face_edges[h0 as usize] as usize;
                    if edge_faces[e][1] != NONE {
                        return Err(Error::Invalid(format!(
                            "non-manifold edge {}-{}: used by 3 or more faces (faces {}, {}, {f})",
                            edge_verts[e][0], edge_verts[e][1], edge_faces[e][0], edge_faces[e][1]
                        )));
                    }
                    if face_verts[h] != edge_verts[e][1] {
                        return Err(Error::Invalid(format!(
                            "inconsistent winding across edge {}-{} (faces {} and {f})",
                            edge_verts[e][0], edge_verts[e][1], edge_faces[e][0]
                        )));
                    }
                    edge_faces[e][1] = f;
                    edge_face_local[e][1] = k;
                    face_edges[h] = e as u32;
                }
                None => {
                    face_edges[h] = edge_verts.len() as u32;
                    edge_verts.push([face_verts[h], face_verts[next(h)]]);
                    edge_faces.push([f, NONE]);
                    edge_face_local.push([k, 0]);
                }
            }
        }
    }
    drop(entries);
    drop(bstart);

    let connectivity = Connectivity {
        face_offsets,
        face_verts,
        face_edges,
        edge_verts,
        edge_faces,
        edge_face_local,
    };
    with_rings(nv, connectivity, &corner_face, max_size as u32, strict)
}

/// Faces and edges of a topology ([`Topology`]'s fields of the same names).
pub(crate) struct Connectivity {
    pub(crate) face_offsets: Vec<u32>,
    pub(crate) face_verts: Vec<u32>,
    pub(crate) face_edges: Vec<u32>,
    pub(crate) edge_verts: Vec<[u32; 2]>,
    pub(crate) edge_faces: Vec<[u32; 2]>,
    pub(crate) edge_face_local: Vec<[u16; 2]>,
}

/// The topology of `nv` vertices and connectivity `c` (`corner_face`: the face of each flat
/// corner) with its one-rings ordered as [`build`] orders them (`strict` as there); sharpness
/// zero, no holes, default options.
fn with_rings(
    nv: usize,
    c: Connectivity,
    corner_face: &[u32],
    max_face_size: u32,
    strict: bool,
) -> Result<Topology> {
    let rings = order_rings(
        nv,
        &c.face_offsets,
        &c.face_verts,
        corner_face,
        &c.face_edges,
        &c.edge_faces,
        &c.edge_face_local,
        strict,
    )?;
    let (nf, ne) = (c.face_offsets.len() - 1, c.edge_verts.len());
    Ok(with_given_rings(
        nv,
        c,
        rings,
        max_face_size,
        vec![0.0; ne],
        vec![false; nf],
    ))
}

/// The topology of `nv` vertices, connectivity `c` and its one-rings `rings` (ordered as
/// [`build`] orders them, e.g. by [`super::fans::RingBuilder`]), per edge `edge_sharpness`
/// and per face `holes` (taken as given: the sparse refinement computes them, so they are
/// written once, not zeroed first); vertex sharpness zero, default options.
pub(crate) fn with_given_rings(
    nv: usize,
    c: Connectivity,
    rings: Rings,
    max_face_size: u32,
    edge_sharpness: Vec<f32>,
    holes: Vec<bool>,
) -> Topology {
    debug_assert_eq!(edge_sharpness.len(), c.edge_verts.len());
    debug_assert_eq!(holes.len(), c.face_offsets.len() - 1);
    Topology {
        num_vertices: nv as u32,
        face_offsets: c.face_offsets,
        face_verts: c.face_verts,
        face_edges: c.face_edges,
        edge_verts: c.edge_verts,
        edge_faces: c.edge_faces,
        edge_face_local: c.edge_face_local,
        vert_face_offsets: rings.vert_face_offsets,
        vert_faces: rings.vert_faces,
        vert_face_local: rings.vert_face_local,
        vert_edge_offsets: rings.vert_edge_offsets,
        vert_edges: rings.vert_edges,
        edge_sharpness,
        vertex_sharpness: vec![0.0; nv],
        promoted: Vec::new(),
        decayed_corner: Vec::new(),
        crease_factors: Vec::new(),
        holes,
        no_limit: Vec::new(),
        options: SchemeOptions::default(),
        max_face_size,
    }
}

/// The ordered one-rings of a connectivity ([`Topology`]'s fields of the same names).
pub(crate) struct Rings {
    pub(crate) vert_face_offsets: Vec<u32>,
    pub(crate) vert_faces: Vec<u32>,
    pub(crate) vert_face_local: Vec<u16>,
    pub(crate) vert_edge_offsets: Vec<u32>,
    pub(crate) vert_edges: Vec<u32>,
}

/// Orders every one-ring of `nv` vertices counter-clockwise (module conventions) from the
/// faces (`corner_face`: the face of each flat corner) and edges; `strict` as in [`build`]:
/// each fan starts at its boundary edge, fans in the order of their first corner, closed rings
/// at their first corner.
#[allow(clippy::too_many_arguments)]
fn order_rings(
    nv: usize,
    face_offsets: &[u32],
    face_verts: &[u32],
    corner_face: &[u32],
    face_edges: &[u32],
    edge_faces: &[[u32; 2]],
    edge_face_local: &[[u16; 2]],
    strict: bool,
) -> Result<Rings> {
    let fv = face_verts.len();
    let prev = |h: usize| -> usize {
        let f = corner_face[h] as usize;
        if h == face_offsets[f] as usize {
            face_offsets[f + 1] as usize - 1
        } else {
            h - 1
        }
    };
    // Vertex -> corners (unordered), and the number of one-ring edges per vertex.
    let mut vfo = vec![0u32; nv + 1];
    let mut veo = vec![0u32; nv + 1];
    for h in 0..fv {
        let v = face_verts[h] as usize;
        vfo[v + 1] += 1;
        veo[v + 1] += 1;
        if edge_faces[face_edges[h] as usize][1] == NONE {
            veo[v + 1] += 1;
        }
    }
    for v in 0..nv {
        vfo[v + 1] += vfo[v];
        veo[v + 1] += veo[v];
    }
    let mut raw = vec![0u32; fv];
    let mut cursor = vfo.clone();
    for h in 0..fv {
        let slot = &mut cursor[face_verts[h] as usize];
        raw[*slot as usize] = h as u32;
        *slot += 1;
    }
    drop(cursor);

    // Order every one-ring counter-clockwise.
    let mut vert_faces = vec![0u32; fv];
    let mut vert_face_local = vec![0u16; fv];
    let mut vert_edges = vec![0u32; veo[nv] as usize];
    let (sf, sl, se) = (
        Shared::new(&mut vert_faces),
        Shared::new(&mut vert_face_local),
        Shared::new(&mut vert_edges),
    );
    let is_bnd = |e: u32| edge_faces[e as usize][1] == NONE;
    try_for_chunks(nv, |lo, hi| {
        let mut visited: Vec<bool> = Vec::new();
        let mut fbuf: Vec<u32> = Vec::new();
        let mut lbuf: Vec<u16> = Vec::new();
        let mut ebuf: Vec<u32> = Vec::new();
        for v in lo..hi {
            let (a, b) = (vfo[v] as usize, vfo[v + 1] as usize);
            let corners = &raw[a..b];
            let n = corners.len();
            visited.clear();
            visited.resize(n, false);
            fbuf.clear();
            lbuf.clear();
            ebuf.clear();
            let mut fans = 0;
            for pass in 0..2 {
                for s in 0..n {
                    if visited[s] {
                        continue;
                    }
                    let h = corners[s] as usize;
                    if pass == 0 && !is_bnd(face_edges[h]) {
                        continue;
                    }
                    fans += 1;
                    if strict && fans > 1 {
                        return Err(Error::Invalid(format!(
                            "non-manifold vertex {v}: its faces form more than one fan"
                        )));
                    }
                    let mut cur = s;
                    ebuf.push(face_edges[h]);
                    loop {
                        visited[cur] = true;
                        let h = corners[cur] as usize;
                        let f = corner_face[h];
                        let k = h - face_offsets[f as usize] as usize;
                        fbuf.push(f);
                        lbuf.push(k as u16);
                        let hp = prev(h);
                        let ine = face_edges[hp];
                        if is_bnd(ine) {
                            ebuf.push(ine);
                            break;
                        }
                        let kp = (hp - face_offsets[f as usize] as usize) as u16;
                        let ef = edge_faces[ine as usize];
                        let el = edge_face_local[ine as usize];
                        let (g, l) = if ef[0] == f && el[0] == kp {
                            (ef[1], el[1])
                        } else {
                            (ef[0], el[0])
                        };
                        let hg = face_offsets[g as usize] as usize + l as usize;
                        let j = corners.iter().position(|&c| c as usize == hg);
                        let Some(j) = j else {
                            return Err(Error::Invalid(format!(
                                "inconsistent winding around vertex {v} (faces {f} and {g})"
                            )));
                        };
                        if visited[j] {
                            break;
                        }
                        ebuf.push(ine);
                        cur = j;
                    }
                }
            }
            let (ea, eb) = (veo[v] as usize, veo[v + 1] as usize);
            if fbuf.len() != n || ebuf.len() != eb - ea {
                return Err(Error::Invalid(format!(
                    "vertex {v}: its one-ring cannot be ordered (non-manifold)"
                )));
            }
            // SAFETY: vertex ranges of monotone prefix sums are disjoint between vertices.
            unsafe {
                sf.range(a, b).copy_from_slice(&fbuf);
                sl.range(a, b).copy_from_slice(&lbuf);
                se.range(ea, eb).copy_from_slice(&ebuf);
            }
        }
        Ok(())
    })?;

    Ok(Rings {
        vert_face_offsets: vfo,
        vert_faces,
        vert_face_local,
        vert_edge_offsets: veo,
        vert_edges,
    })
}
