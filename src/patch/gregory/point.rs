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

    /// `Σ w_i x_i` over `terms` in their order: [`GregoryPoint::add_scaled`] of each term onto
    /// [`GregoryPoint::zero`], which a point type may compute in one pass with the same bits.
    fn combination(terms: &[(f64, &Self)]) -> Self {
        added_one_by_one(terms)
    }
}

/// `Σ w_i x_i` as [`GregoryPoint::add_scaled`] of each term in order onto
/// [`GregoryPoint::zero`] (the default [`GregoryPoint::combination`]).
fn added_one_by_one<P: GregoryPoint>(terms: &[(f64, &P)]) -> P {
    let mut out = P::zero();
    for (w, x) in terms {
        out.add_scaled(*w, x);
    }
    out
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
    P::combination(terms)
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

    /// `Σ w_i unit(v_i)` over `terms` in their order, zero weights dropped: the same bits as
    /// adding the units one by one with [`GregoryPoint::add_scaled`], without merging.
    pub fn from_terms(terms: impl IntoIterator<Item = (u32, f64)>) -> Weights {
        let terms = terms.into_iter();
        // Room for every term up front (a filtered `collect` would grow from nothing).
        let mut t: Vec<(u32, f64)> = Vec::with_capacity(terms.size_hint().0);
        t.extend(terms.filter(|&(_, w)| w != 0.0));
        t.sort_by_key(|&(v, _)| v);
        t.dedup_by(|next, kept| {
            let same = next.0 == kept.0;
            if same {
                kept.1 += next.1;
            }
            same
        });
        Weights(t)
    }

    /// Applies the weights to positions.
    pub fn apply(&self, positions: &[DVec3]) -> DVec3 {
        apply_terms(&self.0, positions)
    }
}

/// The point `(id, weight)` terms `terms` give over `positions`, summed in order
/// ([`Weights::apply`] on a borrowed row).
pub fn apply_terms(terms: &[(u32, f64)], positions: &[DVec3]) -> DVec3 {
    terms.iter().map(|&(v, w)| w * positions[v as usize]).sum()
}

impl GregoryPoint for Weights {
    fn zero() -> Self {
        Weights(Vec::new())
    }

    /// Merges `w * x` in: in place when every id of `x` is already in `self` (the common case
    /// once a row has taken its support), else through a reused per-thread buffer, so a
    /// construction allocates only when a row outgrows its own capacity. Each weight is
    /// `a + w * b` or `w * b` whichever way it is merged.
    fn add_scaled(&mut self, w: f64, x: &Self) {
        if w == 0.0 || x.0.is_empty() {
            return;
        }
        if self.0.is_empty() {
            self.0.extend(x.0.iter().map(|&(v, b)| (v, w * b)));
            return;
        }
        if merge_in_place(&mut self.0, w, &x.0) {
            return;
        }
        MERGE_BUFFER.with(|buffer| {
            let mut out = buffer.borrow_mut();
            merge_into(&mut out, &self.0, w, &x.0);
            // The merged row takes the buffer's allocation, the buffer the row's old one.
            std::mem::swap(&mut self.0, &mut *out);
        });
    }

    /// The merge of every term at once (`merge_terms`): one allocation of the result, the
    /// same bits as adding the terms one by one (each weight is its first term's `w * b`,
    /// then `a + w * b` for each later term holding the id, in term order).
    fn combination(terms: &[(f64, &Self)]) -> Self {
        if terms.len() > MERGE_TERMS {
            return added_one_by_one(terms);
        }
        let mut slices: [(f64, &[(u32, f64)]); MERGE_TERMS] = [(0.0, &[]); MERGE_TERMS];
        for (s, &(w, x)) in slices.iter_mut().zip(terms) {
            *s = (w, &x.0);
        }
        let mut out = Vec::new();
        merge_terms_into(&slices[..terms.len()], &mut out);
        Weights(out)
    }
}

/// A weight vector stored in a caller's arena of terms (`arena[start..end]`, ids ascending): the
/// point type of corner data relabelled in bulk (one arena per batch of end caps instead of one
/// allocation per weight vector), read through its arena.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct ArenaWeights {
    start: u32,
    end: u32,
}

impl ArenaWeights {
    /// Appends `terms` to `arena`, sorted by id (the ids distinct), and names them.
    pub(super) fn push(
        arena: &mut Vec<(u32, f64)>,
        terms: impl IntoIterator<Item = (u32, f64)>,
    ) -> ArenaWeights {
        let start = arena.len();
        arena.extend(terms);
        arena[start..].sort_unstable_by_key(|&(v, _)| v);
        ArenaWeights {
            start: start as u32,
            end: arena.len() as u32,
        }
    }

    /// The terms in `arena`, the arena they were pushed to.
    pub(super) fn get<'a>(&self, arena: &'a [(u32, f64)]) -> &'a [(u32, f64)] {
        &arena[self.start as usize..self.end as usize]
    }

    /// Number of terms.
    pub(super) fn len(&self) -> usize {
        (self.end - self.start) as usize
    }
}

