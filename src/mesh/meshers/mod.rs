//! The meshers of one surface: the square grid, the contour and level-line
//! layouts, greedy insertion, the constrained triangulation they build on,
//! the interpolation error they are compared by, and the element budget
//! checked before meshing.

pub(crate) mod budget;
pub(super) mod constrained;
pub(super) mod contour;
pub(super) mod contour_levels;
pub(super) mod contour_lines;
mod contour_rays;
pub(super) mod greedy_insertion;
pub(super) mod interpolation_error;
pub(super) mod level_lines;
mod sampled_field;
mod scalar_field;
pub(super) mod square;

pub(crate) use budget::estimate_square_elements;
pub(crate) use budget::{check_element_budget, estimate_contour_elements};
pub use constrained::PlaneTriangulation;
pub use contour::{ContourLayout, ContourSettings, contour_layout};
pub use contour_lines::contour_polylines;
pub use greedy_insertion::{GreedySettings, greedy_insertion};
pub use interpolation_error::{ErrorGrid, InterpolationError, interpolation_error};
pub use level_lines::level_line_layout;
pub use sampled_field::SampledField;
pub use scalar_field::ScalarField;
pub use square::SquareMeshSettings;
