//! Gregory patch control points, assembly from per-vertex data, and CPU reference evaluation
//! through the Bézier form with blended face points (Loop et al. 2009, §3.1 and §4.4).

use super::point::{combine, GregoryPoint};
use super::vertex::{face_point_terms, GregoryVertex, VertexKind};
use crate::patch::basis::{bernstein, bernstein_deriv, eval_tensor};
use glam::DVec3;

/// Position and first derivatives of a patch at a parameter point.
///
/// The derivatives are those of the Bézier patch with the face points frozen at the
/// parameter (§4.4): exact along patch edges, continuous inside, and what the GPU computes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PatchPoint {
    /// Surface position.
    pub position: DVec3,
    /// Derivative along the first parameter.
    pub du: DVec3,
    /// Derivative along the second parameter.
    pub dv: DVec3,
}

impl PatchPoint {
    /// `normalize(du x dv)`; zero if the derivatives are parallel.
    pub fn normal(&self) -> DVec3 {
        self.du.cross(self.dv).normalize_or_zero()
    }
}

/// A patch's own normal at its corner from the corner point `p` and its edge points towards the
/// next corner (`e_next`) and the previous one (`e_prev`): the direction of the Bézier net's
/// corner derivatives; where the two edge tangents are collinear (a crease sector of one face),
/// the mean of the corner's face points spans the tangent plane with the edge instead. The CPU
/// side of `gregory_corner_normal` (`glsl/gregory/gregory.glsl`), same test and fallback.
pub fn corner_normal(
    p: DVec3,
    e_next: DVec3,
    e_prev: DVec3,
    f_plus: DVec3,
    f_minus: DVec3,
) -> DVec3 {
    let (a, b) = (e_next - p, e_prev - p);
    let n = a.cross(b);
    if n.length() > 1e-5 * a.length() * b.length() {
        return n.normalize();
    }
    a.cross(0.5 * (f_plus + f_minus) - p).normalize_or_zero()
}

/// The 20 control points of a quad Gregory patch (paper Fig. 4a), indexed by patch corner.
/// Generic over the point type: positions, or stencil weights ([`super::Weights`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GregoryQuad<P = DVec3> {
    /// Corner points.
    pub p: [P; 4],
    /// Edge point at corner `i` towards corner `i + 1`.
    pub e_plus: [P; 4],
    /// Edge point at corner `i` towards corner `i - 1`.
    pub e_minus: [P; 4],
    /// Face point at corner `i` next to the edge `i -> i + 1`.
    pub f_plus: [P; 4],
    /// Face point at corner `i` next to the edge `i -> i - 1`.
    pub f_minus: [P; 4],
}

/// The 15 control points of a triangular Gregory patch (paper Fig. 4b), indexed by corner.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GregoryTriangle<P = DVec3> {
    /// Corner points.
    pub p: [P; 3],
    /// Edge point at corner `i` towards corner `i + 1`.
    pub e_plus: [P; 3],
    /// Edge point at corner `i` towards corner `i - 1`.
    pub e_minus: [P; 3],
    /// Face point at corner `i` next to the edge `i -> i + 1`.
    pub f_plus: [P; 3],
    /// Face point at corner `i` next to the edge `i -> i - 1`.
    pub f_minus: [P; 3],
}

/// One patch corner: the vertex data and the position of the patch's face in that vertex's
/// ring (the face lies between ring edges `j` (towards the next corner) and `j + 1` (towards
/// the previous corner)).
#[derive(Debug)]
pub struct CornerRef<'a, P = DVec3> {
    /// Per-vertex data of the corner's vertex.
    pub vertex: &'a GregoryVertex<P>,
    /// Index of the patch's face in the vertex's ring.
    pub j: usize,
}

impl<P> Clone for CornerRef<'_, P> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<P> Copy for CornerRef<'_, P> {}

/// The five control-point arrays of a patch with `N` corners.
type Parts<P, const N: usize> = ([P; N], [P; N], [P; N], [P; N], [P; N]);

