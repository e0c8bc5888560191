//! The end-cap corners' two-stage data ([`super::gregory_vertex_two_stage`] over unit weights,
//! derived points [`vertex_point_id`]) computed once per ring type, as
//! [`super::shared_rows::shared_vertex_point_rows`] shares their first stage (Loop et al. 2009
//! §4.1): [`GregoryVertex::from_vertex_points`] reads only the vertex's split ring, the build's
//! tangents and dart masks, and its derived points. Over ring slots (the vertex at slot 0, its
//! edges' other ends, its faces' vertices, numbered by first appearance; derived point `b` at
//! `slots + b`) that input is fixed by the [`RingType`] words, so two vertices with equal words
//! get equal data slot by slot; each weight is the same sequence of `a + w * b` updates whatever
//! the ids (the property the shared end-cap rows rest on), so the data relabelled to a vertex's
//! ids and sorted is bitwise its own construction.

use super::build::{far_crease_sectors, vertex_ring_of_units};
use super::point::{ArenaWeights, Weights};
use super::tangents::GregoryTangents;
use super::tangents_boundary::crease_factor_words;
#[cfg(doc)]
use super::vertex::VertexRing;
use super::vertex::{DartLimits, GregoryVertex};
use super::word_hash::WordHashMap;
use crate::mesh::INFINITE_SHARPNESS;
use crate::topology::Topology;

const NONE: u32 = u32::MAX;

/// The words of a vertex's ring over its slots: the slot count, then [`push_ring`]'s.
type RingType = Vec<u32>;

/// Two-stage corner data per ring type, for one tangent rule and one build's dart masks.
pub(super) struct CornerTypes<'a> {
    topo: &'a Topology,
    tangents: GregoryTangents,
    darts: &'a DartLimits,
    /// Per vertex of `topo`: its slot in the ring being typed, [`NONE`] outside it.
    slot: Vec<u32>,
    /// The vertex of each slot of the ring being typed.
    ring: Vec<u32>,
    /// One buffer for every key (a map entry copies it only for a new type).
    key: RingType,
    /// Each type's data over slots (`None`: the construction declines the ring).
    types: WordHashMap<RingType, Option<GregoryVertex<Weights>>>,
    /// Vertices whose data came from a type already built.
    pub shared: usize,
}

impl<'a> CornerTypes<'a> {
    /// No type known yet.
    pub fn new(topo: &'a Topology, tangents: GregoryTangents, darts: &'a DartLimits) -> Self {
        CornerTypes {
            topo,
            tangents,
            darts,
            slot: vec![NONE; topo.vertex_count()],
            ring: Vec::new(),
            key: RingType::new(),
            types: WordHashMap::default(),
            shared: 0,
        }
    }

    /// [`GregoryVertex::from_vertex_points`] of covered vertex `v`'s split ring over unit
    /// weights, derived point `b` the unit of [`vertex_point_id`] `(v, b)`: bitwise what
    /// [`super::build::two_stage_of_ring`] builds over `v`'s ids, its weight vectors stored in
    /// `arena`. The split ring over slots is made only for a new type.
    pub fn vertex(
        &mut self,
        v: u32,
        arena: &mut Vec<(u32, f64)>,
    ) -> Option<GregoryVertex<ArenaWeights>> {
        let topo = self.topo;
        self.number_ring(v);
        let l = self.ring.len() as u32;
        self.key.clear();
        self.key.push(l);
        push_ring(topo, v, &self.slot, &mut self.key);
        let local = match self.types.get(self.key.as_slice()) {
            Some(local) => {
                self.shared += 1;
                local
            }
            None => {
                let slot = &self.slot;
                let ring = vertex_ring_of_units(topo, v, &|u| slot[u as usize]);
                let points = [0, 1, 2].map(|b| Weights::unit(l + b));
                let local =
                    GregoryVertex::from_vertex_points(&ring, self.tangents, self.darts, points);
                self.types.entry(self.key.clone()).or_insert(local)
            }
        };
        let ids = &self.ring;
        let id = |s: u32| match ids.get(s as usize) {
            Some(&u) => u,
            None => vertex_point_id(topo, v, s - l),
        };
        // Each weight vector relabelled (distinct slots to distinct ids) and sorted again.
        let out = local
            .as_ref()
            .map(|d| d.map(|w| ArenaWeights::push(arena, w.0.iter().map(|&(s, x)| (id(s), x)))));
        for &u in &self.ring {
            self.slot[u as usize] = NONE;
        }
        out
    }

