//! The shared end-cap rows of a connectivity type ([`super`]'s module docs) laid out once per
//! order of a face's ring ids: where each term lands in a face's rows (rows ascending in ids)
//! depends only on the type and on the order of the ids of the slots that share a row, which
//! repeats between faces of a type ([`Layouts`]). A face's rows are then its layout with each
//! column written as the face's id, in one pass over the terms into their final place
//! ([`Layouts::rows_into`]).

use crate::patch::gregory::face_rows::{FaceRows, Terms, TERM_PLACEHOLDER};
use crate::patch::gregory::stencil_table::{vertex_point_of, VERTEX_POINTS};
use crate::patch::gregory::vertex::edge_sin_cos;
use crate::patch::gregory::word_hash::WordHashMap;
use crate::topology::Topology;

const NONE: u32 = u32::MAX;

/// One type's rows over its columns (ring slot `s` at column `s`, derived point `b` of slot
/// `s` at `ring_len + 3 s + b`) in the direct construction's values, stored column by column,
/// so that the terms of a face's rows come out ascending in its ids by walking its columns in
/// id order once ([`Layouts::layout`]) rather than sorting every row.
pub(super) struct LocalRows {
    /// `rows + 1` term offsets: every face of the type has these (of the terms kept).
    offsets: Vec<u32>,
    /// `columns + 1` offsets into `columns`.
    starts: Vec<u32>,
    /// Column `c`'s terms `(row, weight)`, rows ascending: `columns[starts[c]..starts[c + 1]]`.
    columns: Vec<(u32, f64)>,
    /// The derived-point columns the rows read (kept terms or not), ascending.
    derived: Vec<u32>,
}

/// What [`LocalRows::turned`] does to the derived points of the vertex at ring slot `slot`.
#[derive(Clone, Copy, Debug)]
pub(super) enum Turn {
    /// A smooth vertex's ring starts `steps` of its `valence` faces on: its cosine and sine
    /// sums (derived points 1, 2) turn by the angle `2 pi steps / valence`, of this cosine and
    /// sine.
    Rotate {
        slot: u32,
        cos: f64,
        sin: f64,
        steps: u32,
        valence: u32,
    },
    /// A crease's sectors come in the other order: its sector tangents (derived points 0, 1)
    /// swap.
    Swap { slot: u32 },
}

impl Turn {
    /// The slot turned.
    fn slot(self) -> u32 {
        match self {
            Turn::Rotate { slot, .. } | Turn::Swap { slot } => slot,
        }
    }
}

