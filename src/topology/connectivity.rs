//! The [`Topology`] type: flat connectivity arrays, tags and the queries on them (conventions in
//! the [module docs](super)).

use crate::mesh::SchemeOptions;

/// Marks "no face" in [`Topology`]'s edge-face slots.
pub(crate) const NONE: u32 = u32::MAX;

/// Per-face classification used by the patch schemes (checked in this order: Hole, Boundary,
/// Creased, Triangle, Polygon, IrregularQuad, RegularQuad).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum FaceClass {
    /// A quad with four interior valence-4 vertices and no sharpness on or around it.
    RegularQuad,
    /// A quad with an extraordinary vertex or a non-quad face around one of its vertices
    /// (no boundary, no sharpness).
    IrregularQuad,
    /// A triangle (no boundary, no sharpness).
    Triangle,
    /// A face with more than four vertices (no boundary, no sharpness).
    Polygon,
    /// A face touching the boundary.
    Boundary,
    /// Sharpness on the face's edges or vertices or on edges incident to its vertices.
    Creased,
    /// A hole face (kept in the topology, no surface).
    Hole,
}

/// Connectivity plus subdivision tags of a polygon mesh (see the module docs for conventions).
#[derive(Debug, Clone)]
pub struct Topology {
    pub(crate) num_vertices: u32,
    pub(crate) face_offsets: Vec<u32>,
    pub(crate) face_verts: Vec<u32>,
    /// Parallel to `face_verts`: edge `k` of a face joins its corners `k` and `k + 1`.
    pub(crate) face_edges: Vec<u32>,
    /// Oriented as in `edge_faces[e][0]`.
    pub(crate) edge_verts: Vec<[u32; 2]>,
    /// Second slot is [`NONE`] on boundary edges.
    pub(crate) edge_faces: Vec<[u32; 2]>,
    /// Index of the edge within each of its faces.
    pub(crate) edge_face_local: Vec<[u16; 2]>,
    pub(crate) vert_face_offsets: Vec<u32>,
    pub(crate) vert_faces: Vec<u32>,
    /// Index of the vertex within each of its faces (parallel to `vert_faces`).
    pub(crate) vert_face_local: Vec<u16>,
    pub(crate) vert_edge_offsets: Vec<u32>,
    pub(crate) vert_edges: Vec<u32>,
    pub(crate) edge_sharpness: Vec<f32>,
    pub(crate) vertex_sharpness: Vec<f32>,
    /// Per edge: a promoted crease, infinitely sharp only because
    /// [`Topology::with_semi_sharpness_as_crease`] made its semi-sharpness so (the end caps'
    /// view of a level); empty when there is none.
    pub(crate) promoted: Vec<bool>,
    /// Per vertex: a decayed corner ([`Topology::is_decayed_corner`]); empty when there is none.
    pub(crate) decayed_corner: Vec<bool>,
    /// Per vertex: the frozen cross-boundary factors of its two crease sectors
    /// ([`Topology::crease_factors`]); empty when none is set.
    pub(crate) crease_factors: Vec<[f32; 2]>,
    pub(crate) holes: Vec<bool>,
    /// Faces without limit surface besides holes (with `BoundaryInterpolation::None`: faces
    /// touching a boundary vertex of the base mesh, and their descendants); empty if none.
    pub(crate) no_limit: Vec<bool>,
    pub(crate) options: SchemeOptions,
    pub(crate) max_face_size: u32,
}

