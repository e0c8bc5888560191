//! One uniform Catmull-Clark step: the child topology derived directly from the parent (no
//! hashing); the refinement matrix of the child vertices is in [`super::points`].
//!
//! Child vertices: `[face points | edge points | vertex points]`. Child faces: corner `k` of
//! parent face `f` (at flat index `h = face_offsets[f] + k`) gives the quad `(vertex point of
//! corner k, edge point of edge k, face point, edge point of edge k-1)`. Child edges:
//! `[one per parent corner h, from the edge point of edge k to the face point | two halves per
//! parent edge e at 2e and 2e + 1, starting at its first and second end]`.

use super::level::{local_vertex_ids, Level};
use super::rules::{child_edge_sharpness, decrement};
use super::sparse::SparseMatrix;
use crate::topology::par::{fill, for_chunks, Shared, CHUNK};
use crate::topology::{self, Topology, NONE};
use crate::{Error, Result};

impl Level {
    /// One uniform Catmull-Clark step: the child level and the matrix giving the child vertices
    /// from this level's vertices.
    pub fn refine(&self) -> (Level, SparseMatrix) {
        if self.topo.corner_count() < 4 * CHUNK {
            return (self.refine_topology(), self.refine_matrix());
        }
        rayon::join(|| self.refine_topology(), || self.refine_matrix())
    }

    /// Vertex indices of the child faces only (four per parent corner, in the order of
    /// [`Level::refine_topology`]'s faces): all that drawing the last level of a uniform
    /// refinement needs. OpenSubdiv's uniform refinement does the same by default
    /// (`fullTopologyInLastLevel = false`).
    pub fn refine_face_vertices(&self) -> Vec<u32> {
        let t = &self.topo;
        let (nf, fv) = (t.face_count(), t.corner_count());
        let mut face_verts = vec![0u32; 4 * fv];
        let shared = Shared::new(&mut face_verts);
        // SAFETY: every parent face writes only the four child slots of each of its corners.
        for_chunks(nf, |lo, hi| {
            let a = t.face_offsets[lo] as usize;
            let b = t.face_offsets[hi] as usize;
            let out = unsafe { shared.range(4 * a, 4 * b) };
            for f in lo..hi {
                let off = t.face_offsets[f] as usize;
                let n = t.face_offsets[f + 1] as usize - off;
                for k in 0..n {
                    let h = off + k;
                    let hp = if k == 0 { off + n - 1 } else { h - 1 };
                    let i = 4 * (h - a);
                    out[i..i + 4].copy_from_slice(&child_face(t, f, h, hp));
                }
            }
        });
        face_verts
    }

    /// Uniform refinement by `depth` levels keeping only the last level's face vertices
    /// (quads, four indices each, into that level's vertices `[face | edge | vertex points]`):
    /// full topology for the intermediate levels, [`Level::refine_face_vertices`] for the last.
    pub fn uniform_face_vertices(&self, depth: u32) -> Vec<u32> {
        if depth == 0 {
            return self.topo.face_verts.clone();
        }
        let mut current: Option<Level> = None;
        for _ in 1..depth {
            let next = current.as_ref().unwrap_or(self).refine_topology();
            current = Some(next);
        }
        current.as_ref().unwrap_or(self).refine_face_vertices()
    }

