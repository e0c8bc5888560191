//! Per-vertex limit frames: one limit position and normal per patch-corner vertex, computed once
//! per surface (and per animation frame) and read by every pass (bindings 2 and 9), so corners
//! shared by patches of different schemes are bitwise equal.

use glam::DVec3;

use crate::topology::Topology;
pub use crate::topology::{is_sharp_edge, sector_count, single_normal_vertex};

/// When a corner vertex gets one shared normal (written to the frame) rather than each patch
/// keeping its own there (zero entry, the shaders' signal).
#[derive(Debug, Clone, Copy)]
pub enum NormalRule<'a> {
    /// The surface's topology is known: shared where the vertex has one sector
    /// ([`single_normal_vertex`]).
    Topology(&'a Topology),
    /// Patches given without topology: shared unless the patch has a boundary or crease side at
    /// the corner (such a corner may lie between sectors).
    PatchSides,
}

/// Limit positions and normals per control vertex. Vertices no patch has as a corner keep their
/// control position and a zero normal; no shader reads them.
#[derive(Debug, Clone, PartialEq)]
pub struct VertexFrames {
    /// Limit positions.
    pub limits: Vec<DVec3>,
    /// Unit limit normals, zero where each patch keeps its own.
    pub normals: Vec<DVec3>,
    done: Vec<bool>,
}

impl VertexFrames {
    /// Frames not yet written by any pass: control positions, zero normals.
    pub fn new(positions: &[DVec3]) -> VertexFrames {
        VertexFrames {
            limits: positions.to_vec(),
            normals: vec![DVec3::ZERO; positions.len()],
            done: vec![false; positions.len()],
        }
    }

    /// Whether a pass already wrote vertex `v` (the first pass that has a corner wins).
    pub fn is_set(&self, v: u32) -> bool {
        self.done[v as usize]
    }

    /// Writes vertex `v` unless already written: `limit`, and `normal` when `shared_normal`.
    pub fn set(&mut self, v: u32, limit: DVec3, normal: DVec3, shared_normal: bool) {
        let i = v as usize;
        if !self.done[i] {
            self.done[i] = true;
            self.limits[i] = limit;
            if shared_normal {
                self.normals[i] = normal;
            }
        }
    }
}
