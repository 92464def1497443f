//! Meshes: vertices, elements and patches, and the meshers that make them.
//!
//! The mesh knows nothing of light.

mod constrained;
mod contacts;
mod patch;
mod square;
mod topology;

pub use patch::{Cell, Patch};
pub use square::{SquareMeshSettings, mesh_square, receiver_inset};
pub use topology::{Element, Mesh, MeshVertex};