    /// The child level only (topology, sharpness, holes, completeness).
    pub fn refine_topology(&self) -> Level {
        let t = &self.topo;
        let (nf, ne, nv, fv) = (
            t.face_count(),
            t.edge_count(),
            t.vertex_count(),
            t.corner_count(),
        );
        let cnv = nf + ne + nv;
        let cne = fv + 2 * ne;
        let ep = |e: u32| nf as u32 + e;
        let vp = |v: u32| (nf + ne) as u32 + v;
        let half = |e: u32, v: u32| -> u32 {
            (fv + 2 * e as usize + (t.edge_verts[e as usize][0] != v) as usize) as u32
        };

        // Prefix of edge face counts, for the rings of the edge points.
        let mut epre = vec![0u32; ne + 1];
        for e in 0..ne {
            epre[e + 1] = epre[e] + 1 + (t.edge_faces[e][1] != NONE) as u32;
        }
        let mut vfo = vec![0u32; cnv + 1];
        let mut veo = vec![0u32; cnv + 1];
        {
            let (vf_f, rest) = vfo.split_at_mut(nf);
            let (vf_e, vf_v) = rest.split_at_mut(ne);
            vf_f.copy_from_slice(&t.face_offsets[..nf]);
            fill(vf_e, |e| fv as u32 + 2 * epre[e]);
            let base = fv as u32 + 2 * epre[ne];
            fill(vf_v, |v| base + t.vert_face_offsets[v]);
            let (ve_f, rest) = veo.split_at_mut(nf);
            let (ve_e, ve_v) = rest.split_at_mut(ne);
            ve_f.copy_from_slice(&t.face_offsets[..nf]);
            fill(ve_e, |e| (fv + 2 * e) as u32 + epre[e]);
            let base = (fv + 2 * ne) as u32 + epre[ne];
            fill(ve_v, |v| base + t.vert_edge_offsets[v]);
        }
        let mut face_offsets = vec![0u32; fv + 1];
        fill(&mut face_offsets, |i| 4 * i as u32);
        let mut face_verts = vec![0u32; 4 * fv];
        let mut face_edges = vec![0u32; 4 * fv];
        let mut edge_verts = vec![[0u32; 2]; cne];
        let mut edge_faces = vec![[0u32; 2]; cne];
        let mut edge_face_local = vec![[0u16; 2]; cne];
        let mut edge_sharpness = vec![0f32; cne];
        let mut vert_faces = vec![0u32; 4 * fv];
        let mut vert_face_local = vec![0u16; 4 * fv];
        let mut vert_edges = vec![0u32; veo[cnv] as usize];
        let mut vertex_sharpness = vec![0f32; cnv];
        let mut holes = vec![false; fv];
        let s_fv = Shared::new(&mut face_verts);
        let s_fe = Shared::new(&mut face_edges);
        let s_ev = Shared::new(&mut edge_verts);
        let s_ef = Shared::new(&mut edge_faces);
        let s_el = Shared::new(&mut edge_face_local);
        let s_es = Shared::new(&mut edge_sharpness);
        let s_vf = Shared::new(&mut vert_faces);
        let s_vl = Shared::new(&mut vert_face_local);
        let s_ve = Shared::new(&mut vert_edges);
        let s_vs = Shared::new(&mut vertex_sharpness);
        let s_h = Shared::new(&mut holes);

        // SAFETY (all three passes): every parent face / edge / vertex writes only the child
        // ranges it owns: corner ranges of its face, slots 2e and 2e + 1, and its own ring
        // range given by the monotone offsets `vfo` / `veo`.
        for_chunks(nf, |lo, hi| {
            let (a, b) = (t.face_offsets[lo] as usize, t.face_offsets[hi] as usize);
            let (fvs, fes, evs, efs, els, vfs, vls, ves, hs) = unsafe {
                (
                    s_fv.range(4 * a, 4 * b),
                    s_fe.range(4 * a, 4 * b),
                    s_ev.range(a, b),
                    s_ef.range(a, b),
                    s_el.range(a, b),
                    s_vf.range(a, b),
                    s_vl.range(a, b),
                    s_ve.range(a, b),
                    s_h.range(a, b),
                )
            };
            for f in lo..hi {
                let off = t.face_offsets[f] as usize;
                let n = t.face_offsets[f + 1] as usize - off;
                let hole = t.holes[f];
                for k in 0..n {
                    let h = off + k;
                    let hp = if k == 0 { off + n - 1 } else { h - 1 };
                    let hn = if k + 1 == n { off } else { h + 1 };
                    let v = t.face_verts[h];
                    let (ek, ekm) = (t.face_edges[h], t.face_edges[hp]);
                    let i = h - a;
                    fvs[4 * i..4 * i + 4].copy_from_slice(&child_face(t, f, h, hp));
                    fes[4 * i..4 * i + 4].copy_from_slice(&[
                        half(ek, v),
                        h as u32,
                        hp as u32,
                        half(ekm, v),
                    ]);
                    evs[i] = [ep(ek), f as u32];
                    efs[i] = [h as u32, hn as u32];
                    els[i] = [1, 2];
                    hs[i] = hole;
                    vfs[i] = h as u32;
                    vls[i] = 2;
                    ves[i] = hp as u32;
                }
            }
        });

        for_chunks(ne, |lo, hi| {
            let (evs, efs, els, ess) = unsafe {
                (
                    s_ev.range(fv + 2 * lo, fv + 2 * hi),
                    s_ef.range(fv + 2 * lo, fv + 2 * hi),
                    s_el.range(fv + 2 * lo, fv + 2 * hi),
                    s_es.range(fv + 2 * lo, fv + 2 * hi),
                )
            };
            let (ra, rb) = (vfo[nf + lo] as usize, vfo[nf + hi] as usize);
            let (ea, eb) = (veo[nf + lo] as usize, veo[nf + hi] as usize);
            let (vfs, vls, ves) =
                unsafe { (s_vf.range(ra, rb), s_vl.range(ra, rb), s_ve.range(ea, eb)) };
            for e in lo..hi {
                let [a, b] = t.edge_verts[e];
                let [f0, f1] = t.edge_faces[e];
                let [k0, k1] = t.edge_face_local[e];
                let off0 = t.face_offsets[f0 as usize];
                let n0 = t.face_offsets[f0 as usize + 1] - off0;
                let c00 = off0 + k0 as u32;
                let c01 = off0 + next_corner(k0 as u32, n0);
                let h0 = (fv + 2 * e) as u32;
                let i = 2 * (e - lo);
                evs[i] = [vp(a), ep(e as u32)];
                evs[i + 1] = [ep(e as u32), vp(b)];
                ess[i] = child_edge_sharpness(t, e as u32, a);
                ess[i + 1] = child_edge_sharpness(t, e as u32, b);
                let r = vfo[nf + e] as usize - ra;
                let q = veo[nf + e] as usize - ea;
                if f1 != NONE {
                    let off1 = t.face_offsets[f1 as usize];
                    let n1 = t.face_offsets[f1 as usize + 1] - off1;
                    let c10 = off1 + k1 as u32;
                    let c11 = off1 + next_corner(k1 as u32, n1);
                    efs[i] = [c00, c11];
                    els[i] = [0, 3];
                    efs[i + 1] = [c01, c10];
                    els[i + 1] = [3, 0];
                    vfs[r..r + 4].copy_from_slice(&[c00, c11, c10, c01]);
                    vls[r..r + 4].copy_from_slice(&[1, 3, 1, 3]);
                    ves[q..q + 4].copy_from_slice(&[c00, h0, c10, h0 + 1]);
                } else {
                    efs[i] = [c00, NONE];
                    els[i] = [0, 0];
                    efs[i + 1] = [c01, NONE];
                    els[i + 1] = [3, 0];
                    vfs[r..r + 2].copy_from_slice(&[c01, c00]);
                    vls[r..r + 2].copy_from_slice(&[3, 1]);
                    ves[q..q + 3].copy_from_slice(&[h0 + 1, c00, h0]);
                }
            }
        });

        for_chunks(nv, |lo, hi| {
            let (ra, rb) = (vfo[nf + ne + lo] as usize, vfo[nf + ne + hi] as usize);
            let (ea, eb) = (veo[nf + ne + lo] as usize, veo[nf + ne + hi] as usize);
            let (vfs, vls, ves, vss) = unsafe {
                (
                    s_vf.range(ra, rb),
                    s_vl.range(ra, rb),
                    s_ve.range(ea, eb),
                    s_vs.range(nf + ne + lo, nf + ne + hi),
                )
            };
            for v in lo..hi {
                let r = vfo[nf + ne + v] as usize - ra;
                for (j, (&g, &l)) in t
                    .vertex_faces(v as u32)
                    .iter()
                    .zip(t.vertex_face_locals(v as u32))
                    .enumerate()
                {
                    vfs[r + j] = t.face_offsets[g as usize] + l as u32;
                    vls[r + j] = 0;
                }
                let q = veo[nf + ne + v] as usize - ea;
                for (j, &e) in t.vertex_edges(v as u32).iter().enumerate() {
                    ves[q + j] = half(e, v as u32);
                }
                vss[v - lo] = decrement(t.vertex_sharpness[v]);
            }
        });

        let topo = Topology {
            num_vertices: cnv as u32,
            face_offsets,
            face_verts,
            face_edges,
            edge_verts,
            edge_faces,
            edge_face_local,
            vert_face_offsets: vfo,
            vert_faces,
            vert_face_local,
            vert_edge_offsets: veo,
            vert_edges,
            edge_sharpness,
            vertex_sharpness,
            promoted: Vec::new(),
            decayed_corner: Vec::new(),
            holes,
            no_limit: child_no_limit(t),
            options: t.options,
            max_face_size: 4,
        };
        let (cut, incomplete) = self.child_flags();
        Level {
            topo,
            cut,
            incomplete,
        }
    }

