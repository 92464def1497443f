//! Meshing a whole scene: each surface's mesher run and assembled, the
//! contact lines where surfaces stand on each other, the hidden parts
//! dropped, and boundary vertices moved just inside their surface.

pub(super) mod boundary_inset;
pub(super) mod contacts;
pub(super) mod hidden;
pub(super) mod remesh;
pub(super) mod surfaces;

pub use hidden::is_enclosed;
pub use surfaces::{SurfaceGuides, mesh_square, mesh_surfaces};
pub(crate) use surfaces::{mesh_surfaces_counted, receiver_inset};
