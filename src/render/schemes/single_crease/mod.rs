//! Single-crease patches on the GPU (Nießner, Loop, Greiner 2012): a regular quad whose only
//! feature is one semi-sharp crease line ([`SingleCreasePatch`], CPU construction and
//! eligibility) is drawn directly instead of on the CPU path. The TCS reads the patch's
//! sharpness and builds the two or three Bézier control sets of its pieces across the crease
//! (§4; fractional sharpness §3.1), the TES picks the set by the parameter across the crease
//! (`glsl/single_crease/`).
//!
//! GPU data: the 16 control-vertex ids per patch in the index buffer, rotated so that the crease
//! runs along `u = 1` ([`gpu_cvs`]; [`Rotation`] maps back to the face's `(u, v)` for capture);
//! set 0 binding 1 the `PatchInfo` records (B-spline layout, flags bits 8-9 the rotation),
//! binding 4 one `f32` sharpness per patch, rewritten by [`SingleCreaseTables::with_sharpness`]
//! through [`crate::render::SurfaceRenderer::set_sharpness`] without rebuilding the tables.
//!
//! Watertightness (module docs of [`crate::render`]): corners read the shared vertex frames
//! (crease vertices written here from the exact [`SingleCreasePatch::eval`]); the edge away from
//! the crease is the B-spline grid curve of the unmodified points (what a B-spline or Gregory
//! neighbour evaluates); the crease edge and the two edges across the crease are evaluated from
//! the 12 grid points and the sharpness in the canonical direction, alike on the single-crease
//! patches on both sides (which have the same sharpness: the line edges at the shared end
//! vertices are theirs too).

use std::any::Any;
use std::collections::{HashMap, HashSet};
use std::sync::Arc;

use ash::vk;
use glam::DVec3;

use super::bspline::{gpu_flags, grid_corner_frames, patch_record, GridPatchPass, GridPatchSpec};
use super::traits::{
    PassContext, PassPlan, PassTables, PatchPass, PatchScheme, PlanOptions, ReferencePatch,
    Refusal, RefusalReason,
};
use crate::gpu::{Buffer, BufferBinding, DescriptorKind};
use crate::mesh::{Crease, INFINITE_SHARPNESS};
use crate::patch::single_crease::SingleCreasePatch;
pub use crate::patch::single_crease::{gpu_cvs, Rotation};
use crate::patch::RegularPatch;
use crate::render::pass::upload::{f32_bytes, host_buffer};
use crate::render::pass::{NormalRule, VertexFrames};
use crate::topology::Topology;
use crate::{Error, Result};

/// The single-crease pass in the registry.
pub static SINGLE_CREASE: SingleCreaseScheme = SingleCreaseScheme;

/// Set-0 binding of the per-patch sharpness (`crease_sharpness` in
/// `glsl/single_crease/single_crease.glsl`).
pub const SHARPNESS_BINDING: u32 = 4;

/// The `flags` word of the GPU record: bits 4-7 the edge directions of the rotated patch (as
/// [`gpu_flags`]), bits 8-9 the [`Rotation`].
pub fn single_crease_flags(p: &SingleCreasePatch) -> u32 {
    let rotated = RegularPatch {
        face: p.face,
        cvs: gpu_cvs(p),
        boundary_mask: 0,
    };
    gpu_flags(&rotated) | (Rotation::of(p.side) as u32) << 8
}

/// Takes the faces [`SingleCreasePatch::gather`] accepts (a regular quad whose 12 corner edges
/// are smooth but for one semi-sharp crease line of one sharpness `0 < s < 10`).
#[derive(Debug, Clone, Copy)]
pub struct SingleCreaseScheme;

impl PatchScheme for SingleCreaseScheme {
    fn name(&self) -> &'static str {
        "single-crease"
    }

    fn plan(&self, topo: &Arc<Topology>, candidates: &[u32], _: &PlanOptions) -> PassPlan {
        let mut patches = Vec::new();
        let mut refused = Vec::new();
        for &f in candidates {
            match SingleCreasePatch::gather(topo, f) {
                Some(p) => patches.push(p),
                None => refused.push(Refusal {
                    face: f,
                    pass: self.name(),
                    reason: RefusalReason::NotSingleCrease,
                }),
            }
        }
        PassPlan {
            tables: (!patches.is_empty()).then(|| {
                Arc::new(SingleCreaseTables::new(topo.clone(), patches)) as Arc<dyn PassTables>
            }),
            refused,
        }
    }
}

/// The single-crease patches of a surface.
#[derive(Debug, Clone)]
pub struct SingleCreaseTables {
    /// Patches in draw order (their `sharpness` the current one).
    pub patches: Vec<SingleCreasePatch>,
    faces: Vec<u32>,
    topo: Arc<Topology>,
    /// Edge ids of each patch's crease line.
    lines: Vec<[u32; 3]>,
}

