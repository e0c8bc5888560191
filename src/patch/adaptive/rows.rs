//! Sparse stencil rows over the global refined vertices (Köbler 2013 §4.2: one vertex buffer
//! for every level): slot frames (limit position and two tangents) and end-cap control points.

use std::ops::Range;

use glam::DVec3;

use super::surface::EndCapTopologies;
use crate::patch::gregory::shared_rows::{FaceRows, RowsFrom};
use crate::patch::gregory::word_hash::WordHashMap;
use crate::patch::gregory::{one_face_crease_sector, GregoryPoint, Weights};
use crate::patch::single_crease::SingleCreasePatch;
use crate::patch::RegularPatch;
use crate::subdiv::adaptive::{AdaptiveRefinement, PatchCensus};
use crate::subdiv::bspline::{bspline, bspline_deriv};
use crate::subdiv::single_crease::{CreaseLine, CreaseSide};

/// The most terms an exact patch's corner rows hold: three rows over its 16 control points.
pub const EXACT_CORNER_TERMS: usize = 3 * 16;

/// A patch corner as [`CornerRows::visit`] visits it.
#[derive(Debug, Clone, Copy)]
pub struct PatchCorner {
    /// Census index of the patch.
    pub patch: usize,
    /// Face corner.
    pub k: usize,
    /// Its vertex in the patch's level.
    pub vertex: u32,
    /// That vertex's global id (`AdaptiveLevel::global`).
    pub global: u32,
    /// End caps: the index of the patch's rows in `caps` ([`END_CAP_ROWS`] rows each).
    cap: usize,
}

/// Rows per end cap: 20 control points and 16 extra rows (quads), 15 + 12 then empty rows
/// (triangles, isolation 0 only), in [`crate::patch::gregory::stencil_table`] order.
pub const END_CAP_ROWS: usize = 36;

/// The corners of census patches in the order frames take their rows, and their frame rows
/// (computable apart from the visit, and on several threads).
pub struct CornerRows<'a> {
    refinement: &'a AdaptiveRefinement,
    census: &'a PatchCensus,
    topologies: &'a EndCapTopologies<'a>,
    caps: &'a FaceRows,
    /// Single-crease corner weights depend on the line's side and sharpness and the corner
    /// only: evaluated once per such shape of the census, not once per corner.
    crease: WordHashMap<CreaseKey, CornerTable>,
    /// B-spline corner weights per face corner and phantom sides ([`bspline_corner_columns`]
    /// of `(k, mask)` at `16 k + mask`): they depend on nothing else.
    bspline: Vec<CornerTable>,
    /// Every corner in [`Self::visit`] order, walked once for every visit.
    corners: Vec<PatchCorner>,
}

impl<'a> CornerRows<'a> {
    /// The corner rows of `census`; `caps` are the end caps' rows in census order, built over
    /// `topologies`; `corners` its [`patch_corners`].
    pub fn new(
        refinement: &'a AdaptiveRefinement,
        census: &'a PatchCensus,
        topologies: &'a EndCapTopologies<'a>,
        caps: &'a FaceRows,
        corners: Vec<PatchCorner>,
    ) -> CornerRows<'a> {
        let mut crease = WordHashMap::default();
        for line in census.patches.iter().filter_map(|p| p.crease.as_ref()) {
            for k in 0..4 {
                crease
                    .entry((line.side, line.sharpness.to_bits(), k))
                    .or_insert_with(|| {
                        CornerTable::new(single_crease_corner_table_rows(
                            line.side,
                            line.sharpness,
                            k,
                        ))
                    });
            }
        }
        CornerRows {
            refinement,
            census,
            topologies,
            caps,
            crease,
            bspline: (0..4 * 16)
                .map(|i| CornerTable::new(bspline_corner_columns(i / 16, i as u8 % 16)))
                .collect(),
            corners,
        }
    }

    /// Rows (position, d/du, d/dv) of corner `c` over the global refined vertices.
    pub fn rows(&self, c: &PatchCorner) -> [Weights; 3] {
        let p = &self.census.patches[c.patch];
        match (&p.crease, &p.bspline) {
            (Some(line), _) => self.crease_table(line, c.k).weights(&line.cvs),
            (None, Some(b)) => self.bspline_table(b, c.k).weights(&b.cvs),
            (None, None) => {
                let n = self.refinement.levels[p.level as usize]
                    .topology()
                    .face_size(p.face);
                gregory_corner_rows(self.cap(c), n, c.k, self.singular(c))
            }
        }
    }

    /// The position row of corner `c` ([`Self::rows`]' first, the same bits), without its
    /// tangent rows.
    pub fn position_row(&self, c: &PatchCorner) -> Weights {
        let p = &self.census.patches[c.patch];
        match (&p.crease, &p.bspline) {
            (None, None) => self.cap(c).weights(c.k),
            _ => {
                let [position, ..] = self.rows(c);
                position
            }
        }
    }

    /// The rows of end-cap corner `c`'s patch.
    fn cap(&self, c: &PatchCorner) -> RowsFrom<'a> {
        self.caps.rows_from(END_CAP_ROWS * c.cap)
    }

    /// Whether end-cap corner `c` lies alone in a crease sector of its end caps' topology
    /// (`one_face_crease_sector`; false for a B-spline patch's corner): asked only of the
    /// corners whose rows are taken, not computed for every corner.
    pub fn singular(&self, c: &PatchCorner) -> bool {
        let p = &self.census.patches[c.patch];
        p.bspline.is_none()
            && one_face_crease_sector(self.topologies.get(p.level), c.vertex, p.face)
    }

    /// [`bspline_corner_columns`] of `b` at corner `k`, from the table.
    fn bspline_table(&self, b: &RegularPatch, k: usize) -> &CornerTable {
        &self.bspline[16 * k + usize::from(b.boundary_mask & 0xf)]
    }

    /// [`single_crease_corner_table_rows`] of `line` at corner `k`, from the table.
    fn crease_table(&self, line: &CreaseLine, k: usize) -> &CornerTable {
        &self.crease[&(line.side, line.sharpness.to_bits(), k)]
    }

    /// Appends the rows of corner `c` ([`Self::rows`], the same bits where its control vertices
    /// are distinct) to `out`; exact patches' rows from their corner table (`push_template`,
    /// gathered in `terms`).
    pub fn push_rows(&self, c: &PatchCorner, out: &mut SparseRows, terms: &mut TemplateTerms) {
        let p = &self.census.patches[c.patch];
        match (&p.crease, &p.bspline) {
            (Some(line), _) => push_template(out, &line.cvs, self.crease_table(line, c.k), terms),
            (None, Some(b)) => push_template(out, &b.cvs, self.bspline_table(b, c.k), terms),
            (None, None) => {
                let n = self.refinement.levels[p.level as usize]
                    .topology()
                    .face_size(p.face);
                push_gregory_corner_rows(out, self.cap(c), n, c.k, self.singular(c));
            }
        }
    }

    /// At least the number of terms [`Self::push_rows`] appends for corner `c` (16 per row of an
    /// exact patch; a Gregory corner's `e - p` rows at most the sum of their two rows' terms,
    /// the second tangent's bound by the larger of its two rows, not asking [`Self::singular`]).
    pub fn terms_bound(&self, c: &PatchCorner) -> usize {
        let p = &self.census.patches[c.patch];
        if p.bspline.is_some() {
            return EXACT_CORNER_TERMS;
        }
        let n = self.refinement.levels[p.level as usize]
            .topology()
            .face_size(p.face);
        let rows = self.cap(c);
        let second = rows.row(2 * n + c.k).len().max(rows.row(3 * n + c.k).len());
        3 * rows.row(c.k).len() + rows.row(n + c.k).len() + second
    }

    /// Visits every corner of every census patch, exact patches (B-spline, single-crease)
    /// first, then end caps (whose Gregory corners are built over `topologies`): the
    /// order in which frames take their rows from the first patch with that corner.
    pub fn visit(&self, visit: impl FnMut(&PatchCorner)) {
        self.corners.iter().for_each(visit);
    }

    /// Corner `i` of the [`Self::visit`] order.
    pub fn corner(&self, i: u32) -> &PatchCorner {
        &self.corners[i as usize]
    }
}

