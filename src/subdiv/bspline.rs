//! Bicubic B-spline patches: the Catmull-Clark limit surface of a (boundary-)regular quad
//! (Köbler 2013 §3.1), including quads next to boundaries and infinitely sharp creases, which use
//! mirrored phantom control points. The uniform cubic B-spline basis (de Boor; Köbler 2013 §2.1)
//! and [`LimitSample`], the result type of every limit evaluation, live here too: exact
//! evaluation ([`super::eval`]) is built on them, and the patch schemes ([`crate::patch`]) build
//! on this module, never the other way round.

use glam::DVec3;

use crate::mesh::INFINITE_SHARPNESS;
use crate::topology::{Topology, NONE};

/// A point of the limit surface with its partial derivatives and unit normal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LimitSample {
    /// Limit position.
    pub position: DVec3,
    /// dP/du. At an extraordinary vertex (where the parametric derivative degenerates) a
    /// tangent along the face's u edge direction, arbitrarily scaled.
    pub du: DVec3,
    /// dP/dv (same caveat as `du`).
    pub dv: DVec3,
    /// `normalize(du x dv)`: outward for counter-clockwise faces.
    pub normal: DVec3,
}

impl LimitSample {
    /// Builds a sample from position and partials; the normal is `normalize(du x dv)` (zero if
    /// the partials are parallel).
    pub fn new(position: DVec3, du: DVec3, dv: DVec3) -> LimitSample {
        LimitSample {
            position,
            du,
            dv,
            normal: du.cross(dv).normalize_or_zero(),
        }
    }
}

/// The bicubic B-spline patch of a (boundary-)regular quad.
///
/// `cvs[4 * j + i]`: `i` along u, `j` along v; the face corners 0, 1, 2, 3 are `cvs[5]`,
/// `cvs[6]`, `cvs[10]`, `cvs[9]`, so patch `(u, v)` equals face `(u, v)`.
/// `boundary_mask` bit `e` is set when patch edge `e` lies on a boundary or infinitely sharp
/// crease: bit 0 = `v = 0` side (row 0 phantom), bit 1 = `u = 1` (column 3 phantom), bit 2 =
/// `v = 1` (row 3 phantom), bit 3 = `u = 0` (column 0 phantom). Phantom entries hold a valid
/// vertex index and are ignored; [`RegularPatch::control_points`] mirrors them: columns first
/// (`col0 = 2 col1 - col2`, `col3 = 2 col2 - col1`), then rows (`row0 = 2 row1 - row2`,
/// `row3 = 2 row2 - row1`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RegularPatch {
    /// The face this patch covers.
    pub face: u32,
    /// Control vertex indices (see the type docs).
    pub cvs: [u32; 16],
    /// Phantom sides (see the type docs).
    pub boundary_mask: u8,
}

/// What a face corner looks like for the regular-patch test.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum CornerKind {
    /// Interior, valence 4, all quads, no sharpness.
    Smooth,
    /// Crease rule, the face's sector between the two sharp edges has 2 faces.
    Crease,
    /// Corner rule, the face's sector has 1 face.
    Corner,
    /// Anything else.
    Irregular,
}

fn is_inf(s: f32) -> bool {
    s >= INFINITE_SHARPNESS
}

fn is_semi(s: f32) -> bool {
    s > 0.0 && s < INFINITE_SHARPNESS
}

/// Classifies vertex `v` as seen from face `f` (one of its faces).
fn corner_kind(topo: &Topology, v: u32, f: u32) -> CornerKind {
    let faces = topo.vertex_faces(v);
    let edges = topo.vertex_edges(v);
    let vs = topo.vertex_sharpness(v);
    if is_semi(vs) || faces.iter().any(|&g| topo.face_size(g) != 4) {
        return CornerKind::Irregular;
    }
    let mut sharp = 0;
    for &e in edges {
        let s = topo.edge_sharpness(e);
        if is_semi(s) {
            return CornerKind::Irregular;
        }
        if is_inf(s) {
            sharp += 1;
        }
    }
    let boundary = topo.is_boundary_vertex(v);
    if sharp == 0 && !is_inf(vs) {
        return if !boundary && faces.len() == 4 && edges.len() == 4 {
            CornerKind::Smooth
        } else {
            CornerKind::Irregular
        };
    }
    let Some(i) = faces.iter().position(|&g| g == f) else {
        return CornerKind::Irregular;
    };
    // Sector size around face i: walk both ways until a sharp edge.
    let nf = faces.len();
    let ne = edges.len();
    let mut size = 1;
    let mut j = i;
    loop {
        let e = edges[(j + 1) % ne];
        if is_inf(topo.edge_sharpness(e)) || size > nf {
            break;
        }
        j = (j + 1) % nf;
        size += 1;
    }
    let mut j = i;
    loop {
        let e = edges[j];
        if is_inf(topo.edge_sharpness(e)) || size > nf {
            break;
        }
        j = (j + nf - 1) % nf;
        size += 1;
    }
    let corner_rule = is_inf(vs) || sharp > 2;
    match (sharp, corner_rule, size) {
        (2, false, 2) => CornerKind::Crease,
        (_, true, 1) if sharp >= 2 => CornerKind::Corner,
        _ => CornerKind::Irregular,
    }
}

