//! The per-vertex stage (paper §5.1, Fig. 9, eq. 13-16): from a vertex's one-ring, its point
//! `v`, one face point `f_j` per facet and the two tangent vectors `t_1`, `t_2` that give the
//! tangent point `t_j` along every spoke.

use super::error::NotPm;
use crate::patch::gregory::{combine, GregoryPoint};
use crate::topology::Topology;
use std::f64::consts::TAU;

/// The crease scalar that reproduces the smooth face point of eq. (13) (module docs, eq. 14).
pub const SMOOTH_CREASE: f64 = 2.0 / 3.0;

/// The tangent scale `κ_n` of eq. (15), `t_1 = κ_n Σ_j cos(2πj/n) e_j` (unreadable in the
/// scan; both readings give `κ_4 = 1/2`, which makes `t_j = e_j` at valence 4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TangentScale {
    /// `κ_n = 1 / (n λ_n)`, the literal reading.
    #[default]
    InverseLambda,
    /// `κ_n = 4 λ_n / n`.
    Lambda,
}

impl TangentScale {
    /// `κ_n`.
    pub fn kappa(self, n: usize) -> f64 {
        let nf = n as f64;
        match self {
            TangentScale::InverseLambda => 1.0 / (nf * lambda(n)),
            TangentScale::Lambda => 4.0 * lambda(n) / nf,
        }
    }
}

/// `λ_n = (c_n + 5 + sqrt((c_n + 9)(c_n + 1))) / 16`, the subdominant eigenvalue of
/// Catmull-Clark at valence `n`.
pub fn lambda(n: usize) -> f64 {
    let c = cos_n(1, n);
    (c + 5.0 + ((c + 9.0) * (c + 1.0)).sqrt()) / 16.0
}

/// `cos(2πj/n)`.
pub fn cos_n(j: usize, n: usize) -> f64 {
    (TAU * j as f64 / n as f64).cos()
}

/// `sin(2πj/n)`.
pub fn sin_n(j: usize, n: usize) -> f64 {
    (TAU * j as f64 / n as f64).sin()
}

/// Per-vertex data (output of the vertex stage).
#[derive(Debug, Clone, PartialEq)]
pub struct PmVertex<P> {
    /// The vertex point `v` (eq. 13; the Catmull-Clark limit point on all-quad rings).
    pub v: P,
    /// Face points `f_j`, one per facet of [`Topology::vertex_faces`] (eq. 13 / 14).
    pub f: Vec<P>,
    /// Tangent vectors `t_1`, `t_2` (eq. 15).
    pub t1: P,
    /// See `t1`.
    pub t2: P,
}

impl<P: GregoryPoint> PmVertex<P> {
    /// Valence `n`.
    pub fn valence(&self) -> usize {
        self.f.len()
    }

    /// The tangent point along spoke `j` (edge `j` of [`Topology::vertex_edges`]), eq. (16):
    /// `t_j = v + cos(2πj/n) t_1 + sin(2πj/n) t_2`.
    pub fn tangent(&self, j: usize) -> P {
        let n = self.valence();
        combine(&[
            (1.0, &self.v),
            (cos_n(j, n), &self.t1),
            (sin_n(j, n), &self.t2),
        ])
    }
}

/// Settings of the construction.
#[derive(Debug, Clone, Default)]
pub struct PmOptions {
    /// `κ_n` of eq. (15).
    pub tangent_scale: TangentScale,
    /// Crease scalar `a` per edge (eq. 14), indexed by edge id; `None` (or [`SMOOTH_CREASE`]
    /// everywhere) is the smooth surface.
    pub crease: Option<Vec<f64>>,
}

impl PmOptions {
    /// The crease scalar of edge `e` ([`SMOOTH_CREASE`] without scalars).
    pub fn edge_crease(&self, e: u32) -> f64 {
        self.crease
            .as_ref()
            .map_or(SMOOTH_CREASE, |a| a[e as usize])
    }
}

/// Checks that `v` is an interior vertex with a closed fan of at least three faces.
pub fn check_vertex(topo: &Topology, face: u32, v: u32) -> Result<(), NotPm> {
    if topo.is_boundary_vertex(v) {
        return Err(NotPm::Boundary { face, vertex: v });
    }
    let n = topo.valence(v);
    if n < 3 || topo.vertex_faces(v).len() != n {
        return Err(NotPm::Valence {
            face,
            vertex: v,
            valence: n,
        });
    }
    Ok(())
}

