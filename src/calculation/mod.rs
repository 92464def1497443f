//! Lighting calculations: calculation grids, isolux plots and false-colour
//! pictures, in lux (and cd/m² for a camera's view).
//!
//! - [`CalculationGrid`]: the points of a regular grid on a named surface
//!   or on the work plane above it, as EN 12464-1 spaces them
//!   ([`en12464_spacing`], at most [`MAX_GRID_POINTS`]), their illuminance
//!   from a solution ([`illuminance_lux`]) and its statistics
//!   ([`IlluminanceStatistics`]: Emin, Eavg, Emax, U₀).
//! - [`ObstructionRule`], [`GridSelection`], [`Obstruction`]: which grid
//!   points lie inside an object or closer than a clearance
//!   ([`DEFAULT_CLEARANCE`]) to another surface, left out of the
//!   statistics unless kept.
//! - [`GridPicture`]: a calculation grid on a plane ready to be drawn, its
//!   illuminance, the surface's outline and the luminaires, in metres.
//! - [`write_isolux_plot`]: its lines of equal illuminance, labelled, on
//!   equal axes in metres (PNG or SVG).
//! - [`FalseColorScale`], [`write_falsecolor_image`],
//!   [`write_falsecolor_grid`]: banded viridis false colour with a legend,
//!   as Radiance's `falsecolor` (PNG), of a camera view's luminance or of
//!   a grid; [`LOG_DECADES`], the span of a logarithmic scale.
//! - [`contour_polylines`]: marching squares over a value grid, joined
//!   into polylines (the mesh's, which the level-line mesher uses too).
//! - [`nice_levels`], [`nice_ceiling`], [`format_lux`]: round levels, a
//!   round maximum, and short labels.
//!
//! The pictures draw plain data and solve nothing; their text is drawn
//! with the bundled DejaVu Sans shared with [`study`](crate::study).

mod falsecolor;
mod falsecolor_scale;
mod grid;
mod grid_layout;
mod grid_obstruction;
mod grid_picture;
mod grid_quantity;
mod isolux;
mod isolux_lines;
mod levels;

pub use crate::mesh::contour_polylines;
pub use falsecolor::{write_falsecolor_grid, write_falsecolor_image};
pub use falsecolor_scale::{FalseColorScale, LOG_DECADES};
pub use grid::{CalculationGrid, illuminance_lux};
pub use grid_layout::{MAX_GRID_POINTS, en12464_spacing};
pub use grid_obstruction::{DEFAULT_CLEARANCE, GridSelection, Obstruction, ObstructionRule};
pub use grid_picture::GridPicture;
pub use grid_quantity::{
    DEFAULT_DF_TARGET, EN17037_TARGETS, GridQuantity, GridStatistics, IlluminanceStatistics,
    share_reaching,
};
pub use isolux::write_isolux_plot;
pub use levels::{format_lux, nice_ceiling, nice_levels};
