//! Lighting calculations: calculation grids with the statistics of
//! EN 12464-1 (Emin, Eavg, Emax, U₀), in lux.

mod grid;

pub use grid::{
    CalculationGrid, IlluminanceStatistics, MAX_GRID_POINTS, en12464_spacing, illuminance_lux,
};