/// Every corner of every census patch in [`CornerRows::visit`] order: exact patches
/// (B-spline, single-crease) first, then end caps.
pub fn patch_corners(refinement: &AdaptiveRefinement, census: &PatchCensus) -> Vec<PatchCorner> {
    let mut out = Vec::with_capacity(4 * census.patches.len());
    for end_caps in [false, true] {
        // End caps: the running count of end caps is the index of the patch's rows.
        let mut next_cap = 0;
        for (i, p) in census.patches.iter().enumerate() {
            if p.bspline.is_none() != end_caps {
                continue;
            }
            let cap = next_cap;
            next_cap += usize::from(end_caps);
            let lev = &refinement.levels[p.level as usize];
            // Extended from the face's vertices (one capacity check a face).
            let face = lev.topology().face_vertices(p.face).iter().enumerate();
            out.extend(face.map(|(k, &v)| PatchCorner {
                patch: i,
                k,
                vertex: v,
                global: lev.global(v),
                cap,
            }));
        }
    }
    out
}

/// Rows of sparse weights: row `r` is terms `offsets[r]..offsets[r + 1]` of `ids` /
/// `weights_f64`, ids ascending (the summation order, so a row two patches share sums to the
/// same bits), weights that round to a zero f32 dropped. The GPU reads the weights rounded to
/// f32 ([`Self::weights_f32`]), rounded where they are read rather than kept as a third array
/// every term is written to.
#[derive(Clone, Default, PartialEq)]
pub struct SparseRows {
    /// `rows + 1` term offsets.
    pub offsets: Vec<u32>,
    /// Global refined vertex ids.
    pub ids: Vec<u32>,
    /// The weights (CPU references; the GPU's are these rounded to f32).
    pub weights_f64: Vec<f64>,
}

/// The fields, and the GPU's f32 weights as `weights` (so a fingerprint of the debug output
/// covers both roundings).
impl std::fmt::Debug for SparseRows {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseRows")
            .field("offsets", &self.offsets)
            .field("ids", &self.ids)
            .field("weights", &self.weights_f32().collect::<Vec<_>>())
            .field("weights_f64", &self.weights_f64)
            .finish()
    }
}

impl SparseRows {
    /// No rows yet.
    pub fn new() -> SparseRows {
        SparseRows {
            offsets: vec![0],
            ..Default::default()
        }
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        self.offsets.len() - 1
    }

    /// Whether there is no row.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Appends a row of weights over local vertices, `first` added to every id (ascending
    /// local ids stay ascending).
    pub fn push(&mut self, row: &Weights, first: u32) {
        self.push_terms(&row.0, first);
    }

    /// [`Self::push`] of a row given as its `(id, weight)` terms.
    pub fn push_terms(&mut self, row: &[(u32, f64)], first: u32) {
        for &(v, w) in row {
            self.push_term((first + v, w));
        }
        self.end_row();
    }

