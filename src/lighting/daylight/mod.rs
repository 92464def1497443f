//! Daylight in a model: where the sky comes in (openings found in the
//! geometry, glazing panes), how much of it a ray reaches, and the direct
//! light of the sky, the ground and the sun at a point.

mod direct;
mod openings;
mod plane_groups;
mod portals;
mod transmission;

pub use direct::{DaylightReceiver, DaylightSource};
pub use openings::{Opening, find_openings};
pub use portals::{Portal, PortalKind, Portals};
pub use transmission::sky_transmittance;
