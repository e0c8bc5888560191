//! The shared end-cap rows of a connectivity type ([`super`]'s module docs) laid out once per
//! order of a face's ring ids: where each term lands in a face's rows (rows ascending in ids)
//! depends only on the type and on the order of the ring's ids, which repeats between faces
//! of a type (on the car at isolation 2, 1,066 shared faces take 232 layouts). A face's rows
//! are then its layout with each column written as the face's id, in one pass over the terms
//! into their final place ([`Layouts::rows`]).

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

/// The types' rows and their layouts, each layout made on first use.
pub(super) struct Layouts {
    types: Vec<LocalRows>,
    /// Per layout: its type and its terms `(column, weight)` in the place they take in a face's
    /// rows.
    layouts: Vec<(u32, Vec<(u32, f64)>)>,
    /// A type and its ring's slots in ascending id order, to the layout.
    index: WordHashMap<Vec<u32>, u32>,
    /// [`Self::layout`]'s key buffer.
    key: Vec<u32>,
    /// [`Self::layout`]'s `(id, slot)` buffer.
    sorted: Vec<u64>,
}

impl Layouts {
    /// No layout made yet.
    pub fn new(types: Vec<LocalRows>) -> Self {
        Layouts {
            types,
            layouts: Vec::new(),
            index: WordHashMap::default(),
            key: Vec::new(),
            sorted: Vec::new(),
        }
    }

    /// The layout of type `t`'s rows for a face with ring `ring` (the id of each slot).
    pub fn layout(&mut self, t: u32, ring: &[u32]) -> u32 {
        // The slots in ascending order of their ids, sorted as one word each.
        self.sorted.clear();
        let slots = ring.iter().enumerate();
        self.sorted
            .extend(slots.map(|(s, &u)| u64::from(u) << 32 | s as u64));
        self.sorted.sort_unstable();
        self.key.clear();
        self.key.push(t);
        self.key.extend(self.sorted.iter().map(|&w| w as u32));
        if let Some(&at) = self.index.get(self.key.as_slice()) {
            return at;
        }
        let at = self.layouts.len() as u32;
        let terms = scatter(&self.types[t as usize], &self.key[1..]);
        self.layouts.push((t, terms));
        self.index.insert(self.key.clone(), at);
        at
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

    /// The rows of layout `at` for the face with ring `ring`: slot `s` written as
    /// `vertex(ring[s])`, its derived point `b` as `derived(ring[s], b)` (both monotone, every
    /// derived id past every vertex id, as the layout assumes).
    pub fn rows(
        &self,
        at: u32,
        ring: &[u32],
        vertex: &(impl Fn(u32) -> u32 + ?Sized),
        derived: &(impl Fn(u32, u32) -> u32 + ?Sized),
    ) -> FaceRows {
        let (t, terms) = &self.layouts[at as usize];
        let t = &self.types[*t as usize];
        let l = ring.len();
        let terms = IDS.with(|ids| {
            let ids = &mut *ids.borrow_mut();
            ids.clear();
            ids.extend(ring.iter().map(|&u| vertex(u)));
            ids.resize(t.starts.len() - 1, NONE);
            for &c in &t.derived {
                let d = c - l as u32;
                let s = (d / VERTEX_POINTS) as usize;
                ids[c as usize] = derived(ring[s], d % VERTEX_POINTS);
            }
            terms.iter().map(|&(c, x)| (ids[c as usize], x)).collect()
        });
        FaceRows {
            offsets: t.offsets.clone(),
            terms,
        }
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

thread_local! {
    /// [`Layouts::rows`]'s ids per column (it keeps its capacity).
    static IDS: std::cell::RefCell<Vec<u32>> = const { std::cell::RefCell::new(Vec::new()) };
}
