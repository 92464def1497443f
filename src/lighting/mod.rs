//! Lighting: what the emitters make of a scene before any light is shot.
//!
//! Area lights (touching coplanar emitters of one material grouped into
//! lamps), the exact direct field of one light on a receiver's plane
//! (value, gradient, visibility, maximum, kink line: what the contour mesher
//! meshes), the dominant-small-emitter analysis that decides which receivers
//! the contour mesher gets, the stratified points, cosine-weighted
//! directions and deterministic random stream their estimates use, and the
//! shadow boundaries the lights cast through occluders (discontinuity
//! meshing). "Luminaire" means only the photometric
//! `scene::PhotometricLuminaire`; an [`AreaLight`] is a lamp of emitting
//! surfaces.
//!
//! It uses the scene and radiometry; the mesh never imports it: the
//! meshing layer hands its fields down to the meshers as closures.

mod area_light;
mod daylight;
mod direct_field;
mod dominance;
mod hemisphere;
mod sample_stream;
mod shadow_boundaries;
mod stratified;

pub use area_light::{AreaLight, area_lights};
pub use daylight::{
    DaylightReceiver, DaylightSource, Opening, Portal, PortalKind, Portals, find_openings,
    sky_transmittance,
};
pub use direct_field::DirectField;
pub(crate) use dominance::analyse_receivers_reporting;
pub use dominance::{
    ContourMesher, DominanceSettings, ReceiverAnalysis, analyse_receivers, analyse_receivers_among,
    dominant_field,
};
pub(crate) use hemisphere::{cosine_direction, cosine_direction_at};
pub(crate) use sample_stream::SampleStream;
pub use shadow_boundaries::{
    BoundaryLimits, EdgeNeighbours, OccludersIn, ShadowReceiver, light_reaches, shadow_boundaries,
};
pub(crate) use stratified::stratified_points;