    /// Numbers `v`'s ring in `slot` / `ring` by first appearance: `v`, its edges' other ends,
    /// its faces' vertices.
    fn number_ring(&mut self, v: u32) {
        let topo = self.topo;
        self.ring.clear();
        let (slot, ring) = (&mut self.slot, &mut self.ring);
        let mut at = |u: u32| {
            if slot[u as usize] == NONE {
                slot[u as usize] = ring.len() as u32;
                ring.push(u);
            }
        };
        at(v);
        for &e in topo.vertex_edges(v) {
            at(topo.other_vertex(e, v));
        }
        for &f in topo.vertex_faces(v) {
            topo.face_vertices(f).iter().for_each(|&u| at(u));
        }
    }
}

/// What `v`'s split ring over its slots ([`vertex_ring_of_units`]) is made of, without making
/// it: each edge's other end and its sharp and promoted flags (the midpoints,
/// [`VertexRing::sharp`], [`VertexRing::promoted`]), each face's size and vertices (the
/// centroids, [`VertexRing::face_sizes`]), the corner and decayed-corner tags, the frozen
/// crease-sector factors ([`VertexRing::crease_factors`]), and a crease
/// ring's far crease sectors ([`far_crease_sectors`], which reads the edges' far ends' rings).
fn push_ring(topo: &Topology, v: u32, slot: &[u32], key: &mut RingType) {
    let (edges, faces) = (topo.vertex_edges(v), topo.vertex_faces(v));
    let is_sharp = |e: u32| topo.edge_sharpness(e) >= INFINITE_SHARPNESS;
    key.push(edges.len() as u32);
    let mut sharp_count = 0;
    for &e in edges {
        sharp_count += usize::from(is_sharp(e));
        key.push(slot[topo.other_vertex(e, v) as usize]);
        key.push(u32::from(is_sharp(e)) | u32::from(topo.is_promoted_edge(e)) << 1);
    }
    key.push(faces.len() as u32);
    for &f in faces {
        let fv = topo.face_vertices(f);
        key.push(fv.len() as u32);
        key.extend(fv.iter().map(|&u| slot[u as usize]));
    }
    let corner = topo.vertex_sharpness(v) >= INFINITE_SHARPNESS || sharp_count > 2;
    key.push(u32::from(corner) | u32::from(topo.is_decayed_corner(v)) << 1);
    key.extend(crease_factor_words(topo, v));
    if sharp_count == 2 && !corner {
        let sharp: Vec<bool> = edges.iter().map(|&e| is_sharp(e)).collect();
        key.extend(
            far_crease_sectors(topo, v, &sharp)
                .iter()
                .map(|&s| s as u32),
        );
    }
}

/// Derived points per vertex in the two-stage rows ([`GregoryVertex::vertex_points`]: a smooth
/// vertex's limit position, cosine and sine sums, a dart's limit position and two tangents, a
/// crease's sector tangents).
pub const VERTEX_POINTS: u32 = super::vertex::VERTEX_POINTS as u32;

/// The id of derived point `b` ([`GregoryVertex::vertex_points`]) of vertex `v` in the rows of
/// the direct sparse face rows (`sparse_face_rows_direct`): past every vertex of `topo` (`vertex_count + 3 v + b`), so it
/// sorts after the vertices and with `v`.
pub fn vertex_point_id(topo: &Topology, v: u32, b: u32) -> u32 {
    topo.vertex_count() as u32 + VERTEX_POINTS * v + b
}

/// The vertex and derived point of `id`, `None` for a vertex id ([`vertex_point_id`]).
pub fn vertex_point_of(topo: &Topology, id: u32) -> Option<(u32, u32)> {
    let d = id.checked_sub(topo.vertex_count() as u32)?;
    Some((d / VERTEX_POINTS, d % VERTEX_POINTS))
}

