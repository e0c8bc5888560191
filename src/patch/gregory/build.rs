//! Gregory patches from a mesh's topology (paper §3, one patch per face).

use super::eval::{CornerRef, GregoryQuad, GregoryTriangle};
use super::vertex::{GregoryVertex, VertexRing};
use crate::topology::Topology;
use crate::{Error, Result};
use glam::DVec3;

/// One Gregory patch, the shape following the face.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GregoryPatch {
    /// A quad face.
    Quad(GregoryQuad),
    /// A triangle.
    Triangle(GregoryTriangle),
}

/// Centroid of face `f`.
fn centroid(topo: &Topology, positions: &[DVec3], f: u32) -> DVec3 {
    let fv = topo.face_vertices(f);
    fv.iter().map(|&v| positions[v as usize]).sum::<DVec3>() / fv.len() as f64
}

/// The split one-ring of vertex `v` (paper Fig. 5) in the topology's ring order.
pub fn vertex_ring(topo: &Topology, positions: &[DVec3], v: u32) -> VertexRing {
    let pv = positions[v as usize];
    VertexRing {
        v: pv,
        m: topo
            .vertex_edges(v)
            .iter()
            .map(|&e| 0.5 * (pv + positions[topo.other_vertex(e, v) as usize]))
            .collect(),
        c: topo
            .vertex_faces(v)
            .iter()
            .map(|&f| centroid(topo, positions, f))
            .collect(),
    }
}

/// Whether the Gregory construction of this crate covers vertex `v`: interior, no sharpness on
/// it or its edges.
pub fn is_supported_vertex(topo: &Topology, v: u32) -> bool {
    !topo.is_boundary_vertex(v)
        && topo.vertex_sharpness(v) == 0.0
        && topo
            .vertex_edges(v)
            .iter()
            .all(|&e| topo.edge_sharpness(e) == 0.0)
}

/// Per-vertex Gregory data for every vertex (`None` where [`is_supported_vertex`] is false).
pub fn gregory_vertices(topo: &Topology, positions: &[DVec3]) -> Vec<Option<GregoryVertex>> {
    (0..topo.vertex_count() as u32)
        .map(|v| {
            is_supported_vertex(topo, v)
                .then(|| GregoryVertex::interior(&vertex_ring(topo, positions, v)))
        })
        .collect()
}

/// The Gregory patch of face `f`, from per-vertex data made by [`gregory_vertices`].
///
/// Errors name the face when it is not a triangle or quad or touches an unsupported vertex.
pub fn gregory_patch(
    topo: &Topology,
    vertices: &[Option<GregoryVertex>],
    f: u32,
) -> Result<GregoryPatch> {
    let fv = topo.face_vertices(f);
    let mut refs = Vec::with_capacity(fv.len());
    for &v in fv {
        let vertex = vertices[v as usize].as_ref().ok_or_else(|| {
            Error::Invalid(format!(
                "face {f}: vertex {v} is on a boundary or crease, which the Gregory construction does not cover yet"
            ))
        })?;
        let j = topo
            .vertex_faces(v)
            .iter()
            .position(|&g| g == f)
            .ok_or_else(|| Error::Invalid(format!("face {f}: not in the ring of vertex {v}")))?;
        refs.push(CornerRef { vertex, j });
    }
    match refs.len() {
        3 => Ok(GregoryPatch::Triangle(GregoryTriangle::new(&[
            refs[0], refs[1], refs[2],
        ]))),
        4 => Ok(GregoryPatch::Quad(GregoryQuad::new(&[
            refs[0], refs[1], refs[2], refs[3],
        ]))),
        n => Err(Error::Invalid(format!(
            "face {f} has {n} vertices: Gregory patches exist for triangles and quads only"
        ))),
    }
}