/// Whether vertex `v` is a regular corner of every face around it (smooth valence 4, or a
/// crease/corner vertex whose every sector is the size a regular patch takes). Feature-adaptive
/// refinement judges regularity per vertex so that neighbouring patch levels differ by at most
/// one (Köbler 2013 §3.7): a crease vertex with sectors of 2 and 4 faces is irregular for both.
/// `quads_only`: whether every face of `topo` is a quad ([`Topology::quads_only`], asked once
/// per level); then a smooth vertex's face sizes are not read.
pub(crate) fn is_regular_vertex(topo: &Topology, v: u32, quads_only: bool) -> bool {
    // Without sharpness the vertex looks the same from each of its faces (`corner_kind`'s
    // smooth case): judged once, not once per face.
    let vs = topo.vertex_sharpness(v);
    let plain = vs == 0.0
        && topo
            .vertex_edges(v)
            .iter()
            .all(|&e| topo.edge_sharpness(e) == 0.0);
    let faces = topo.vertex_faces(v);
    if plain && !faces.is_empty() {
        // The counts first: they are the cheap tests and settle most vertices. As many edges
        // as faces: interior (`Topology::is_boundary_vertex`).
        return faces.len() == 4
            && topo.vertex_edges(v).len() == 4
            && (quads_only || faces.iter().all(|&g| topo.face_size(g) == 4));
    }
    faces
        .iter()
        .all(|&f| corner_kind(topo, v, f) != CornerKind::Irregular)
}

/// Grid position `(i, j)` of face corner `k`.
const CORNER_POS: [(i32, i32); 4] = [(1, 1), (2, 1), (2, 2), (1, 2)];
/// Outward grid direction of face edge `k`.
const OUT: [(i32, i32); 4] = [(0, -1), (1, 0), (0, 1), (-1, 0)];

const fn slot(p: (i32, i32)) -> usize {
    (4 * p.1 + p.0) as usize
}

/// Grid slot of face corner `k` (`CORNER_POS`).
const CORNER_SLOT: [usize; 4] = {
    let mut s = [0; 4];
    let mut k = 0;
    while k < 4 {
        s[k] = slot(CORNER_POS[k]);
        k += 1;
    }
    s
};

/// Grid slots of the far corners `r2`, `r3` of the neighbour across face edge `k` (beside
/// corners `k` and `k + 1`, one step out along `OUT[k]`).
const SIDE_SLOTS: [[usize; 2]; 4] = {
    let mut s = [[0; 2]; 4];
    let mut k = 0;
    while k < 4 {
        let (a, b, o) = (CORNER_POS[k], CORNER_POS[(k + 1) % 4], OUT[k]);
        s[k] = [slot((a.0 + o.0, a.1 + o.1)), slot((b.0 + o.0, b.1 + o.1))];
        k += 1;
    }
    s
};

/// Grid slot of the diagonal vertex at face corner `k` (out along `OUT[k]` and `OUT[k - 1]`).
const DIAGONAL_SLOT: [usize; 4] = {
    let mut s = [0; 4];
    let mut k = 0;
    while k < 4 {
        let (a, o, p) = (CORNER_POS[k], OUT[k], OUT[(k + 3) % 4]);
        s[k] = slot((a.0 + o.0 + p.0, a.1 + o.1 + p.1));
        k += 1;
    }
    s
};