    /// The child faces `keep` (flat parent corner indices, increasing) of this level's
    /// refinement as a level of their own, with the map from its vertices to the child
    /// numbering `[face points | edge points | vertex points]`: the same level and map as
    /// `self.refine_topology().try_extract(keep)`, without building the whole child level nor
    /// bucketing the kept quads' edges. Every child edge is a spoke (face point to the edge
    /// point of a face's corner) or a half of a parent edge; in the child vertices' increasing
    /// order (face points, then edge points) its id, ends, faces, sharpness and cut flag follow
    /// from the parent by index arithmetic, in the order `topology::build` gives them (by
    /// smaller end vertex, then by first corner), and so do the one-rings (`kept_rings`).
    ///
    /// The sparse step of feature-adaptive refinement (Köbler 2013 §3.3; OpenSubdiv's
    /// `Vtr::Refinement` with sparse selection): `keep` is the refined faces' children and
    /// their ring, a fraction of the child level.
    pub fn refine_kept(&self, keep: &[u32]) -> Result<(Level, Vec<u32>)> {
        let t = &self.topo;
        let (nf, ne, fv) = (t.face_count(), t.edge_count(), t.corner_count());
        let cnv = nf + ne + t.vertex_count();
        if keep.is_empty() {
            return Err(Error::EmptyMesh("topology needs vertices and faces".into()));
        }
        // Per parent corner: its kept child's index, or NONE.
        let mut kept = vec![NONE; fv];
        let mut parent_face = Vec::with_capacity(keep.len());
        let mut old_verts = Vec::with_capacity(4 * keep.len());
        let mut f = 0usize;
        for (i, &h) in keep.iter().enumerate() {
            if h as usize >= fv || (i > 0 && h <= keep[i - 1]) {
                return Err(Error::Invalid(format!(
                    "refine_kept: child face {i} is corner {h}: corners must increase and be \
                     below {fv}"
                )));
            }
            while t.face_offsets[f + 1] <= h {
                f += 1;
            }
            kept[h as usize] = i as u32;
            parent_face.push(f as u32);
            old_verts.extend_from_slice(&child_face(t, f, h as usize, prev_corner(t, f, h)));
        }
        let nk = keep.len();
        let (map, local) = local_vertex_ids(&old_verts, cnv);
        drop(old_verts);

        // Edges, in `topology::build`'s order: by smaller end (face points before edge
        // points, vertex points never), then by first corner (kept child `i`, edge `k`).
        let mut edges = KeptEdges::new(nk);
        // Per edge point of `map`, in order: its kept children (`edge_point_children`).
        let mut edge_children = Vec::with_capacity(map.len());
        for &old in &map {
            let o = old as usize;
            if o < nf {
                // The spokes of face `o`: child `c` (edge 1) and child `c + 1` (edge 2) of
                // spoke `c`; kept children in increasing corner order are in increasing `i`.
                let off = t.face_offsets[o] as usize;
                let n = t.face_offsets[o + 1] as usize - off;
                for c in 0..n {
                    let i = kept[off + c];
                    if i == NONE {
                        continue;
                    }
                    for (s, k) in [(c, 1u16), ((c + n - 1) % n, 2)] {
                        if edges.face_edges[4 * i as usize + k as usize] != NONE {
                            continue;
                        }
                        let other = if k == 1 {
                            (kept[off + (s + 1) % n], 2)
                        } else {
                            (kept[off + s], 1)
                        };
                        let second = (other.0 != NONE).then_some(other);
                        edges.push(&local, (i, k), second, 0.0, second.is_none());
                    }
                }
            } else if o < nf + ne {
                let e = (o - nf) as u32;
                let [a, b] = t.edge_verts[e as usize];
                // The half at `a`: edge 0 of the child at `a` in `f0`, edge 3 of the one in
                // `f1`; the half at `b` the other way round.
                let children = edge_point_children(t, &kept, e);
                edge_children.push(children);
                let [c00, c01, c10, c11] = children;
                let mut halves =
                    [((c00, 0u16), (c11, 3u16), a), ((c10, 0), (c01, 3), b)].map(|(x, y, v)| {
                        let (first, second) = if y.0 < x.0 { (y, x) } else { (x, y) };
                        (first, second, v)
                    });
                if halves[1].0 .0 < halves[0].0 .0 {
                    halves.swap(0, 1);
                }
                for (first, second, v) in halves {
                    if first.0 == NONE {
                        continue;
                    }
                    let second = (second.0 != NONE).then_some(second);
                    let opened = second.is_none() && !t.is_boundary_edge(e);
                    let sharp = child_edge_sharpness(t, e, v);
                    let c = opened || self.is_cut_edge(e);
                    edges.push(&local, first, second, sharp, c);
                }
            } else {
                break;
            }
        }
        let face_offsets: Vec<u32> = (0..=nk as u32).map(|i| 4 * i).collect();
        let rings = self.kept_rings(
            &kept,
            &map,
            &edge_children,
            &face_offsets,
            &edges.face_edges,
            edges.verts.len(),
        );
        let connectivity = topology::Connectivity {
            face_offsets,
            face_verts: local,
            face_edges: edges.face_edges,
            edge_verts: edges.verts,
            edge_faces: edges.faces,
            edge_face_local: edges.locals,
        };
        let mut sub = topology::with_given_rings(map.len(), connectivity, rings, 4);
        sub.edge_sharpness = edges.sharpness;
        sub.holes = parent_face.iter().map(|&f| t.holes[f as usize]).collect();
        if !t.no_limit.is_empty() {
            sub.no_limit = parent_face
                .iter()
                .map(|&f| t.no_limit[f as usize])
                .collect();
        }
        sub.options = t.options;
        // A child vertex is incomplete when its child-level counterpart is (`child_flags`) or
        // when the kept quads miss some of its faces there.
        let flagged = !(self.cut.is_empty() && self.incomplete.is_empty());
        let bad = |v: u32| !self.is_complete_vertex(v);
        let face_bad = |f: u32| t.face_vertices(f).iter().any(|&v| bad(v));
        let mut incomplete = vec![false; map.len()];
        for (v, &old) in map.iter().enumerate() {
            let o = old as usize;
            let (valence, inc) = if o < nf {
                (t.face_size(old), flagged && face_bad(old))
            } else if o < nf + ne {
                let e = old - nf as u32;
                let faces = t.edge_faces(e);
                let inc = flagged && (self.is_cut_edge(e) || faces.iter().any(|&f| face_bad(f)));
                (2 * faces.len(), inc)
            } else {
                let pv = old - (nf + ne) as u32;
                sub.vertex_sharpness[v] = decrement(t.vertex_sharpness[pv as usize]);
                let faces = t.vertex_faces(pv);
                let inc = flagged && (bad(pv) || faces.iter().any(|&f| face_bad(f)));
                (faces.len(), inc)
            };
            incomplete[v] = inc || sub.vertex_faces(v as u32).len() != valence;
        }
        Ok((Level::with_flags(sub, edges.cut, incomplete), map))
    }