    /// [`Self::push_terms`] of a long row (no id offset), the same terms: copied whole, array
    /// by array, then its terms whose weight rounds to a zero f32 dropped where there are any
    /// (as [`Self::append_face_row_range`] does), rather than two pushes and a test per term.
    pub fn push_long_row(&mut self, row: &[(u32, f64)]) {
        let first_row = self.len();
        self.offsets.push((self.ids.len() + row.len()) as u32);
        self.extend_terms(row, 0, first_row);
    }

    /// Appends term `(id, w)` to the row being pushed, unless `w` rounds to a zero f32.
    fn push_term(&mut self, (id, w): (u32, f64)) {
        if w as f32 != 0.0 {
            self.ids.push(id);
            self.weights_f64.push(w);
        }
    }

    /// Every term's weight as the GPU reads it (rounded to f32).
    pub fn weights_f32(&self) -> impl Iterator<Item = f32> + '_ {
        self.weights_f64.iter().map(|&w| w as f32)
    }

    /// Ends the row being pushed ([`Self::push_term`]).
    fn end_row(&mut self) {
        self.offsets.push(self.ids.len() as u32);
    }

    /// Appends every row of `other`.
    pub fn append(&mut self, other: &SparseRows) {
        let base = *self.offsets.last().expect("offsets start with 0");
        self.offsets
            .extend(other.offsets[1..].iter().map(|&o| base + o));
        self.ids.extend_from_slice(&other.ids);
        self.weights_f64.extend_from_slice(&other.weights_f64);
    }

    /// Appends every row of `rows` ([`Self::push_terms`] of each, the same terms): copied
    /// whole, array by array (a copy per array rather than two pushes per term), then the
    /// terms whose weight rounds to a zero f32 dropped in place where there are any: the end
    /// caps' rows come without their exact zeros (`Terms::Nonzero`, dropped once per type),
    /// so for them this is mostly a check, made as the weights are copied.
    pub fn append_face_rows(&mut self, rows: &FaceRows) {
        self.append_face_row_range(rows, 0..rows.len(), 0);
    }

    /// [`Self::append_face_rows`] of rows `range` of `rows` with `first` added to every id
    /// ([`Self::push_terms`] of each): a run of rows is one run of terms, copied as one.
    pub fn append_face_row_range(&mut self, rows: &FaceRows, range: Range<usize>, first: u32) {
        let first_row = self.len();
        let ends = &rows.offsets[range.start..=range.end];
        let terms = &rows.terms[ends[0] as usize..ends[ends.len() - 1] as usize];
        // The run's term offsets moved to where its terms go.
        let base = (self.ids.len() as u32).wrapping_sub(ends[0]);
        self.offsets
            .extend(ends[1..].iter().map(|&o| base.wrapping_add(o)));
        self.extend_terms(terms, first, first_row);
    }

    /// Appends `terms` (`first` added to every id) as the terms of the rows from `first_row`
    /// on, whose offsets already count them whole, then drops those whose weight rounds to a
    /// zero f32 where there are any: copied array by array, zeros checked by magnitude as the
    /// weights are copied (no conversion per weight, no early exit, no pass of its own).
    #[inline(always)]
    fn extend_terms(&mut self, terms: &[(u32, f64)], first: u32, first_row: usize) {
        self.ids.extend(terms.iter().map(|t| first + t.0));
        let mut zero = false;
        self.weights_f64.extend(terms.iter().map(|&(_, w)| {
            zero |= w.abs() <= LARGEST_F32_ZERO;
            w
        }));
        if zero {
            self.drop_zero_terms(first_row);
        }
    }

    /// Drops the terms of the rows from `first_row` on whose f32 weight is zero
    /// ([`close_up_rows`]).
    fn drop_zero_terms(&mut self, first_row: usize) {
        let first = self.offsets[first_row] as usize;
        let n = self.ids.len() - first;
        // Two slices of one length, so one bounds check a row covers both.
        let (ids, weights) = (
            &mut self.ids[first..],
            &mut self.weights_f64[first..first + n],
        );
        let kept = close_up_rows(&mut self.offsets[first_row + 1..], first, n, |to, from| {
            let w = weights[from];
            ids[to] = ids[from];
            weights[to] = w;
            w as f32 != 0.0
        });
        self.ids.truncate(first + kept);
        self.weights_f64.truncate(first + kept);
    }

    /// Reserves room for `rows` more rows of `terms` terms together.
    pub fn reserve(&mut self, rows: usize, terms: usize) {
        self.offsets.reserve(rows);
        self.ids.reserve(terms);
        self.weights_f64.reserve(terms);
    }

    /// Appends `n` empty rows.
    pub fn push_empty(&mut self, n: usize) {
        let end = self.ids.len() as u32;
        self.offsets.extend(std::iter::repeat_n(end, n));
    }

    /// Terms `(id, f64 weight)` of row `r`.
    pub fn row(&self, r: usize) -> impl Iterator<Item = (u32, f64)> + '_ {
        let (a, b) = (self.offsets[r] as usize, self.offsets[r + 1] as usize);
        self.ids[a..b]
            .iter()
            .copied()
            .zip(self.weights_f64[a..b].iter().copied())
    }

    /// Row `r` applied to global positions with the f64 weights.
    pub fn apply(&self, r: usize, positions: &[DVec3]) -> DVec3 {
        self.row(r).map(|(v, w)| w * positions[v as usize]).sum()
    }

    /// Row `r` applied with the f32 weights (products and sums in f64).
    pub fn apply_f32(&self, r: usize, positions: &[DVec3]) -> DVec3 {
        let (a, b) = (self.offsets[r] as usize, self.offsets[r + 1] as usize);
        self.ids[a..b]
            .iter()
            .zip(&self.weights_f64[a..b])
            .map(|(&v, &w)| f64::from(w as f32) * positions[v as usize])
            .sum()
    }
}

