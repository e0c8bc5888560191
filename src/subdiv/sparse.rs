//! Row-compressed sparse matrices: refinement matrices (child vertices from parent vertices)
//! and the storage of [`super::StencilTable`].

use crate::topology::par::{map_chunks, Shared, CHUNK};
use glam::DVec3;
use rayon::prelude::*;

/// A CSR matrix with `f64` weights. Row `r` is `indices/weights[offsets[r]..offsets[r + 1]]`.
/// Within a row every column index appears once (rows are merged on construction).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SparseMatrix {
    pub(crate) cols: usize,
    pub(crate) offsets: Vec<usize>,
    pub(crate) indices: Vec<u32>,
    pub(crate) weights: Vec<f64>,
}

/// A block of consecutive rows: row lengths, indices, weights.
pub(crate) type Block = (Vec<usize>, Vec<u32>, Vec<f64>);

/// Sorts a row by column and adds up repeated columns, dropping exact zeros.
pub(crate) fn merge_row(row: &mut Vec<(u32, f64)>) {
    merge_row_from(row, 0);
}

/// [`merge_row`] of the terms of `row` from `start` on (the row pushed last into a list of
/// rows), the terms before them untouched.
pub(crate) fn merge_row_from(row: &mut Vec<(u32, f64)>, start: usize) {
    if row.len() > start + 1 {
        row[start..].sort_unstable_by_key(|x| x.0);
        let mut w = start;
        for r in start + 1..row.len() {
            if row[r].0 == row[w].0 {
                row[w].1 += row[r].1;
            } else {
                w += 1;
                row[w] = row[r];
            }
        }
        row.truncate(w + 1);
    }
    let mut k = start;
    for r in start..row.len() {
        if row[r].1 != 0.0 {
            row[k] = row[r];
            k += 1;
        }
    }
    row.truncate(k);
}

impl SparseMatrix {
    /// An empty matrix with `cols` columns and no rows.
    pub fn new(cols: usize) -> Self {
        SparseMatrix {
            cols,
            offsets: vec![0],
            indices: Vec::new(),
            weights: Vec::new(),
        }
    }

    /// Builds `rows` rows in parallel: `row(r, buf)` pushes `(column, weight)` pairs into the
    /// empty `buf`; repeated columns are added up and zeros dropped.
    pub fn from_rows<F>(rows: usize, cols: usize, row: F) -> Self
    where
        F: Fn(usize, &mut Vec<(u32, f64)>) + Sync + Send,
    {
        let chunks = rows.div_ceil(CHUNK).max(1);
        let parts: Vec<Block> = map_chunks(chunks, |c| {
            let (lo, hi) = (c * CHUNK, ((c + 1) * CHUNK).min(rows));
            let mut lens = Vec::with_capacity(hi - lo);
            let mut idx = Vec::with_capacity((hi - lo) * 8);
            let mut wts = Vec::with_capacity((hi - lo) * 8);
            let mut buf = Vec::with_capacity(32);
            for r in lo..hi {
                buf.clear();
                row(r, &mut buf);
                merge_row(&mut buf);
                lens.push(buf.len());
                for &(i, w) in &buf {
                    idx.push(i);
                    wts.push(w);
                }
            }
            (lens, idx, wts)
        });
        Self::concat(cols, parts)
    }