/// The vertex stage at `v` (checked with `check_vertex`) over points `point(vertex)`.
///
/// Facet `j` lies between spokes `j` and `j + 1`; `p̄_j` is the mean of its vertices that are
/// neither `v` nor a spoke end (a quad's diagonal vertex, a pentagon's two far vertices), or
/// the mean of the two spoke ends for a triangle.
pub fn pm_vertex<P: GregoryPoint>(
    topo: &Topology,
    v: u32,
    point: &impl Fn(u32) -> P,
    options: &PmOptions,
) -> PmVertex<P> {
    let edges = topo.vertex_edges(v);
    let n = edges.len();
    let p = point(v);
    let spoke = |j: usize| topo.other_vertex(edges[j % n], v);
    let f: Vec<P> = (0..n)
        .map(|j| {
            let (a, b) = (spoke(j), spoke(j + 1));
            let far = far_vertices(topo, v, j);
            let pa = point(a);
            let pb = point(b);
            let pbar = if far.is_empty() {
                combine(&[(0.5, &pa), (0.5, &pb)])
            } else {
                let w = 1.0 / far.len() as f64;
                let pts: Vec<P> = far.iter().map(|&x| point(x)).collect();
                combine(&pts.iter().map(|x| (w, x)).collect::<Vec<_>>())
            };
            face_point(
                &p,
                &pa,
                &pb,
                &pbar,
                options.edge_crease(edges[j]),
                options.edge_crease(edges[(j + 1) % n]),
            )
        })
        .collect();
    vertex_from_faces(p, f, options.tangent_scale)
}

/// The vertices of facet `j` of `v`'s ring (between spokes `j` and `j + 1`) that are neither `v`
/// nor a spoke end, in facet order: `p̄_j` is their mean (none for a triangle).
pub fn far_vertices(topo: &Topology, v: u32, j: usize) -> Vec<u32> {
    let edges = topo.vertex_edges(v);
    let n = edges.len();
    let (a, b) = (
        topo.other_vertex(edges[j % n], v),
        topo.other_vertex(edges[(j + 1) % n], v),
    );
    topo.face_vertices(topo.vertex_faces(v)[j])
        .iter()
        .copied()
        .filter(|&x| x != v && x != a && x != b)
        .collect()
}

/// Eq. (14): the face point of facet `j` with crease scalars `a_j` (spoke `j`, end `pa`) and
/// `a_{j+1}` (spoke `j + 1`, end `pb`); `a_j = 0` puts `f_j` on spoke `j`, `a = 2/3` on both
/// gives eq. (13) `f_j = (4p + 2(pa + pb) + p̄)/9`.
fn face_point<P: GregoryPoint>(p: &P, pa: &P, pb: &P, pbar: &P, aj: f64, aj1: f64) -> P {
    let (w_p, w_a, w_b, w_q) = (
        (1.0 - aj) * (1.0 - aj1),
        (1.0 - aj) * aj1 / 2.0,
        aj * (1.0 - aj1) / 2.0,
        aj * aj1 / 4.0,
    );
    combine(&[
        (w_p + w_a + w_b + w_q, p),
        (w_a + w_q, pa),
        (w_b + w_q, pb),
        (w_q, pbar),
    ])
}

/// Eq. (13) `v = Σ_j (9 f_j + (n - 4) p) / (n (n + 5))` and eq. (15) from the face points.
fn vertex_from_faces<P: GregoryPoint>(p: P, f: Vec<P>, scale: TangentScale) -> PmVertex<P> {
    let n = f.len();
    let nf = n as f64;
    let mut terms: Vec<(f64, &P)> = vec![((nf - 4.0) / (nf + 5.0), &p)];
    terms.extend(f.iter().map(|x| (9.0 / (nf * (nf + 5.0)), x)));
    let v = combine(&terms);
    let kappa = scale.kappa(n);
    // e_j = (f_j + f_{j-1}) / 2, so Σ_j c_j e_j = Σ_j f_j (c_j + c_{j+1}) / 2.
    let tangent = |trig: fn(usize, usize) -> f64| {
        combine(
            &f.iter()
                .enumerate()
                .map(|(j, x)| (kappa * (trig(j, n) + trig(j + 1, n)) / 2.0, x))
                .collect::<Vec<_>>(),
        )
    };
    let t1 = tangent(cos_n);
    let t2 = tangent(sin_n);
    PmVertex { v, f, t1, t2 }
}
