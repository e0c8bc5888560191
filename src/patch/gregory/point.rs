//! The point type the Gregory construction is generic over: positions ([`DVec3`]) for the
//! direct construction and sparse weight vectors ([`Weights`]) for the stencil form (§4.3),
//! so that one construction produces both.

use glam::DVec3;

/// A value the construction can form affine and linear combinations of.
pub trait GregoryPoint: Clone {
    /// The additive identity.
    fn zero() -> Self;
    /// `self += w * x`.
    fn add_scaled(&mut self, w: f64, x: &Self);
}

impl GregoryPoint for DVec3 {
    fn zero() -> Self {
        DVec3::ZERO
    }

    fn add_scaled(&mut self, w: f64, x: &Self) {
        *self += w * *x;
    }
}

impl GregoryPoint for f64 {
    fn zero() -> Self {
        0.0
    }

    fn add_scaled(&mut self, w: f64, x: &Self) {
        *self += w * x;
    }
}

/// `Σ w_i x_i`.
pub fn combine<P: GregoryPoint>(terms: &[(f64, &P)]) -> P {
    let mut out = P::zero();
    for (w, x) in terms {
        out.add_scaled(*w, x);
    }
    out
}

/// A sparse weight vector over control-mesh vertices: `(vertex, weight)` sorted by vertex, no
/// duplicates. Combining weight vectors with the construction gives stencil rows.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Weights(pub Vec<(u32, f64)>);

impl Weights {
    /// The unit vector of vertex `v` (the "position" of `v` in weight space).
    pub fn unit(v: u32) -> Weights {
        Weights(vec![(v, 1.0)])
    }

    /// Applies the weights to positions.
    pub fn apply(&self, positions: &[DVec3]) -> DVec3 {
        self.0.iter().map(|&(v, w)| w * positions[v as usize]).sum()
    }
}

impl GregoryPoint for Weights {
    fn zero() -> Self {
        Weights(Vec::new())
    }

    fn add_scaled(&mut self, w: f64, x: &Self) {
        if w == 0.0 {
            return;
        }
        let a = std::mem::take(&mut self.0);
        let mut out = Vec::with_capacity(a.len() + x.0.len());
        let (mut i, mut j) = (0, 0);
        while i < a.len() || j < x.0.len() {
            if j == x.0.len() || (i < a.len() && a[i].0 < x.0[j].0) {
                out.push(a[i]);
                i += 1;
            } else if i == a.len() || x.0[j].0 < a[i].0 {
                out.push((x.0[j].0, w * x.0[j].1));
                j += 1;
            } else {
                out.push((a[i].0, a[i].1 + w * x.0[j].1));
                i += 1;
                j += 1;
            }
        }
        self.0 = out;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_merge_sorted() {
        let mut a = Weights(vec![(1, 1.0), (4, 2.0)]);
        a.add_scaled(0.5, &Weights(vec![(0, 2.0), (4, 2.0), (7, 1.0)]));
        assert_eq!(a.0, vec![(0, 1.0), (1, 1.0), (4, 3.0), (7, 0.5)]);
        let p = [
            DVec3::X,
            DVec3::Y,
            DVec3::Z,
            DVec3::ONE,
            DVec3::ONE,
            DVec3::ZERO,
            DVec3::ZERO,
            DVec3::X,
        ];
        assert_eq!(a.apply(&p), DVec3::new(1.0 + 3.0 + 0.5, 1.0 + 3.0, 3.0));
    }
}
