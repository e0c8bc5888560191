//! One uniform Catmull-Clark step: the child topology derived directly from the parent (no
//! hashing); the refinement matrix of the child vertices is in [`super::points`].
//!
//! Child vertices: `[face points | edge points | vertex points]`. Child faces: corner `k` of
//! parent face `f` (at flat index `h = face_offsets[f] + k`) gives the quad `(vertex point of
//! corner k, edge point of edge k, face point, edge point of edge k-1)`. Child edges:
//! `[one per parent corner h, from the edge point of edge k to the face point | two halves per
//! parent edge e at 2e and 2e + 1, starting at its first and second end]`.

use super::corners::{child_face, next_corner};
use super::kept::refine_kept_in;
use super::level::Level;
use super::rules::{child_edge_sharpness, decrement};
use super::sparse::SparseMatrix;
use crate::topology::par::{fill, for_chunks, Shared, CHUNK};
use crate::topology::{Topology, NONE};
use crate::Result;

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
            crease_factors: Vec::new(),
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
    /// bucketing the kept quads' edges (`subdiv::kept`).
    ///
    /// The sparse step of feature-adaptive refinement (Köbler 2013 §3.3; OpenSubdiv's
    /// `Vtr::Refinement` with sparse selection): `keep` is the refined faces' children and
    /// their ring, a fraction of the child level.
    pub fn refine_kept(&self, keep: &[u32]) -> Result<(Level, Vec<u32>)> {
        refine_kept_in(self, keep)
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
