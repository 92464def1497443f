//! The mesh itself: vertices, elements and their topology, the patches
//! that group elements, and the element hierarchy that refines them.

pub(super) mod hierarchy;
pub(super) mod patch;
pub(super) mod topology;

pub use hierarchy::{ElementHierarchy, ElementKey, ElementNode};
pub use patch::{Cell, Patch};
pub use topology::{Element, Mesh, MeshVertex};