/// Closes up rows in place, dropping terms: the rows end at `ends` (absolute term offsets, the
/// first row starting at `first`; `n` terms from `first` on), and `keep(to, from)` writes term
/// `from` (relative to `first`) at place `to <= from` and says whether it is kept. Each term is
/// written at the next place whether kept or not (no branch per term); the ends are rewritten
/// and the kept count returned.
#[inline(always)]
fn close_up_rows(
    ends: &mut [u32],
    first: usize,
    n: usize,
    mut keep: impl FnMut(usize, usize) -> bool,
) -> usize {
    let (mut to, mut start) = (0, 0);
    for end in ends {
        let stop = *end as usize - first;
        // Ends within the terms, so the caller's slices of `n` need no check per term.
        assert!(stop <= n, "row ends within the terms");
        for from in start..stop {
            // `to <= from`: the minimum only tells the compiler so.
            to += usize::from(keep(to.min(from), from));
        }
        *end = (first + to) as u32;
        start = stop;
    }
    to
}

/// The largest f64 magnitude that rounds to a zero f32: half the least subnormal f32 (2^-150,
/// a tie rounded to the even zero); `w as f32 == 0.0` exactly where `w.abs()` is at most this.
const LARGEST_F32_ZERO: f64 = 1.0 / (1u64 << 50) as f64 / (1u128 << 100) as f64;

/// Folds the weights of a patch's mirrored control points onto its real ones: the transpose of
/// [`RegularPatch::control_points`] (columns mirrored first, then rows, each phantom `2a - b`).
fn fold_phantoms(mut c: [f64; 16], mask: u8) -> [f64; 16] {
    let fold = |c: &mut [f64; 16], phantom: usize, a: usize, b: usize| {
        let w = std::mem::take(&mut c[phantom]);
        c[a] += 2.0 * w;
        c[b] -= w;
    };
    for i in 0..4 {
        if mask & 1 != 0 {
            fold(&mut c, i, 4 + i, 8 + i);
        }
        if mask & 4 != 0 {
            fold(&mut c, 12 + i, 8 + i, 4 + i);
        }
    }
    for r in (0..16).step_by(4) {
        if mask & 8 != 0 {
            fold(&mut c, r, r + 1, r + 2);
        }
        if mask & 2 != 0 {
            fold(&mut c, r + 3, r + 2, r + 1);
        }
    }
    c
}

/// Rows (position, d/du, d/dv) of B-spline patch `p` (global control vertices) at its face
/// corner `k` (Köbler 2013 §3.1: the basis at the domain corner), phantoms folded in.
pub fn bspline_corner_rows(p: &RegularPatch, k: usize) -> [Weights; 3] {
    bspline_corner_columns(k, p.boundary_mask)
        .map(|c| Weights::from_terms(p.cvs.iter().copied().zip(c)))
}

/// The weights of [`bspline_corner_rows`] per control point (`cvs` order) at face corner `k` of
/// a patch with phantom sides `mask` (`RegularPatch::boundary_mask`), phantoms folded in.
fn bspline_corner_columns(k: usize, mask: u8) -> [[f64; 16]; 3] {
    let (s, t) = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)][k];
    let (bu, du, bv, dv) = (bspline(s), bspline_deriv(s), bspline(t), bspline_deriv(t));
    let tensor = |a: [f64; 4], b: [f64; 4]| {
        let mut c = [0.0; 16];
        for (j, &y) in b.iter().enumerate() {
            for (i, &x) in a.iter().enumerate() {
                c[4 * j + i] = x * y;
            }
        }
        fold_phantoms(c, mask)
    };
    [tensor(bu, bv), tensor(du, bv), tensor(bu, dv)]
}

/// A corner's rows (position, d/du, d/dv) as weights per control point (`cvs` order), with
/// the control points each row weights: a template per corner shape
/// ([`CornerRows`]; a regular corner's rows are the fixed B-spline corner masks over its 3x3
/// block), which [`push_template`] writes over a corner's control vertices.
struct CornerTable {
    rows: [[f64; 16]; 3],
    /// Per row: bit `i` set where its f32 weight of control point `i` is not zero.
    live: [u16; 3],
    /// The rows' `live` together.
    any: u16,
    /// Per row: the place of its first term among the three rows' terms.
    starts: [usize; 3],
    /// Per row: the place past its last term (the next row's start, then the terms' count).
    ends: [u32; 3],
}

impl CornerTable {
    fn new(rows: [[f64; 16]; 3]) -> CornerTable {
        let live = rows.map(|row| {
            (0..16)
                .filter(|&i| row[i] as f32 != 0.0)
                .fold(0, |m, i| m | 1 << i)
        });
        CornerTable {
            rows,
            live,
            any: live[0] | live[1] | live[2],
            starts: [0, 1, 2].map(|r| live[..r].iter().map(|l| l.count_ones() as usize).sum()),
            ends: [1, 2, 3].map(|r| live[..r].iter().map(|l| l.count_ones()).sum()),
        }
    }

    /// The rows over control vertices `cvs` as [`Weights`].
    fn weights(&self, cvs: &[u32; 16]) -> [Weights; 3] {
        self.rows
            .map(|row| Weights::from_terms(cvs.iter().copied().zip(row)))
    }
}