/// A control point of a patch before it is formed: one of its corners' points as it is, or a
/// face point's terms (eq. 6), so that a caller can take the first by reference and combine
/// the second where it likes (the end caps' rows: straight into their storage).
#[derive(Debug)]
pub(super) enum PointRecipe<'a, P> {
    /// A corner's limit or edge point.
    Given(&'a P),
    /// `Σ w_i x_i` over the terms in order ([`combine`]).
    Combination([(f64, &'a P); 4]),
}

impl<P> Clone for PointRecipe<'_, P> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<P> Copy for PointRecipe<'_, P> {}

impl<P: GregoryPoint> PointRecipe<'_, P> {
    /// The point.
    pub(super) fn point(&self) -> P {
        match self {
            PointRecipe::Given(p) => (*p).clone(),
            PointRecipe::Combination(terms) => combine(terms),
        }
    }
}

impl<'a, P> CornerRef<'a, P> {
    /// Edge point towards the next corner.
    fn e_plus(&self) -> &'a P {
        &self.vertex.e[self.j]
    }

    /// Edge point towards the previous corner.
    fn e_minus(&self) -> &'a P {
        &self.vertex.e[(self.j + 1) % self.vertex.e.len()]
    }

    /// `cos(2π/n)` of the sector holding the patch.
    fn cos(&self) -> f64 {
        self.vertex.cosine[self.j]
    }

    /// Which of the patch's edges at this corner are sharp with one-sided face points
    /// ([`GregoryVertex::one_sided`]).
    fn sides(&self) -> u8 {
        self.vertex.one_sided.get(self.j).copied().unwrap_or(0)
    }

    /// The far corner's cosine in eq. 6, except at a corner alone in its corner sector, whose
    /// face points are the B-spline corner's `e + r/3` (`tangents_boundary`).
    fn far_cos(&self, far: &Self) -> f64 {
        if self.sides() == 3 && self.vertex.kind == VertexKind::Corner {
            0.0
        } else {
            far.cos()
        }
    }

    /// Face point next to the edge towards the next corner `next` (eq. 6), before the
    /// one-sided rule.
    fn f_plus(&self, next: &Self, d: f64) -> PointRecipe<'a, P> {
        PointRecipe::Combination(face_point_terms(
            d,
            self.cos(),
            self.far_cos(next),
            &self.vertex.p,
            self.e_plus(),
            next.e_minus(),
            &self.vertex.r_plus[self.j],
        ))
    }

    /// Face point next to the edge towards the previous corner `prev` (eq. 6), before the
    /// one-sided rule.
    fn f_minus(&self, prev: &Self, d: f64) -> PointRecipe<'a, P> {
        PointRecipe::Combination(face_point_terms(
            d,
            self.cos(),
            self.far_cos(prev),
            &self.vertex.p,
            self.e_minus(),
            prev.e_plus(),
            &self.vertex.r_minus[self.j],
        ))
    }
}

/// Corner, edge and face points for a patch with `N` corners; `d` is 3 for quads, 4 for
/// triangles (§3.4).
fn assemble<'a, P, const N: usize>(
    corners: &[CornerRef<'a, P>; N],
    d: f64,
) -> Parts<PointRecipe<'a, P>, N> {
    let p = std::array::from_fn(|i| PointRecipe::Given(&corners[i].vertex.p));
    let e_plus = std::array::from_fn(|i| PointRecipe::Given(corners[i].e_plus()));
    let e_minus = std::array::from_fn(|i| PointRecipe::Given(corners[i].e_minus()));
    let mut f_plus: [_; N] = std::array::from_fn(|i| corners[i].f_plus(&corners[(i + 1) % N], d));
    let mut f_minus: [_; N] =
        std::array::from_fn(|i| corners[i].f_minus(&corners[(i + N - 1) % N], d));
    // Beside one sharp edge the face point is the corner's other one (`tangents_boundary`).
    for i in 0..N {
        match corners[i].sides() {
            1 => f_plus[i] = f_minus[i],
            2 => f_minus[i] = f_plus[i],
            _ => {}
        }
    }
    (p, e_plus, e_minus, f_plus, f_minus)
}

