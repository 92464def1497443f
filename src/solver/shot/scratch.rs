//! The buffers a shot works in and the caches it keeps between shots.

use crate::rgb::Rgb;
use crate::solver::shot::patch_reception::{PatchReception, ReceptionPlan};
use crate::solver::shot::shaft_culling::{ReceiverShafts, ReceivingBoxes};
use crate::solver::shot::visibility_memory::VisibilityMemory;

/// Buffers that hold one shot's values, kept from shot to shot so as not
/// to allocate: they hold nothing between shots.
#[derive(Default)]
pub(crate) struct ShotScratch {
    /// A shot's irradiance per vertex of its closed zone (or of the mesh),
    /// at each one's `ShotPlaces`: a shot in one room of a building holds
    /// that room's vertices alone.
    pub(crate) incident: Vec<Rgb>,
    /// A shot's power per receiving element.
    pub(crate) element_powers: Vec<Rgb>,
    /// Per patch, the irradiance above which its vertices interpolate the
    /// current shot (all infinite between shots).
    pub(crate) thresholds: Vec<Rgb>,
    /// The current shot's thresholds, in the order of its zone's patches.
    pub(crate) patch_thresholds: Vec<Rgb>,
    /// The last shot's reception plan, kept for its buffers.
    pub(crate) reception_plan: ReceptionPlan,
    /// Per vertex: whether it sees all of the current shooter, or which few
    /// triangles alone can block its rays to it.
    pub(crate) receiver_shafts: ReceiverShafts,
    /// Every patch's index, for the plans of a scene without closed zones.
    pub(crate) every_patch: Vec<u32>,
    /// Every vertex's index, likewise.
    pub(crate) every_vertex: Vec<u32>,
}

/// What shots remember of the mesh and of earlier shots.
#[derive(Default)]
pub(crate) struct ShotMemory {
    /// Each patch's sample vertices for dim shots, and how its other
    /// vertices are interpolated from them (built on first use).
    pub(crate) reception: PatchReception,
    /// The box of each patch's receiving points, for shaft culling.
    pub(crate) receiving_boxes: ReceivingBoxes,
    /// What each vertex saw of each shooter at its last shot.
    pub(crate) visibility_memory: VisibilityMemory,
}