impl LocalRows {
    /// The rows of a face of the same connectivity but for where the rings of some vertices
    /// start, over the same slots, at each slot of `turns` its derived points' weights
    /// changed ([`Turn`]). Smooth: `e_j = p + cos(2 pi j / n) q_c + sin(2 pi j / n) q_s`
    /// (`InteriorBasis`), so a ring read `d` faces later has `q_c' = cos a q_c + sin a q_s`,
    /// `q_s' = -sin a q_c + cos a q_s` (`a = 2 pi d / n`) and a weight pair `(c, s)` on
    /// `(q_c, q_s)` is one on `(q_c', q_s')` as `(cos a c - sin a s, sin a c + cos a s)`:
    /// equal to the face's own construction to rounding (not bitwise; a rounding residue
    /// made zero, `residue_zeroed`), but for an edge point's pair (the construction's
    /// `(cos, sin)(2 pi j / n)` bitwise, `edge_sin_cos`), written as the construction writes
    /// edge point `j + d` ([`turned_pair`]): the boundary curves two end caps share read the
    /// same bits from both. Terms `kept` drops dropped after the turn,
    /// and a turned pair read whole where either is read. Crease:
    /// the two sector tangents' columns swapped.
    pub(super) fn turned(&self, turns: &[Turn], kept: Terms, angles: &EdgeAngles) -> LocalRows {
        let points = VERTEX_POINTS as usize;
        let slots = self.starts.len() - 1;
        let l = slots / (1 + points);
        let column = |c: usize| &self.columns[self.starts[c] as usize..self.starts[c + 1] as usize];
        // The turn of a derived column and which derived point of its slot it is.
        let turn_of = |c: usize| match c < l {
            true => None,
            false => (turns.iter())
                .find(|t| t.slot() as usize == (c - l) / points)
                .map(|&t| (t, (c - l) % points)),
        };
        // Each column's terms in place (rows ascending), a turned pair's merged by row (the
        // second's kept aside until its column).
        let rows = self.offsets.len() - 1;
        let mut columns = Vec::with_capacity(self.columns.len() + 2 * rows * turns.len());
        let mut starts = Vec::with_capacity(slots + 1);
        // Per row: its terms (those of a turned pair counted anew).
        let mut per_row: Vec<u32> = (0..=rows)
            .map(|r| match r {
                0 => 0,
                r => self.offsets[r] - self.offsets[r - 1],
            })
            .collect();
        starts.push(0);
        let mut pair = Vec::new();
        for c in 0..slots {
            match turn_of(c) {
                Some((
                    Turn::Rotate {
                        cos,
                        sin,
                        steps,
                        valence,
                        ..
                    },
                    1,
                )) => {
                    pair.clear();
                    for &(r, _) in column(c).iter().chain(column(c + 1)) {
                        per_row[r as usize + 1] -= 1;
                    }
                    let (mut a, mut b) =
                        (column(c).iter().peekable(), column(c + 1).iter().peekable());
                    loop {
                        let r = match (a.peek(), b.peek()) {
                            (None, None) => break,
                            (Some(x), None) => x.0,
                            (None, Some(y)) => y.0,
                            (Some(x), Some(y)) => x.0.min(y.0),
                        };
                        let wc = a.next_if(|x| x.0 == r).map_or(0.0, |x| x.1);
                        let ws = b.next_if(|y| y.0 == r).map_or(0.0, |y| y.1);
                        let edges = angles.of(valence as usize);
                        let (x, y) = turned_pair([wc, ws], [cos, sin], steps, edges);
                        if kept.keeps(x) {
                            columns.push((r, x));
                            per_row[r as usize + 1] += 1;
                        }
                        if kept.keeps(y) {
                            pair.push((r, y));
                            per_row[r as usize + 1] += 1;
                        }
                    }
                }
                Some((Turn::Rotate { .. }, 2)) => columns.extend_from_slice(&pair),
                Some((Turn::Swap { .. }, 0)) => columns.extend_from_slice(column(c + 1)),
                Some((Turn::Swap { .. }, 1)) => columns.extend_from_slice(column(c - 1)),
                _ => columns.extend_from_slice(column(c)),
            }
            starts.push(columns.len() as u32);
        }
        for r in 0..rows {
            per_row[r + 1] += per_row[r];
        }
        let mut derived: Vec<u32> = (self.derived.iter())
            .flat_map(|&c| {
                let c = c as usize;
                let (own, other) = match turn_of(c) {
                    Some((Turn::Rotate { .. }, 1)) => (Some(c), Some(c + 1)),
                    Some((Turn::Rotate { .. }, 2)) => (Some(c), Some(c - 1)),
                    Some((Turn::Swap { .. }, 0)) => (None, Some(c + 1)),
                    Some((Turn::Swap { .. }, 1)) => (None, Some(c - 1)),
                    _ => (Some(c), None),
                };
                own.into_iter().chain(other).map(|c| c as u32)
            })
            .collect();
        derived.sort_unstable();
        derived.dedup();
        LocalRows {
            offsets: per_row,
            starts,
            columns,
            derived,
        }
    }
}

/// The weight pair `[c, s]` on a smooth vertex's `(q_c, q_s)` turned by `steps` of its
/// faces (`[cos, sin]` of that angle, [`LocalRows::turned`]; `edges` its valence's
/// [`EdgeAngles`]): where the pair is an edge point's, `edges[j]` bitwise (the
/// construction's `edge_sin_cos(j, n)`), edge point `j + steps`'s as the
/// construction writes it (bitwise its rows: the end caps' boundary curves, `p`, `e_plus`,
/// `e_minus` and the neighbours' edge points, are the same bits in both patches at an edge);
/// otherwise the pair rotated, its rounding residues zeroed.
fn turned_pair(
    [c, s]: [f64; 2],
    [cos, sin]: [f64; 2],
    steps: u32,
    edges: &[(f64, f64)],
) -> (f64, f64) {
    if let Some(j) = edges.iter().position(|&e| e == (s, c)) {
        let (s, c) = edges[(j + steps as usize) % edges.len()];
        return (c, s);
    }
    let size = c.abs() + s.abs();
    (
        residue_zeroed(cos * c - sin * s, size),
        residue_zeroed(sin * c + cos * s, size),
    )
}

/// The edge points' weight pairs of smooth vertices up to a valence, `edge_sin_cos(j, n)`
/// for `j < n`, computed once per call rather than per turned pair.
pub(super) struct EdgeAngles(Vec<(f64, f64)>);

