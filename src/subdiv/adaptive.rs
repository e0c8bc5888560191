//! Feature-adaptive refinement (Köbler 2013 ch. 3, after Nießner, Loop, Meyer, DeRose 2012):
//! refine only around faces that are not (boundary-)regular B-spline patches, up to an
//! isolation level, and take a census of the patches every level draws.
//!
//! Each level is *sparse* (as OpenSubdiv's sparse selection): level `l + 1` holds the children
//! of the faces refined at level `l` plus, for every other face touching a vertex of a refined
//! face, its child at that corner — exactly the ring that gives each child of a refined face
//! its 4x4 neighbourhood (§3.3). Refining level `l` is one uniform [`Level::refine`] of the
//! sub-level made of the refined faces and that ring, keeping the child faces just described
//! ([`UniformStep`]); those are made from level `l` in place, as OpenSubdiv's `Vtr::Refinement`
//! refines a selection of its parent: the child vertices are the face, edge and vertex points of
//! the selected components, their edges and one-rings written from level `l`'s relations
//! (`ring_step`), with no sub-level extracted; so the step is that refinement up to numbering
//! and ring starts. Vertices are numbered globally level after level:
//! vertex `i` of level `l` is global vertex [`AdaptiveLevel::first_vertex`]` + i`, one buffer for
//! every level (thesis §4.2).

use glam::{DVec2, DVec3};

use super::bspline::{is_grid_corner, is_regular_vertex, RegularPatch};
use super::level::Level;
use super::ring_step::refine_in_place;
use super::single_crease::{single_crease_line_at_grid_corners, CreaseLine};
use crate::mesh::INFINITE_SHARPNESS;
use crate::topology::Topology;
use crate::{Error, Result};

/// The largest isolation level accepted.
pub const MAX_ISOLATION: u32 = 8;

/// Where a face of some level lies in its base face's parameter domain (README,
/// "Parameterisation"): face-local `(s, t)` maps to `origin + s u + t v`, in the base quad's
/// `(u, v)` or, for other base faces, in sub-face [`Self::sub_face`]'s.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Domain {
    /// The base face.
    pub base_face: u32,
    /// The sub-face of a non-quad base face (its corner), `None` for quads and for the
    /// non-quad base face itself at level 0.
    pub sub_face: Option<u32>,
    /// Image of the face's corner 0.
    pub origin: DVec2,
    /// Image of the face's u axis (corner 0 to corner 1).
    pub u: DVec2,
    /// Image of the face's v axis (corner 0 to corner 3).
    pub v: DVec2,
}

impl Domain {
    /// The domains of the children (child `k` the quad at corner `k`) of a face with this
    /// domain and `n` corners, by `k`: the corners' images computed once a face, not once a
    /// child.
    fn children(self, n: usize) -> impl Fn(usize) -> Domain {
        let corner = [
            self.origin,
            self.origin + self.u,
            self.origin + self.u + self.v,
            self.origin + self.v,
        ];
        move |k| {
            if n != 4 {
                return Domain {
                    sub_face: Some(k as u32),
                    origin: DVec2::ZERO,
                    u: DVec2::X,
                    v: DVec2::Y,
                    ..self
                };
            }
            let p = corner[k];
            Domain {
                origin: p,
                u: 0.5 * (corner[(k + 1) % 4] - p),
                v: 0.5 * (corner[(k + 3) % 4] - p),
                ..self
            }
        }
    }
}

/// What produces a vertex of the child level: the face point, edge point or vertex point of a
/// component of the parent level (parent level numbering).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ChildOf {
    /// Face point of this parent face.
    Face(u32),
    /// Edge point of this parent edge.
    Edge(u32),
    /// Vertex point of this parent vertex.
    Vertex(u32),
}

/// One sparse refinement step, level `l` to `l + 1`: what a table builder needs. The step
/// refines the level's faces `parent_faces` in place (`subdiv::ring_step`): level `l + 1` is
/// made from level `l` by index arithmetic, with no sub-level extracted.
#[derive(Clone)]
pub struct Refinement {
    /// The level-`l` faces the step refines (increasing): the refined faces and their ring.
    pub parent_faces: Vec<u32>,
    /// Level-`l + 1` face to the level-`l` corner it is the child of (a flat corner index);
    /// increasing.
    pub child_corners: Vec<u32>,
    /// Level-`l + 1` face to the level-`l` face it is a child of (the face of its
    /// `child_corners` entry); increasing.
    child_faces: Vec<u32>,
    /// Per level-`l + 1` vertex: the level-`l` component producing it.
    child_of: Vec<ChildOf>,
}