/// Grid slots read from the face diagonal to quad `face` at its corner `k` (corner `l` of that
/// face is `c[k]`): its corners `l + 1`, `l + 2`, `l + 3` are the grid vertex beside corner `k`
/// out across face edge `k - 1`, the diagonal vertex, and the one out across face edge `k`
/// (counter-clockwise faces and rings, see [`grid_cvs_from_rings`]).
const RING_SLOTS: [[usize; 3]; 4] = {
    let mut s = [[0; 3]; 4];
    let mut k = 0;
    while k < 4 {
        s[k] = [
            SIDE_SLOTS[(k + 3) % 4][1],
            DIAGONAL_SLOT[k],
            SIDE_SLOTS[k][0],
        ];
        k += 1;
    }
    s
};

/// The 16 grid vertices of quad `face` (corners `c`) without phantom sides whose corners are
/// interior vertices with four quads around them: the outer twelve read from the face opposite
/// `face` in each corner's ring ([`RING_SLOTS`]), four faces read instead of eight walked across
/// edges. The grid [`grid_cvs`] walks (tested); `None` when a corner's ring is not four faces
/// holding `face` or a face read is not a quad.
fn grid_cvs_from_rings(topo: &Topology, face: u32, c: &[u32; 4]) -> Option<[u32; 16]> {
    let quads_only = topo.quads_only();
    let mut cvs = [c[0]; 16];
    for k in 0..4 {
        let v = c[k];
        cvs[CORNER_SLOT[k]] = v;
        let (faces, locals) = (topo.vertex_faces(v), topo.vertex_face_locals(v));
        if faces.len() != 4 || locals.len() != 4 {
            return None;
        }
        let i = faces.iter().position(|&g| g == face)?;
        // The diagonal face: two steps round the ring of four.
        let opposite = (i + 2) & 3;
        let (dv, _) = topo.quad_with(faces[opposite], quads_only)?;
        let l = usize::from(locals[opposite]);
        for (j, &s) in RING_SLOTS[k].iter().enumerate() {
            cvs[s] = dv[(l + 1 + j) & 3];
        }
    }
    Some(cvs)
}

/// Tests' check of [`grid_cvs_from_rings`] on every quad of `topo`: for those whose corners are
/// interior with four quads around them, the grid [`grid_cvs`] walks (`Err(face)` at the first
/// that differs, else how many agree); how many others it declines.
#[cfg(test)]
pub(crate) fn grids_from_rings_checked(topo: &Topology) -> (Result<usize, u32>, usize) {
    let four_quads = |v: u32| {
        topo.vertex_faces(v).len() == 4
            && topo.vertex_edges(v).len() == 4
            && topo.vertex_faces(v).iter().all(|&g| topo.face_size(g) == 4)
    };
    let (mut same, mut declined) = (0, 0);
    for f in 0..topo.face_count() as u32 {
        let Some((c, fe)) = topo.quad(f) else {
            continue;
        };
        let from_rings = grid_cvs_from_rings(topo, f, c);
        if c.iter().all(|&v| four_quads(v)) {
            if from_rings != grid_cvs(topo, f, (c, fe), 0) {
                return (Err(f), declined);
            }
            same += 1;
        } else if from_rings.is_none() {
            declined += 1;
        }
    }
    (Ok(same), declined)
}

/// The neighbour across edge `e` that quad `f` runs `a -> b`, with its corners rotated to
/// `[b, a, r2, r3]` (`r2` adjacent to `a`, `r3` adjacent to `b`) and its edges in the same
/// rotation (edge `i` from corner `i` to `i + 1`): its index, `[r2, r3]` and its edges 1
/// (`a -> r2`) and 3 (`r3 -> b`), the only ones the grid needs.
///
/// The rotation is the edge's position in the neighbour (a face repeats no vertex, so `b` is the
/// neighbour's corner there exactly when it runs the edge `b -> a`); `across_by_search` is the
/// oracle that finds `b` among the corners instead. Inlined into the grid walk (eight calls a
/// grid), whose per-call overhead was a third of its cost.
#[inline(always)]
fn across(
    topo: &Topology,
    quads_only: bool,
    f: u32,
    e: u32,
    a: u32,
    b: u32,
) -> Option<(u32, [u32; 2], [u32; 2])> {
    let (g, s) = topo.face_across_edge(e, f)?;
    let (gv, ge) = topo.quad_with(g, quads_only)?;
    // `s < 4` (an edge of the quad `g`): masked, it needs no bounds check.
    (gv[s & 3] == b && gv[(s + 1) & 3] == a).then(|| {
        (
            g,
            [gv[(s + 2) & 3], gv[(s + 3) & 3]],
            [ge[(s + 1) & 3], ge[(s + 3) & 3]],
        )
    })
}