impl EdgeAngles {
    /// The pairs of every valence up to `max`.
    pub(super) fn new(max: usize) -> EdgeAngles {
        let pairs = (1..=max).flat_map(|n| (0..n).map(move |j| edge_sin_cos(j, n)));
        EdgeAngles(pairs.collect())
    }

    /// Valence `n`'s pairs (`j` at `j`).
    fn of(&self, n: usize) -> &[(f64, f64)] {
        let first = n * (n - 1) / 2;
        &self.0[first..first + n]
    }
}

/// `x`, or zero where it is rounding residue (within a few ulps of `size`, the turned pair's
/// weights' size): a turned weight whose construction's value is an exact zero (a cosine or
/// sine sum's weight `sin(2 pi j / n)` at `j = 0`, say) comes out of [`LocalRows::turned`] as
/// zero, so [`Terms::Nonzero`] drops it as it drops the construction's (a tiny term would
/// move a corner's tangent rows' bits, [`Terms`]).
fn residue_zeroed(x: f64, size: f64) -> f64 {
    match x.abs() <= 8.0 * f64::EPSILON * size {
        true => 0.0,
        false => x,
    }
}

/// `rows` over columns with the terms `kept` keeps, or `None` when a weight (kept or not) lies
/// outside the ring: vertex `v` at its slot, derived point `b` of `v`
/// ([`super::vertex_point_id`]) at `ring_len + 3 slot(v) + b`. The derived points read are
/// those of every term, so a face reads the same vertex points whichever terms it keeps.
pub(super) fn to_slots(
    topo: &Topology,
    rows: &FaceRows,
    slot: &[u32],
    ring_len: usize,
    kept: Terms,
) -> Option<LocalRows> {
    let slot_of = |id: u32| match vertex_point_of(topo, id) {
        None => Some(slot[id as usize]).filter(|&s| s != NONE),
        Some((v, b)) => match slot[v as usize] {
            NONE => None,
            s => Some(ring_len as u32 + VERTEX_POINTS * s + b),
        },
    };
    let slots = (1 + VERTEX_POINTS as usize) * ring_len;
    // Each kept term's column, row and weight, then a counting sort of them by column (rows
    // stay ascending).
    let mut offsets = Vec::with_capacity(rows.offsets.len());
    offsets.push(0);
    let mut at: Vec<(u32, u32, f64)> = Vec::with_capacity(rows.terms.len());
    let mut starts = vec![0u32; slots + 1];
    let mut read = vec![false; slots];
    for (r, row) in rows.rows().enumerate() {
        for &(v, x) in row {
            let s = slot_of(v)?;
            read[s as usize] = true;
            if kept.keeps(x) {
                at.push((s, r as u32, x));
                starts[s as usize + 1] += 1;
            }
        }
        offsets.push(at.len() as u32);
    }
    for s in 0..slots {
        starts[s + 1] += starts[s];
    }
    let derived = (ring_len..slots)
        .filter(|&c| read[c])
        .map(|c| c as u32)
        .collect();
    let mut next = starts.clone();
    let mut columns = vec![TERM_PLACEHOLDER; at.len()];
    for &(s, r, x) in &at {
        columns[next[s as usize] as usize] = (r, x);
        next[s as usize] += 1;
    }
    Some(LocalRows {
        offsets,
        starts,
        columns,
        derived,
    })
}

/// The types' rows and their layouts, each layout made on first use and keyed by the order of
/// the ids of the slot pairs that decide it ([`order_pairs`]): a face's ring order decides more
/// than its rows read (on the car at isolation 2, 1,223 shared faces per build take 281
/// layouts where their whole rings' orders would make 542).
pub(super) struct Layouts {
    types: Vec<LocalRows>,
    /// Per type: how its layouts are keyed.
    keying: Vec<Keying>,
    /// Per layout: its type and its terms `(column, weight)` in the place they take in a face's
    /// rows.
    layouts: Vec<(u32, Vec<(u32, f64)>)>,
    /// A type and its key ([`Keying`]), to the layout.
    index: WordHashMap<Vec<u64>, u32>,
    /// [`Self::layout`]'s key buffer.
    key: Vec<u64>,
    /// [`Self::layout`]'s `(id, slot)` buffer.
    sorted: Vec<u64>,
    /// [`Self::layout`]'s slots in id order.
    order: Vec<u32>,
}

/// How the layouts of a type are keyed.
#[derive(Clone)]
enum Keying {
    /// No layout made yet.
    Unknown,
    /// A bit per pair of [`order_pairs`], set where its first slot's id is the lower.
    Pairs(Vec<(u32, u32)>),
    /// The ring's slots in id order (a ring of more than 64 slots).
    Whole,
}