/// The step's faces, child corners and child points; each child face's parent face is derived
/// from its corner and left out (as [`AdaptiveRefinement`]'s census is).
impl std::fmt::Debug for Refinement {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Refinement")
            .field("parent_faces", &self.parent_faces)
            .field("child_corners", &self.child_corners)
            .field("child_of", &self.child_of)
            .finish()
    }
}

/// A step as one uniform [`Level::refine`] of the sub-level its faces make
/// ([`Level::extract_increasing`]), keeping the children it keeps ([`Level::refine_kept`]): how
/// the step was once computed, rebuilt on demand ([`AdaptiveLevel::uniform_step`]) for the
/// refined positions and tests. The child vertices are rows of `parent.refine()`'s matrix
/// (columns: `parent` vertices), so `child = M[child_points] * positions_l[parent_vertices]`.
#[derive(Debug, Clone)]
pub struct UniformStep {
    /// The refined sub-level of level `l`: the refined faces and their ring.
    pub parent: Level,
    /// `parent` face to level-`l` face.
    pub parent_faces: Vec<u32>,
    /// `parent` vertex to level-`l` vertex.
    pub parent_vertices: Vec<u32>,
    /// Level-`l + 1` vertex to its index in `parent.refine()`'s child numbering
    /// (`[face points | edge points | vertex points]`).
    pub child_points: Vec<u32>,
    /// Level-`l + 1` face to its index in `parent.refine()`'s child faces (the corner of
    /// `parent` it comes from, as a flat corner index).
    pub child_faces: Vec<u32>,
    /// Level `l + 1` as `parent.refine_kept(&child_faces)` makes it: the same quads as the
    /// step's level, corner for corner, numbered and ordered as `topology::build` would.
    pub child: Level,
    /// `child` vertex to its index in `parent.refine()`'s child numbering; increasing.
    pub child_map: Vec<u32>,
}

/// One level of an [`AdaptiveRefinement`].
#[derive(Debug, Clone)]
pub struct AdaptiveLevel {
    /// The sparse topology of this level (the whole base mesh at level 0).
    pub level: Level,
    /// Global id of this level's vertex 0.
    pub first_vertex: u32,
    /// Per face: a face of this level proper (a child of a refined face; every face at level
    /// 0). The other faces are the ring, drawn by coarser patches.
    pub own: Vec<bool>,
    /// Per face: refined into the next level.
    pub refined: Vec<bool>,
    /// Per face: its place in its base face.
    pub domains: Vec<Domain>,
    /// The step to the next level (`None` on the last level).
    pub refinement: Option<Refinement>,
}

impl AdaptiveLevel {
    /// The topology of this level.
    pub fn topology(&self) -> &Topology {
        self.level.topology()
    }

    /// Global id of local vertex `v`.
    pub fn global(&self, v: u32) -> u32 {
        self.first_vertex + v
    }

    /// The component of this level producing vertex `v` of the next level.
    ///
    /// # Panics
    /// On the last level (no refinement).
    pub fn child_of(&self, v: u32) -> ChildOf {
        self.step().child_of[v as usize]
    }

    /// [`Self::child_of`] of every vertex of the next level, in order.
    ///
    /// # Panics
    /// On the last level (no refinement).
    pub fn children_of(&self) -> &[ChildOf] {
        &self.step().child_of
    }

    /// The face of this level and the corner face `c` of the next level comes from.
    ///
    /// # Panics
    /// On the last level (no refinement).
    pub fn child_face_parent(&self, c: u32) -> (u32, usize) {
        let step = self.step();
        let (h, f) = (step.child_corners[c as usize], step.child_faces[c as usize]);
        (f, (h - self.topology().face_offsets()[f as usize]) as usize)
    }

    /// The step to `next` (the next level) as one uniform refinement of an extracted sub-level
    /// ([`UniformStep`]); `None` on the last level.
    pub fn uniform_step(&self, next: &AdaptiveLevel) -> Option<Result<UniformStep>> {
        let r = self.refinement.as_ref()?;
        let step = || {
            let (parent, parent_vertices) = self.level.extract_increasing(&r.parent_faces)?;
            let (to, so) = (
                self.topology().face_offsets(),
                parent.topology().face_offsets(),
            );
            let mut i = 0;
            let child_faces = r
                .child_corners
                .iter()
                .map(|&h| {
                    while to[r.parent_faces[i] as usize + 1] <= h {
                        i += 1;
                    }
                    so[i] + h - to[r.parent_faces[i] as usize]
                })
                .collect::<Vec<u32>>();
            let (child, child_map) = parent.refine_kept(&child_faces)?;
            // The step's level and `child` have the same quads, corner for corner: a vertex's
            // child point is its counterpart's at any corner it holds.
            let mut child_points = vec![0; next.level.vertex_count()];
            let corners = next.topology().face_verts.iter();
            for (&v, &w) in corners.zip(&child.topology().face_verts) {
                child_points[v as usize] = child_map[w as usize];
            }
            Ok(UniformStep {
                parent,
                parent_faces: r.parent_faces.clone(),
                parent_vertices,
                child_points,
                child_faces,
                child,
                child_map,
            })
        };
        Some(step())
    }