    /// The one-rings of `Level::refine_kept`'s level (kept child `kept[h]` of each corner `h`,
    /// NONE if not kept; its vertices `map` in the child numbering, its edge points' kept
    /// children `edge_children` in that order; its quads' `face_offsets` and `face_edges`,
    /// `edges` edges) from this level's: a face point's ring is its face's children (corner 2,
    /// in corner order), an edge point's the children beside the edge (corners 1 and 3, as
    /// `refine_topology` orders them), a vertex point's the children at its faces' corners
    /// (corner 0) in its ring's order, fan by fan; the kept ones ordered as `topology::build`
    /// orders them ([`topology::RingBuilder`]; a single fan by its quad arithmetic).
    fn kept_rings(
        &self,
        kept: &[u32],
        map: &[u32],
        edge_children: &[[u32; 4]],
        face_offsets: &[u32],
        face_edges: &[u32],
        edges: usize,
    ) -> topology::Rings {
        let t = &self.topo;
        let (nf, ne) = (t.face_count(), t.edge_count());
        let mut rings = topology::RingBuilder::new(
            face_offsets,
            face_edges,
            map.len(),
            face_edges.len(),
            edges,
        );
        let mut edge_children = edge_children.iter();
        let mut fan = Vec::with_capacity(16);
        for &old in map {
            let o = old as usize;
            fan.clear();
            if o < nf {
                let (a, b) = (t.face_offsets[o] as usize, t.face_offsets[o + 1] as usize);
                fan.extend(kept[a..b].iter().map(|&i| (i, 2)));
                rings.quad_fan(true, &fan);
            } else if o < nf + ne {
                let [c00, c01, c10, c11] = *edge_children
                    .next()
                    .expect("an edge point's children per edge point");
                if t.edge_faces[o - nf][1] == NONE {
                    rings.quad_fan(false, &[(c01, 3), (c00, 1)]);
                } else {
                    rings.quad_fan(true, &[(c00, 1), (c11, 3), (c10, 1), (c01, 3)]);
                }
            } else {
                let v = old - (nf + ne) as u32;
                let child = |g: u32, k: u16| {
                    (
                        kept[(t.face_offsets[g as usize] + u32::from(k)) as usize],
                        0,
                    )
                };
                let (faces, locals) = (t.vertex_faces(v), t.vertex_face_locals(v));
                let open = t.vertex_edges(v).len() - faces.len();
                if open <= 1 {
                    fan.extend(faces.iter().zip(locals).map(|(&g, &k)| child(g, k)));
                    rings.quad_fan(open == 0, &fan);
                } else {
                    rings.fans_of(t, v, child);
                    rings.end_vertex();
                }
            }
        }
        rings.finish()
    }

