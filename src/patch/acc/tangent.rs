//! ACC tangent patches (Loop and Schaefer 2008, §4): a continuous normal field over the C0
//! geometry patches. The paper is not among the project's papers; the construction is
//! re-derived here from the condition the Gregory paper (§3.4) states for it.
//!
//! Per quad, a u-tangent patch `U` (degree 2 in u, 3 in v: 12 control vectors, `u[3 j + i]`)
//! and a v-tangent patch `V` (degree 3 in u, 2 in v: `v[4 j + i]`); the shading normal is
//! `U(u, v) × V(u, v)`. They start as the derivatives of the geometry patch and change where the
//! geometry is not G1:
//!
//! - **Corners**: the Catmull-Clark limit tangents. At a vertex of valence `n`, the tangent
//!   along ring edge `j` is `T_j = 3 (e_j − p)` with the Gregory construction's edge point
//!   `e_j = p + 2/3 λ q_j` (paper tangents, [`GregoryVertex::interior`]): `q_j` is the exact
//!   limit tangent mask, so `T_{j−1} + T_{j+1} = 2 cos(2π/n) T_j` holds exactly and the corner
//!   normal is the limit normal. At valence 4 this is the B-spline patch's own derivative.
//! - **Edges**: along an edge from corner `a` (valence `n_a`) to `b` (`n_b`) with versal
//!   derivative `D(t)` (quadratic: `T_a`, the geometry boundary's middle difference, `−T_b`),
//!   the two patches' cross derivatives `C_L`, `C_R` (cubic, into each face) must satisfy
//!   `C_L + C_R = λ(t) D(t)` with `λ(t) = (1 − t) 2 cos(2π/n_a) − t 2 cos(2π/n_b)` (the sign
//!   at `b` because `D(1)` points away from `b`); then `D × C_L` and `C_R × D` are parallel and
//!   the normal is continuous. In Bernstein form `λ D` has the coefficients
//!   `P = (λ0 D0, (2 λ0 D1 + λ1 D0) / 3, (λ0 D2 + 2 λ1 D1) / 3, λ1 D2)`. Its end coefficients
//!   hold through the corner tangents; the inner ones are met by the smallest symmetric change of
//!   the geometry's own cross derivatives `A`, `B`: `C_L = (A − B + P) / 2`, `C_R = (B − A + P) / 2`.
//!   Where both corners have valence 4 and the geometry is C1 (`A = −B`, `λ = 0`) nothing changes,
//!   so regular patches keep their exact normals.
//!
//! [`AccEdgeFrame`] holds an edge's `D` and `X = C_L − C_R` in the edge's canonical direction
//! (from its smaller vertex id), computed the same way from either face, so the GPU evaluates
//! the same normal bits on both sides (`normalize(D × X)`).

use std::collections::HashMap;
use std::f64::consts::PI;

use glam::DVec3;

use super::geometry::{acc_patch, check_face, edge_point, interior, NotAcc};
use crate::patch::gregory::{vertex_ring, GregoryTangents, GregoryVertex};
use crate::topology::Topology;

/// The tangent patches of one ACC quad (module docs; corners 0-3 at `(0,0) (1,0) (1,1) (0,1)`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AccTangentPatches {
    /// u-tangent control vectors, `u[3 j + i]`, `i` (0..3) along u, `j` (0..4) along v.
    pub u: [DVec3; 12],
    /// v-tangent control vectors, `v[4 j + i]`, `i` (0..4) along u, `j` (0..3) along v.
    pub v: [DVec3; 12],
}

/// Quadratic Bernstein polynomials at `t`.
fn bernstein2(t: f64) -> [f64; 3] {
    let s = 1.0 - t;
    [s * s, 2.0 * s * t, t * t]
}

/// Cubic Bernstein polynomials at `t`.
fn bernstein3(t: f64) -> [f64; 4] {
    let s = 1.0 - t;
    [s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t]
}

impl AccTangentPatches {
    /// `U(u, v)` and `V(u, v)`.
    pub fn eval(&self, u: f64, v: f64) -> (DVec3, DVec3) {
        let (u2, u3, v2, v3) = (bernstein2(u), bernstein3(u), bernstein2(v), bernstein3(v));
        let tu = self
            .u
            .iter()
            .enumerate()
            .map(|(k, &x)| x * (u2[k % 3] * v3[k / 3]))
            .sum();
        let tv = self
            .v
            .iter()
            .enumerate()
            .map(|(k, &x)| x * (u3[k % 4] * v2[k / 4]))
            .sum();
        (tu, tv)
    }

    /// The unit shading normal `U × V` at `(u, v)`.
    pub fn normal(&self, u: f64, v: f64) -> DVec3 {
        let (tu, tv) = self.eval(u, v);
        tu.cross(tv).normalize_or_zero()
    }
}

/// One edge's normal data in its canonical direction (module docs): the versal derivative `D`
/// (quadratic) and the difference `X = C_L − C_R` of the cross derivatives of the patches left
/// and right of it (cubic), so that the normal there is `normalize(D(t) × X(t))`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AccEdgeFrame {
    /// Bernstein coefficients of `D`.
    pub versal: [DVec3; 3],
    /// Bernstein coefficients of `X`.
    pub cross: [DVec3; 4],
}

