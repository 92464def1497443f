//! The ambient term: the light not yet shot, gathered at the vertices along
//! rays (cast once per room and kept), swept over its further bounces and
//! smoothed; and the patch shots, which carry what the vertices' shots leave
//! from patch to patch (small patches shot as clusters).
//!
//! `rays.rs` explains the term and holds what its parts share; the
//! patches' rays (`patch_rays.rs`), the vertices' rays (`vertex_rays.rs`),
//! where they land (`patch_locator.rs`, `landing.rs`), the rooms it is made
//! in (`rooms.rs`), its sweeps and smoothing, and the term made from a
//! solver's parts (`term.rs`) into an `AmbientIrradiance`.
//! The patch shots (`patch_shots.rs`) shoot along links (`patch_links.rs`)
//! between nodes (`patch_clusters.rs`); `state.rs` is what a solver keeps
//! of all this between images.

pub(super) mod irradiance;
pub(super) mod landing;
pub(super) mod patch_clusters;
pub(super) mod patch_links;
pub(super) mod patch_locator;
pub(super) mod patch_rays;
pub(super) mod patch_shots;
pub(super) mod rays;
pub(super) mod rooms;
pub(super) mod smoothing;
pub(super) mod state;
pub(super) mod sweeps;
pub(super) mod term;
#[cfg(test)]
mod term_tests;
pub(super) mod vertex_rays;
