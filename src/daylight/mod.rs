//! Daylight: sky luminance models, the sun's position, and clear glazing.
//!
//! Pure functions of directions and time, in local (east, north, up)
//! coordinates: nothing here knows of scenes, meshes or solvers (it takes
//! only photometry's 179 lm/W).
//!
//! - [`Sky`] with a [`SkyModel`]: the CIE overcast, clear and intermediate
//!   skies, the fifteen types of the CIE standard general sky
//!   ([`cie_general_parameters`]) and the uniform sky; their luminance in a
//!   [`SkyDirection`] and the illuminance they give an unobstructed plane.
//! - [`solar_position`] at an [`Instant`] parsed from ISO 8601: NOAA's
//!   algorithm after Meeus, with refraction.
//! - [`Daylight`]: a scene's sky, [`Sun`] and ground placed in its
//!   coordinates by a [`SkyFrame`] (up, north, east), with the radiance
//!   toward any direction ([`SkyRadiance`]).
//! - [`pane_transmittance`] and [`pane_reflectance`] of a clear glass pane
//!   as Radiance's `glass` computes them, and their diffuse averages.
//!
//! # Example
//!
//! ```
//! use isorad::daylight::{Instant, Sky, SkyModel, solar_position};
//!
//! let noon: Instant = "2026-06-21T12:00+02:00".parse()?;
//! let sun = solar_position(48.85, 2.35, &noon).direction();
//! let sky = Sky::new(SkyModel::CieClear, 6000.0, Some(sun))?;
//! let e_h = sky.horizontal_illuminance();
//! assert!(e_h > 10_000.0 && e_h < 40_000.0);
//! # Ok::<(), String>(())
//! ```
//!
//! # References
//! - ISO 15469:2004 / CIE S 011/E:2003, *Spatial distribution of daylight —
//!   CIE standard general sky*; CIE 110-1994.
//! - P. Moon, D. E. Spencer, "Illumination from a non-uniform sky", 1942.
//! - J. Meeus, *Astronomical Algorithms*, 2nd ed., 1998; NOAA Global
//!   Monitoring Laboratory, *Solar Calculation Details*.
//! - G. Ward, Radiance: `src/gen/gensky.c`, `src/gen/skybright.cal`,
//!   `src/rt/glass.c` (LBNL-ETA/Radiance).

mod cie_general;
mod direction;
mod glazing;
mod instant;
mod model;
mod outdoor;
mod quadrature;
mod sky;
mod sun_position;

#[cfg(test)]
mod tests;

pub use cie_general::{CieGeneralParameters, cie_general_parameters};
pub use direction::SkyDirection;
pub use glazing::{
    GLASS_REFRACTIVE_INDEX, lossless_pane_transmittance, pane_diffuse_reflectance,
    pane_diffuse_transmittance, pane_reflectance, pane_transmittance,
    transmissivity_from_transmittance,
};
pub use instant::Instant;
pub use model::{SkyModel, SkyPattern};
pub use outdoor::{Daylight, SUN_DIAMETER_DEG, SkyFrame, SkyRadiance, Sun};
pub use sky::Sky;
pub use sun_position::{
    SolarGeometry, SolarPosition, refraction_deg, solar_geometry, solar_position,
};
