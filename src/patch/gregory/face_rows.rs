//! One face's sparse stencil rows in flat arrays ([`FaceRows`]): what the end caps' row
//! construction ([`super::stencil_table`], [`super::shared_rows`]) hands on, without an
//! allocation per row.

use std::borrow::Borrow;

use super::point::Weights;

/// What a buffer of terms is filled with before each entry is written out of order: not all
/// zero bytes, so it is filled by a store loop rather than allocated zeroed (whose `memset`
/// runs one `rep stosb` step per byte, which cachegrind counts as an instruction each).
pub(super) const TERM_PLACEHOLDER: (u32, f64) = (u32::MAX, 0.0);

/// One face's rows in two allocations rather than one per row: row `r` is
/// `terms[offsets[r]..offsets[r + 1]]`, `(id, weight)` ids ascending, as a [`Weights`] holds
/// them (vertices, then vertex points: [`super::stencil_table::vertex_point_id`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FaceRows {
    /// `rows + 1` term offsets.
    pub offsets: Vec<u32>,
    /// The terms of every row.
    pub terms: Vec<(u32, f64)>,
}

impl FaceRows {
    /// The same rows as `rows` (owned or borrowed), in exactly sized storage.
    pub fn from_weights<W: Borrow<Weights>>(rows: &[W]) -> FaceRows {
        let mut out = FaceRows {
            offsets: Vec::with_capacity(rows.len() + 1),
            terms: Vec::with_capacity(rows.iter().map(|w| w.borrow().0.len()).sum()),
        };
        out.offsets.push(0);
        for w in rows {
            out.terms.extend_from_slice(&w.borrow().0);
            out.offsets.push(out.terms.len() as u32);
        }
        out
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// Whether there is no row.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Row `r`.
    pub fn row(&self, r: usize) -> &[(u32, f64)] {
        &self.terms[self.offsets[r] as usize..self.offsets[r + 1] as usize]
    }

    /// Every row in order.
    pub fn rows(&self) -> impl Iterator<Item = &[(u32, f64)]> {
        (0..self.len()).map(|r| self.row(r))
    }

    /// Row `r` as a [`Weights`].
    pub fn weights(&self, r: usize) -> Weights {
        Weights(self.row(r).to_vec())
    }

    /// Every row as a [`Weights`].
    pub fn to_weights(&self) -> Vec<Weights> {
        (0..self.len()).map(|r| self.weights(r)).collect()
    }

    /// No rows, ready to take some ([`Self::append`], [`Self::push_empty`]).
    pub fn new() -> FaceRows {
        FaceRows {
            offsets: vec![0],
            terms: Vec::new(),
        }
    }

    /// Rows `first..` read in place, numbered from 0 (one face's rows in the rows of many).
    pub fn rows_from(&self, first: usize) -> RowsFrom<'_> {
        RowsFrom { rows: self, first }
    }

    /// Appends `n` empty rows.
    pub fn push_empty(&mut self, n: usize) {
        let end = self.terms.len() as u32;
        self.offsets.extend(std::iter::repeat_n(end, n));
    }

    /// Appends the rows `offsets` over `terms` with each id written as `id(id)`, without the
    /// terms `kept` drops (the others in order): one pass over the terms into their final
    /// place, `id` asked only of the terms kept.
    pub(super) fn relabelled_into(
        &mut self,
        offsets: &[u32],
        terms: &[(u32, f64)],
        kept: Terms,
        id: impl Fn(u32) -> u32,
    ) {
        let relabel = |&(u, x): &(u32, f64)| (id(u), x);
        let start = offsets.first().map_or(0, |&o| o as usize);
        if kept == Terms::All || !terms.iter().any(|t| t.1 == 0.0) {
            // The rows' offsets moved to where their terms go.
            let base = (self.terms.len() as u32).wrapping_sub(start as u32);
            self.offsets
                .extend(offsets.iter().skip(1).map(|&o| base.wrapping_add(o)));
            self.terms.extend(terms[start..].iter().map(relabel));
            return;
        }
        // One loop over every term (an `extend` per row costs a call and its set-up per row).
        let mut t = start;
        for &end in offsets.iter().skip(1) {
            for term in &terms[t..end as usize] {
                if kept.keeps(term.1) {
                    self.terms.push(relabel(term));
                }
            }
            t = end as usize;
            self.offsets.push(self.terms.len() as u32);
        }
    }

    /// Appends `rows`' rows (their terms moved to follow this one's).
    pub fn append(&mut self, rows: &FaceRows) {
        self.relabelled_into(&rows.offsets, &rows.terms, Terms::All, |u| u);
    }
}

/// Rows `first..` of a [`FaceRows`] read in place ([`FaceRows::rows_from`]): row `r` is its
/// row `first + r`.
#[derive(Debug, Clone, Copy)]
pub struct RowsFrom<'a> {
    rows: &'a FaceRows,
    first: usize,
}

impl RowsFrom<'_> {
    /// Row `r`.
    pub fn row(&self, r: usize) -> &[(u32, f64)] {
        self.rows.row(self.first + r)
    }

    /// Row `r` as a [`Weights`].
    pub fn weights(&self, r: usize) -> Weights {
        self.rows.weights(self.first + r)
    }
}

/// Which terms of the end caps' rows a caller takes: the draw tables drop the terms whose
/// weight rounds to a zero f32, which are exact zeros in most end caps' rows, so dropping
/// those once per connectivity type saves doing it per face. Exact
/// zeros only: a Gregory corner's tangent rows `3 e - 3 p` (draw tables' corner rows) have the
/// same bits with an exact zero term or without it, not with a tiny one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Terms {
    /// Every term, as the direct construction writes it.
    All,
    /// The terms whose weight is not zero (nor minus zero), in order.
    Nonzero,
}

impl Terms {
    /// Whether a term of weight `w` is kept.
    pub fn keeps(self, w: f64) -> bool {
        self == Terms::All || w != 0.0
    }
}
