//! Per-vertex limit frames: one limit position and normal per patch-corner vertex, computed once
//! per surface (and per animation frame) and read by every pass (bindings 2 and 9), so corners
//! shared by patches of different schemes are bitwise equal. Where infinitely sharp edges split
//! a vertex's faces into sectors, each sector a pass wrote has its own normal, found by face
//! ([`VertexFrames::normal_bytes`], `shared_corner` in `glsl/common/watertight.glsl`).

use std::collections::BTreeMap;

use glam::DVec3;

pub use crate::topology::{is_sharp_edge, sector_count, single_normal_vertex};
use crate::topology::{sector_faces, Topology};

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
    /// At vertices of several sectors: the unit normal of each face whose sector a pass wrote
    /// ([`Self::set_sector`]), by vertex, then face.
    pub sector_normals: BTreeMap<u32, BTreeMap<u32, DVec3>>,
    done: Vec<bool>,
}

impl VertexFrames {
    /// Frames not yet written by any pass: control positions, zero normals.
    pub fn new(positions: &[DVec3]) -> VertexFrames {
        VertexFrames {
            limits: positions.to_vec(),
            normals: vec![DVec3::ZERO; positions.len()],
            sector_normals: BTreeMap::new(),
            done: vec![false; positions.len()],
        }
    }

    /// The faces of the sector of `face` at `v`, when that corner takes its sector's normal
    /// ([`Self::set_sector`]) and no pass wrote it yet: infinitely sharp edges split `v` into two
    /// sectors or more (elsewhere one normal is shared, or at a cone every face has its own) and
    /// the sector has two faces or more (one face keeps its own).
    pub fn pending_sector(&self, topo: &Topology, v: u32, face: u32) -> Option<Vec<u32>> {
        let written = self
            .sector_normals
            .get(&v)
            .is_some_and(|m| m.contains_key(&face));
        if sector_count(topo, v) < 2 || written {
            return None;
        }
        Some(sector_faces(topo, v, face)).filter(|sector| sector.len() >= 2)
    }

    /// Gives every face of `sector` (from [`Self::pending_sector`]) at `v` the unit normal
    /// `normal`; the first pass that has a corner there writes it, as for [`Self::set`].
    pub fn set_sector(&mut self, v: u32, sector: &[u32], normal: DVec3) {
        let by_face = self.sector_normals.entry(v).or_default();
        for &f in sector {
            by_face.insert(f, normal);
        }
    }

    /// The normal buffer (binding 9): per vertex `vec4(normal, 0)`, except that a vertex with
    /// sector normals has a zero normal and the bits of `w` index its list after the vertices:
    /// a header whose `w` bits are the count, then `vec4(normal, face bits)` per face.
    pub fn normal_bytes(&self) -> Vec<u8> {
        let lists: usize = self.sector_normals.values().map(|m| m.len() + 1).sum();
        let mut words: Vec<[u32; 4]> = Vec::with_capacity(self.normals.len() + lists);
        let xyz = |n: DVec3| n.as_vec3().to_array().map(f32::to_bits);
        words.extend(self.normals.iter().map(|&n| {
            let [x, y, z] = xyz(n);
            [x, y, z, 0]
        }));
        for (&v, by_face) in &self.sector_normals {
            words[v as usize] = [0, 0, 0, words.len() as u32];
            words.push([0, 0, 0, by_face.len() as u32]);
            words.extend(by_face.iter().map(|(&f, &n)| {
                let [x, y, z] = xyz(n);
                [x, y, z, f]
            }));
        }
        words
            .iter()
            .flatten()
            .flat_map(|w| w.to_le_bytes())
            .collect()
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