/// Room for one corner's template rows (`push_template`: three rows of at most 16 terms, and
/// a last place, `DISCARDED`, for the terms a row does not weight), reused from corner to
/// corner: filled afresh by each, never cleared (64 terms, so a term's place is in range by
/// masking).
pub struct TemplateTerms {
    ids: [u32; 64],
    weights_f64: [f64; 64],
}

impl Default for TemplateTerms {
    fn default() -> Self {
        TemplateTerms {
            ids: [0; 64],
            weights_f64: [0.0; 64],
        }
    }
}

/// Pushes the rows of `table` over control vertices `cvs` onto `out`, each row's terms (those
/// whose f32 weight is not zero) by increasing id: [`Weights::from_terms`]' rows bit for bit
/// where the ids are distinct (the rule; where a control vertex comes twice, on small meshes,
/// its row holds two terms of that id, whose sum is the merged term). The control points some
/// row weights are sorted once for the three rows (keys `id << 4 | i`, [`sort_keys`]), the rows
/// gathered in `terms` in that order ([`scatter_keys`]) and appended with one copy per array.
/// The GPU sums a row's terms in its order, and id order is the one the exact patches' normals
/// are checked in (`tests/scheme_adaptive.rs`: another order moved the car's worst corner
/// normal from 6.7e-5 to 1.2e-4 rad of the exact limit, f32 rounding of the terms).
fn push_template(
    out: &mut SparseRows,
    cvs: &[u32; 16],
    table: &CornerTable,
    terms: &mut TemplateTerms,
) {
    let (mut keys, mut n, mut bits) = ([u64::MAX; 16], 0, table.any);
    while bits != 0 {
        let i = bits.trailing_zeros();
        keys[n] = u64::from(cvs[i as usize]) << 4 | u64::from(i);
        n += 1;
        bits &= bits - 1;
    }
    sort_keys(&mut keys, n);
    if table.live[0] == table.any {
        scatter_keys::<1>(&keys[..n], table, terms);
    } else {
        scatter_keys::<0>(&keys[..n], table, terms);
    }
    let (base, at) = (out.ids.len() as u32, table.ends[2] as usize);
    out.ids.extend_from_slice(&terms.ids[..at]);
    out.weights_f64.extend_from_slice(&terms.weights_f64[..at]);
    out.offsets.extend(table.ends.map(|e| base + e));
}

/// Writes `table`'s rows over the sorted `keys` into `terms` (each row at its place,
/// `CornerTable::starts`): in one pass over the keys, each written to every row from `FULL` on
/// at the row's next place if the row weights it, else to the discarded place (no branch per
/// term); the first `FULL` rows (none, or a first row weighting every key: an interior
/// corner's position row) take each key at its own place, with no test.
#[inline(always)]
// Indexed rows: the same loop over `zip`/`skip` iterators cost 1.4 M more on the car.
#[allow(clippy::needless_range_loop)]
fn scatter_keys<const FULL: usize>(keys: &[u64], table: &CornerTable, terms: &mut TemplateTerms) {
    let mut at = table.starts;
    for (j, &key) in keys.iter().enumerate() {
        let (i, id) = ((key & 15) as usize, (key >> 4) as u32);
        if FULL == 1 {
            terms.ids[j & 63] = id;
            terms.weights_f64[j & 63] = table.rows[0][i];
        }
        for r in FULL..3 {
            let live = table.live[r] >> i & 1 != 0;
            let to = if live { at[r] & 63 } else { DISCARDED };
            terms.ids[to] = id;
            terms.weights_f64[to] = table.rows[r][i];
            at[r] += usize::from(live);
        }
    }
}

/// The place in [`TemplateTerms`] of the terms a row does not weight (past every row's).
const DISCARDED: usize = 63;

/// Compare-exchanges `(a, b)` of array `k` in order, each leaving the smaller key at `a`.
macro_rules! compare_exchange {
    ($k:ident: $(($a:literal, $b:literal)),* $(,)?) => {
        $(
            let (x, y) = ($k[$a], $k[$b]);
            $k[$a] = x.min(y);
            $k[$b] = x.max(y);
        )*
    };
}

/// Sorts the first `n` of `keys` by increasing value, the rest `u64::MAX`: up to nine (an
/// interior B-spline corner weights its 3x3 block) with a sorting network of 25
/// compare-exchanges in 7 layers (Knuth TAOCP vol. 3 §5.3.4, the optimum for nine), no branch
/// on the keys, more with `sort_unstable`.
fn sort_keys(keys: &mut [u64; 16], n: usize) {
    if n > 9 {
        keys[..n].sort_unstable();
        return;
    }
    let mut k: [u64; 9] = std::array::from_fn(|i| keys[i]);
    compare_exchange!(k: (0, 3), (1, 7), (2, 5), (4, 8));
    compare_exchange!(k: (0, 7), (2, 4), (3, 8), (5, 6));
    compare_exchange!(k: (0, 2), (1, 3), (4, 5), (7, 8));
    compare_exchange!(k: (1, 4), (3, 6), (5, 7));
    compare_exchange!(k: (0, 1), (2, 4), (3, 5), (6, 8));
    compare_exchange!(k: (2, 3), (4, 5), (6, 7));
    compare_exchange!(k: (1, 2), (3, 4), (5, 6));
    keys[..9].copy_from_slice(&k);
}

/// A single-crease corner's shape: crease side, sharpness bits, face corner.
type CreaseKey = (CreaseSide, u32, usize);