impl SingleCreaseTables {
    /// Tables drawing `patches` of `topo`.
    pub fn new(topo: Arc<Topology>, patches: Vec<SingleCreasePatch>) -> SingleCreaseTables {
        let faces = patches.iter().map(|p| p.face).collect();
        let lines = patches
            .iter()
            .map(|p| {
                p.side.line().map(|(a, b)| {
                    topo.find_edge(p.cvs[a], p.cvs[b])
                        .expect("gather found the line edges")
                })
            })
            .collect();
        SingleCreaseTables {
            patches,
            faces,
            topo,
            lines,
        }
    }

    /// The per-patch sharpness (binding 4).
    pub fn sharpness_bytes(&self) -> Vec<u8> {
        f32_bytes(&self.patches.iter().map(|p| p.sharpness).collect::<Vec<_>>())
    }

    /// These tables with new sharpness on crease edges (`v0`, `v1`, `sharpness`), without
    /// re-planning: allowed when every face whose limit depends on a changed edge (the faces
    /// around its two end vertices) is a patch of these tables, the new sharpness is in
    /// `0 < s < 10`, and every such patch keeps one sharpness along its crease line (the same
    /// configuration, [`SingleCreasePatch`] eligibility). Otherwise an error saying why; the
    /// surface must then be planned again from a mesh with the new creases.
    pub fn with_sharpness(&self, creases: &[Crease]) -> Result<SingleCreaseTables> {
        let topo = &self.topo;
        let index: HashMap<u32, usize> = self
            .faces
            .iter()
            .enumerate()
            .map(|(i, &f)| (f, i))
            .collect();
        let mut edge_s: HashMap<u32, f32> = HashMap::new();
        for (p, line) in self.patches.iter().zip(&self.lines) {
            for &e in line {
                edge_s.insert(e, p.sharpness);
            }
        }
        let mut affected = HashSet::new();
        for c in creases {
            let what = format!("edge ({}, {})", c.v0, c.v1);
            let e = topo.find_edge(c.v0, c.v1).ok_or_else(|| {
                Error::Invalid(format!("set_sharpness: {what} is not a mesh edge"))
            })?;
            if !(c.sharpness > 0.0 && c.sharpness < INFINITE_SHARPNESS) {
                return Err(Error::Invalid(format!(
                    "set_sharpness: {what}: sharpness {} is outside 0 < s < {INFINITE_SHARPNESS}, \
                     which single-crease patches draw (smooth and infinitely sharp edges are other \
                     patch types: plan the surface again)",
                    c.sharpness
                )));
            }
            for v in topo.edge_vertices(e) {
                for &f in topo.vertex_faces(v) {
                    let Some(&i) = index.get(&f) else {
                        return Err(Error::Invalid(format!(
                            "set_sharpness: face {f} depends on the sharpness of {what} but is not \
                             a single-crease patch of this surface (another pass or the CPU path \
                             bakes it in): plan the surface again"
                        )));
                    };
                    if !self.lines[i].contains(&e) {
                        return Err(Error::Invalid(format!(
                            "set_sharpness: {what} is a smooth corner edge of face {f}, off its \
                             crease line: a second crease changes the patch type, plan the \
                             surface again"
                        )));
                    }
                    affected.insert(i);
                }
            }
            edge_s.insert(e, c.sharpness);
        }
        let mut out = self.clone();
        for i in affected {
            let s = self.lines[i].map(|e| edge_s[&e]);
            if s.iter().any(|&x| x != s[0]) {
                return Err(Error::Invalid(format!(
                    "set_sharpness: face {} would have sharpness {} / {} / {} along its crease line; \
                     a single-crease patch needs one sharpness on the three line edges at its \
                     corners (change them together)",
                    self.faces[i], s[0], s[1], s[2]
                )));
            }
            out.patches[i].sharpness = s[0];
        }
        Ok(out)
    }
}

impl PassTables for SingleCreaseTables {
    fn pass_name(&self) -> &'static str {
        SINGLE_CREASE.name()
    }

    fn faces(&self) -> &[u32] {
        &self.faces
    }

    fn patch_count(&self) -> usize {
        self.patches.len()
    }

    fn exact(&self) -> bool {
        true
    }

    fn corner_frames(&self, positions: &[DVec3], rule: NormalRule<'_>, frames: &mut VertexFrames) {
        for p in &self.patches {
            // The exact limit (§3): the crease vertices' frames are only written here; a
            // semi-sharp crease keeps one tangent plane.
            grid_corner_frames(
                &p.cvs,
                p.face,
                rule,
                frames,
                |u, v| p.eval(positions, u, v),
                |_| true,
            );
        }
    }

    fn framing_points(&self, frames: &VertexFrames) -> Vec<DVec3> {
        self.patches
            .iter()
            .flat_map(|p| [p.cvs[5], p.cvs[6], p.cvs[10], p.cvs[9]])
            .map(|v| frames.limits[v as usize])
            .collect()
    }

    fn reference(&self, positions: &[DVec3], face: u32) -> Option<ReferencePatch> {
        let p = *self.patches.iter().find(|p| p.face == face)?;
        let positions = positions.to_vec();
        Some(Box::new(move |u, v| {
            let s = p.eval(&positions, u, v);
            (s.position, s.normal)
        }))
    }

    fn create_pass(&self, pc: &PassContext<'_>) -> Result<Box<dyn PatchPass>> {
        Ok(Box::new(SingleCreasePass::new(pc, self)?))
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}