#[cfg(test)]
/// Both end-cap topologies (residual semi-sharpness smooth, or infinitely sharp from
/// `CREASE_FROM`) of every level of the isolation-2 refinement of corpus mesh `name`; for
/// [`DECAYED_CORNER_DISKS`] those of [`decayed_corner_disks`] and each level's own end-cap
/// topology (`AdaptiveRefinement::end_cap_topology`, the build's: it marks decayed corners).
pub(super) fn end_cap_topologies(name: &str) -> Vec<Topology> {
    use crate::mesh::ControlMesh;
    let mesh = if name == DECAYED_CORNER_DISKS {
        ControlMesh::from_obj_str(&decayed_corner_disks(), name, &Default::default())
    } else {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/meshes/osd/");
        ControlMesh::from_obj_file(format!("{dir}{name}.obj"), &Default::default())
    };
    let level = crate::subdiv::Level::from_mesh(&mesh.unwrap()).unwrap();
    let adaptive = crate::subdiv::adaptive::AdaptiveRefinement::new(&level, 2).unwrap();
    let mut out: Vec<Topology> = adaptive
        .levels
        .iter()
        .flat_map(|l| {
            let t = l.topology();
            [
                t.without_semi_sharpness().into_owned(),
                t.with_semi_sharpness_as_crease(
                    crate::subdiv::adaptive::EndCapSharpness::CREASE_FROM,
                )
                .into_owned(),
            ]
        })
        .collect();
    if name == DECAYED_CORNER_DISKS {
        let own = (0..adaptive.levels.len()).map(|l| adaptive.end_cap_topology(l).into_owned());
        out.extend(own);
        let decayed = out
            .iter()
            .flat_map(|t| (0..t.vertex_count() as u32).filter(|&v| t.is_decayed_corner(v)))
            .count();
        assert_eq!(decayed, 1, "the first disk's centre decays once");
    }
    out
}

#[cfg(test)]
/// `topo` with frozen crease-sector factors (`GregoryTangents::Fitted`), a different pair at
/// every vertex: rings of one connectivity with different factors.
pub(super) fn with_test_crease_factors(topo: Topology) -> Topology {
    let factors = (0..topo.vertex_count())
        .map(|v| [0.5 + 1e-3 * v as f32, 1.5 + 1e-3 * v as f32])
        .collect();
    topo.with_crease_factors(factors)
}

#[cfg(test)]
/// The name [`end_cap_topologies`] takes for [`decayed_corner_disks`].
pub(super) const DECAYED_CORNER_DISKS: &str = "decayed corner disks";