    /// Joins row blocks `(row lengths, indices, weights)` in order.
    pub(crate) fn concat(cols: usize, parts: Vec<Block>) -> Self {
        let rows: usize = parts.iter().map(|p| p.0.len()).sum();
        let mut offsets = Vec::with_capacity(rows + 1);
        offsets.push(0usize);
        let mut starts = Vec::with_capacity(parts.len());
        for p in &parts {
            starts.push(*offsets.last().unwrap_or(&0));
            for &l in &p.0 {
                let last = *offsets.last().unwrap_or(&0);
                offsets.push(last + l);
            }
        }
        let nnz = *offsets.last().unwrap_or(&0);
        let mut indices = vec![0u32; nnz];
        let mut weights = vec![0f64; nnz];
        let (si, sw) = (Shared::new(&mut indices), Shared::new(&mut weights));
        let copy = |(p, &s): (&Block, &usize)| {
            // SAFETY: blocks occupy consecutive disjoint ranges of the output.
            unsafe {
                si.range(s, s + p.1.len()).copy_from_slice(&p.1);
                sw.range(s, s + p.2.len()).copy_from_slice(&p.2);
            }
        };
        if parts.len() <= 1 {
            parts.iter().zip(starts.iter()).for_each(copy);
        } else {
            parts.par_iter().zip(starts.par_iter()).for_each(copy);
        }
        SparseMatrix {
            cols,
            offsets,
            indices,
            weights,
        }
    }

    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.offsets.len() - 1
    }

    /// Number of columns.
    pub fn cols(&self) -> usize {
        self.cols
    }

    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.indices.len()
    }

    /// Row offsets (`rows() + 1` entries).
    pub fn offsets(&self) -> &[usize] {
        &self.offsets
    }

    /// Column indices of all rows.
    pub fn indices(&self) -> &[u32] {
        &self.indices
    }

    /// Weights of all rows.
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// Row `r` as `(columns, weights)`.
    pub fn row(&self, r: usize) -> (&[u32], &[f64]) {
        let (a, b) = (self.offsets[r], self.offsets[r + 1]);
        (&self.indices[a..b], &self.weights[a..b])
    }

    /// Appends one row (repeated columns are added up, zeros dropped).
    pub fn push_row(&mut self, entries: &[(u32, f64)]) {
        let mut buf = entries.to_vec();
        merge_row(&mut buf);
        for (i, w) in buf {
            self.indices.push(i);
            self.weights.push(w);
        }
        self.offsets.push(self.indices.len());
    }

    /// Appends all rows of `other` (which must have the same number of columns).
    pub fn append(&mut self, other: &SparseMatrix) {
        let base = self.indices.len();
        self.indices.extend_from_slice(&other.indices);
        self.weights.extend_from_slice(&other.weights);
        self.offsets
            .extend(other.offsets[1..].iter().map(|&o| o + base));
        self.cols = self.cols.max(other.cols);
    }

    /// `dst[r] = sum_j w_rj src[c_rj]` (parallel when large). `dst.len()` must be `rows()`
    /// and every column index must be `< src.len()`.
    pub fn apply(&self, src: &[DVec3], dst: &mut [DVec3]) {
        let rows = self.rows().min(dst.len());
        let one = |r: usize| -> DVec3 {
            let (a, b) = (self.offsets[r], self.offsets[r + 1]);
            let mut acc = DVec3::ZERO;
            for k in a..b {
                acc += src[self.indices[k] as usize] * self.weights[k];
            }
            acc
        };
        if rows < 4 * CHUNK {
            for (r, d) in dst[..rows].iter_mut().enumerate() {
                *d = one(r);
            }
        } else {
            dst[..rows]
                .par_chunks_mut(CHUNK)
                .enumerate()
                .for_each(|(c, out)| {
                    for (i, d) in out.iter_mut().enumerate() {
                        *d = one(c * CHUNK + i);
                    }
                });
        }
    }

    /// Applies to `src` and returns the result.
    pub fn apply_vec(&self, src: &[DVec3]) -> Vec<DVec3> {
        let mut dst = vec![DVec3::ZERO; self.rows()];
        self.apply(src, &mut dst);
        dst
    }

    /// The product `self * rhs` (rows of `self` combine rows of `rhs`), exact zeros pruned.
    pub fn compose(&self, rhs: &SparseMatrix) -> SparseMatrix {
        Self::compose_rows(self.rows(), rhs, |r, buf| {
            let (i, w) = self.row(r);
            buf.extend(i.iter().copied().zip(w.iter().copied()));
        })
    }

    /// `rows` rows, row `r` being `sum_k w_k * rhs.row(c_k)` for the `(c_k, w_k)` that
    /// `row(r, buf)` pushes (repeats allowed); columns sorted, exact zeros pruned.
    pub fn compose_rows<F>(rows: usize, rhs: &SparseMatrix, row: F) -> SparseMatrix
    where
        F: Fn(usize, &mut Vec<(u32, f64)>) + Sync + Send,
    {
        let cols = rhs.cols;
        let chunks = rows.div_ceil(CHUNK).max(1);
        type State = (Vec<f64>, Vec<u32>, Vec<(u32, f64)>);
        let init = || -> State {
            (
                vec![0f64; cols],
                Vec::with_capacity(64),
                Vec::with_capacity(32),
            )
        };
        let body = |(acc, touched, buf): &mut State, c: usize| {
            let (lo, hi) = (c * CHUNK, ((c + 1) * CHUNK).min(rows));
            let acc: &mut [f64] = acc.as_mut_slice();
            let (ro, ri, rw) = (&rhs.offsets[..], &rhs.indices[..], &rhs.weights[..]);
            let mut lens = Vec::with_capacity(hi - lo);
            let mut idx = Vec::with_capacity((hi - lo) * 20);
            let mut wts = Vec::with_capacity((hi - lo) * 20);
            for r in lo..hi {
                buf.clear();
                row(r, buf);
                for &(p, w) in buf.iter() {
                    let (a, b) = (ro[p as usize], ro[p as usize + 1]);
                    for (&q, &x) in ri[a..b].iter().zip(&rw[a..b]) {
                        let slot = &mut acc[q as usize];
                        // A column may be pushed twice if its sum cancels to zero on
                        // the way; the read-out below zeroes it after the first copy.
                        if *slot == 0.0 {
                            touched.push(q);
                        }
                        *slot += w * x;
                    }
                }
                touched.sort_unstable();
                let mut n = 0;
                for &q in touched.iter() {
                    let w = std::mem::take(&mut acc[q as usize]);
                    if w != 0.0 {
                        idx.push(q);
                        wts.push(w);
                        n += 1;
                    }
                }
                touched.clear();
                lens.push(n);
            }
            (lens, idx, wts)
        };
        let parts: Vec<Block> = if chunks == 1 {
            vec![body(&mut init(), 0)]
        } else {
            (0..chunks).into_par_iter().map_init(init, body).collect()
        };
        Self::concat(cols, parts)
    }
}