    fn step(&self) -> &Refinement {
        self.refinement
            .as_ref()
            .expect("the last adaptive level has no refinement")
    }
}

/// How to refine feature-adaptively.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct AdaptiveOptions {
    /// The isolation level, `0..=MAX_ISOLATION`.
    pub isolation: u32,
    /// Stop refining at single-crease patches (Nießner, Loop, Greiner 2012 §3; OpenSubdiv's
    /// `useSingleCreasePatch`): a face whose only feature is one semi-sharp crease line along
    /// one of its edges ([`single_crease_line`](super::single_crease::single_crease_line)) is
    /// drawn as a [`PatchType::SingleCrease`] patch at the first level where it is one, instead
    /// of being refined `ceil(s)` levels deep, so the patch count grows linearly, not
    /// exponentially, with the sharpness.
    pub single_crease: bool,
    /// How end caps treat semi-sharpness left at the isolation level.
    pub end_cap_sharpness: EndCapSharpness,
    /// Whether end caps near irregular crease vertices draw the exact limit normals of a
    /// `2^-3` lattice (`crate::patch::adaptive::lattice_frames`; on by default). Off: the end
    /// caps' own normals there, whose error does not fall with the isolation level, for about
    /// 2.3× less preprocessing on `catmark_car` at isolation 2 (README, preprocessing table).
    pub lattice_normals: bool,
}

impl AdaptiveOptions {
    /// Isolation `isolation`, single-crease patches off, default end-cap sharpness, lattice
    /// normals on.
    pub fn new(isolation: u32) -> AdaptiveOptions {
        AdaptiveOptions {
            isolation,
            single_crease: false,
            end_cap_sharpness: EndCapSharpness::default(),
            lattice_normals: true,
        }
    }
}

/// How the end caps (Gregory patches at the isolation level) treat the residual semi-sharpness
/// of their level's edges and vertices. The refined points keep the semi-sharp rules up to that
/// level either way; only the end caps' corner and edge rules differ.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum EndCapSharpness {
    /// Edges of residual sharpness `s >= 1` infinitely sharp, `s < 1` smooth: the limit keeps
    /// such a crease for `s` more levels and rounds it only within about `2^-s` of the patch
    /// (Nießner, Loop, Greiner 2012 §3), so the crease rules of the Gregory construction (Loop
    /// et al. 2009 §4.6) are the closer stand-in. Semi-sharp vertex tags stay smooth: as
    /// infinitely sharp ones they would make cone points, measured no closer (README).
    #[default]
    Crease,
    /// Residual semi-sharpness smooth, infinitely sharp tags kept, as OpenSubdiv's Gregory-basis
    /// end caps (`Far::PatchBuilder::GetIrregularPatchCornerSpans` sharpens corner spans from
    /// infinitely sharp tags only).
    Smooth,
}

impl EndCapSharpness {
    /// Residual sharpness from which [`EndCapSharpness::Crease`] makes an edge infinitely sharp.
    pub const CREASE_FROM: f32 = 1.0;

    /// `level`'s topology as the end caps see it.
    pub fn end_cap_topology(self, level: &Topology) -> std::borrow::Cow<'_, Topology> {
        match self {
            EndCapSharpness::Crease => level.with_semi_sharpness_as_crease(Self::CREASE_FROM),
            EndCapSharpness::Smooth => level.without_semi_sharpness(),
        }
    }

    /// Lower-case name (`crease`, `smooth`).
    pub fn name(self) -> &'static str {
        match self {
            EndCapSharpness::Crease => "crease",
            EndCapSharpness::Smooth => "smooth",
        }
    }
}

impl std::str::FromStr for EndCapSharpness {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, Self::Err> {
        match s {
            "crease" => Ok(EndCapSharpness::Crease),
            "smooth" => Ok(EndCapSharpness::Smooth),
            _ => Err(format!(
                "end-cap sharpness {s:?}: expected crease or smooth"
            )),
        }
    }
}

