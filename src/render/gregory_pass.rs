//! The Gregory-patch pass of a [`super::SurfaceRenderer`]: whichever GPU variant the surface
//! asks for ([`super::gregory_vs`] or [`super::gregory_stencil`]), behind one interface, plus
//! the per-vertex limit frames every patch corner (regular or Gregory) reads.

use std::sync::Arc;

use ash::vk;
use glam::DVec3;

use super::gregory_layout::{vertex_frames, GregoryLayout};
use super::gregory_stencil::{StencilPatches, StencilPlan};
use super::gregory_vs::{GregoryVsPatches, SharedBuffers};
use super::layout::BSplinePatch;
use super::renderer::RenderDesc;
use super::scheme::{GregorySurface, Scheme};
use crate::gpu::{Context, TargetFormat};
use crate::patch::RegularPatch;
use crate::topology::Topology;
use crate::Result;

/// The variant's tables before the GPU resources exist (they need the vertex frames first).
pub enum GregoryPassPlan {
    /// Two-stage variant.
    Vs(Arc<Topology>, GregoryLayout),
    /// Stencil variant.
    Stencil(Arc<Topology>, StencilPlan),
}

impl GregoryPassPlan {
    /// Plans the faces of `g` for `ctx`'s device.
    pub fn new(ctx: &Context, g: &GregorySurface) -> GregoryPassPlan {
        match g.scheme {
            Scheme::GregoryStencil => GregoryPassPlan::Stencil(
                g.topology.clone(),
                StencilPlan::new(
                    &g.topology,
                    &g.faces,
                    ctx.info().limits.max_tessellation_patch_size,
                ),
            ),
            _ => GregoryPassPlan::Vs(
                g.topology.clone(),
                GregoryLayout::new(&g.topology, &g.faces),
            ),
        }
    }

    fn parts(&self) -> (&Topology, &GregoryLayout) {
        match self {
            GregoryPassPlan::Vs(t, l) => (t, l),
            GregoryPassPlan::Stencil(t, p) => (t, &p.layout),
        }
    }
}

/// Limit positions and normals of every patch corner: regular corners from the B-spline patch,
/// Gregory-only corners from the Gregory construction ([`vertex_frames`]).
pub fn surface_vertex_frames(
    positions: &[DVec3],
    regular: &[BSplinePatch],
    plan: Option<&GregoryPassPlan>,
) -> (Vec<DVec3>, Vec<DVec3>) {
    match plan {
        Some(p) => {
            let (topo, layout) = p.parts();
            vertex_frames(topo, positions, regular, layout)
        }
        None => {
            let mut lim = positions.to_vec();
            // No topology here: a corner with a boundary/crease side of its patch keeps its
            // own normal (zero entry), as it may lie between sectors.
            let mut nrm = vec![DVec3::ZERO; positions.len()];
            let mut done = vec![false; positions.len()];
            for p in regular {
                let rp = RegularPatch {
                    face: p.face,
                    cvs: p.cvs,
                    boundary_mask: p.boundary_mask,
                };
                for (k, (u, v)) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
                    .into_iter()
                    .enumerate()
                {
                    let vid = p.corners()[k] as usize;
                    if !done[vid] {
                        done[vid] = true;
                        let s = rp.eval(positions, u, v);
                        lim[vid] = s.position;
                        let sides = [9u8, 3, 6, 12][k];
                        if p.boundary_mask & sides == 0 {
                            nrm[vid] = s.normal;
                        }
                    }
                }
            }
            (lim, nrm)
        }
    }
}

enum Pass {
    Vs(GregoryVsPatches),
    Stencil(StencilPatches),
}

/// GPU Gregory patches of one surface.
pub struct GregoryPass {
    topo: Arc<Topology>,
    layout: GregoryLayout,
    pass: Pass,
}

impl GregoryPass {
    /// Creates the variant's resources. `normals`: the vertex normals of
    /// [`surface_vertex_frames`] for the same plan.
    pub fn new(
        ctx: &Context,
        plan: GregoryPassPlan,
        positions: &[DVec3],
        normals: &[DVec3],
        shared: SharedBuffers<'_>,
        desc: &RenderDesc,
        target: TargetFormat,
    ) -> Result<GregoryPass> {
        Ok(match plan {
            GregoryPassPlan::Vs(topo, layout) => {
                let p = GregoryVsPatches::new(
                    ctx,
                    &topo,
                    layout.clone(),
                    positions,
                    normals,
                    shared,
                    desc,
                    target,
                )?;
                GregoryPass {
                    topo,
                    layout,
                    pass: Pass::Vs(p),
                }
            }
            GregoryPassPlan::Stencil(topo, plan) => {
                let layout = plan.layout.clone();
                let p = StencilPatches::new(ctx, plan, positions, normals, shared, desc, target)?;
                GregoryPass {
                    topo,
                    layout,
                    pass: Pass::Stencil(p),
                }
            }
        })
    }

    /// Number of Gregory patches.
    pub fn patch_count(&self) -> u32 {
        self.layout.patch_count()
    }

    /// Limit frames for new positions (see [`surface_vertex_frames`]).
    pub fn vertex_frames(
        &self,
        positions: &[DVec3],
        regular: &[BSplinePatch],
    ) -> (Vec<DVec3>, Vec<DVec3>) {
        vertex_frames(&self.topo, positions, regular, &self.layout)
    }

    /// Animation: new control positions and vertex normals; the patches are rebuilt on the GPU.
    pub fn update_positions(&mut self, positions: &[DVec3], normals: &[DVec3]) -> Result<()> {
        match &mut self.pass {
            Pass::Vs(p) => p.update_positions(positions, normals),
            Pass::Stencil(p) => p.update_positions(positions, normals),
        }
    }

    /// Records the draws (inside the caller's render pass).
    pub fn record(&self, cmd: vk::CommandBuffer) {
        match &self.pass {
            Pass::Vs(p) => p.record(cmd),
            Pass::Stencil(p) => p.record(cmd),
        }
    }
}