impl AccEdgeFrame {
    /// The unit normal at canonical parameter `t`.
    pub fn normal(&self, t: f64) -> DVec3 {
        let (b2, b3) = (bernstein2(t), bernstein3(t));
        let d: DVec3 = (0..3).map(|i| self.versal[i] * b2[i]).sum();
        let x: DVec3 = (0..4).map(|i| self.cross[i] * b3[i]).sum();
        d.cross(x).normalize_or_zero()
    }
}

/// An edge as face `f` runs it counter-clockwise, from corner `a` to corner `b`, with the corners
/// before `a` (`prev`) and after `b` (`next`) of `f`.
#[derive(Debug, Clone, Copy)]
struct FaceEdge {
    f: u32,
    prev: u32,
    a: u32,
    b: u32,
    next: u32,
}

impl FaceEdge {
    /// Edge `k` of quad `f` (corner `k` to `k + 1`).
    fn of(topo: &Topology, f: u32, k: usize) -> FaceEdge {
        let fv = topo.face_vertices(f);
        FaceEdge {
            f,
            prev: fv[(k + 3) % 4],
            a: fv[k],
            b: fv[(k + 1) % 4],
            next: fv[(k + 2) % 4],
        }
    }

    /// The same edge run counter-clockwise by the quad on its other side.
    fn across(&self, topo: &Topology) -> FaceEdge {
        let e = topo.find_edge(self.a, self.b).expect("an edge of f");
        let g = topo
            .edge_faces(e)
            .iter()
            .copied()
            .find(|&g| g != self.f)
            .expect("ACC edges are interior");
        let gv = topo.face_vertices(g);
        let k = gv
            .iter()
            .position(|&x| x == self.b)
            .expect("b is a corner of g");
        FaceEdge::of(topo, g, k)
    }
}

/// The rows of a face edge (`D`, the corrected `C`, `P = λ D`; [`TangentBuilder::edge_rows`]).
type EdgeRows = ([DVec3; 3], [DVec3; 4], [DVec3; 4]);

/// The tangent patches and edge frames of an ACC surface for one set of control positions;
/// every vertex's limit data and every face edge's rows are computed once and shared by the
/// faces (and both sides of an edge) that need them.
pub struct TangentBuilder<'a> {
    topo: &'a Topology,
    p: &'a [DVec3],
    /// Per vertex: `3 (e_j − p)` per ring edge, in the topology's ring order.
    tangents: HashMap<u32, Vec<DVec3>>,
    /// Per vertex: the geometry patches' corner point, the average of its interior points.
    limits: HashMap<u32, DVec3>,
    /// Per face edge, keyed by its counter-clockwise direction `(a, b)` (which names the face).
    rows: HashMap<(u32, u32), EdgeRows>,
}