impl std::fmt::Display for EndCapSharpness {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// A mesh refined feature-adaptively to an isolation level (Köbler 2013 §3.3).
#[derive(Clone)]
pub struct AdaptiveRefinement {
    /// Levels `0..=` the last one reached (at most the isolation level: refinement stops early
    /// when every face is a patch).
    pub levels: Vec<AdaptiveLevel>,
    /// The isolation level asked for.
    pub isolation: u32,
    /// Whether single-crease faces end refinement ([`AdaptiveOptions::single_crease`]).
    pub single_crease: bool,
    /// How the end caps treat residual semi-sharpness ([`AdaptiveOptions::end_cap_sharpness`]).
    pub end_cap_sharpness: EndCapSharpness,
    /// Whether end caps draw lattice normals ([`AdaptiveOptions::lattice_normals`]).
    pub lattice_normals: bool,
    /// The drawn patches, classified by the same per-level regularity test that chose the
    /// refined faces ([`Self::census`]).
    census: PatchCensus,
}

/// The levels and options; the census is derived from them and left out.
impl std::fmt::Debug for AdaptiveRefinement {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("AdaptiveRefinement")
            .field("levels", &self.levels)
            .field("isolation", &self.isolation)
            .field("single_crease", &self.single_crease)
            .field("end_cap_sharpness", &self.end_cap_sharpness)
            .finish()
    }
}

/// The patch tests of a level's faces. A face's regular patch when it is regular: `gather`
/// succeeds (quad, valence-4 or boundary/crease/corner configurations, no semi-sharp edge or
/// vertex at a corner; §3.3) and every corner is regular for all its faces, not only this one
/// (§3.7, see [`is_regular_vertex`]); and the single-crease patch of a face that is not, its
/// corners [`is_grid_corner`]s. Each vertex is judged once per level for each test (a vertex is
/// a corner of up to four faces, and every face tested).
struct PatchTests<'a> {
    topo: &'a Topology,
    /// Whether every face of `topo` is a quad ([`Topology::quads_only`]; levels 1 and up).
    quads_only: bool,
    /// Per vertex: 0 irregular, 1 regular, 2 not judged yet.
    vertex: Vec<u8>,
    /// Per vertex: 0 not a grid corner, 1 a grid corner, 2 not judged yet (empty until a
    /// single-crease patch is looked for).
    grid_corner: Vec<u8>,
}

/// Judges `v` by `test` once: `memo[v]` 0 false, 1 true, 2 not judged yet.
fn judged_once(memo: &mut [u8], v: u32, test: impl FnOnce() -> bool) -> bool {
    let r = &mut memo[v as usize];
    if *r == 2 {
        *r = u8::from(test());
    }
    *r == 1
}

impl<'a> PatchTests<'a> {
    fn new(topo: &'a Topology) -> PatchTests<'a> {
        PatchTests {
            topo,
            quads_only: topo.quads_only(),
            vertex: vec![2; topo.vertex_count()],
            grid_corner: Vec::new(),
        }
    }

    /// Face `f`'s corners and edges if it is a quad ([`Topology::quad`]; on a level of quads
    /// only, without reading the face offsets).
    fn quad(&self, f: u32) -> Option<(&'a [u32; 4], &'a [u32; 4])> {
        self.topo.quad_with(f, self.quads_only)
    }

    fn regular_vertex(&mut self, v: u32) -> bool {
        judged_once(&mut self.vertex, v, || {
            is_regular_vertex(self.topo, v, self.quads_only)
        })
    }

    /// The single-crease line of face `f` (one with a limit surface), if any
    /// ([`super::single_crease::single_crease_line`]).
    fn single_crease_line(&mut self, f: u32) -> Option<CreaseLine> {
        let (topo, quads_only) = (self.topo, self.quads_only);
        let quad = self.quad(f)?;
        if self.grid_corner.is_empty() {
            self.grid_corner = vec![2; topo.vertex_count()];
        }
        let memo = &mut self.grid_corner;
        if !quad
            .0
            .iter()
            .all(|&v| judged_once(memo, v, || is_grid_corner(topo, v, quads_only)))
        {
            return None;
        }
        single_crease_line_at_grid_corners(topo, f, quad)
    }

    /// The regular patch of face `f` (one with a limit surface), if any.
    fn patch(&mut self, f: u32) -> Option<RegularPatch> {
        let quad = self.quad(f)?;
        if !quad.0.iter().all(|&v| self.regular_vertex(v)) {
            return None;
        }
        RegularPatch::gather_at_regular_corners(self.topo, f, quad)
    }
}

impl AdaptiveRefinement {
    /// Refines `base` to `isolation` (`0..=MAX_ISOLATION`): at each level every own face with a
    /// limit surface that is not a regular patch is refined (non-quads in the first step), and
    /// the test is repeated on its children. Holes are never refined. Single-crease patches
    /// off ([`Self::with_options`]).
    pub fn new(base: &Level, isolation: u32) -> Result<AdaptiveRefinement> {
        Self::with_options(base, AdaptiveOptions::new(isolation))
    }

