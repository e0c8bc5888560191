//! The kept children of one Catmull-Clark step as a level of their own ([`refine_kept_in`]),
//! made from the parent by index arithmetic: the sparse step of feature-adaptive refinement
//! (Köbler 2013 §3.3; OpenSubdiv's `Vtr::Refinement` with sparse selection).
//!
//! The parent is a [`Level`] refined as a whole (its children numbered
//! `[face points | edge points | vertex points]`, [`Level::refine_kept`]). The adaptive step
//! refines a level's faces around a selection in place instead (`super::ring_step`), without
//! `topology::build`'s numbering.

use super::corners::{child_face_with, next_corner, prev_corner};
use super::level::{local_vertex_ids, Level};
use super::rules::{child_edge_sharpness, decrement};
use crate::topology::{self, NONE};
use crate::{Error, Result};

/// An edge of the parent: ends oriented as in its first face, its faces (the second [`NONE`]
/// on a boundary) and its index in each.
#[derive(Debug, Clone, Copy)]
struct StepEdge {
    verts: [u32; 2],
    faces: [u32; 2],
    locals: [u16; 2],
}

impl StepEdge {
    /// Edge `e` of `t`.
    fn of(t: &topology::Topology, e: u32) -> StepEdge {
        StepEdge {
            verts: t.edge_verts[e as usize],
            faces: t.edge_faces[e as usize],
            locals: t.edge_face_local[e as usize],
        }
    }
}

/// The child faces `keep` (flat corner indices of `lv`, increasing) of `lv`'s refinement as a
/// level of their own, with the map from its vertices to the child numbering
/// `[face points | edge points | vertex points]`: the same level and map as
/// `lv.refine_topology().try_extract(keep)`, without building the whole child
/// level nor bucketing the kept quads' edges. Every child edge is a spoke (face point to the
/// edge point of a face's corner) or a half of a parent edge; in the child vertices' increasing
/// order (face points, then edge points) its id, ends, faces, sharpness and cut flag follow
/// from the parent by index arithmetic, in the order `topology::build` gives them (by smaller
/// end vertex, then by first corner), and so do the one-rings (`kept_rings`).
pub(super) fn refine_kept_in(lv: &Level, keep: &[u32]) -> Result<(Level, Vec<u32>)> {
    let t = &lv.topo;
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
                "refine_kept: child face {i} is corner {h}: corners must increase and be below \
                 {fv}"
            )));
        }
        while t.face_offsets[f + 1] <= h {
            f += 1;
        }
        kept[h as usize] = i as u32;
        parent_face.push(f as u32);
        let hp = prev_corner(t, f, h);
        let quad = child_face_with(t, f, h as usize, hp, ne as u32, |e| e);
        old_verts.extend_from_slice(&quad);
    }
    let nk = keep.len();
    let (map, local) = local_vertex_ids(&old_verts, cnv);
    drop(old_verts);

    // Edges, in `topology::build`'s order: by smaller end (face points before edge points,
    // vertex points never), then by first corner (kept child `i`, edge `k`).
    let mut edges = KeptEdges::new(nk);
    // Per edge point of `map`, in order: its kept children (`edge_point_children`) and
    // whether its edge is a boundary of the parent.
    let mut edge_children = Vec::with_capacity(map.len());
    for &old in &map {
        let o = old as usize;
        if o < nf {
            // The spokes of face `o`: child `c` (edge 1) and child `c + 1` (edge 2) of spoke
            // `c`; kept children in increasing corner order are in increasing `i`.
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
            let edge = StepEdge::of(t, e);
            let [a, b] = edge.verts;
            let boundary = edge.faces[1] == NONE;
            // The half at `a`: edge 0 of the child at `a` in `f0`, edge 3 of the one in `f1`;
            // the half at `b` the other way round.
            let children = edge_point_children(lv, &kept, &edge);
            edge_children.push((children, boundary));
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
                let opened = second.is_none() && !boundary;
                let sharp = child_edge_sharpness(t, e, v);
                let c = opened || lv.is_cut_edge(e);
                edges.push(&local, first, second, sharp, c);
            }
        } else {
            break;
        }
    }
    let face_offsets: Vec<u32> = (0..=nk as u32).map(|i| 4 * i).collect();
    let rings = kept_rings(
        lv,
        ne,
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
    let holes = parent_face.iter().map(|&f| t.holes[f as usize]).collect();
    let mut sub =
        topology::with_given_rings(map.len(), connectivity, rings, 4, edges.sharpness, holes);
    if !t.no_limit.is_empty() {
        sub.no_limit = parent_face
            .iter()
            .map(|&f| t.no_limit[f as usize])
            .collect();
    }
    sub.options = t.options;
    // A child vertex is incomplete when its counterpart in the whole child level is
    // (`Level::child_flags`) or when the kept quads miss some of its faces there.
    let flagged = !(lv.cut.is_empty() && lv.incomplete.is_empty());
    let bad = |v: u32| !lv.is_complete_vertex(v);
    // Per parent face: whether a corner is incomplete, judged once (a face is asked for by its
    // face point, the edge points of its edges and the vertex points of its corners).
    let mut face_bad_memo = vec![UNJUDGED; if flagged { nf } else { 0 }];
    let mut face_bad = |f: u32| {
        let memo = &mut face_bad_memo[f as usize];
        if *memo == UNJUDGED {
            *memo = u8::from(t.face_vertices(f).iter().any(|&v| bad(v)));
        }
        *memo == 1
    };
    let mut incomplete = vec![false; map.len()];
    for (v, &old) in map.iter().enumerate() {
        let o = old as usize;
        let (valence, inc) = if o < nf {
            (t.face_size(old), flagged && face_bad(old))
        } else if o < nf + ne {
            let e = (o - nf) as u32;
            let faces = t.edge_faces[e as usize];
            let faces = if faces[1] == NONE {
                &faces[..1]
            } else {
                &faces[..]
            };
            let inc = flagged && (lv.is_cut_edge(e) || faces.iter().any(|&f| face_bad(f)));
            (2 * faces.len(), inc)
        } else {
            let pv = (o - nf - ne) as u32;
            sub.vertex_sharpness[v] = decrement(t.vertex_sharpness[pv as usize]);
            let faces = t.vertex_faces(pv);
            let inc = flagged && (bad(pv) || faces.iter().any(|&f| face_bad(f)));
            (faces.len(), inc)
        };
        incomplete[v] = inc || sub.vertex_faces(v as u32).len() != valence;
    }
    Ok((Level::with_flags(sub, edges.cut, incomplete), map))
}