/// [`across`] finding `b` among the neighbour's corners (the former path; tests' oracle).
#[cfg(test)]
fn across_by_search(
    topo: &Topology,
    f: u32,
    e: u32,
    a: u32,
    b: u32,
) -> Option<(u32, [u32; 2], [u32; 2])> {
    let g = *topo.edge_faces(e).iter().find(|&&g| g != f)?;
    let gv = topo.face_vertices(g);
    if gv.len() != 4 {
        return None;
    }
    let s = gv.iter().position(|&x| x == b)?;
    let ge = topo.face_edges(g);
    (gv[(s + 1) & 3] == a).then(|| {
        (
            g,
            [gv[(s + 2) & 3], gv[(s + 3) & 3]],
            [ge[(s + 1) & 3], ge[(s + 3) & 3]],
        )
    })
}

/// The 16 grid vertices around quad `face` (corners `c`, layout of [`RegularPatch::cvs`]); sides
/// in `mask` are left phantom (holding `c[0]`). `None` when a needed neighbour is missing or not
/// a quad.
///
/// Edges are taken from the faces (an edge is the only one between its two vertices, so this is
/// the edge `find_edge` would find).
fn grid_cvs(
    topo: &Topology,
    face: u32,
    (c, fe): (&[u32; 4], &[u32; 4]),
    mask: u8,
) -> Option<[u32; 16]> {
    grid_cvs_edges(topo, face, (c, fe), mask).map(|(cvs, _)| cvs)
}

/// [`grid_cvs`] with the grid edges leaving the face's corners: for face edge `k` not in `mask`,
/// entry `2 k` is the edge from corner `k` and entry `2 k + 1` the edge from corner `k + 1`,
/// both outward across edge `k` (`NONE` for the sides in `mask`). `(c, fe)`: the quad's
/// corners and edges ([`Topology::quad`]).
fn grid_cvs_edges(
    topo: &Topology,
    face: u32,
    (c, fe): (&[u32; 4], &[u32; 4]),
    mask: u8,
) -> Option<([u32; 16], [u32; 8])> {
    // Levels 1 and up: the neighbours' corners at `4 g`, no face offset read.
    let quads_only = topo.quads_only();
    let mut cvs = [c[0]; 16];
    let mut outward = [NONE; 8];
    for k in 0..4 {
        cvs[CORNER_SLOT[k]] = c[k];
    }
    for k in 0..4 {
        if mask & (1 << k) != 0 {
            continue;
        }
        let (a, b) = (c[k], c[(k + 1) % 4]);
        let (g, [r2, r3], [e1, e3]) = across(topo, quads_only, face, fe[k], a, b)?;
        let [s2, s3] = SIDE_SLOTS[k];
        cvs[s2] = r2;
        cvs[s3] = r3;
        outward[2 * k] = e1;
        outward[2 * k + 1] = e3;
        let prev = (k + 3) % 4;
        if mask & (1 << prev) == 0 {
            // Diagonal face at corner k: the neighbour of `g` across its edge c_k -> r2.
            let (_, [_, d3], _) = across(topo, quads_only, g, e1, c[k], r2)?;
            cvs[DIAGONAL_SLOT[k]] = d3;
        }
    }
    Some((cvs, outward))
}

/// The corners and edges of `face` ([`Topology::quad`]) if it is a quad with a limit surface.
fn quad_with_limit(topo: &Topology, face: u32) -> Option<(&[u32; 4], &[u32; 4])> {
    if face as usize >= topo.face_count() || !topo.has_limit_surface(face) {
        return None;
    }
    topo.quad(face)
}

/// The 16 grid vertices of an interior quad whose corners are all interior valence-4 vertices
/// with only quads around them and no vertex sharpness, whatever the edge sharpness: the net of
/// [`interior_grid_lines`] alone (tests' oracles).
#[cfg(test)]
pub(crate) fn interior_grid(topo: &Topology, face: u32) -> Option<[u32; 16]> {
    interior_grid_lines(topo, face).map(|(cvs, _)| cvs)
}

