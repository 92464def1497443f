//! The ambient term: the light not yet shot, gathered at the vertices along
//! rays (cast once per room and kept), swept over its further bounces and
//! smoothed; and the patch shots, which carry what the vertices' shots leave
//! from patch to patch (small patches shot as clusters).

pub(super) mod irradiance;
pub(super) mod patch_clusters;
pub(super) mod patch_shots;
pub(super) mod rays;
pub(super) mod rooms;
pub(super) mod smoothing;
pub(super) mod state;
pub(super) mod sweeps;
pub(super) mod term;