/// The one-rings of [`refine_kept_in`]'s level (kept child `kept[h]` of each corner `h` of
/// `parent`, NONE if not kept; `ne` edge points; its vertices `map` in the child numbering, its
/// edge points' kept children and boundary flags `edge_children` in that order; its quads'
/// `face_offsets` and `face_edges`, `edges` edges) from `parent`'s: a face point's ring is its
/// face's children (corner 2, in corner order), an edge point's the children beside the edge
/// (corners 1 and 3, as `refine_topology` orders them), a vertex point's the children at its
/// faces' corners (corner 0) in its ring's order, fan by fan; the kept ones ordered as
/// `topology::build` orders them ([`topology::RingBuilder`]; a single fan by its quad
/// arithmetic).
#[allow(clippy::too_many_arguments)]
fn kept_rings(
    parent: &Level,
    ne: usize,
    kept: &[u32],
    map: &[u32],
    edge_children: &[([u32; 4], bool)],
    face_offsets: &[u32],
    face_edges: &[u32],
    edges: usize,
) -> topology::Rings {
    let t = &parent.topo;
    let nf = t.face_count();
    let mut rings =
        topology::RingBuilder::new(face_offsets, face_edges, map.len(), face_edges.len(), edges);
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
            let ([c00, c01, c10, c11], boundary) = *edge_children
                .next()
                .expect("an edge point's children per edge point");
            if boundary {
                rings.quad_fan(false, &[(c01, 3), (c00, 1)]);
            } else {
                rings.quad_fan(true, &[(c00, 1), (c11, 3), (c10, 1), (c01, 3)]);
            }
        } else {
            let v = (o - nf - ne) as u32;
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

/// The kept children (`kept`, per corner of `parent`) beside the edge point of `edge`: at its
/// first face's corner at the edge's first end and at the next corner, then the same in its
/// second face (NONE where not kept or there is no second face).
fn edge_point_children(parent: &Level, kept: &[u32], edge: &StepEdge) -> [u32; 4] {
    let t = &parent.topo;
    let [f0, f1] = edge.faces;
    let [k0, k1] = edge.locals;
    let corner = |g: u32, k: u16, step: u32| -> u32 {
        let off = t.face_offsets[g as usize];
        let n = t.face_offsets[g as usize + 1] - off;
        let k = if step == 0 {
            u32::from(k)
        } else {
            next_corner(u32::from(k), n)
        };
        kept[(off + k) as usize]
    };
    let (c00, c01) = (corner(f0, k0, 0), corner(f0, k0, 1));
    let (c10, c11) = if f1 == NONE {
        (NONE, NONE)
    } else {
        (corner(f1, k1, 0), corner(f1, k1, 1))
    };
    [c00, c01, c10, c11]
}

/// A parent face not judged yet in `refine_kept_in`'s per-face memo (0 complete, 1 not).
const UNJUDGED: u8 = 2;

/// The edges of a level of kept child quads ([`refine_kept_in`], `super::ring_step`) as they
/// are made.
pub(super) struct KeptEdges {
    /// Per kept child's corner `4 i + k`: its edge `k` (`NONE` until made).
    pub face_edges: Vec<u32>,
    pub verts: Vec<[u32; 2]>,
    pub faces: Vec<[u32; 2]>,
    pub locals: Vec<[u16; 2]>,
    pub sharpness: Vec<f32>,
    /// A boundary of the level that is none of the whole refinement (see [`Level`]).
    pub cut: Vec<bool>,
}

impl KeptEdges {
    /// Room for the edges of `kept` quads.
    pub fn new(kept: usize) -> KeptEdges {
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
    #[inline(always)]
    pub fn push(
        &mut self,
        local: &[u32],
        (i, k): (u32, u16),
        second: Option<(u32, u16)>,
        sharpness: f32,
        cut: bool,
    ) {
        let id = self.verts.len() as u32;
        let h = 4 * i as usize + k as usize;
        // The quad's corners read as one array: one bounds check.
        let quad: &[u32; 4] = local[4 * i as usize..][..4].try_into().expect("a quad");
        self.verts
            .push([quad[usize::from(k)], quad[usize::from(k + 1) & 3]]);
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