    /// Cut edges and incomplete vertices of the child level (empty vectors when none).
    fn child_flags(&self) -> (Vec<bool>, Vec<bool>) {
        if self.cut.is_empty() && self.incomplete.is_empty() {
            return (Vec::new(), Vec::new());
        }
        let t = &self.topo;
        let (nf, ne, nv, fv) = (
            t.face_count(),
            t.edge_count(),
            t.vertex_count(),
            t.corner_count(),
        );
        let bad = |v: u32| !self.is_complete_vertex(v);
        let face_bad = |f: u32| t.face_vertices(f).iter().any(|&v| bad(v));
        let mut cut = vec![false; fv + 2 * ne];
        if !self.cut.is_empty() {
            for e in 0..ne {
                cut[fv + 2 * e] = self.cut[e];
                cut[fv + 2 * e + 1] = self.cut[e];
            }
        }
        let mut inc = vec![false; nf + ne + nv];
        for (f, x) in inc[..nf].iter_mut().enumerate() {
            *x = face_bad(f as u32);
        }
        for e in 0..ne {
            inc[nf + e] =
                self.is_cut_edge(e as u32) || t.edge_faces(e as u32).iter().any(|&f| face_bad(f));
        }
        for v in 0..nv {
            inc[nf + ne + v] =
                bad(v as u32) || t.vertex_faces(v as u32).iter().any(|&f| face_bad(f));
        }
        let any_cut = cut.iter().any(|&c| c);
        let any_inc = inc.iter().any(|&c| c);
        (
            if any_cut { cut } else { Vec::new() },
            if any_inc { inc } else { Vec::new() },
        )
    }
}

