//! One shot: the shooter and its sampling of the source, the shadow rays it
//! casts to every receiving vertex (with shaft culling and the memory of what
//! each vertex saw of the same shooter before), the reception of dim shots
//! patch by patch, and the power each receiving element takes.

pub(super) mod cache_runs;
pub(super) mod coarse_reception;
pub(super) mod context;
pub(super) mod daylight;
pub(super) mod element_power;
pub(super) mod incident;
pub(super) mod landing_scale;
pub(super) mod luminaire;
pub(super) mod new_vertices;
pub(super) mod patch_reception;
pub(super) mod receive;
pub(super) mod receivers;
pub(super) mod sample_fan;
pub(super) mod samples;
pub(super) mod scratch;
pub(super) mod shaft_culling;
pub(super) mod shooter;
pub(super) mod visibility_memory;
