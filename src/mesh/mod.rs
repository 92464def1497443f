//! Meshes: vertices, elements and patches, and the meshers that make them.
//!
//! The mesh knows nothing of light.

mod assembly;
mod boundary_inset;
pub(crate) mod budget;
mod constrained;
mod contacts;
mod contour;
mod contour_lines;
mod greedy_insertion;
mod hierarchy;
mod interpolation_error;
mod level_lines;
mod patch;
mod square;
mod topology;

pub(crate) use assembly::mesh_surfaces_counted;
pub(crate) use assembly::receiver_inset;
pub use assembly::{SurfaceGuides, mesh_square, mesh_surfaces};
pub(crate) use budget::estimate_square_elements;
pub(crate) use budget::{check_element_budget, estimate_contour_elements};
pub use constrained::PlaneTriangulation;
pub use contacts::is_enclosed;
pub use contour::{ContourLayout, ContourSettings, ScalarField, contour_layout};
pub use contour_lines::contour_polylines;
pub use greedy_insertion::{GreedySettings, SampledField, greedy_insertion};
pub use hierarchy::{ElementHierarchy, ElementKey, ElementNode};
pub use interpolation_error::{ErrorGrid, InterpolationError, interpolation_error};
pub use level_lines::level_line_layout;
pub use patch::{Cell, Patch};
pub use square::SquareMeshSettings;
pub use topology::{Element, Mesh, MeshVertex};