/// The 16 grid vertices of an interior quad whose corners are all interior valence-4 vertices
/// with only quads around them and no vertex sharpness, whatever the edge sharpness (the
/// single-crease patch gathers its net with this, [`crate::patch::single_crease`]), with the
/// grid's four lines through the face's edges: line `k` the three
/// edges of the grid row or column through face edge `k`, in that edge's direction (the edge
/// from corner `k` away from the face, face edge `k`, the edge from corner `k + 1` away from the
/// face). Read from the faces the grid walk crosses, so no edge is looked up by its ends.
pub(crate) fn interior_grid_lines(
    topo: &Topology,
    face: u32,
) -> Option<([u32; 16], [[u32; 3]; 4])> {
    let quad = quad_with_limit(topo, face)?;
    let quads_only = topo.quads_only();
    if !quad.0.iter().all(|&v| is_grid_corner(topo, v, quads_only)) {
        return None;
    }
    interior_grid_lines_at_grid_corners(topo, face, quad)
}

/// Whether `v` is an interior valence-4 vertex with only quads around it and no vertex
/// sharpness, whatever its edges' sharpness: a corner [`interior_grid_lines`] takes. The counts
/// first: they are the cheap tests and settle most vertices; as many edges as faces, it is
/// interior ([`Topology::is_boundary_vertex`]). `quads_only` as [`is_regular_vertex`] takes it.
pub(crate) fn is_grid_corner(topo: &Topology, v: u32, quads_only: bool) -> bool {
    let faces = topo.vertex_faces(v);
    faces.len() == 4
        && topo.vertex_edges(v).len() == 4
        && topo.vertex_sharpness(v) == 0.0
        && (quads_only || faces.iter().all(|&g| topo.face_size(g) == 4))
}

/// [`interior_grid_lines`] of a quad with a limit surface whose corners are known to pass
/// [`is_grid_corner`], given its corners and edges `quad` ([`Topology::quad`]): the adaptive
/// census judges each vertex once, not once per face.
pub(crate) fn interior_grid_lines_at_grid_corners(
    topo: &Topology,
    face: u32,
    quad: (&[u32; 4], &[u32; 4]),
) -> Option<([u32; 16], [[u32; 3]; 4])> {
    let (cvs, outward) = grid_cvs_edges(topo, face, quad, 0)?;
    let fe = quad.1;
    // Corner `k` continues face edge `k` backwards along the outward edge across face edge
    // `k - 1`, corner `k + 1` forwards along the one across face edge `k + 1`.
    let lines = std::array::from_fn(|k| {
        [
            outward[2 * ((k + 3) % 4) + 1],
            fe[k],
            outward[2 * ((k + 1) % 4)],
        ]
    });
    Some((cvs, lines))
}

impl RegularPatch {
    /// Builds the patch of face `face`, or `None` when the face is not (boundary-)regular: every
    /// corner must be smooth interior valence 4 (all quads, no sharpness), a crease vertex whose
    /// sector containing the face has 2 faces, or a corner whose sector has 1 face, with no
    /// semi-sharp edge or vertex at any corner. Holes and faces without limit surface give `None`.
    pub fn gather(topo: &Topology, face: u32) -> Option<RegularPatch> {
        let quad = quad_with_limit(topo, face)?;
        for &v in quad.0 {
            if corner_kind(topo, v, face) == CornerKind::Irregular {
                return None;
            }
        }
        Self::grid(topo, face, quad)
    }

    /// [`Self::gather`] of a quad with a limit surface whose corners are known to pass
    /// [`is_regular_vertex`] (a corner regular for every face around it is regular for this
    /// one), given its corners and edges `quad` ([`Topology::quad`], which the adaptive census
    /// has in hand when it has judged the corners): neither the corners nor the face are judged
    /// again.
    pub(crate) fn gather_at_regular_corners(
        topo: &Topology,
        face: u32,
        quad: (&[u32; 4], &[u32; 4]),
    ) -> Option<RegularPatch> {
        Self::grid(topo, face, quad)
    }