impl<'a> TangentBuilder<'a> {
    /// A builder over control positions `p`.
    pub fn new(topo: &'a Topology, p: &'a [DVec3]) -> TangentBuilder<'a> {
        TangentBuilder {
            topo,
            p,
            tangents: HashMap::new(),
            limits: HashMap::new(),
            rows: HashMap::new(),
        }
    }

    /// The unit normal of the tangent patches at corner `k` of ACC face `f`: the limit normal
    /// `T(next) × T(prev)` of its vertex ([`AccTangentPatches::normal`] there, without building
    /// the patches).
    pub fn corner_normal(&mut self, f: u32, k: usize) -> DVec3 {
        let fe = FaceEdge::of(self.topo, f, k);
        let next = self.tangent(fe.a, fe.b);
        next.cross(self.tangent(fe.a, fe.prev)).normalize_or_zero()
    }

    /// The limit tangent at `v` along its edge to `w` (module docs; `v` smooth interior with a
    /// quad ring, as [`check_face`] ensures).
    fn tangent(&mut self, v: u32, w: u32) -> DVec3 {
        let (topo, p) = (self.topo, self.p);
        let t = self.tangents.entry(v).or_insert_with(|| {
            let g = GregoryVertex::interior(&vertex_ring(topo, p, v), GregoryTangents::Paper);
            g.e.iter().map(|&e| 3.0 * (e - g.p)).collect()
        });
        let j = topo
            .vertex_edges(v)
            .iter()
            .position(|&e| topo.other_vertex(e, v) == w)
            .expect("w is a ring neighbour of v");
        t[j]
    }

    /// `2 cos(2π / n)` at vertex `v`.
    fn lambda(&self, v: u32) -> f64 {
        2.0 * (2.0 * PI / self.topo.vertex_faces(v).len() as f64).cos()
    }

    /// The geometry's cross derivative beside face edge `fe`, into its face, from `a` to `b`.
    fn geometry_cross(&mut self, fe: &FaceEdge) -> [DVec3; 4] {
        let (topo, p) = (self.topo, self.p);
        let edge = self.geometry_edge(fe);
        let inner = [
            edge_point(topo, p, fe.f, fe.a, fe.prev),
            interior(topo, p, fe.a, fe.f),
            interior(topo, p, fe.b, fe.f),
            edge_point(topo, p, fe.f, fe.b, fe.next),
        ];
        std::array::from_fn(|i| 3.0 * (inner[i] - edge[i]))
    }

    /// The geometry patches' corner point at `v`: the average of its interior points.
    fn limit(&mut self, v: u32) -> DVec3 {
        let (topo, p) = (self.topo, self.p);
        *self.limits.entry(v).or_insert_with(|| {
            let ring = topo.vertex_faces(v);
            ring.iter()
                .fold(DVec3::ZERO, |acc, &g| acc + interior(topo, p, v, g))
                / ring.len() as f64
        })
    }

    /// The geometry's boundary cubic of face edge `fe`, from `a` to `b`.
    fn geometry_edge(&mut self, fe: &FaceEdge) -> [DVec3; 4] {
        let (topo, p) = (self.topo, self.p);
        [
            self.limit(fe.a),
            edge_point(topo, p, fe.f, fe.a, fe.b),
            edge_point(topo, p, fe.f, fe.b, fe.a),
            self.limit(fe.b),
        ]
    }

    /// Versal derivative `D` and the corrected cross derivative `C` of face edge `fe` (module
    /// docs), both from `a` to `b`, and `P = λ D`; computed once per face edge.
    fn edge_rows(&mut self, fe: &FaceEdge) -> EdgeRows {
        if let Some(rows) = self.rows.get(&(fe.a, fe.b)) {
            return *rows;
        }
        let rows = self.compute_edge_rows(fe);
        self.rows.insert((fe.a, fe.b), rows);
        rows
    }

    /// [`Self::edge_rows`], computed.
    fn compute_edge_rows(&mut self, fe: &FaceEdge) -> EdgeRows {
        let edge = self.geometry_edge(fe);
        let d = [
            self.tangent(fe.a, fe.b),
            3.0 * (edge[2] - edge[1]),
            -self.tangent(fe.b, fe.a),
        ];
        let (l0, l1) = (self.lambda(fe.a), -self.lambda(fe.b));
        let lambda_d = [
            l0 * d[0],
            (2.0 * l0 * d[1] + l1 * d[0]) / 3.0,
            (l0 * d[2] + 2.0 * l1 * d[1]) / 3.0,
            l1 * d[2],
        ];
        let own = self.geometry_cross(fe);
        let other = self.geometry_cross(&fe.across(self.topo));
        // The other face runs the edge from b to a: reverse its row.
        let inner = |i: usize| (own[i] - other[3 - i] + lambda_d[i]) * 0.5;
        let c = [
            self.tangent(fe.a, fe.prev),
            inner(1),
            inner(2),
            self.tangent(fe.b, fe.next),
        ];
        (d, c, lambda_d)
    }

    /// The tangent patches of ACC face `f`.
    pub fn patches(&mut self, f: u32) -> Result<AccTangentPatches, NotAcc> {
        check_face(self.topo, f)?;
        let mut u = [DVec3::ZERO; 12];
        let mut v = [DVec3::ZERO; 12];
        let rows: Vec<_> = (0..4)
            .map(|k| self.edge_rows(&FaceEdge::of(self.topo, f, k)))
            .collect();
        // Edge 0 (+u at v = 0), 1 (+v at u = 1), 2 (-u at v = 1), 3 (-v at u = 0); cross
        // derivatives point into the face.
        for i in 0..3 {
            u[i] = rows[0].0[i];
            v[4 * i + 3] = rows[1].0[i];
            u[9 + i] = -rows[2].0[2 - i];
            v[4 * i] = -rows[3].0[2 - i];
        }
        for i in 0..4 {
            v[i] = rows[0].1[i];
            u[3 * i + 2] = -rows[1].1[i];
            v[8 + i] = -rows[2].1[3 - i];
            u[3 * i] = rows[3].1[3 - i];
        }
        // Inside: the geometry patch's own derivatives.
        let b = acc_patch(self.topo, self.p, f)?.bezier;
        u[4] = 3.0 * (b[6] - b[5]);
        u[7] = 3.0 * (b[10] - b[9]);
        v[5] = 3.0 * (b[9] - b[5]);
        v[6] = 3.0 * (b[10] - b[6]);
        Ok(AccTangentPatches { u, v })
    }

    /// The frame of edge `k` of ACC face `f` in the edge's canonical direction, computed from the
    /// face on the left of that direction, so both faces of the edge get the same values.
    pub fn edge_frame(&mut self, f: u32, k: usize) -> AccEdgeFrame {
        let mine = FaceEdge::of(self.topo, f, k);
        let left = if mine.a < mine.b {
            mine
        } else {
            mine.across(self.topo)
        };
        let (d, c, lambda_d) = self.edge_rows(&left);
        // C_R = P - C_L, so X = 2 C_L - P.
        AccEdgeFrame {
            versal: d,
            cross: std::array::from_fn(|i| 2.0 * c[i] - lambda_d[i]),
        }
    }
}