/// The points of `parts` formed.
fn formed<P: GregoryPoint, const N: usize>(parts: Parts<PointRecipe<'_, P>, N>) -> Parts<P, N> {
    let form = |r: [PointRecipe<'_, P>; N]| r.map(|r| r.point());
    let (p, e_plus, e_minus, f_plus, f_minus) = parts;
    (
        form(p),
        form(e_plus),
        form(e_minus),
        form(f_plus),
        form(f_minus),
    )
}

/// The points of a patch beside its edge from corner `y` to the next corner `x`, as `assemble`
/// makes them: `[e_plus at x, e_minus at y, f_minus at x, f_plus at y]` (what a neighbour
/// across that edge reads, `stencil_table`), from the two corners and, where the one-sided rule
/// makes one of these face points the corner's other one, from the patch's corner after `x`
/// (`x_next`) or before `y` (`y_prev`): the same terms as `assemble`, so the same bits. `None`
/// where such a corner is needed and not given.
pub(super) fn edge_side_points<'a, P>(
    x: &CornerRef<'a, P>,
    y: &CornerRef<'a, P>,
    d: f64,
    x_next: Option<&CornerRef<'a, P>>,
    y_prev: Option<&CornerRef<'a, P>>,
) -> Option<[PointRecipe<'a, P>; 4]> {
    let (needs_next, needs_prev) = edge_side_far_corners(x, y);
    let x_next = if needs_next { Some(x_next?) } else { None };
    let y_prev = if needs_prev { Some(y_prev?) } else { None };
    let f_minus_x = match x_next {
        Some(next) => x.f_plus(next, d),
        None => x.f_minus(y, d),
    };
    let f_plus_y = match y_prev {
        Some(prev) => y.f_minus(prev, d),
        None => y.f_plus(x, d),
    };
    Some([
        PointRecipe::Given(x.e_plus()),
        PointRecipe::Given(y.e_minus()),
        f_minus_x,
        f_plus_y,
    ])
}

/// Whether [`edge_side_points`] of the edge from corner `y` to corner `x` reads the patch's
/// corner after `x`, and the one before `y`: where `assemble`'s swap (beside one sharp edge the
/// face point is the corner's other one) makes the face point there one-sided.
pub(super) fn edge_side_far_corners<P>(x: &CornerRef<'_, P>, y: &CornerRef<'_, P>) -> (bool, bool) {
    (x.sides() == 2, y.sides() == 1)
}

/// `(a * x + b * y) / (a + b)`, or the mean at the singular corner `a + b == 0` (§4.4).
fn blend(a: f64, x: DVec3, b: f64, y: DVec3) -> DVec3 {
    let s = a + b;
    if s > 0.0 {
        (a * x + b * y) / s
    } else {
        0.5 * (x + y)
    }
}

impl<P: GregoryPoint> GregoryQuad<P> {
    /// Builds the patch of a quad face from its four corners (in face order).
    pub fn new(corners: &[CornerRef<'_, P>; 4]) -> GregoryQuad<P> {
        GregoryQuad::from_parts(formed(assemble(corners, 3.0)))
    }
}

impl<'a, P> GregoryQuad<PointRecipe<'a, P>> {
    /// [`GregoryQuad::new`] with the points not formed.
    pub(super) fn recipes(corners: &[CornerRef<'a, P>; 4]) -> Self {
        GregoryQuad::from_parts(assemble(corners, 3.0))
    }
}

impl<P> GregoryQuad<P> {
    fn from_parts((p, e_plus, e_minus, f_plus, f_minus): Parts<P, 4>) -> Self {
        GregoryQuad {
            p,
            e_plus,
            e_minus,
            f_plus,
            f_minus,
        }
    }
}

impl<P: GregoryPoint> GregoryQuad<PointRecipe<'_, P>> {
    /// The patch with its points formed.
    pub(super) fn formed(&self) -> GregoryQuad<P> {
        let q = *self;
        GregoryQuad::from_parts(formed((q.p, q.e_plus, q.e_minus, q.f_plus, q.f_minus)))
    }
}

impl GregoryQuad {
    /// The bicubic Bézier control net at `(u, v)`, `b[4*j + i]` with `i` along u: the paper's
    /// matrix `G` (§3.1) with `F_i` blended from the face points.
    pub fn bezier_at(&self, u: f64, v: f64) -> [DVec3; 16] {
        let (p, ep, em, fp, fm) = (
            &self.p,
            &self.e_plus,
            &self.e_minus,
            &self.f_plus,
            &self.f_minus,
        );
        let f0 = blend(u, fp[0], v, fm[0]);
        let f1 = blend(1.0 - u, fm[1], v, fp[1]);
        let f2 = blend(1.0 - u, fp[2], 1.0 - v, fm[2]);
        let f3 = blend(u, fm[3], 1.0 - v, fp[3]);
        // G[i][j] from the paper (row i along u, column j along v), stored at b[4*j + i].
        let g = [
            [p[0], em[0], ep[3], p[3]],
            [ep[0], f0, f3, em[3]],
            [em[1], f1, f2, ep[2]],
            [p[1], ep[1], em[2], p[2]],
        ];
        let mut b = [DVec3::ZERO; 16];
        for (i, row) in g.iter().enumerate() {
            for (j, x) in row.iter().enumerate() {
                b[4 * j + i] = *x;
            }
        }
        b
    }