    /// The patch of quad `face` with regular corners and edges `(c, fe)`: phantom mask and
    /// grid.
    fn grid(topo: &Topology, face: u32, (c, fe): (&[u32; 4], &[u32; 4])) -> Option<RegularPatch> {
        let mut mask = 0u8;
        for (k, &e) in fe.iter().enumerate() {
            if is_inf(topo.edge_sharpness(e)) {
                mask |= 1 << k;
            }
        }
        // Without phantom sides every corner is smooth (a crease or corner vertex is regular
        // for this face only with a sharp edge of the face at it): interior, four quads round.
        let cvs = if mask == 0 {
            grid_cvs_from_rings(topo, face, c)?
        } else {
            grid_cvs(topo, face, (c, fe), mask)?
        };
        Some(RegularPatch {
            face,
            cvs,
            boundary_mask: mask,
        })
    }

    /// The 16 control points with phantom points filled in by the mirror rule (type docs).
    pub fn control_points(&self, positions: &[DVec3]) -> [DVec3; 16] {
        let mut p = [DVec3::ZERO; 16];
        for (k, &i) in self.cvs.iter().enumerate() {
            p[k] = positions[i as usize];
        }
        let m = self.boundary_mask;
        for j in 0..4 {
            let r = 4 * j;
            if m & 8 != 0 {
                p[r] = 2.0 * p[r + 1] - p[r + 2];
            }
            if m & 2 != 0 {
                p[r + 3] = 2.0 * p[r + 2] - p[r + 1];
            }
        }
        for i in 0..4 {
            if m & 1 != 0 {
                p[i] = 2.0 * p[4 + i] - p[8 + i];
            }
            if m & 4 != 0 {
                p[12 + i] = 2.0 * p[8 + i] - p[4 + i];
            }
        }
        p
    }

    /// Vertex ids of the face corners (u,v) = (0,0), (1,0), (1,1), (0,1) (cvs 5, 6, 10, 9).
    pub fn corners(&self) -> [u32; 4] {
        [self.cvs[5], self.cvs[6], self.cvs[10], self.cvs[9]]
    }

