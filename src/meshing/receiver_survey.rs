//! What `isorad info` shows of every receiver: its dominance analysis and
//! its shadow boundaries, with the scene's closed zones found once for both.

use glam::DVec2;

use super::analyses::{analyses_in_zones, closed_zones};
use super::boundaries::boundaries_in_zones;
use super::resolved::ResolvedMeshSettings;
use crate::lighting::{AreaLight, DominanceSettings, ReceiverAnalysis};
use crate::phase::PhaseReporter;
use crate::scene::{Scene, Visibility};

/// Every receiver's analysis and every surface's shadow boundaries.
#[derive(Clone, Debug)]
pub struct ReceiverSurvey {
    /// [`super::scene_receiver_analyses`]'s answer.
    pub analyses: Vec<ReceiverAnalysis>,
    /// [`super::scene_shadow_boundaries`]'s answer, by surface index.
    pub boundaries: Vec<Vec<[DVec2; 2]>>,
}

/// [`super::scene_receiver_analyses`] and [`super::scene_shadow_boundaries`]
/// with the closed zones found once: `report` hears [`crate::Phase::ClosedRooms`]
/// once, then the dominance analysis and the shadow boundaries.
#[must_use]
pub fn survey_receivers(
    scene: &Scene,
    visibility: &Visibility,
    area_lights: &[AreaLight],
    dominance: &DominanceSettings,
    mesh: &ResolvedMeshSettings,
    report: PhaseReporter,
) -> ReceiverSurvey {
    let zones = closed_zones(scene, visibility, report);
    let analyses = analyses_in_zones(scene, visibility, area_lights, dominance, &zones, report);
    let boundaries = boundaries_in_zones(scene, visibility, area_lights, mesh, &zones, report);
    ReceiverSurvey {
        analyses,
        boundaries,
    }
}