/// Rows (position, d/du, d/dv) of the single-crease patch of `line` (global control vertices)
/// at its face corner `k`: its exact evaluation ([`SingleCreasePatch::eval`], Nießner, Loop,
/// Greiner 2012 §3) as weights, read off by linearity (one unit control point at a time).
pub fn single_crease_corner_rows(line: &CreaseLine, k: usize) -> [Weights; 3] {
    CornerTable::new(single_crease_corner_table_rows(
        line.side,
        line.sharpness,
        k,
    ))
    .weights(&line.cvs)
}

/// The weights of [`single_crease_corner_rows`] (position, d/du, d/dv rows over the 16 control
/// points, `cvs` order): they depend on the crease's side and sharpness and the corner, not on
/// the control vertices.
fn single_crease_corner_table_rows(side: CreaseSide, sharpness: f32, k: usize) -> [[f64; 16]; 3] {
    let (local, (u, v)) = local_crease_corner(side, sharpness, k);
    // Three unit control points a call, one per coordinate: the evaluation is linear and takes
    // each coordinate alone, so coordinate `c` of the result is control point `i + c`'s column.
    let mut unit = [DVec3::ZERO; 16];
    let mut rows = [[0.0; 16]; 3];
    for i in (0..16).step_by(3) {
        let group = i..(i + 3).min(16);
        for (j, axis) in group.clone().zip([DVec3::X, DVec3::Y, DVec3::Z]) {
            unit[j] = axis;
        }
        let e = local.eval(&unit, u, v);
        for (c, j) in group.enumerate() {
            unit[j] = DVec3::ZERO;
            [rows[0][j], rows[1][j], rows[2][j]] = [e.position[c], e.du[c], e.dv[c]];
        }
    }
    rows
}

/// The single-crease patch of `side` and `sharpness` over control points `0..16`, and the
/// domain point of its face corner `k`.
fn local_crease_corner(
    side: CreaseSide,
    sharpness: f32,
    k: usize,
) -> (SingleCreasePatch, (f64, f64)) {
    let local = SingleCreasePatch {
        face: 0,
        cvs: std::array::from_fn(|i| i as u32),
        side,
        sharpness,
    };
    (local, [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)][k])
}

/// Rows (position, tangent towards corner `k + 1`, tangent towards corner `k - 1`) of a Gregory
/// patch at corner `k` from its rows ([`crate::patch::gregory::stencil_table`] order: kind by
/// kind, `n` corners): `p`, `3 (e+ - p)`, `3 (e- - p)` (Loop et al. 2009 §3.2-3.3), so
/// `cross(du, dv)` is the outward normal of a counter-clockwise face.
///
/// `singular`: the corner lies alone in a crease sector, where `e- - p = -(e+ - p)` (the crease
/// curve passes through; `GregoryVertex::sectored`): the second row is then `3 (f+ - p)`, the
/// face point the construction puts in the exact tangent plane, pointing into the face.
pub fn gregory_corner_rows(rows: RowsFrom, n: usize, k: usize, singular: bool) -> [Weights; 3] {
    let p = rows.weights(k);
    let tangent = |e: Weights| {
        let mut w = Weights::zero();
        w.add_scaled(3.0, &e);
        w.add_scaled(-3.0, &p);
        w
    };
    let second = if singular { 3 * n + k } else { 2 * n + k };
    let du = tangent(rows.weights(n + k));
    let dv = tangent(rows.weights(second));
    [p, du, dv]
}

/// Pushes [`gregory_corner_rows`] onto `out` (the same rows, bit for bit) without a [`Weights`]
/// per row: the position row as it is, each tangent merged from its two rows
/// ([`push_tangent`]).
fn push_gregory_corner_rows(
    out: &mut SparseRows,
    rows: RowsFrom,
    n: usize,
    k: usize,
    singular: bool,
) {
    let p = rows.row(k);
    let second = if singular { 3 * n + k } else { 2 * n + k };
    out.push_terms(p, 0);
    push_tangent(out, rows.row(n + k), p);
    push_tangent(out, rows.row(second), p);
}