impl Layouts {
    /// No layout made yet.
    pub fn new(types: Vec<LocalRows>) -> Self {
        Layouts {
            keying: vec![Keying::Unknown; types.len()],
            types,
            layouts: Vec::new(),
            index: WordHashMap::default(),
            key: Vec::new(),
            sorted: Vec::new(),
            order: Vec::new(),
        }
    }

    /// The layout of type `t`'s rows for a face with ring `ring` (the id of each slot).
    pub fn layout(&mut self, t: u32, ring: &[u32]) -> u32 {
        if let Keying::Pairs(pairs) = &self.keying[t as usize] {
            order_key(t, pairs, ring, &mut self.key);
            if let Some(&at) = self.index.get(self.key.as_slice()) {
                return at;
            }
        }
        // The slots in ascending order of their ids, sorted as one word each.
        self.sorted.clear();
        let slots = ring.iter().enumerate();
        self.sorted
            .extend(slots.map(|(s, &u)| u64::from(u) << 32 | s as u64));
        self.sorted.sort_unstable();
        self.order.clear();
        self.order.extend(self.sorted.iter().map(|&w| w as u32));
        let whole = |key: &mut Vec<u64>, order: &[u32]| {
            key.clear();
            key.push(u64::from(t));
            key.extend(order.iter().map(|&s| u64::from(s)));
        };
        if let Keying::Whole = self.keying[t as usize] {
            whole(&mut self.key, &self.order);
            if let Some(&at) = self.index.get(self.key.as_slice()) {
                return at;
            }
        }
        let rows = &self.types[t as usize];
        let terms = scatter(rows, &self.order);
        if let Keying::Unknown = self.keying[t as usize] {
            let keying = match order_pairs(&terms, &rows.offsets, ring.len()) {
                Some(pairs) => {
                    order_key(t, &pairs, ring, &mut self.key);
                    Keying::Pairs(pairs)
                }
                None => {
                    whole(&mut self.key, &self.order);
                    Keying::Whole
                }
            };
            self.keying[t as usize] = keying;
        }
        let at = self.layouts.len() as u32;
        self.layouts.push((t, terms));
        self.index.insert(self.key.clone(), at);
        at
    }

    /// Number of terms of layout `at`'s rows.
    pub fn term_count(&self, at: u32) -> usize {
        self.layouts[at as usize].1.len()
    }

    /// Calls `mark(s, b)` for each derived point `b` of ring slot `s` layout `at`'s rows read.
    pub fn derived_read(&self, at: u32, mut mark: impl FnMut(usize, u32)) {
        let t = &self.types[self.layouts[at as usize].0 as usize];
        let l = (t.starts.len() - 1) / (1 + VERTEX_POINTS as usize);
        for &c in &t.derived {
            let d = c - l as u32;
            mark((d / VERTEX_POINTS) as usize, d % VERTEX_POINTS);
        }
    }

    /// Appends to `out` the rows of layout `at` for the face with ring `ring`: slot `s` written
    /// as `vertex(ring[s])`, its derived point `b` as `derived(ring[s], b)` (both monotone,
    /// every derived id past every vertex id, as the layout assumes).
    pub fn rows_into(
        &self,
        at: u32,
        ring: &[u32],
        vertex: &(impl Fn(u32) -> u32 + ?Sized),
        derived: &(impl Fn(u32, u32) -> u32 + ?Sized),
        out: &mut FaceRows,
    ) {
        let (t, terms) = &self.layouts[at as usize];
        let t = &self.types[*t as usize];
        let l = ring.len();
        IDS.with(|ids| {
            let ids = &mut *ids.borrow_mut();
            ids.clear();
            ids.extend(ring.iter().map(|&u| vertex(u)));
            ids.resize(t.starts.len() - 1, NONE);
            for &c in &t.derived {
                let d = c - l as u32;
                let s = (d / VERTEX_POINTS) as usize;
                ids[c as usize] = derived(ring[s], d % VERTEX_POINTS);
            }
            out.relabelled_into(&t.offsets, terms, Terms::All, |c| ids[c as usize]);
        });
    }
}

/// The terms of `rows` as `(column, weight)` in the place they take in the rows of a face
/// whose ring slots ascend in id in the order `order`: its columns walked in id order (the
/// slots in `order`, then their derived points in that order), each column's terms appended
/// to their rows.
fn scatter(rows: &LocalRows, order: &[u32]) -> Vec<(u32, f64)> {
    let l = order.len();
    let mut next = rows.offsets.clone();
    let mut terms = vec![TERM_PLACEHOLDER; rows.columns.len()];
    let mut put = |c: usize| {
        let column = &rows.columns[rows.starts[c] as usize..rows.starts[c + 1] as usize];
        for &(r, x) in column {
            terms[next[r as usize] as usize] = (c as u32, x);
            next[r as usize] += 1;
        }
    };
    for &s in order {
        put(s as usize);
    }
    for &s in order {
        for b in 0..VERTEX_POINTS {
            put(l + (VERTEX_POINTS * s + b) as usize);
        }
    }
    terms
}