    /// Limit positions of the four face corners ([`Self::eval`] at the domain corners).
    pub fn corner_limits(&self, positions: &[DVec3]) -> [DVec3; 4] {
        [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
            .map(|(u, v)| self.eval(positions, u, v).position)
    }

    /// Evaluates position, partial derivatives and unit normal at `(u, v)` in `[0, 1]^2`.
    pub fn eval(&self, positions: &[DVec3], u: f64, v: f64) -> LimitSample {
        let p = self.control_points(positions);
        eval_bspline(&p, u, v)
    }
}

/// Evaluates a bicubic B-spline patch given its 16 control points.
pub fn eval_bspline(p: &[DVec3; 16], u: f64, v: f64) -> LimitSample {
    let (pos, du, dv) = eval_tensor(
        p,
        &bspline(u),
        &bspline_deriv(u),
        &bspline(v),
        &bspline_deriv(v),
    );
    LimitSample::new(pos, du, dv)
}

/// Uniform cubic B-spline basis values `B0..B3` at `t` in `[0, 1]`.
///
/// `B0 = (1-t)^3/6`, `B1 = (3t^3 - 6t^2 + 4)/6`, `B2 = (-3t^3 + 3t^2 + 3t + 1)/6`, `B3 = t^3/6`.
pub fn bspline(t: f64) -> [f64; 4] {
    let s = 1.0 - t;
    let t2 = t * t;
    let t3 = t2 * t;
    [
        s * s * s / 6.0,
        (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0,
        (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0,
        t3 / 6.0,
    ]
}

/// First derivatives of [`bspline`] with respect to `t`.
pub fn bspline_deriv(t: f64) -> [f64; 4] {
    let s = 1.0 - t;
    let t2 = t * t;
    [
        -0.5 * s * s,
        1.5 * t2 - 2.0 * t,
        -1.5 * t2 + t + 0.5,
        0.5 * t2,
    ]
}

/// Evaluates a bicubic tensor patch given basis values in u and v: returns `(P, dP/du, dP/dv)`.
pub fn eval_tensor(
    cvs: &[DVec3; 16],
    bu: &[f64; 4],
    du: &[f64; 4],
    bv: &[f64; 4],
    dv: &[f64; 4],
) -> (DVec3, DVec3, DVec3) {
    let mut p = DVec3::ZERO;
    let mut pu = DVec3::ZERO;
    let mut pv = DVec3::ZERO;
    for j in 0..4 {
        let mut row = DVec3::ZERO;
        let mut row_u = DVec3::ZERO;
        for i in 0..4 {
            row += bu[i] * cvs[4 * j + i];
            row_u += du[i] * cvs[4 * j + i];
        }
        p += bv[j] * row;
        pu += bv[j] * row_u;
        pv += dv[j] * row;
    }
    (p, pu, pv)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{ControlMeshDesc, Crease};
    use crate::ControlMesh;

    /// A 4 x 4 quad grid; vertex (i, j) has index 5 j + i.
    fn grid(creases: Vec<Crease>) -> Topology {
        let mut d = ControlMeshDesc::default();
        for j in 0..5 {
            for i in 0..5 {
                d.positions.push(DVec3::new(i as f64, j as f64, 0.0));
            }
        }
        for j in 0..4u32 {
            for i in 0..4u32 {
                let v = 5 * j + i;
                d.face_sizes.push(4);
                d.face_vertices.extend([v, v + 1, v + 6, v + 5]);
            }
        }
        d.creases = creases;
        Topology::new(&ControlMesh::new(d).unwrap()).unwrap()
    }

    #[test]
    fn gathers_interior_boundary_and_corner_faces() {
        let t = grid(Vec::new());
        // Interior face 5 (corner vertex 6): the 4 x 4 block starting at vertex 0.
        let p = RegularPatch::gather(&t, 5).unwrap();
        assert_eq!(p.boundary_mask, 0);
        let expect: Vec<u32> = (0..4)
            .flat_map(|j| (0..4).map(move |i| 5 * j + i))
            .collect();
        assert_eq!(p.cvs.to_vec(), expect);
        // Bottom edge face 1: row 0 phantom; its real rows start at vertex 0.
        let p = RegularPatch::gather(&t, 1).unwrap();
        assert_eq!(p.boundary_mask, 0b0001);
        assert_eq!(&p.cvs[4..], &[0, 1, 2, 3, 5, 6, 7, 8, 10, 11, 12, 13]);
        // Corner face 0: v = 0 and u = 0 sides phantom.
        assert_eq!(RegularPatch::gather(&t, 0).unwrap().boundary_mask, 0b1001);
        // Top-right corner face 15: u = 1 and v = 1 sides.
        assert_eq!(RegularPatch::gather(&t, 15).unwrap().boundary_mask, 0b0110);
    }

    #[test]
    fn creases_decide_regularity() {
        // Infinitely sharp crease along the row j = 2 through the whole grid: faces below it
        // get a phantom row on their v = 1 side.
        let row = |s: f32| {
            (0..4)
                .map(|i| Crease {
                    v0: 10 + i,
                    v1: 11 + i,
                    sharpness: s,
                })
                .collect()
        };
        let t = grid(row(10.0));
        assert_eq!(RegularPatch::gather(&t, 5).unwrap().boundary_mask, 0b0100);
        assert_eq!(RegularPatch::gather(&t, 9).unwrap().boundary_mask, 0b0001);
        // Semi-sharp: no patch next to it.
        let t = grid(row(2.5));
        assert!(RegularPatch::gather(&t, 5).is_none());
        assert!(RegularPatch::gather(&t, 1).is_some());
        // A dart (one sharp edge ending inside) makes its end vertex irregular.
        let t = grid(vec![Crease {
            v0: 11,
            v1: 12,
            sharpness: 10.0,
        }]);
        assert!(RegularPatch::gather(&t, 5).is_none());
        assert!(RegularPatch::gather(&t, 0).is_some());
    }

    #[test]
    fn phantoms_mirror_columns_then_rows() {
        let t = grid(Vec::new());
        let pos: Vec<DVec3> = (0..25)
            .map(|k| DVec3::new((k % 5) as f64, (k / 5) as f64, ((k * 7) % 5) as f64))
            .collect();
        let p = RegularPatch::gather(&t, 0).unwrap();
        let c = p.control_points(&pos);
        let at = |i: usize, j: usize| c[4 * j + i];
        assert_eq!(at(0, 1), 2.0 * at(1, 1) - at(2, 1));
        assert_eq!(at(1, 0), 2.0 * at(1, 1) - at(1, 2));
        // The corner phantom mirrors the mirrored column.
        assert_eq!(at(0, 0), 2.0 * at(0, 1) - at(0, 2));
        // The corner of the patch interpolates the mesh corner (corner rule).
        let s = p.eval(&pos, 0.0, 0.0);
        assert!((s.position - pos[0]).length() < 1e-12);
    }

    /// `across` reads the neighbour's rotation from the edge's position in it; the search for
    /// `b` among its corners must agree on every face edge, in both directions and from both
    /// faces (fails if the position is off by one or a reversed edge is accepted).
    #[test]
    fn across_by_position_is_across_by_search() {
        let levels = crate::subdiv::corpus_levels(
            &[
                "catmark_car",
                "catmark_nonquads",
                "catmark_dart_edgecorner",
                "catmark_hole_test1",
                "catmark_val2_interior",
            ],
            2,
        );
        let (mut some, mut none) = (0, 0);
        for (name, _, level) in &levels {
            let t = level.topology();
            for f in 0..t.face_count() as u32 {
                let (fv, fe) = (t.face_vertices(f), t.face_edges(f));
                for (k, &e) in fe.iter().enumerate() {
                    let (a, b) = (fv[k], fv[(k + 1) % fv.len()]);
                    for (a, b) in [(a, b), (b, a)] {
                        let got = across(t, t.quads_only(), f, e, a, b);
                        assert_eq!(
                            got,
                            across_by_search(t, f, e, a, b),
                            "{name} face {f} edge {e}"
                        );
                        if got.is_some() {
                            some += 1;
                        } else {
                            none += 1;
                        }
                    }
                }
            }
        }
        assert!(some > 10_000 && none > 10_000, "{some} found, {none} not");
    }

    /// Reading the outer twelve from the corners' rings gives the grid the walk across edges
    /// gives on every quad of uniform levels whose corners are interior with four quads around
    /// them, and declines most others (fails if the ring's diagonal face or the slots of its
    /// corners are off by one). The adaptive step's sparse rings: `subdiv`'s tests.
    #[test]
    fn grid_from_rings_is_grid_across_edges() {
        let levels = crate::subdiv::corpus_levels(
            &["catmark_car", "catmark_nonquads", "catmark_hole_test1"],
            2,
        );
        let (mut same, mut declined) = (0, 0);
        for (name, _, level) in &levels {
            let (s, d) = grids_from_rings_checked(level.topology());
            assert!(s.is_ok(), "{name}: {s:?}");
            same += s.unwrap_or(0);
            declined += d;
        }
        assert!(
            same > 10_000 && declined > 1000,
            "{same} same, {declined} declined"
        );
    }

    /// The once-per-vertex judgement is the per-face one (every face around the vertex sees a
    /// regular corner), and a face whose corners pass it gathers the patch `gather` does, on
    /// every vertex and face of levels 0-2 of meshes with boundaries, creases, corners,
    /// semi-sharp edges, darts, n-gons and triangles (fails if the sharpness-free shortcut drops
    /// a condition of `corner_kind`'s smooth case, e.g. the face sizes).
    #[test]
    fn vertex_regularity_once_is_per_face_regularity() {
        let mut regular = 0;
        let levels = crate::subdiv::corpus_levels(
            &[
                "catmark_car",
                "catmark_nonquads",
                "catmark_smoothtris1",
                "catmark_cube_creases2",
                "catmark_cubes_semisharp",
                "catmark_dart_edgecorner",
                "catmark_hole_test1",
                "catmark_val2_interior",
            ],
            2,
        );
        for (name, _, level) in &levels {
            let t = level.topology();
            let quads_only = t.quads_only();
            for v in 0..t.vertex_count() as u32 {
                let per_face = t
                    .vertex_faces(v)
                    .iter()
                    .all(|&f| corner_kind(t, v, f) != CornerKind::Irregular);
                assert_eq!(
                    is_regular_vertex(t, v, quads_only),
                    per_face,
                    "{name} vertex {v}"
                );
                regular += usize::from(per_face);
            }
            for f in 0..t.face_count() as u32 {
                let Some(quad) = t.quad(f).filter(|_| t.has_limit_surface(f)) else {
                    continue;
                };
                if quad.0.iter().all(|&v| is_regular_vertex(t, v, quads_only)) {
                    assert_eq!(
                        RegularPatch::gather_at_regular_corners(t, f, quad),
                        RegularPatch::gather(t, f),
                        "{name} face {f}"
                    );
                }
            }
        }
        assert!(regular > 1000);
    }
}