    /// Refines `base` as [`Self::new`] does; with [`AdaptiveOptions::single_crease`] a face
    /// that is a single-crease patch is not refined either.
    ///
    /// Levels of neighbouring patches still differ by at most one (Köbler 2013 §3.7): the
    /// corners of a single-crease face are interior valence-4 vertices with all their edges
    /// smooth or on the line, so the children next to it of a refined neighbour are regular or
    /// single-crease again (tested on the corpus).
    pub fn with_options(base: &Level, options: AdaptiveOptions) -> Result<AdaptiveRefinement> {
        Self::from_level(base.clone(), options)
    }

    /// [`Self::with_options`] of a base level the refinement takes as its level 0 (no copy
    /// of its topology).
    pub fn from_level(base: Level, options: AdaptiveOptions) -> Result<AdaptiveRefinement> {
        let AdaptiveOptions {
            isolation,
            single_crease,
            end_cap_sharpness,
            lattice_normals,
        } = options;
        if isolation > MAX_ISOLATION {
            return Err(Error::Invalid(format!(
                "isolation {isolation} out of range 0..={MAX_ISOLATION}"
            )));
        }
        let nf = base.face_count();
        let domains = (0..nf as u32)
            .map(|f| Domain {
                base_face: f,
                sub_face: None,
                origin: DVec2::ZERO,
                u: DVec2::X,
                v: DVec2::Y,
            })
            .collect();
        let mut current = AdaptiveLevel {
            level: base,
            first_vertex: 0,
            own: vec![true; nf],
            refined: vec![false; nf],
            domains,
            refinement: None,
        };
        let mut levels = Vec::new();
        let mut census = PatchCensus {
            patches: Vec::new(),
            levels: Vec::new(),
        };
        for l in 0..=isolation {
            let level_census = classify_level(
                &mut current,
                l,
                l < isolation,
                single_crease,
                &mut census.patches,
            );
            census.levels.push(level_census);
            let any = current.refined.iter().any(|&r| r);
            if !any {
                levels.push(current);
                break;
            }
            let next = refine_sparse(&mut current)?;
            log::debug!(
                "adaptive level {}: {} faces ({} own), {} vertices",
                l + 1,
                next.level.face_count(),
                next.own.iter().filter(|&&o| o).count(),
                next.level.vertex_count()
            );
            levels.push(std::mem::replace(&mut current, next));
        }
        // Reserved a level ahead (`classify_level`): cut to the patches (a shrinking
        // `realloc`, which glibc does in place).
        census.patches.shrink_to_fit();
        Ok(AdaptiveRefinement {
            levels,
            isolation,
            single_crease,
            end_cap_sharpness,
            lattice_normals,
            census,
        })
    }

    /// The drawn patches and their counts by type and level.
    pub fn census(&self) -> &PatchCensus {
        &self.census
    }

    /// Positions of every vertex of every level (the global vertex buffer) from the base mesh's
    /// positions, by the uniform refinement matrices of the refined sub-levels.
    pub fn refine_positions(&self, base: &[DVec3]) -> Vec<DVec3> {
        let mut out = Vec::with_capacity(self.vertex_count());
        out.extend_from_slice(base);
        for pair in self.levels.windows(2) {
            let (lev, next) = (&pair[0], &pair[1]);
            let Some(r) = lev.uniform_step(next) else {
                break;
            };
            let r = r.expect("a refined level's faces extract");
            let first = lev.first_vertex as usize;
            let sub: Vec<DVec3> = r
                .parent_vertices
                .iter()
                .map(|&v| out[first + v as usize])
                .collect();
            let child = r.parent.refine_positions(&sub);
            out.extend(r.child_points.iter().map(|&p| child[p as usize]));
        }
        out
    }

    /// Total number of vertices over all levels (the size of the global vertex buffer).
    pub fn vertex_count(&self) -> usize {
        self.levels
            .last()
            .map_or(0, |l| l.first_vertex as usize + l.level.vertex_count())
    }

    /// Level `level`'s topology as its end caps see it ([`Self::end_cap_sharpness`]), with its
    /// decayed corners marked ([`Topology::is_decayed_corner`]).
    pub fn end_cap_topology(&self, level: usize) -> std::borrow::Cow<'_, Topology> {
        let caps = self
            .end_cap_sharpness
            .end_cap_topology(self.levels[level].topology());
        let decayed = self.decayed_corners(level, &caps);
        if !decayed.contains(&true) {
            return caps;
        }
        let mut t = caps.into_owned();
        t.decayed_corner = decayed;
        std::borrow::Cow::Owned(t)
    }