/// Most terms [`merge_terms_into`] merges in one pass (the construction combines at most five).
const MERGE_TERMS: usize = 8;

/// `Σ w_i x_i` of sorted sparse vectors in one pass over all of them, ids ascending, appended to
/// `out` (a caller's storage of several rows): for each id, the terms holding it in term order
/// (`w * b` first, then `a + w * b`), as repeated [`GregoryPoint::add_scaled`] computes it.
/// Zero weights and empty vectors contribute nothing, as there. At most [`MERGE_TERMS`] terms
/// ([`Weights::combination`] adds more one by one).
pub(super) fn merge_terms_into(terms: &[(f64, &[(u32, f64)])], out: &mut Vec<(u32, f64)>) {
    assert!(terms.len() <= MERGE_TERMS, "{} terms", terms.len());
    let mut live: [(f64, &[(u32, f64)]); MERGE_TERMS] = [(0.0, &[]); MERGE_TERMS];
    let mut n = 0;
    for &(w, x) in terms {
        if w != 0.0 && !x.is_empty() {
            live[n] = (w, x);
            n += 1;
        }
    }
    let live = &live[..n];
    match live {
        [] => {}
        [(w, x)] => out.extend(x.iter().map(|&(v, b)| (v, *w * b))),
        [a, b] => merged::<2>(&[*a, *b], out),
        [a, b, c] => merged::<3>(&[*a, *b, *c], out),
        [a, b, c, d] => merged::<4>(&[*a, *b, *c, *d], out),
        _ => merged_n(live, out),
    }
}

/// One output term of a k-way merge: the id `v` every term's head is compared with, the
/// weight `Σ w * b` of the terms whose head is `v`, in term order, those heads advanced. The
/// sum starts from `-0.0`, the exact additive identity (`-0.0 + t` is `t` bitwise, `-0.0` and
/// NaN included), so the first term's product is kept as it is.
#[inline(always)]
fn merge_step(
    v: u64,
    head: &mut [u64],
    rest: &mut [&[(u32, f64)]],
    live: &[(f64, &[(u32, f64)])],
) -> f64 {
    let mut acc = -0.0;
    for ((h, r), &(w, _)) in head.iter_mut().zip(rest.iter_mut()).zip(live) {
        if *h == v {
            if let Some((&(_, b), tail)) = r.split_first() {
                acc += w * b;
                *r = tail;
                *h = tail.first().map_or(u64::MAX, |e| u64::from(e.0));
            }
        }
    }
    acc
}

/// [`merge_terms_into`] of exactly `N` live terms (at least one id each): the loops unrolled.
fn merged<const N: usize>(live: &[(f64, &[(u32, f64)]); N], out: &mut Vec<(u32, f64)>) {
    let mut rest: [&[(u32, f64)]; N] = std::array::from_fn(|k| live[k].1);
    let mut head: [u64; N] = std::array::from_fn(|k| u64::from(live[k].1[0].0));
    merge_loop(&mut head, &mut rest, live, out);
}

/// [`merged`] of any number of live terms up to [`MERGE_TERMS`].
fn merged_n(live: &[(f64, &[(u32, f64)])], out: &mut Vec<(u32, f64)>) {
    let n = live.len();
    let mut rest: [&[(u32, f64)]; MERGE_TERMS] = [&[]; MERGE_TERMS];
    let mut head = [u64::MAX; MERGE_TERMS];
    for ((r, h), (_, x)) in rest.iter_mut().zip(&mut head).zip(live) {
        *r = x;
        *h = u64::from(x[0].0);
    }
    merge_loop(&mut head[..n], &mut rest[..n], live, out);
}

/// The merge of the terms `live` from each one's `head` id and `rest` (`u64::MAX` and empty
/// once used up), ids ascending, appended to `out`.
#[inline(always)]
fn merge_loop(
    head: &mut [u64],
    rest: &mut [&[(u32, f64)]],
    live: &[(f64, &[(u32, f64)])],
    out: &mut Vec<(u32, f64)>,
) {
    out.reserve(rest.iter().map(|x| x.len()).sum());
    loop {
        let v = head.iter().copied().fold(u64::MAX, u64::min);
        if v == u64::MAX {
            return;
        }
        out.push((v as u32, merge_step(v, head, rest, live)));
    }
}

