//! Meshes: vertices, elements and patches, and the meshers that make them.
//!
//! The mesh knows nothing of light. `data/` holds the mesh itself
//! (vertices, elements, patches, the element hierarchy); `meshers/` the
//! ways to lay elements on one surface (square grid, contour lines, level
//! lines, greedy insertion, over a constrained triangulation); `assembly/`
//! meshing a whole scene (contact lines, hidden parts, boundary inset).

mod assembly;
mod data;
pub(crate) mod meshers;

pub(crate) use assembly::mesh_surfaces_counted;
pub(crate) use assembly::receiver_inset;
pub use assembly::{SurfaceGuides, is_enclosed, mesh_square, mesh_surfaces};
pub use data::{Cell, Element, ElementHierarchy, ElementKey, ElementNode, Mesh, MeshVertex, Patch};
pub(crate) use meshers::estimate_square_elements;
pub use meshers::{
    ContourLayout, ContourSettings, ErrorGrid, GreedySettings, InterpolationError,
    PlaneTriangulation, SampledField, ScalarField, SquareMeshSettings, contour_layout,
    contour_polylines, greedy_insertion, interpolation_error, level_line_layout,
};
pub(crate) use meshers::{check_element_budget, estimate_contour_elements};