    /// Per vertex of level `level` seen as `caps`: a decayed corner, smooth in `caps` (no
    /// sharp, semi-sharp or boundary edge, no vertex sharpness) and the vertex point of a level-`level - 1` vertex
    /// with three or more incident edges of sharpness `>= 1` there, so the last step applied
    /// the corner rule to it in full. Empty on level 0.
    fn decayed_corners(&self, level: usize, caps: &Topology) -> Vec<bool> {
        let Some(parent) = level.checked_sub(1).map(|l| &self.levels[l]) else {
            return Vec::new();
        };
        let pt = parent.topology();
        // A decayed corner's parent edges are all finite (an infinitely sharp one stays sharp),
        // three or more of them `>= 1`: without such an edge there is none to look for.
        let decaying = |s: f32| (1.0..INFINITE_SHARPNESS).contains(&s);
        if !pt.edge_sharpnesses().iter().any(|&s| decaying(s)) {
            return Vec::new();
        }
        // Per parent vertex: its edges of sharpness `>= 1`, from one pass over the edges (at
        // most a few vertices have three), so the rings are walked only at those vertices'
        // vertex points.
        let mut sharp_before = vec![0u8; pt.vertex_count()];
        for (&[a, b], &s) in pt.edge_verts.iter().zip(pt.edge_sharpnesses()) {
            if s >= 1.0 {
                for v in [a, b] {
                    let n = &mut sharp_before[v as usize];
                    *n = n.saturating_add(1);
                }
            }
        }
        // Without a parent vertex of three such edges (most levels) no vertex is asked.
        if !sharp_before.iter().any(|&n| n >= 3) {
            return Vec::new();
        }
        let smooth_now = |v: u32| {
            caps.vertex_sharpness(v) == 0.0
                && caps
                    .vertex_edges(v)
                    .iter()
                    .all(|&e| caps.edge_sharpness(e) == 0.0 && !caps.is_boundary_edge(e))
        };
        let child_of = &parent.step().child_of;
        (0..caps.vertex_count() as u32)
            .map(|v| match child_of[v as usize] {
                ChildOf::Vertex(pv) => sharp_before[pv as usize] >= 3 && smooth_now(v),
                _ => false,
            })
            .collect()
    }
}

/// Adds to `selected` every vertex of a hole touching a selected vertex, until no hole adds
/// one. Holes are refined topologically but never drawn (as OpenSubdiv does): a hole next to a
/// refined face is kept whole in the next level with the faces around its corners, so the
/// one-rings of the vertices it shares with drawn patches stay complete (otherwise a hole's far
/// corners, missing their faces, would make every child next to the hole incomplete and the end
/// caps there impossible). Only ring faces are added: which faces are refined, and so the patch
/// census, is unchanged.
fn close_over_holes(t: &Topology, selected: &mut [bool]) {
    let holes: Vec<u32> = (0..t.face_count() as u32)
        .filter(|&f| t.is_hole(f))
        .collect();
    let mut grew = !holes.is_empty();
    while grew {
        grew = false;
        for &f in &holes {
            let fv = t.face_vertices(f);
            if fv.iter().any(|&v| selected[v as usize]) && !fv.iter().all(|&v| selected[v as usize])
            {
                fv.iter().for_each(|&v| selected[v as usize] = true);
                grew = true;
            }
        }
    }
}

/// Builds the level after `cur` from its `refined` faces, storing the step in `cur`.
fn refine_sparse(cur: &mut AdaptiveLevel) -> Result<AdaptiveLevel> {
    let t = cur.topology();
    let mut selected = vec![false; t.vertex_count()];
    for f in 0..t.face_count() as u32 {
        if cur.refined[f as usize] {
            for &v in t.face_vertices(f) {
                selected[v as usize] = true;
            }
        }
    }
    close_over_holes(t, &mut selected);
    // Every array sized up front (at most every face in the ring, at most every corner of the
    // ring kept): no growth, each of which would copy the array.
    let mut ring = Vec::with_capacity(t.face_count());
    ring.extend(
        (0..t.face_count() as u32)
            .filter(|&f| t.face_vertices(f).iter().any(|&v| selected[v as usize])),
    );
    let corners = ring.iter().map(|&f| t.face_size(f)).sum();
    let mut keep = Vec::with_capacity(corners);
    let mut own = Vec::with_capacity(corners);
    let mut domains = Vec::with_capacity(corners);
    for &f in &ring {
        let r = cur.refined[f as usize];
        let fv = t.face_vertices(f);
        let off = t.face_offsets()[f as usize];
        let child = cur.domains[f as usize].children(fv.len());
        for (k, &v) in fv.iter().enumerate() {
            if r || selected[v as usize] {
                keep.push(off + k as u32);
                own.push(r);
                domains.push(child(k));
            }
        }
    }
    let (level, mut points) = refine_in_place(&cur.level, &ring, &keep)?;
    let mut child_of = Vec::with_capacity(level.vertex_count());
    child_of.extend(points.faces.iter().map(|&f| ChildOf::Face(f)));
    child_of.extend(points.edges.iter().map(|&e| ChildOf::Edge(e)));
    child_of.extend(points.vertices.iter().map(|&v| ChildOf::Vertex(v)));
    let next = AdaptiveLevel {
        first_vertex: cur.first_vertex + t.vertex_count() as u32,
        own,
        refined: vec![false; level.face_count()],
        domains,
        refinement: None,
        level,
    };
    cur.refinement = Some(Refinement {
        parent_faces: ring,
        child_corners: keep,
        child_faces: std::mem::take(&mut points.quad_faces),
        child_of,
    });
    Ok(next)
}