/// Pushes the row `3 (e - p)` of two ascending rows as [`gregory_corner_rows`] forms it (`3 e`,
/// then `-3 p` merged in with [`GregoryPoint::add_scaled`]): per id `3 e + -3 p` where both
/// hold it, else `3 e` or `-3 p`.
fn push_tangent(out: &mut SparseRows, e: &[(u32, f64)], p: &[(u32, f64)]) {
    let (mut i, mut j) = (0, 0);
    while i < e.len() || j < p.len() {
        let term = if j == p.len() || (i < e.len() && e[i].0 < p[j].0) {
            i += 1;
            (e[i - 1].0, 3.0 * e[i - 1].1)
        } else if i == e.len() || p[j].0 < e[i].0 {
            j += 1;
            (p[j - 1].0, -3.0 * p[j - 1].1)
        } else {
            i += 1;
            j += 1;
            (e[i - 1].0, 3.0 * e[i - 1].1 + -3.0 * p[j - 1].1)
        };
        out.push_term(term);
    }
    out.end_row();
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `LARGEST_F32_ZERO` is 2^-150 and the boundary of the f64s that round to a zero f32: it
    /// and everything smaller in magnitude round to zero, the next f64 up does not.
    #[test]
    fn largest_f32_zero_is_the_rounding_boundary() {
        assert_eq!(LARGEST_F32_ZERO, 2f64.powi(-150));
        let next_up = f64::from_bits(LARGEST_F32_ZERO.to_bits() + 1);
        for sign in [1.0, -1.0] {
            for (w, zero) in [
                (LARGEST_F32_ZERO, true),
                (LARGEST_F32_ZERO / 3.0, true),
                (0.0, true),
                (next_up, false),
                (f64::from(f32::from_bits(1)), false),
                (1e-30, false),
            ] {
                let w = sign * w;
                assert_eq!(w as f32 == 0.0, zero, "{w:e}");
                assert_eq!(w.abs() <= LARGEST_F32_ZERO, zero, "{w:e}");
            }
        }
        assert_eq!(f64::NAN.abs() <= LARGEST_F32_ZERO, f64::NAN as f32 == 0.0);
    }

    /// The template push gives `Weights::from_terms`' rows: bit for bit over distinct ids
    /// (shuffled ids, and ids multiples of 64 apart), in id order; over repeated ids the same
    /// terms unmerged, in id order, whose per-id sums are its merged weights. Each row with its
    /// own zeros (fails if a row's zero weights are taken from another row), a weight below f32's
    /// range dropped.
    #[test]
    fn template_rows_are_from_terms() {
        let ws = [0.1, 0.2, 0.3, 0.0, -0.5, 1.0 / 3.0, 0.7, 1e-60];
        for (shift, ids) in (0..16).flat_map(|s| [(s, 0), (s, 1), (s, 2)]) {
            let cvs: [u32; 16] = std::array::from_fn(|i| {
                let shuffled = ((i * 7 + shift) % 16) as u32;
                match ids {
                    0 => [7, 3, 7, 9, 3, 7, 1, 9][((i + shift) % 16) % 8],
                    1 => shuffled * 3 + 1,
                    _ => shuffled * 64 + 5,
                }
            });
            // `dead` control points (from `shift` on) with no weight in any row: 16 to 4 keys
            // sorted, over nine by `sort_unstable`, nine or fewer by the network (a B-spline
            // corner's weights leave 7 of 16 dead).
            for dead in [0, 5, 7, 12] {
                let rows: [[f64; 16]; 3] = std::array::from_fn(|r| {
                    std::array::from_fn(|i| {
                        let j = (i + shift + 5 * r) % 16;
                        let zero = (i + shift) % 16 < dead;
                        if zero {
                            [0.0, -0.0][r % 2]
                        } else {
                            ws[j % 8] * (1.0 + j as f64)
                        }
                    })
                });
                let mut got = SparseRows::new();
                push_template(
                    &mut got,
                    &cvs,
                    &CornerTable::new(rows),
                    &mut TemplateTerms::default(),
                );
                let mut want = SparseRows::new();
                for row in &rows {
                    want.push(&Weights::from_terms(cvs.iter().copied().zip(*row)), 0);
                }
                let case = format!("shift {shift}, ids {ids}, dead {dead}");
                if ids != 0 {
                    assert_eq!(got, want, "{case}");
                    continue;
                }
                assert_eq!(got.len(), 3, "{case}");
                for r in 0..3 {
                    let got_ids: Vec<u32> = got.row(r).map(|t| t.0).collect();
                    assert!(got_ids.windows(2).all(|p| p[0] <= p[1]), "{case}, row {r}");
                    for (id, w) in want.row(r) {
                        let sum: f64 = got.row(r).filter(|t| t.0 == id).map(|t| t.1).sum();
                        assert!((sum - w).abs() < 1e-14, "{case}, row {r}, id {id}");
                    }
                }
            }
        }
    }

    /// Appending whole face rows gives `push_terms`' rows row by row: rows with no term to drop,
    /// with weights that round to a zero f32 (0, -0, 1e-60) first, last, alone in their row
    /// and in a row of their own, and empty rows, after rows already there; so does appending
    /// runs of them with an id offset.
    #[test]
    fn appended_face_rows_are_pushed_rows() {
        let tiny = [0.0, -0.0, 1e-60];
        for zeros in 0..5 {
            let rows: Vec<Weights> = (0..6usize)
                .map(|r| {
                    let terms = (0..r as u32 % 4).map(|i| {
                        let w = 0.25 * (1.0 + (r * 3 + i as usize) as f64);
                        let zero = zeros > 0 && (r + i as usize) % zeros == 0;
                        (10 * r as u32 + i, if zero { tiny[r % 3] } else { w })
                    });
                    Weights(terms.collect())
                })
                .collect();
            let face = FaceRows::from_weights(&rows);
            let mut got = SparseRows::new();
            got.push_terms(&[(1, 0.5), (2, 1e-60)], 0);
            let mut want = got.clone();
            got.append_face_rows(&face);
            for r in face.rows() {
                want.push_terms(r, 0);
            }
            assert_eq!(got, want, "zeros every {zeros}");
            if zeros > 0 {
                assert!(want.ids.len() < face.terms.len() + 1, "zeros every {zeros}");
            }
            // Runs of rows (inner, first, last, empty) with an offset added to every id.
            for range in [1..4, 0..2, 4..6, 3..3] {
                let (mut got, mut want) = (got.clone(), want.clone());
                got.append_face_row_range(&face, range.clone(), 7);
                for r in range.clone() {
                    want.push_terms(face.row(r), 7);
                }
                assert_eq!(got, want, "zeros every {zeros}, rows {range:?}");
            }
        }
    }

    /// A long row pushed array by array is `push_terms`' row: rows with no term to drop, with
    /// weights that round to a zero f32 (0, -0, 1e-60, 2^-150) first, last, inside and
    /// throughout, an empty row, after rows already there.
    #[test]
    fn long_rows_are_pushed_rows() {
        let tiny = [0.0, -0.0, 1e-60, LARGEST_F32_ZERO, -1e-46];
        for len in [0usize, 1, 5, 24] {
            for zeros in 0..4 {
                let row: Vec<(u32, f64)> = (0..len)
                    .map(|i| {
                        let zero = match zeros {
                            0 => false,
                            1 => i == 0 || i + 1 == len,
                            2 => i % 3 == 1,
                            _ => true,
                        };
                        let w = if zero {
                            tiny[i % 5]
                        } else {
                            0.125 * (i as f64 + 1.0)
                        };
                        (3 * i as u32 + 2, w)
                    })
                    .collect();
                let mut got = SparseRows::new();
                got.push_terms(&[(1, 0.5), (2, 1e-60)], 0);
                let mut want = got.clone();
                got.push_long_row(&row);
                want.push_terms(&row, 0);
                assert_eq!(got, want, "{len} terms, zeros {zeros}");
                // Every tiny weight is at most 2^-150 in magnitude, so each is dropped.
                let tiny_terms = row.iter().filter(|t| tiny.contains(&t.1)).count();
                assert_eq!(
                    got.row(1).count(),
                    len - tiny_terms,
                    "{len} terms, zeros {zeros}"
                );
            }
        }
    }

    /// The nine-key network sorts every sequence of zeros and ones, so every sequence (the
    /// zero-one principle, Knuth TAOCP vol. 3 §5.3.4), and `sort_keys` sorts fewer keys with
    /// the `u64::MAX` padding left at the end.
    #[test]
    fn nine_key_network_sorts() {
        for bits in 0u32..1 << 9 {
            let mut keys = [u64::MAX; 16];
            for (i, key) in keys.iter_mut().enumerate().take(9) {
                *key = u64::from(bits >> i & 1);
            }
            sort_keys(&mut keys, 9);
            let ones = bits.count_ones() as usize;
            let want: Vec<u64> = (0..9).map(|i| u64::from(i >= 9 - ones)).collect();
            assert_eq!(keys[..9], want[..], "bits {bits:09b}");
        }
        for n in 0..=9 {
            let mut keys = [u64::MAX; 16];
            for (i, key) in keys.iter_mut().enumerate().take(n) {
                *key = ((i as u64 * 7 + 3) % 11) << 4 | i as u64;
            }
            let mut want = keys;
            want[..n].sort_unstable();
            sort_keys(&mut keys, n);
            assert_eq!(keys, want, "{n} keys");
        }
    }

    /// The single-crease corner tables, three unit control points an evaluation, are those of
    /// one unit control point an evaluation bit for bit (the evaluation is linear and takes each
    /// coordinate alone), for every side, corner and a range of sharpness.
    #[test]
    fn crease_tables_three_at_a_time_are_one_at_a_time() {
        for side in [
            CreaseSide::U0,
            CreaseSide::U1,
            CreaseSide::V0,
            CreaseSide::V1,
        ] {
            for sharpness in [0.25f32, 1.0, 1.5, 2.75, 6.0] {
                for k in 0..4 {
                    let (local, (u, v)) = local_crease_corner(side, sharpness, k);
                    let mut want = [[0u64; 16]; 3];
                    for i in 0..16 {
                        let mut unit = [DVec3::ZERO; 16];
                        unit[i] = DVec3::X;
                        let e = local.eval(&unit, u, v);
                        for (r, x) in [e.position.x, e.du.x, e.dv.x].into_iter().enumerate() {
                            want[r][i] = x.to_bits();
                        }
                    }
                    let got = single_crease_corner_table_rows(side, sharpness, k)
                        .map(|row| row.map(f64::to_bits));
                    assert_eq!(got, want, "{side:?}, sharpness {sharpness}, corner {k}");
                }
            }
        }
    }

    /// The pushed Gregory corner rows are those of `gregory_corner_rows` (the `Weights`
    /// merges) bit for bit: ids in both rows, in one only, tangents that cancel to zero (dropped
    /// by both), empty rows, both one-face-sector and ordinary second tangents.
    #[test]
    fn pushed_gregory_corner_rows_are_the_merged_rows() {
        let n = 4;
        // Row r: ids from a window that moves with r (overlapping its neighbours' partly).
        let rows: Vec<Weights> = (0..9 * n)
            .map(|r| {
                if r % 7 == 5 {
                    return Weights::default();
                }
                Weights(
                    (0..6u32)
                        .map(|i| {
                            (
                                r as u32 % 5 + 2 * i,
                                0.1 * (1.0 + ((r * 7 + i as usize) % 11) as f64),
                            )
                        })
                        .collect(),
                )
            })
            .collect();
        let mut rows = rows;
        // A tangent row equal to its position row: 3 (e - p) is zero throughout.
        rows[n + 1] = rows[1].clone();
        let face = FaceRows::from_weights(&rows);
        for k in 0..n {
            for singular in [false, true] {
                let mut got = SparseRows::new();
                push_gregory_corner_rows(&mut got, face.rows_from(0), n, k, singular);
                let mut want = SparseRows::new();
                for w in gregory_corner_rows(face.rows_from(0), n, k, singular) {
                    want.push(&w, 0);
                }
                assert_eq!(got, want, "corner {k}, singular {singular}");
                let bits = |r: &SparseRows| {
                    r.weights_f64
                        .iter()
                        .map(|w| w.to_bits())
                        .collect::<Vec<_>>()
                };
                assert_eq!(bits(&got), bits(&want));
            }
        }
        let mut cancel = SparseRows::new();
        push_gregory_corner_rows(&mut cancel, face.rows_from(0), n, 1, false);
        assert_eq!(
            cancel.offsets[1], cancel.offsets[2],
            "the cancelled tangent is empty"
        );
    }
}