thread_local! {
    /// The buffer [`Weights::add_scaled`] merges into before copying back (it keeps its capacity).
    static MERGE_BUFFER: std::cell::RefCell<Vec<(u32, f64)>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// `a += w * x` when every id of `x` is in `a` (both ascending); false, `a` untouched, otherwise.
fn merge_in_place(a: &mut [(u32, f64)], w: f64, x: &[(u32, f64)]) -> bool {
    // Galloping search from `i` (`x` is often a few ids against a row of thousands around a
    // high-valence vertex): the first entry at or after `i` with id `>= v`.
    let find = |a: &[(u32, f64)], i: &mut usize, v: u32| {
        let rest = &a[*i..];
        let mut bound = 1;
        while bound < rest.len() && rest[bound].0 < v {
            bound *= 2;
        }
        *i += rest[..(bound + 1).min(rest.len())].partition_point(|e| e.0 < v);
        *i < a.len() && a[*i].0 == v
    };
    let mut i = 0;
    if x.len() > a.len() || !x.iter().all(|&(v, _)| find(a, &mut i, v)) {
        return false;
    }
    let mut i = 0;
    for &(v, b) in x {
        find(a, &mut i, v);
        a[i].1 += w * b;
    }
    true
}

/// `out = a + w * x`, ids ascending (the sorted merge of both).
fn merge_into(out: &mut Vec<(u32, f64)>, a: &[(u32, f64)], w: f64, x: &[(u32, f64)]) {
    out.clear();
    out.reserve(a.len() + x.len());
    let (mut i, mut j) = (0, 0);
    while i < a.len() || j < x.len() {
        if j == x.len() || (i < a.len() && a[i].0 < x[j].0) {
            out.push(a[i]);
            i += 1;
        } else if i == a.len() || x[j].0 < a[i].0 {
            out.push((x[j].0, w * x[j].1));
            j += 1;
        } else {
            out.push((a[i].0, a[i].1 + w * x[j].1));
            i += 1;
            j += 1;
        }
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

    #[test]
    fn from_terms_equals_adding_units() {
        let terms = [
            (5, 0.1),
            (2, 0.7),
            (5, 0.3),
            (9, 0.0),
            (2, -0.25),
            (0, 1e-3),
        ];
        let mut added = Weights::zero();
        for &(v, w) in &terms {
            added.add_scaled(w, &Weights::unit(v));
        }
        assert_eq!(Weights::from_terms(terms), added);
        assert_eq!(added.0, vec![(0, 1e-3), (2, 0.7 - 0.25), (5, 0.1 + 0.3)]);
    }

    /// Bits of every weight, so that `-0.0` and `0.0` differ.
    fn bits(w: &Weights) -> Vec<(u32, u64)> {
        w.0.iter().map(|&(v, x)| (v, x.to_bits())).collect()
    }

    #[test]
    fn combination_is_adding_term_by_term() {
        // Overlapping supports, a zero weight, an empty vector, a product that is -0.0 first
        // (kept as -0.0: no `0.0 +` before the first term) and sums in term order
        // (non-associative: 1e16 + 1 - 1e16).
        let a = Weights(vec![(0, 1e16), (2, 0.0), (5, 0.5)]);
        let b = Weights(vec![(0, 1.0), (3, 2.0), (5, 0.25)]);
        let c = Weights(vec![(0, -1e16), (1, 0.1), (9, 3.0)]);
        let empty = Weights::zero();
        let cases: Vec<Vec<(f64, &Weights)>> = vec![
            vec![],
            vec![(0.0, &a)],
            vec![(-1.0, &a)],
            vec![(1.0, &a), (1.0, &b), (1.0, &c)],
            vec![(1.0, &c), (0.3, &b), (1.0, &a), (0.0, &b), (2.0, &empty)],
            vec![(0.7, &b), (-1.5, &a), (1.0, &c), (0.25, &a)],
            vec![(0.5, &c), (-2.0, &b)],
            // Six live terms: the merge of any count.
            vec![
                (0.7, &b),
                (-1.5, &a),
                (1.0, &c),
                (0.25, &a),
                (3.0, &b),
                (-0.5, &c),
            ],
            // More terms than one pass merges: the term-by-term fallback.
            (0..11)
                .map(|k| (0.1 * k as f64 - 0.4, [&a, &b, &c][k % 3]))
                .collect(),
        ];
        for terms in cases {
            let mut added = Weights::zero();
            for (w, x) in &terms {
                added.add_scaled(*w, x);
            }
            assert_eq!(bits(&combine(&terms)), bits(&added), "{terms:?}");
        }
        let neg = combine(&[(-1.0, &a)]);
        assert_eq!(neg.0[1].1.to_bits(), (-0.0f64).to_bits());
        let order = combine(&[(1.0, &a), (1.0, &b), (1.0, &c)]);
        assert_eq!(order.0[0].1, 0.0, "(1e16 + 1) - 1e16 in f64");
    }

    #[test]
    fn in_place_and_buffered_merges_agree() {
        let a = Weights(vec![(1, 0.5), (3, 0.25), (8, 2.0)]);
        let subset = Weights(vec![(1, 4.0), (8, -1.0)]);
        let mut in_place = a.clone();
        in_place.add_scaled(0.3, &subset);
        assert_eq!(
            in_place.0,
            vec![(1, 0.5 + 0.3 * 4.0), (3, 0.25), (8, 2.0 - 0.3)]
        );
        let wider = Weights(vec![(0, 1.0), (3, 1.0)]);
        let mut merged = a;
        merged.add_scaled(-2.0, &wider);
        assert_eq!(
            merged.0,
            vec![(0, -2.0), (1, 0.5), (3, 0.25 - 2.0), (8, 2.0)]
        );
    }
}
