//! Per-vertex quantities of the Gregory construction: limit position, edge points and the
//! transversal vectors `r` (Loop et al. 2009, §3.2-3.4, computed per vertex as in §4.1).

use glam::DVec3;
use std::f64::consts::PI;

/// The split one-ring of a vertex (paper Fig. 5), in the crate's ring order: `m[i]` is the
/// midpoint of the `i`-th incident edge, `c[i]` the centroid of the `i`-th incident face, which
/// lies between edges `i` and `i + 1`, counter-clockwise seen from outside.
#[derive(Debug, Clone, Default)]
pub struct VertexRing {
    /// The vertex itself.
    pub v: DVec3,
    /// Edge midpoints, one per incident edge.
    pub m: Vec<DVec3>,
    /// Face centroids, one per incident face.
    pub c: Vec<DVec3>,
}

/// Corner point, edge points and transversal vectors of one interior vertex.
///
/// `e[j]` is the edge point on incident edge `j`; `r[j]` the transversal vector across edge
/// `j`, pointing from face `j - 1` into face `j`.
#[derive(Debug, Clone)]
pub struct GregoryVertex {
    /// Number of incident faces (the valence of an interior vertex).
    pub n: usize,
    /// Limit position (§3.2).
    pub p: DVec3,
    /// Edge points `p + 2/3 λ q_j` (§3.3), one per incident edge.
    pub e: Vec<DVec3>,
    /// Transversal vectors `r_j` (§3.4), one per incident edge.
    pub r: Vec<DVec3>,
}

/// `λ`, the subdominant eigenvalue of Catmull-Clark subdivision at valence `n` (§3.3).
pub fn subdominant_eigenvalue(n: usize) -> f64 {
    let n = n as f64;
    let c2 = (2.0 * PI / n).cos();
    let c1 = (PI / n).cos();
    (5.0 + c2 + c1 * (18.0 + 2.0 * c2).sqrt()) / 16.0
}

impl GregoryVertex {
    /// The construction for a vertex whose faces close around it (no boundary, no crease).
    ///
    /// Limit position `p = (n-3)/(n+5) v + 4/(n(n+5)) Σ (m_i + c_i)` (§3.2, the stencil
    /// generalised to mixed quad/triangle rings); limit tangent along edge `j`
    /// `q_j = 2/n Σ_i ((1 - σ cos(π/n)) cos(2π(i-j)/n) m_i + 2σ cos((2π(i-j)+π)/n) c_i)` with
    /// `σ = (4 + cos²(π/n))^(-1/2)` and edge point `e_j = p + 2/3 λ q_j` (§3.3);
    /// `r_j = 1/3 (m_{j+1} - m_{j-1}) + 2/3 (c_j - c_{j-1})` (§3.4).
    pub fn interior(ring: &VertexRing) -> GregoryVertex {
        let n = ring.m.len();
        debug_assert_eq!(ring.c.len(), n);
        let nf = n as f64;
        let sum: DVec3 = ring.m.iter().zip(&ring.c).map(|(m, c)| *m + *c).sum();
        let p = (nf - 3.0) / (nf + 5.0) * ring.v + 4.0 / (nf * (nf + 5.0)) * sum;

        let cos_pi_n = (PI / nf).cos();
        let sigma = 1.0 / (4.0 + cos_pi_n * cos_pi_n).sqrt();
        let lambda = subdominant_eigenvalue(n);
        let e = (0..n)
            .map(|j| {
                let mut q = DVec3::ZERO;
                for i in 0..n {
                    let k = ((i + n - j) % n) as f64;
                    let wm = (1.0 - sigma * cos_pi_n) * (2.0 * PI * k / nf).cos();
                    let wc = 2.0 * sigma * ((2.0 * PI * k + PI) / nf).cos();
                    q += wm * ring.m[i] + wc * ring.c[i];
                }
                q *= 2.0 / nf;
                p + (2.0 / 3.0) * lambda * q
            })
            .collect();
        let r = (0..n)
            .map(|j| {
                let next = (j + 1) % n;
                let prev = (j + n - 1) % n;
                (ring.m[next] - ring.m[prev]) / 3.0 + 2.0 / 3.0 * (ring.c[j] - ring.c[prev])
            })
            .collect();
        GregoryVertex { n, p, e, r }
    }
}

/// Face point next to the edge from corner `a` to corner `b` of a patch (eq. 6, re-derived from
/// conditions (1) and (3)):
/// `f = (c_b p_a + (d - 2 c_a - c_b) e_ab + 2 c_a e_ba + r) / d`, where `c_x = cos(2π/n_x)`,
/// `e_ab` is the edge point at `a` towards `b`, `e_ba` the one at `b` towards `a`, `r` the
/// transversal vector at `a` across the edge pointing into the patch, and `d` is 3 for quads and
/// 4 for triangles. (The printed eq. 6 shows `v` and `e_0^-` where the derivation from
/// condition (3) gives `p_a` and the edge point at the far end; with `n = 4` both reduce to
/// `e_ab + r/3`, the B-spline case.)
pub fn face_point(
    d: f64,
    n_a: usize,
    n_b: usize,
    p_a: DVec3,
    e_ab: DVec3,
    e_ba: DVec3,
    r: DVec3,
) -> DVec3 {
    let ca = (2.0 * PI / n_a as f64).cos();
    let cb = (2.0 * PI / n_b as f64).cos();
    (cb * p_a + (d - 2.0 * ca - cb) * e_ab + 2.0 * ca * e_ba + r) / d
}