/// The kind of a drawn patch.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum PatchType {
    /// Full regular B-spline patch, 16 real control vertices.
    Regular,
    /// Regular with phantom rows on real boundary edges only.
    Boundary,
    /// Regular with a phantom row on an interior infinitely sharp edge.
    Crease,
    /// Still irregular at the isolation level: a Gregory patch over that level's points.
    EndCap,
    /// A regular quad with one semi-sharp crease line (Nießner, Loop, Greiner 2012 §3), only
    /// with [`AdaptiveOptions::single_crease`].
    SingleCrease,
}

impl PatchType {
    /// Every type, in census order.
    pub const ALL: [PatchType; 5] = [
        PatchType::Regular,
        PatchType::Boundary,
        PatchType::Crease,
        PatchType::EndCap,
        PatchType::SingleCrease,
    ];

    /// Lower-case name (`regular`, `boundary`, `crease`, `end-cap`, `single-crease`).
    pub fn name(self) -> &'static str {
        match self {
            PatchType::Regular => "regular",
            PatchType::Boundary => "boundary",
            PatchType::Crease => "crease",
            PatchType::EndCap => "end-cap",
            PatchType::SingleCrease => "single-crease",
        }
    }
}

/// A drawn patch of an [`AdaptiveRefinement`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AdaptivePatch {
    /// Its level.
    pub level: u32,
    /// The face (index in its level).
    pub face: u32,
    /// Its type.
    pub kind: PatchType,
    /// B-spline and single-crease patches: control vertices as global ids, phantom mask (no
    /// phantoms for single-crease patches; `None` for end caps).
    pub bspline: Option<RegularPatch>,
    /// Single-crease patches: the crease line (its `cvs` global ids, as `bspline`'s).
    pub crease: Option<CreaseLine>,
    /// Bit `k`: the neighbour across face edge `k` is one level finer (thesis §3.4).
    pub transition: u8,
}

/// Patch counts of one level.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct LevelCensus {
    /// Per [`PatchType`] (in [`PatchType::ALL`] order).
    pub by_type: [usize; PatchType::ALL.len()],
    /// Of those, B-spline patches with a finer neighbour.
    pub transition: usize,
}

impl LevelCensus {
    /// All patches of the level.
    pub fn total(&self) -> usize {
        self.by_type.iter().sum()
    }
}

/// The patches of an [`AdaptiveRefinement`] and their counts by type and level.
#[derive(Debug, Clone)]
pub struct PatchCensus {
    /// Every drawn patch, level by level.
    pub patches: Vec<AdaptivePatch>,
    /// Counts per level.
    pub levels: Vec<LevelCensus>,
}

impl PatchCensus {
    /// Classifies every own face with a limit surface that is not refined: a B-spline patch
    /// when [`RegularPatch::gather`] takes it, else (with single-crease patches on) a
    /// single-crease patch when [`single_crease_line`](super::single_crease::single_crease_line)
    /// takes it, an end cap otherwise (only possible on the isolation level).
    ///
    /// The refinement classified them while choosing its refined faces: this is a copy of
    /// [`AdaptiveRefinement::census`].
    pub fn new(refinement: &AdaptiveRefinement) -> PatchCensus {
        refinement.census.clone()
    }

    /// All patches.
    pub fn total(&self) -> usize {
        self.patches.len()
    }

    /// Patches of one type over all levels.
    pub fn count(&self, kind: PatchType) -> usize {
        self.levels.iter().map(|c| c.by_type[kind as usize]).sum()
    }
}