impl Topology {
    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.num_vertices as usize
    }

    /// Number of faces (holes included).
    pub fn face_count(&self) -> usize {
        self.face_offsets.len() - 1
    }

    /// Number of edges.
    pub fn edge_count(&self) -> usize {
        self.edge_verts.len()
    }

    /// Total number of face corners (sum of face sizes).
    pub fn corner_count(&self) -> usize {
        self.face_verts.len()
    }

    /// Offsets of the faces in the flat face arrays (`face_count() + 1` entries).
    pub fn face_offsets(&self) -> &[u32] {
        &self.face_offsets
    }

    /// Number of vertices of face `f`.
    pub fn face_size(&self, f: u32) -> usize {
        (self.face_offsets[f as usize + 1] - self.face_offsets[f as usize]) as usize
    }

    /// Largest face size.
    pub fn max_face_size(&self) -> usize {
        self.max_face_size as usize
    }

    /// The vertices of face `f`, counter-clockwise.
    pub fn face_vertices(&self, f: u32) -> &[u32] {
        let (a, b) = self.face_range(f);
        &self.face_verts[a..b]
    }

    /// The edges of face `f`: edge `k` joins corners `k` and `k + 1`.
    pub fn face_edges(&self, f: u32) -> &[u32] {
        let (a, b) = self.face_range(f);
        &self.face_edges[a..b]
    }

    fn face_range(&self, f: u32) -> (usize, usize) {
        (
            self.face_offsets[f as usize] as usize,
            self.face_offsets[f as usize + 1] as usize,
        )
    }

    /// End vertices of edge `e`, oriented as in its first face.
    pub fn edge_vertices(&self, e: u32) -> [u32; 2] {
        self.edge_verts[e as usize]
    }

    /// The one or two faces of edge `e`; the edge runs `v0 -> v1` in the first.
    pub fn edge_faces(&self, e: u32) -> &[u32] {
        let ef = &self.edge_faces[e as usize];
        if ef[1] == NONE {
            &ef[..1]
        } else {
            &ef[..]
        }
    }

    /// Position of edge `e` within each of its faces (parallel to [`Self::edge_faces`]).
    pub fn edge_face_locals(&self, e: u32) -> &[u16] {
        let n = self.edge_faces(e).len();
        &self.edge_face_local[e as usize][..n]
    }

    /// Faces around `v`, counter-clockwise (see the module docs).
    #[inline]
    pub fn vertex_faces(&self, v: u32) -> &[u32] {
        let (a, b) = (
            self.vert_face_offsets[v as usize] as usize,
            self.vert_face_offsets[v as usize + 1] as usize,
        );
        &self.vert_faces[a..b]
    }

    /// Position of `v` within each face of [`Self::vertex_faces`].
    #[inline]
    pub fn vertex_face_locals(&self, v: u32) -> &[u16] {
        let (a, b) = (
            self.vert_face_offsets[v as usize] as usize,
            self.vert_face_offsets[v as usize + 1] as usize,
        );
        &self.vert_face_local[a..b]
    }

    /// Edges around `v`, counter-clockwise; face `i` lies between edges `i` and `i + 1`.
    #[inline]
    pub fn vertex_edges(&self, v: u32) -> &[u32] {
        let (a, b) = (
            self.vert_edge_offsets[v as usize] as usize,
            self.vert_edge_offsets[v as usize + 1] as usize,
        );
        &self.vert_edges[a..b]
    }

    /// The end of edge `e` that is not `v`.
    pub fn other_vertex(&self, e: u32, v: u32) -> u32 {
        let [a, b] = self.edge_verts[e as usize];
        if a == v {
            b
        } else {
            a
        }
    }

    /// The face across edge `k` (joining corners `k` and `k + 1`) of face `f`, if any.
    #[inline]
    pub fn adjacent_face(&self, f: u32, k: usize) -> Option<u32> {
        let e = self.face_edges(f)[k] as usize;
        match self.edge_faces[e] {
            [a, b] if a == f && b != NONE => Some(b),
            [a, b] if b == f => Some(a),
            _ => None,
        }
    }

    /// The face across edge `e` from face `f` (the first of [`Self::edge_faces`] that is not
    /// `f`) with the edge's position in it ([`Self::edge_face_locals`]); `None` when there is
    /// none.
    #[inline]
    pub(crate) fn face_across_edge(&self, e: u32, f: u32) -> Option<(u32, usize)> {
        let [f0, f1] = self.edge_faces[e as usize];
        let [l0, l1] = self.edge_face_local[e as usize];
        if f0 != f {
            Some((f0, l0 as usize))
        } else if f1 != NONE && f1 != f {
            Some((f1, l1 as usize))
        } else {
            None
        }
    }

    /// The corners and edges of face `f` ([`Self::face_vertices`], [`Self::face_edges`]) when it
    /// is a quad.
    #[inline]
    pub(crate) fn quad(&self, f: u32) -> Option<(&[u32; 4], &[u32; 4])> {
        let (a, b) = self.face_range(f);
        // The size first (offsets increase): then each array's read is one bounds check.
        if b - a != 4 {
            return None;
        }
        Some((
            self.face_verts.get(a..a + 4)?.try_into().ok()?,
            self.face_edges.get(a..a + 4)?.try_into().ok()?,
        ))
    }

    /// Whether every face is a quad (every level of a Catmull-Clark refinement after the
    /// first): none larger than 4 and four corners a face on average (none has fewer than 3).
    pub(crate) fn quads_only(&self) -> bool {
        self.max_face_size == 4 && self.face_verts.len() == 4 * self.face_count()
    }

    /// [`Self::quad`] of face `f` of a topology of quads only ([`Self::quads_only`]): its
    /// corners are `4 f..4 f + 4`, no face offset read.
    #[inline]
    pub(crate) fn quad_of_quads(&self, f: u32) -> Option<(&[u32; 4], &[u32; 4])> {
        debug_assert!(self.quads_only());
        let a = 4 * f as usize;
        Some((
            self.face_verts.get(a..a + 4)?.try_into().ok()?,
            self.face_edges.get(a..a + 4)?.try_into().ok()?,
        ))
    }

    /// [`Self::quad`] of face `f`, read as [`Self::quad_of_quads`] where the caller knows the
    /// topology is of quads only (`quads_only`: [`Self::quads_only`], asked once per level).
    #[inline(always)]
    pub(crate) fn quad_with(&self, f: u32, quads_only: bool) -> Option<(&[u32; 4], &[u32; 4])> {
        if quads_only {
            self.quad_of_quads(f)
        } else {
            self.quad(f)
        }
    }

    /// Whether edge `e` has a single face.
    pub fn is_boundary_edge(&self, e: u32) -> bool {
        self.edge_faces[e as usize][1] == NONE
    }

    /// Whether `v` lies on the boundary (or has no face at all).
    pub fn is_boundary_vertex(&self, v: u32) -> bool {
        let nf = self.vertex_faces(v).len();
        nf == 0 || self.vertex_edges(v).len() != nf
    }

    /// Number of edges incident to `v`.
    pub fn valence(&self, v: u32) -> usize {
        self.vertex_edges(v).len()
    }

    /// The edge joining `a` and `b`, if any.
    pub fn find_edge(&self, a: u32, b: u32) -> Option<u32> {
        if a as usize >= self.vertex_count() || b as usize >= self.vertex_count() {
            return None;
        }
        self.vertex_edges(a)
            .iter()
            .copied()
            .find(|&e| self.other_vertex(e, a) == b)
    }

    /// Sharpness of edge `e` after tags and the boundary rule (`>= INFINITE_SHARPNESS`: infinite).
    pub fn edge_sharpness(&self, e: u32) -> f32 {
        self.edge_sharpness[e as usize]
    }

    /// Whether edge `e` is a promoted crease: infinitely sharp only because
    /// [`Topology::with_semi_sharpness_as_crease`] made its semi-sharpness so, while the limit
    /// is smooth across it.
    pub fn is_promoted_edge(&self, e: u32) -> bool {
        self.promoted.get(e as usize).copied().unwrap_or(false)
    }

    /// Whether vertex `v` is a decayed corner: smooth here, while the step that made it took the
    /// corner rule (three or more incident edges of sharpness `>= 1` on the parent level), so its
    /// ring has the corner rule's layout, not the smooth characteristic one. Only the adaptive
    /// end caps' view of a level marks them
    /// ([`crate::subdiv::adaptive::AdaptiveRefinement::end_cap_topology`]).
    pub fn is_decayed_corner(&self, v: u32) -> bool {
        self.decayed_corner
            .get(v as usize)
            .copied()
            .unwrap_or(false)
    }

    /// The cross-boundary factors of crease vertex `v`'s two crease sectors (in the order of
    /// `patch::gregory::sectors`), fitted on a rest pose and frozen
    /// (`patch::gregory::vertex_fit`, read under `GregoryTangents::Fitted`); `None` where no
    /// factor was set, and a 0 entry for a sector without one.
    pub fn crease_factors(&self, v: u32) -> Option<[f32; 2]> {
        self.crease_factors
            .get(v as usize)
            .copied()
            .filter(|f| f != &[0.0; 2])
    }

    /// This topology with the per-vertex crease-sector factors `factors` (one entry per vertex,
    /// or empty for none; [`Topology::crease_factors`]).
    ///
    /// # Panics
    /// If `factors` is neither empty nor one entry per vertex (a caller's bug).
    pub fn with_crease_factors(mut self, factors: Vec<[f32; 2]>) -> Topology {
        assert!(factors.is_empty() || factors.len() == self.vertex_count());
        self.crease_factors = factors;
        self
    }

    /// Sharpness of vertex `v` after tags and the boundary rule.
    pub fn vertex_sharpness(&self, v: u32) -> f32 {
        self.vertex_sharpness[v as usize]
    }

    /// All edge sharpness values.
    pub fn edge_sharpnesses(&self) -> &[f32] {
        &self.edge_sharpness
    }

    /// All vertex sharpness values.
    pub fn vertex_sharpnesses(&self) -> &[f32] {
        &self.vertex_sharpness
    }

    /// Whether face `f` is a hole.
    pub fn is_hole(&self, f: u32) -> bool {
        self.holes[f as usize]
    }

    /// Scheme options the tags were applied with.
    pub fn options(&self) -> SchemeOptions {
        self.options
    }

    /// False for holes and, with [`crate::mesh::BoundaryInterpolation::None`], for faces
    /// touching a boundary vertex of the base mesh and their descendants in refined levels
    /// (OpenSubdiv treats them as holes).
    pub fn has_limit_surface(&self, f: u32) -> bool {
        !self.is_hole(f) && (self.no_limit.is_empty() || !self.no_limit[f as usize])
    }

    /// Whether any sharpness lies on face `f`'s edges or vertices or on edges incident to them.
    pub fn is_creased_face(&self, f: u32) -> bool {
        self.face_vertices(f).iter().any(|&v| {
            self.vertex_sharpness(v) > 0.0
                || self
                    .vertex_edges(v)
                    .iter()
                    .any(|&e| self.edge_sharpness(e) > 0.0)
        })
    }

    /// Classification of face `f` (see [`FaceClass`]).
    pub fn face_class(&self, f: u32) -> FaceClass {
        let verts = self.face_vertices(f);
        if self.is_hole(f) {
            FaceClass::Hole
        } else if verts.iter().any(|&v| self.is_boundary_vertex(v)) {
            FaceClass::Boundary
        } else if self.is_creased_face(f) {
            FaceClass::Creased
        } else if verts.len() == 3 {
            FaceClass::Triangle
        } else if verts.len() > 4 {
            FaceClass::Polygon
        } else if verts.iter().any(|&v| {
            self.valence(v) != 4 || self.vertex_faces(v).iter().any(|&g| self.face_size(g) != 4)
        }) {
            FaceClass::IrregularQuad
        } else {
            FaceClass::RegularQuad
        }
    }
}