/// The no-limit flags of the child faces: inherited from their parent face.
fn child_no_limit(t: &Topology) -> Vec<bool> {
    if t.no_limit.is_empty() {
        return Vec::new();
    }
    let mut out = vec![false; t.corner_count()];
    for f in 0..t.face_count() {
        let (a, b) = (t.face_offsets[f] as usize, t.face_offsets[f + 1] as usize);
        out[a..b].fill(t.no_limit[f]);
    }
    out
}

/// The kept children (`kept`, per corner) beside edge `e`'s edge point: at its first face's
/// corner at the edge's first end and at the next corner, then the same in its second face
/// (NONE where not kept or there is no second face).
fn edge_point_children(t: &Topology, kept: &[u32], e: u32) -> [u32; 4] {
    let [f0, f1] = t.edge_faces[e as usize];
    let [k0, k1] = t.edge_face_local[e as usize];
    let corner = |g: u32, k: u16, step: u32| -> u32 {
        let off = t.face_offsets[g as usize];
        let n = t.face_offsets[g as usize + 1] - off;
        kept[(off + (k as u32 + step) % n) as usize]
    };
    let (c00, c01) = (corner(f0, k0, 0), corner(f0, k0, 1));
    let (c10, c11) = if f1 == NONE {
        (NONE, NONE)
    } else {
        (corner(f1, k1, 0), corner(f1, k1, 1))
    };
    [c00, c01, c10, c11]
}

