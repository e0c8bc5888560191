//! The lattice frames' tangent rows in two flat buffers: one allocation for all the frames of a
//! build instead of two per frame (a build makes some hundreds of frames, each appended to the
//! draw tables' rows and dropped).

/// Per frame its two exact limit tangent rows `(d1, d2)`, `(id, weight)` terms over global
/// refined ids, `cross(d1, d2)` outward.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FrameRows {
    /// The rows' terms, row after row.
    terms: Vec<(u32, f64)>,
    /// Per row (two per frame): where its terms end.
    ends: Vec<u32>,
}

impl FrameRows {
    /// Number of frames.
    pub fn len(&self) -> usize {
        self.ends.len() / 2
    }

    /// Whether there is no frame.
    pub fn is_empty(&self) -> bool {
        self.ends.is_empty()
    }

    /// Number of terms of all the rows.
    pub fn term_count(&self) -> usize {
        self.terms.len()
    }

    /// The rows `[d1, d2]` of frame `f`, `None` past the last.
    pub fn get(&self, f: usize) -> Option<[&[(u32, f64)]; 2]> {
        (f < self.len()).then(|| self.frame(f))
    }

    /// The frames' rows in order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = [&[(u32, f64)]; 2]> + '_ {
        (0..self.len()).map(|f| self.frame(f))
    }

    /// The rows of frame `f < len`.
    fn frame(&self, f: usize) -> [&[(u32, f64)]; 2] {
        let row = |r: usize| {
            let start = if r == 0 { 0 } else { self.ends[r - 1] };
            &self.terms[start as usize..self.ends[r] as usize]
        };
        [row(2 * f), row(2 * f + 1)]
    }

    /// Room for `frames` more frames of `terms` terms in all.
    pub(super) fn reserve(&mut self, frames: usize, terms: usize) {
        self.ends.reserve(2 * frames);
        self.terms.reserve(terms);
    }

    /// Appends `term` to the row being made.
    pub(super) fn push_term(&mut self, term: (u32, f64)) {
        self.terms.push(term);
    }

    /// Ends the row being made (a frame's rows: d1, then d2).
    pub(super) fn end_row(&mut self) {
        self.ends.push(self.terms.len() as u32);
    }

    /// Appends a frame of rows `[d1, d2]`.
    pub(super) fn push(&mut self, rows: [&[(u32, f64)]; 2]) {
        for row in rows {
            self.terms.extend_from_slice(row);
            self.end_row();
        }
    }
}