#[cfg(test)]
/// Two disjoint quad disks around a valence-8 centre (every quad `centre, spoke i, rim i,
/// spoke i + 1`), the first with three spokes at sharpness 1: at level 1 its centre's vertex
/// point is a decayed corner (`Topology::is_decayed_corner`) with the ring of the second's,
/// which is not, and the end caps' tangents read the tag there
/// (`GregoryTangents::decayed_corner_scale` at valence 8). No corpus mesh has a decayed corner.
fn decayed_corner_disks() -> String {
    let mut obj = String::new();
    for copy in 0..2 {
        let x = 5.0 * copy as f64;
        obj += &format!("v {x} 0 0\n");
        for k in 0..16 {
            let (r, a) = (
                1.0 + 0.2 * (k % 2) as f64,
                std::f64::consts::PI * k as f64 / 8.0,
            );
            obj += &format!(
                "v {} {} {}\n",
                x + r * a.cos(),
                r * a.sin(),
                0.1 * (k % 3) as f64
            );
        }
        let o = 17 * copy + 1;
        for i in 0..8 {
            let spoke = |i: usize| o + 1 + 2 * (i % 8);
            obj += &format!("f {o} {} {} {}\n", spoke(i), spoke(i) + 1, spoke(i + 1));
        }
    }
    for spoke in [0, 3, 5] {
        obj += &format!("t crease 2/1/0 0 {} 1.0\n", 1 + 2 * spoke);
    }
    obj
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::patch::gregory::build::{two_stage_of_ring, vertex_covered, Coverage};
    use crate::patch::gregory::VertexKind;
    use std::collections::HashSet;

    /// Every field of `d` with weights as `(id, bits)`.
    fn bits(d: &GregoryVertex<Weights>) -> impl PartialEq + std::fmt::Debug {
        let w = |w: &Weights| {
            w.0.iter()
                .map(|&(u, x)| (u, x.to_bits()))
                .collect::<Vec<_>>()
        };
        let all = |ws: &[Weights]| ws.iter().map(w).collect::<Vec<_>>();
        let cosine: Vec<u64> = d.cosine.iter().map(|c| c.to_bits()).collect();
        (
            (d.kind, d.n, w(&d.p), all(&d.e)),
            (all(&d.r_plus), all(&d.r_minus), cosine, d.one_sided.clone()),
        )
    }

    /// The data shared per ring type is bitwise the per-vertex two-stage construction over the
    /// vertex's own ids (`two_stage_of_ring` over the unit ring of those ids, the path
    /// `EndCapCorners` took before), on every covered vertex of every level of the isolation-2
    /// refinement of meshes with triangles, n-gons, high valence, boundaries, holes, bands,
    /// creases, corners, darts and promoted semi-sharp creases, in both end-cap topologies and
    /// every tangent rule (`Bands` reads the far crease sectors); smooth, crease, corner and dart
    /// vertices compared, and types shared (fails if the key leaves out a tag the construction
    /// reads, e.g. the far crease sectors, promoted edges or, on `xord_boundary` with
    /// [`with_test_crease_factors`] under `Fitted`, the frozen factors, or the relabelling
    /// misplaces a derived point). A decayed corner is compared too; the key's decayed-corner tag cannot
    /// be shown missing here: the tag changes only the first stage (the vertex points, whose
    /// key `shared_rows` tests) at the valences where it has a factor.
    #[test]
    fn shared_corner_data_is_the_per_vertex_construction() {
        let (mut compared, mut shared) = (0, 0);
        let mut kinds = HashSet::new();
        for name in [
            DECAYED_CORNER_DISKS,
            "catmark_car",
            "catmark_nonquads",
            "catmark_smoothtris1",
            "catmark_pole8",
            "catmark_hole_test1",
            "catmark_dart_edgecorner",
            "catmark_cube_corner4",
            "catmark_cube_creases2",
            "catmark_cubes_semisharp",
            "catmark_val2_interior",
            "catmark_xord_boundary",
            "catmark_gregory_test3",
        ] {
            let mut topos = end_cap_topologies(name);
            if name == "catmark_xord_boundary" {
                let fitted: Vec<Topology> = topos
                    .iter()
                    .cloned()
                    .map(with_test_crease_factors)
                    .collect();
                topos.extend(fitted);
            }
            for topo in topos {
                for tangents in [
                    GregoryTangents::Paper,
                    GregoryTangents::Optimal,
                    GregoryTangents::Bands,
                    GregoryTangents::EndCaps,
                    GregoryTangents::Scaled(1.1),
                    GregoryTangents::Fitted,
                ] {
                    let darts = DartLimits::new();
                    let mut types = CornerTypes::new(&topo, tangents, &darts);
                    let basis =
                        |v: u32| [0, 1, 2].map(|b| Weights::unit(vertex_point_id(&topo, v, b)));
                    for v in 0..topo.vertex_count() as u32 {
                        if !vertex_covered(&topo, v, Coverage::EndCap) {
                            continue;
                        }
                        let want = two_stage_of_ring(
                            &topo,
                            v,
                            || vertex_ring_of_units(&topo, v, &|u| u),
                            tangents,
                            Coverage::EndCap,
                            &darts,
                            &basis,
                        );
                        let mut arena = Vec::new();
                        let got = types
                            .vertex(v, &mut arena)
                            .map(|d| d.map(|w| Weights(w.get(&arena).to_vec())));
                        assert_eq!(
                            got.as_ref().map(bits),
                            want.as_ref().map(bits),
                            "{name}: vertex {v}"
                        );
                        kinds.extend(want.map(|d| d.kind));
                        compared += 1;
                    }
                    shared += types.shared;
                }
            }
        }
        let want = [
            VertexKind::Smooth,
            VertexKind::Crease,
            VertexKind::Corner,
            VertexKind::Dart,
        ];
        assert!(want.iter().all(|k| kinds.contains(k)), "{kinds:?}");
        assert!(shared * 2 > compared, "{shared} of {compared} shared");
    }
}