/// The child quad of corner `h` (previous corner `hp`) of parent face `f`: (vertex point of the
/// corner, edge point of its edge, face point, edge point of the previous edge).
fn child_face(t: &Topology, f: usize, h: usize, hp: usize) -> [u32; 4] {
    let (nf, ne) = (t.face_count() as u32, t.edge_count() as u32);
    [
        nf + ne + t.face_verts[h],
        nf + t.face_edges[h],
        f as u32,
        nf + t.face_edges[hp],
    ]
}

/// `(k + 1) % n` for `k < n`, without a division.
#[inline]
fn next_corner(k: u32, n: u32) -> u32 {
    if k + 1 == n {
        0
    } else {
        k + 1
    }
}

/// The edges of a `Level::refine_kept` level as they are made.
struct KeptEdges {
    /// Per kept child's corner `4 i + k`: its edge `k` (`NONE` until made).
    face_edges: Vec<u32>,
    verts: Vec<[u32; 2]>,
    faces: Vec<[u32; 2]>,
    locals: Vec<[u16; 2]>,
    sharpness: Vec<f32>,
    cut: Vec<bool>,
}

impl KeptEdges {
    fn new(kept: usize) -> KeptEdges {
        // At most one edge per corner (no reallocation).
        let cap = 4 * kept;
        KeptEdges {
            face_edges: vec![NONE; 4 * kept],
            verts: Vec::with_capacity(cap),
            faces: Vec::with_capacity(cap),
            locals: Vec::with_capacity(cap),
            sharpness: Vec::with_capacity(cap),
            cut: Vec::with_capacity(cap),
        }
    }

    /// The next edge: edge `k` of kept child `i` (`first`, oriented as there; `local` the
    /// kept quads' corners), and of `second` if kept.
    fn push(
        &mut self,
        local: &[u32],
        (i, k): (u32, u16),
        second: Option<(u32, u16)>,
        sharpness: f32,
        cut: bool,
    ) {
        let id = self.verts.len() as u32;
        let (h, hn) = (
            4 * i as usize + k as usize,
            4 * i as usize + (k as usize + 1) % 4,
        );
        self.verts.push([local[h], local[hn]]);
        self.face_edges[h] = id;
        let (g, l) = second.unwrap_or((NONE, 0));
        if g != NONE {
            self.face_edges[4 * g as usize + l as usize] = id;
        }
        self.faces.push([i, g]);
        self.locals.push([k, l]);
        self.sharpness.push(sharpness);
        self.cut.push(cut);
    }
}

/// The corner before corner `h` of face `f`.
fn prev_corner(t: &Topology, f: usize, h: u32) -> usize {
    if h == t.face_offsets[f] {
        t.face_offsets[f + 1] as usize - 1
    } else {
        h as usize - 1
    }
}
