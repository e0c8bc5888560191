//! The GPU records of [`super::draw::AdaptiveDrawTables`], each with its std430 words
//! (little-endian u32, f32 as bits).

use crate::patch::RegularPatch;

/// Words of a [`PatchRecord`] (144 bytes).
pub const PATCH_RECORD_WORDS: usize = 36;
/// Words of a B-spline or Gregory `PatchInfo` (32 bytes).
pub const PATCH_INFO_WORDS: usize = 8;
/// Words of a [`TransitionTriangle`] (16 bytes).
pub const TRIANGLE_WORDS: usize = 4;
/// Words of a [`CoarseEdge`] (64 bytes).
pub const COARSE_EDGE_WORDS: usize = 16;

/// Per drawn patch (census order): where it lies and how its edges meet other levels.
///
/// Patch edge `k`: for B-spline patches the B-spline edge `k` of
/// [`crate::patch::edge_grid::PATCH_EDGES`] (0: v=0, 1: u=1, 2: v=1, 3: u=0; it is face edge
/// `k`, so transition bits equal the census's face-edge bits); for end caps face edge `k`
/// (corner `k` -> `k + 1`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PatchRecord {
    /// Base face.
    pub base_face: u32,
    /// Sub-face of a non-quad base face, `u32::MAX` for none.
    pub sub_face: u32,
    /// Refinement level.
    pub level: u32,
    /// [`crate::subdiv::adaptive::PatchType`] as u32 (0 regular, 1 boundary, 2 crease, 3 end cap,
    /// 4 single-crease).
    pub kind: u32,
    /// Domain origin, u axis, v axis in the base face's (or sub-face's) `(u, v)`.
    pub domain: [[f32; 2]; 3],
    /// Bit `k`: the neighbour across patch edge `k` is one level finer (Köbler 2013 §3.4). End
    /// caps, bit `8 + k`: the fillet at corner `k` turns the normals of the edges from it
    /// ([`crate::patch::adaptive::promoted::fillet_rotation`]) rather than bending their tangent,
    /// with bit `12 + k` from the normal at the point
    /// ([`crate::patch::adaptive::promoted::turn_towards`] by
    /// [`crate::patch::adaptive::promoted::fillet_many_share`]: three or more creases meet there);
    /// bit `16 + k`: corner `k`'s vertex is an irregular crease vertex
    /// ([`crate::patch::adaptive::promoted::irregular_crease_vertex`]), whose fillet turns the
    /// shared normal of the promoted creases from it
    /// ([`crate::patch::adaptive::promoted::crease_turn_share`]); bit `20 + k`: the positional
    /// fillet reaches corner `k` whole
    /// ([`crate::patch::adaptive::promoted::positional_fillet_end`]).
    pub transition: u32,
    /// Slot of the midpoint of transition edge `k` (the next level's edge point), else `u32::MAX`.
    pub mid_slots: [u32; 4],
    /// Index into the coarse edges when patch edge `k` lies on an edge of a one-level-coarser
    /// patch, else `u32::MAX`.
    pub coarse: [u32; 4],
    /// Per patch corner (GPU corner order: (0,0), (1,0), (1,1), (0,1) of the drawn patch): the
    /// frame whose normal the corner takes in its sector (`patch::adaptive::sector_frames`), else
    /// `u32::MAX` (the slot's normal, or the patch's own).
    pub corner_frames: [u32; 4],
    /// The same for the midpoint of transition edge `k`.
    pub mid_frames: [u32; 4],
    /// End caps, per face edge `k` that is no promoted crease (draw flag bit `28 + k` off; a
    /// promoted one's sharpness is in [`PatchRecord::fillet_fine`]) between two end caps, bits
    /// `8k..8k + 4` / `8k + 4..8k + 8`: the fillet sharpness at corner `k` / `k + 1`
    /// ([`crate::patch::adaptive::promoted::fillet_end_code`], 0: none); 0 elsewhere.
    pub fillet: u32,
    /// Quad end caps, per face corner `k`: the frame holding the exact limit position there when
    /// the end caps add the corner offset (`patch::adaptive::exact_corners`), else `u32::MAX`.
    pub corner_exact: [u32; 4],
    /// Bits `8k..8k + 8`: the width code of corner `k`'s offset
    /// ([`crate::patch::adaptive::promoted::corner_offset_code`]), 0 where it has none.
    pub corner_fade: u32,
    /// Per face edge `k` that is a promoted crease between two end caps (draw flag bit `28 + k`):
    /// its residual sharpness in 24 bits, whose fillet the interior normals follow
    /// ([`crate::patch::adaptive::promoted::fillet_fine_code`], packed by
    /// [`crate::patch::adaptive::promoted::fillet_fine_words`]), which its fillet and band
    /// offset read instead of [`PatchRecord::fillet`]'s 16ths; 0 elsewhere.
    pub fillet_fine: [u32; 3],
}