/// The slot pairs `(a, b)`, `a < b`, whose ids' order decides where the terms of a type's rows
/// go in a face's rows (`terms` and `offsets`: one of its layouts, over a ring of `ring_len`
/// slots): in a row the vertex columns come first, then the derived points, each in the order
/// of their slots' ids (a slot's derived points by their index), so the row's order is that of
/// its vertex columns' slots and that of its derived columns' slots: every pair of distinct
/// slots with columns of one kind in one row, each once, in ascending `(a, b)`. `None` for a
/// ring of more than 64 slots (its layouts keyed by the whole ring's order).
fn order_pairs(terms: &[(u32, f64)], offsets: &[u32], ring_len: usize) -> Option<Vec<(u32, u32)>> {
    if ring_len > 64 {
        return None;
    }
    let l = ring_len as u32;
    // Per slot: the slots it shares a row with in columns of one kind.
    let mut with = [0u64; 64];
    let mut join = |set: u64| {
        // A set of one slot pairs none.
        let mut rest = match set & set.wrapping_sub(1) {
            0 => 0,
            _ => set,
        };
        while rest != 0 {
            with[rest.trailing_zeros() as usize] |= set;
            rest &= rest - 1;
        }
    };
    for row in offsets.windows(2) {
        // The row's vertex columns' slots and derived columns' slots.
        let (mut vertices, mut derived) = (0u64, 0u64);
        for &(c, _) in &terms[row[0] as usize..row[1] as usize] {
            match c.checked_sub(l) {
                None => vertices |= 1 << c,
                Some(d) => derived |= 1 << (d / VERTEX_POINTS),
            }
        }
        join(vertices);
        join(derived);
    }
    let mut pairs = Vec::new();
    for (a, &set) in with.iter().enumerate().take(ring_len) {
        // The slots after `a`.
        let mut rest = set & !(u64::MAX >> (63 - a));
        while rest != 0 {
            pairs.push((a as u32, rest.trailing_zeros()));
            rest &= rest - 1;
        }
    }
    Some(pairs)
}

/// The key of the layout of type `t` for a face with ring `ring` in `key`: `t`, then a bit
/// per pair of `pairs` ([`order_pairs`]), set where its first slot's id is the lower.
fn order_key(t: u32, pairs: &[(u32, u32)], ring: &[u32], key: &mut Vec<u64>) {
    key.clear();
    key.push(u64::from(t));
    for chunk in pairs.chunks(64) {
        let lower = |(j, &(a, b)): (usize, &(u32, u32))| {
            u64::from(ring[a as usize] < ring[b as usize]) << j
        };
        key.push(chunk.iter().enumerate().map(lower).fold(0, |w, b| w | b));
    }
}

thread_local! {
    /// [`Layouts::rows_into`]'s ids per column (it keeps its capacity).
    static IDS: std::cell::RefCell<Vec<u32>> = const { std::cell::RefCell::new(Vec::new()) };
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The pairs of a hand-made layout over a ring of 4 slots (derived point `b` of slot `s` at
    /// column `4 + 3 s + b`): those of distinct slots with columns of one kind in one row, each
    /// once; none for a slot alone in its kind (fails if kinds mix, a slot pairs itself, or a
    /// pair comes twice).
    #[test]
    fn order_pairs_are_a_rows_slots_of_one_kind() {
        let terms = [
            // Row 0: vertices 0, 2; derived points of slots 1 and 3.
            (0, 1.0),
            (2, 1.0),
            (7, 1.0),
            (15, 1.0),
            // Row 1: vertex 1; slot 1's derived points 0 and 1.
            (1, 1.0),
            (7, 1.0),
            (8, 1.0),
            // Row 2: vertices 2, 0 again and 3; slot 0's derived point.
            (0, 1.0),
            (2, 1.0),
            (3, 1.0),
            (4, 1.0),
        ];
        let pairs = order_pairs(&terms, &[0, 4, 7, 11], 4);
        assert_eq!(pairs, Some(vec![(0, 2), (0, 3), (1, 3), (2, 3)]));
        assert_eq!(order_pairs(&terms, &[0, 4, 7, 11], 65), None);
    }
}
