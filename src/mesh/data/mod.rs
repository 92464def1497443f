//! The mesh itself: vertices, elements and their topology, the patches
//! that group elements, the element hierarchy that refines them, the
//! mesh's adjacency and its invariants.

pub(super) mod hierarchy;
mod neighbourhood;
pub(super) mod patch;
pub(super) mod topology;
pub(super) mod validate;

pub use hierarchy::{ElementHierarchy, ElementKey, ElementNode};
pub use patch::{Cell, Patch};
pub use topology::{Element, Mesh, MeshVertex};