impl PatchRecord {
    /// Words 0-27: base_face, sub_face, level, kind, origin xy, u xy, v xy, transition, fillet,
    /// mid_slots, coarse, corner_frames, mid_frames; 28-32: corner_exact, corner_fade; 33-35:
    /// fillet_fine.
    pub fn words(&self) -> [u32; PATCH_RECORD_WORDS] {
        let mut w = [0u32; PATCH_RECORD_WORDS];
        w[..4].copy_from_slice(&[self.base_face, self.sub_face, self.level, self.kind]);
        for (i, x) in self.domain.iter().flatten().enumerate() {
            w[4 + i] = x.to_bits();
        }
        w[10] = self.transition;
        w[11] = self.fillet;
        w[12..16].copy_from_slice(&self.mid_slots);
        w[16..20].copy_from_slice(&self.coarse);
        w[20..24].copy_from_slice(&self.corner_frames);
        w[24..28].copy_from_slice(&self.mid_frames);
        w[28..32].copy_from_slice(&self.corner_exact);
        w[32] = self.corner_fade;
        w[33..36].copy_from_slice(&self.fillet_fine);
        w
    }
}

/// A B-spline patch as drawn (`PatchInfo` of `glsl/common/frame.glsl`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BSplineDraw {
    /// Index of its [`PatchRecord`].
    pub record: u32,
    /// Base face.
    pub base_face: u32,
    /// Control vertices (global ids) and phantom mask.
    pub patch: RegularPatch,
    /// Boundary mask bits 0-3, bit `4 + e` when B-spline edge `e` runs from the larger slot to
    /// the smaller.
    pub flags: u32,
    /// Corner slots, corners (0,0), (1,0), (1,1), (0,1).
    pub corners: [u32; 4],
}

impl BSplineDraw {
    /// `face, flags, pad0 = record, pad1 = 0, corners`.
    pub fn words(&self) -> [u32; PATCH_INFO_WORDS] {
        info_words([self.base_face, self.flags, self.record, 0], self.corners)
    }
}

/// One triangle of a transition patch's fan around the domain centre: (centre, start, end) of
/// B-spline edge `edge`, or of its half.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TransitionTriangle {
    /// Index into the transition patches.
    pub patch: u32,
    /// B-spline edge.
    pub edge: u32,
    /// 0 whole edge, 1 the half from the edge's start corner, 2 the half to its end corner.
    pub half: u32,
}

impl TransitionTriangle {
    /// `patch, edge, half, 0`.
    pub fn words(&self) -> [u32; TRIANGLE_WORDS] {
        [self.patch, self.edge, self.half, 0]
    }
}

/// An end cap as drawn (`GregoryPatchInfo` plus its grid ids).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EndCapDraw {
    /// Index of its [`PatchRecord`].
    pub record: u32,
    /// Base face.
    pub base_face: u32,
    /// `GregoryLayout` flags, canonical orders by slot
    /// ([`crate::patch::gregory::edge_flags::EdgeFlags::flags`]), and bit `28 + k`: edge `k` is
    /// a promoted crease between two end caps ([`PatchRecord::fillet`]).
    pub flags: u32,
    /// First of its 36 rows.
    pub first_row: u32,
    /// Corner slots (w repeats corner 0 for triangles).
    pub corners: [u32; 4],
    /// Grid ids of edges shared with a same-level B-spline patch (global ids, canonical by slot).
    pub grid: [u32; 48],
}

impl EndCapDraw {
    /// `face, flags, pad0 = record, pad1 = first row, corners`.
    pub fn words(&self) -> [u32; PATCH_INFO_WORDS] {
        info_words(
            [self.base_face, self.flags, self.record, self.first_row],
            self.corners,
        )
    }
}

/// The edge of a coarse B-spline or single-crease patch with a one-level-finer neighbour: what both sides
/// evaluate the shared curve from (thesis §3.4, transition patches).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CoarseEdge {
    /// Rows left / on / right of the direction from the smaller slot, each from the smaller-slot
    /// end (global ids; see [`crate::patch::edge_grid::EdgeGrid`]).
    pub rows: [u32; 12],
    /// Slot of the end with the smaller slot.
    pub lo_slot: u32,
    /// Slot of the other end.
    pub hi_slot: u32,
    /// Slot of the midpoint (the finer level's edge point).
    pub mid_slot: u32,
    /// Bit 0: boundary or infinitely sharp edge; bit 1 / 2: the first / last point along is a
    /// phantom mirrored `2 x1 - x2`; bits 3-5 and 8-31 the single-crease curve of a
    /// single-crease coarse patch and its record (`CREASE_EDGE`, `ACROSS_CREASE`,
    /// `CREASE_AT_LO` of `coarse.rs`; 0: the B-spline grid curve).
    pub flags: u32,
}

impl CoarseEdge {
    /// `rows[12], lo_slot, hi_slot, mid_slot, flags`.
    pub fn words(&self) -> [u32; COARSE_EDGE_WORDS] {
        let mut w = [0u32; COARSE_EDGE_WORDS];
        w[..12].copy_from_slice(&self.rows);
        w[12..].copy_from_slice(&[self.lo_slot, self.hi_slot, self.mid_slot, self.flags]);
        w
    }
}

/// A `PatchInfo` record: four header words (face, flags, pad0, pad1), then the corners.
fn info_words(head: [u32; 4], corners: [u32; 4]) -> [u32; PATCH_INFO_WORDS] {
    let mut w = [0u32; PATCH_INFO_WORDS];
    w[..4].copy_from_slice(&head);
    w[4..].copy_from_slice(&corners);
    w
}

/// Little-endian bytes of records' words.
pub fn words_bytes<const N: usize>(words: impl Iterator<Item = [u32; N]>) -> Vec<u8> {
    words.flatten().flat_map(u32::to_le_bytes).collect()
}