    /// Position and (approximate, §4.4) derivatives at the face's `(u, v)`.
    pub fn eval(&self, u: f64, v: f64) -> PatchPoint {
        let b = self.bezier_at(u, v);
        let (position, du, dv) = eval_tensor(
            &b,
            &bernstein(u),
            &bernstein_deriv(u),
            &bernstein(v),
            &bernstein_deriv(v),
        );
        PatchPoint { position, du, dv }
    }
}

impl<P: GregoryPoint> GregoryTriangle<P> {
    /// Builds the patch of a triangle from its three corners (in face order).
    pub fn new(corners: &[CornerRef<'_, P>; 3]) -> GregoryTriangle<P> {
        GregoryTriangle::from_parts(formed(assemble(corners, 4.0)))
    }
}

impl<'a, P> GregoryTriangle<PointRecipe<'a, P>> {
    /// [`GregoryTriangle::new`] with the points not formed.
    pub(super) fn recipes(corners: &[CornerRef<'a, P>; 3]) -> Self {
        GregoryTriangle::from_parts(assemble(corners, 4.0))
    }
}

impl<P> GregoryTriangle<P> {
    fn from_parts((p, e_plus, e_minus, f_plus, f_minus): Parts<P, 3>) -> Self {
        GregoryTriangle {
            p,
            e_plus,
            e_minus,
            f_plus,
            f_minus,
        }
    }
}

impl<P: GregoryPoint> GregoryTriangle<PointRecipe<'_, P>> {
    /// The patch with its points formed.
    pub(super) fn formed(&self) -> GregoryTriangle<P> {
        let q = *self;
        GregoryTriangle::from_parts(formed((q.p, q.e_plus, q.e_minus, q.f_plus, q.f_minus)))
    }
}

impl GregoryTriangle {
    /// Position and (approximate) derivatives at the point with barycentric weights
    /// `(1 - s - t, s, t)` of corners 0, 1, 2: `du = dT/ds`, `dv = dT/dt`, so that
    /// `du x dv` points outwards for a counter-clockwise face.
    ///
    /// `T(u,v,w) = u³p0 + v³p1 + w³p2 + 3uv(u+v)(u e0+ + v e1-) + 3vw(v+w)(v e1+ + w e2-)
    /// + 3wu(w+u)(w e2+ + u e0-) + 12uvw(u F0 + v F1 + w F2)` with
    /// `F0 = (w f0- + v f0+)/(v+w)`, `F1 = (u f1- + w f1+)/(w+u)`, `F2 = (v f2- + u f2+)/(u+v)`
    /// (§3.1), differentiated with the `F_i` frozen.
    pub fn eval(&self, s: f64, t: f64) -> PatchPoint {
        let (u, v, w) = (1.0 - s - t, s, t);
        let (p, ep, em, fp, fm) = (
            &self.p,
            &self.e_plus,
            &self.e_minus,
            &self.f_plus,
            &self.f_minus,
        );
        let f0 = blend(w, fm[0], v, fp[0]);
        let f1 = blend(u, fm[1], w, fp[1]);
        let f2 = blend(v, fm[2], u, fp[2]);
        // One edge term 3ab(a+b)(a X + b Y) and its partials in a and b.
        let edge = |a: f64, b: f64, x: DVec3, y: DVec3| {
            let val = 3.0 * a * b * (a + b) * (a * x + b * y);
            let da = 3.0 * b * ((2.0 * a + b) * (a * x + b * y) + a * (a + b) * x);
            let db = 3.0 * a * ((a + 2.0 * b) * (a * x + b * y) + b * (a + b) * y);
            (val, da, db)
        };
        let (e01, e01_u, e01_v) = edge(u, v, ep[0], em[1]);
        let (e12, e12_v, e12_w) = edge(v, w, ep[1], em[2]);
        let (e20, e20_w, e20_u) = edge(w, u, ep[2], em[0]);
        let inner = u * f0 + v * f1 + w * f2;
        let position = u * u * u * p[0]
            + v * v * v * p[1]
            + w * w * w * p[2]
            + e01
            + e12
            + e20
            + 12.0 * u * v * w * inner;
        let tu = 3.0 * u * u * p[0] + e01_u + e20_u + 12.0 * (v * w * inner + u * v * w * f0);
        let tv = 3.0 * v * v * p[1] + e01_v + e12_v + 12.0 * (u * w * inner + u * v * w * f1);
        let tw = 3.0 * w * w * p[2] + e12_w + e20_w + 12.0 * (u * v * inner + u * v * w * f2);
        PatchPoint {
            position,
            du: tv - tu,
            dv: tw - tu,
        }
    }
}