/// Classifies the own faces with a limit surface of level `l` in one pass: with `refine` (below
/// the isolation level) a face that is neither a regular patch nor (with `single_crease`) a
/// single-crease patch is marked refined, the others are appended to `patches` (end caps too,
/// on the isolation level), face order, with their transition bits once every face of the
/// level is judged. Returns the level's counts.
fn classify_level(
    lev: &mut AdaptiveLevel,
    l: u32,
    refine: bool,
    single_crease: bool,
    patches: &mut Vec<AdaptivePatch>,
) -> LevelCensus {
    let first = patches.len();
    {
        let t = lev.level.topology();
        // At most one patch an own face, and (below the isolation level) at most one an own
        // face of the next level, a child of a refined face: one a corner at most. Reserved a
        // level ahead, the next level's patches need no growth, which would copy every earlier
        // level's.
        let own = lev.own.iter().filter(|&&o| o).count();
        let next = match (refine, t.quads_only()) {
            (false, _) => 0,
            (true, true) => 4 * own,
            (true, false) => t.corner_count(),
        };
        reserve_copying_len(patches, own + next);
        let mut tests = PatchTests::new(t);
        for f in 0..t.face_count() as u32 {
            if !lev.own[f as usize] || !t.has_limit_surface(f) {
                continue;
            }
            match classify(lev, &mut tests, f, l, single_crease) {
                p if p.kind == PatchType::EndCap && refine => lev.refined[f as usize] = true,
                p => patches.push(p),
            }
        }
    }
    let t = lev.level.topology();
    let mut census = LevelCensus::default();
    // No face refined (the isolation level, or every face a patch): no transition to look for.
    let any_refined = lev.refined.contains(&true);
    let quads_only = t.quads_only();
    for p in &mut patches[first..] {
        // B-spline and single-crease patches are quads: edge `k` is the quad's.
        let quad =
            (any_refined && p.kind != PatchType::EndCap).then(|| t.quad_with(p.face, quads_only));
        if let Some(Some((_, edges))) = quad {
            for (k, &e) in edges.iter().enumerate() {
                if t.face_across_edge(e, p.face)
                    .is_some_and(|(g, _)| lev.refined[g as usize])
                {
                    p.transition |= 1 << k;
                }
            }
        }
        census.by_type[p.kind as usize] += 1;
        census.transition += usize::from(p.transition != 0);
    }
    census
}

/// Room in `patches` for `additional` more: when short, a new allocation the patches are
/// copied to (`Vec::reserve`'s `realloc` would copy the whole old capacity, reserved a level
/// ahead by `classify_level`, not just the patches).
fn reserve_copying_len(patches: &mut Vec<AdaptivePatch>, additional: usize) {
    if patches.capacity() - patches.len() < additional {
        let mut grown = Vec::with_capacity(patches.len() + additional);
        grown.extend_from_slice(patches);
        *patches = grown;
    }
}

/// The patch of own face `f` of `lev` (transition bits not set: they need the level's refined
/// faces, `classify_level`).
///
/// Single-crease patches keep their full sharpness, also where it exceeds the levels left to
/// the isolation level: OpenSubdiv caps it at `isolation - level` (`patchTableFactory.cpp`,
/// which then draws a single-crease face of the isolation level as a plain regular patch),
/// which only changes the surface, not the count; uncapped, the patch is the exact limit.
fn classify(
    lev: &AdaptiveLevel,
    tests: &mut PatchTests,
    f: u32,
    level: u32,
    single_crease: bool,
) -> AdaptivePatch {
    let t = lev.topology();
    // The level's offset read once (not per control point): the 16 sums vectorise.
    let first = lev.first_vertex;
    let global = |cvs: &mut [u32; 16]| *cvs = cvs.map(|c| first + c);
    let (mut p, kind, crease) = if let Some(p) = tests.patch(f) {
        // A phantom side on an edge that is not a boundary: a crease patch (most patches have
        // no phantom side, and need no edge).
        let crease = |mask: u8| {
            let edges = t.face_edges(f);
            (0..4).any(|k| mask & (1 << k) != 0 && !t.is_boundary_edge(edges[k]))
        };
        let kind = match p.boundary_mask {
            0 => PatchType::Regular,
            mask if crease(mask) => PatchType::Crease,
            _ => PatchType::Boundary,
        };
        (p, kind, None)
    } else if let Some(mut line) = single_crease.then(|| tests.single_crease_line(f)).flatten() {
        let p = RegularPatch {
            face: f,
            cvs: line.cvs,
            boundary_mask: 0,
        };
        global(&mut line.cvs);
        (p, PatchType::SingleCrease, Some(line))
    } else {
        return AdaptivePatch {
            level,
            face: f,
            kind: PatchType::EndCap,
            bspline: None,
            crease: None,
            transition: 0,
        };
    };
    global(&mut p.cvs);
    AdaptivePatch {
        level,
        face: f,
        kind,
        bspline: Some(p),
        crease,
        transition: 0,
    }
}

/// Each corpus mesh of `cases` (`(name, isolation)`) adaptively refined to its isolation level,
/// as `(name, refinement)`: unit tests' inputs.
#[cfg(test)]
pub(crate) fn corpus_refinements(cases: &[(&str, u32)]) -> Vec<(String, AdaptiveRefinement)> {
    let names: Vec<&str> = cases.iter().map(|c| c.0).collect();
    (super::corpus_levels(&names, 0).iter().zip(cases))
        .map(|((name, _, level), &(_, isolation))| {
            let refinement = AdaptiveRefinement::new(level, isolation).unwrap();
            (name.clone(), refinement)
        })
        .collect()
}