/// GPU resources of the single-crease patches of one surface.
pub struct SingleCreasePass {
    grid: GridPatchPass,
    sharpness: Buffer,
}

impl SingleCreasePass {
    fn new(pc: &PassContext<'_>, tables: &SingleCreaseTables) -> Result<SingleCreasePass> {
        let sharpness = host_buffer(
            pc.ctx,
            &tables.sharpness_bytes(),
            vk::BufferUsageFlags::STORAGE_BUFFER,
            "single-crease sharpness",
        )?;
        let grid = GridPatchPass::new(
            pc,
            GridPatchSpec {
                label: "single-crease patches",
                tess_control: "single_crease.tesc",
                tess_eval_stem: "single_crease",
                patches: tables
                    .patches
                    .iter()
                    .map(|p| (p.face, gpu_cvs(p)))
                    .collect(),
                records: tables
                    .patches
                    .iter()
                    .flat_map(|p| patch_record(p.face, single_crease_flags(p), &gpu_cvs(p)))
                    .collect(),
                own: &[BufferBinding {
                    binding: SHARPNESS_BINDING,
                    kind: DescriptorKind::StorageBuffer,
                    buffer: &sharpness,
                }],
            },
        )?;
        Ok(SingleCreasePass { grid, sharpness })
    }
}

impl PatchPass for SingleCreasePass {
    fn label(&self) -> &'static str {
        self.grid.label()
    }

    fn memory_bytes(&self) -> u64 {
        self.grid.memory_bytes() + self.sharpness.size()
    }

    fn patch_count(&self) -> u32 {
        self.grid.patch_count()
    }

    fn record(&self, cmd: vk::CommandBuffer, slot: usize) {
        self.grid.record(cmd, slot);
    }

    fn update_positions(&mut self, positions: &[DVec3], frames: &VertexFrames) -> Result<()> {
        self.grid.update_positions(positions, frames)
    }

    fn update_tables(&mut self, tables: &dyn PassTables) -> Result<()> {
        let t = tables
            .as_any()
            .downcast_ref::<SingleCreaseTables>()
            .ok_or_else(|| Error::Invalid("single-crease pass: not single-crease tables".into()))?;
        let bytes = t.sharpness_bytes();
        if bytes.len() != 4 * self.grid.patch_count() as usize {
            return Err(Error::Invalid(format!(
                "single-crease pass: {} patches in the new tables, {} drawn",
                t.patch_count(),
                self.grid.patch_count()
            )));
        }
        self.sharpness.write(0, &bytes)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::patch::single_crease::CreaseSide;

    fn patch(side: CreaseSide) -> SingleCreasePatch {
        SingleCreasePatch {
            face: 3,
            cvs: std::array::from_fn(|k| k as u32),
            side,
            sharpness: 1.5,
        }
    }

    /// The GPU frame has the crease along u = 1 (column 2), and its (u', v') maps to the face's
    /// (u, v) by the same rotation: the rotated patch evaluates as the face's own.
    #[test]
    fn rotation_puts_the_crease_at_u1() {
        let positions: Vec<DVec3> = (0..16)
            .map(|k| {
                let (i, j) = ((k % 4) as f64, (k / 4) as f64);
                DVec3::new(i + 0.1 * j * j, j - 0.2 * i, (0.7 * i).sin() + 0.3 * j * i)
            })
            .collect();
        for side in CreaseSide::ALL {
            let p = patch(side);
            let rotated = SingleCreasePatch {
                cvs: gpu_cvs(&p),
                side: CreaseSide::U1,
                ..p
            };
            let rot = Rotation::of(side);
            assert_eq!(single_crease_flags(&p) >> 8, rot as u32);
            for (u, v) in [(0.0, 0.0), (0.3, 0.8), (1.0, 0.25), (0.9, 0.1)] {
                let (fu, fv) = rot.face_uv(u, v);
                let a = rotated.eval(&positions, u, v).position;
                let b = p.eval(&positions, fu, fv).position;
                assert!((a - b).length() < 1e-12, "{side:?} at ({u}, {v})");
            }
        }
    }
}
