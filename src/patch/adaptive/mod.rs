//! The patches of a feature-adaptive refinement ([`crate::subdiv::adaptive`]) as a CPU surface:
//! B-spline patches (regular, boundary, crease) at the level where their face became regular,
//! and end caps at the isolation level: the Gregory patch ([`super::gregory`]) of every face
//! still irregular there, built over that level's refined points, so the inexact area shrinks
//! by four per level (Köbler 2013 ch. 3; Nießner et al. 2012).
//!
//! Every patch keeps its face's [`Domain`](crate::subdiv::adaptive::Domain), the map from the patch's own `(s, t)` to its base
//! face's `(u, v)` (quads) or sub-face `(u, v)` (other faces), so the surface is evaluated at the
//! same parameters as [`crate::subdiv::eval::LimitEvaluator`]. End caps of level 0 (isolation 0)
//! on triangles use the Gregory triangle's own barycentric parameters.
//!
//! [`draw`] turns the same patches into the GPU draw tables ([`AdaptiveDrawTables`]).

mod census_index;
mod coarse;
pub mod decayed_fit;
pub mod draw;
mod error;
mod exact_corners;
pub mod lattice_frames;
pub mod promoted;
pub mod records;
pub mod rows;
mod sector_frames;
mod slot_rows;
pub mod slots;
mod surface;

pub use draw::AdaptiveDrawTables;
pub use error::DrawTablesError;
pub use surface::{
    end_caps, AdaptiveSurface, EndCapError, EndCapFailure, EndCapTopologies, PatchShape,
    SurfacePatch, SurfacePoint,
};
