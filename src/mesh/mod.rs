//! Control meshes: positions, polygonal faces of any size >= 3, and the subdivision tags
//! (creases, corners, holes, boundary interpolation, crease method) that OpenSubdiv-style
//! files carry.
//!
//! A [`ControlMesh`] is always valid once constructed: [`ControlMesh::new`] runs the checks in
//! [`validate`] and refuses bad input with a typed [`crate::Error`] naming the offending element.

mod control_mesh;
mod desc;
pub mod obj;
mod tags;
pub mod uv;
pub mod validate;
mod warning;

pub use control_mesh::ControlMesh;
pub use desc::{
    BoundaryInterpolation, ControlMeshDesc, Corner, Crease, CreaseMethod, SchemeOptions,
    INFINITE_SHARPNESS,
};
pub use obj::ObjOptions;
pub use uv::FaceUvs;
pub use warning::MeshWarning;
