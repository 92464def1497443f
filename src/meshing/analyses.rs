//! Each receiver's dominant-emitter analysis, paired only with the lights
//! of its own closed zone.

use super::zones::Zones;
use crate::lighting::{
    AreaLight, DominanceSettings, ReceiverAnalysis, analyse_receivers_reporting,
};
use crate::phase::{Phase, PhaseCounter, PhaseReporter};
use crate::scene::{Scene, Visibility};

/// What [`crate::lighting::analyse_receivers`] finds on every receiver, each paired only
/// with the lights of its own closed zone
/// ([`crate::lighting::analyse_receivers_among`]): as `mesh_scene`
/// analyses them. `report` hears [`Phase::ClosedRooms`], then
/// [`Phase::Dominance`] receiver by receiver.
#[must_use]
pub fn scene_receiver_analyses(
    scene: &Scene,
    visibility: &Visibility,
    area_lights: &[AreaLight],
    settings: &DominanceSettings,
    report: PhaseReporter,
) -> Vec<ReceiverAnalysis> {
    let zones = closed_zones(scene, visibility, report);
    analyses_in_zones(scene, visibility, area_lights, settings, &zones, report)
}

/// The scene's closed zones, reported as [`Phase::ClosedRooms`].
pub(super) fn closed_zones(scene: &Scene, visibility: &Visibility, report: PhaseReporter) -> Zones {
    let counter = PhaseCounter::start(Phase::ClosedRooms, 1, report);
    let zones = Zones::new(scene, visibility);
    counter.finish();
    zones
}

/// [`scene_receiver_analyses`] with the scene's closed zones found: each
/// receiver gets the area lights and emitting bodies of its zone, and
/// every photometric luminaire (a point, in no zone).
pub(super) fn analyses_in_zones(
    scene: &Scene,
    visibility: &Visibility,
    area_lights: &[AreaLight],
    settings: &DominanceSettings,
    zones: &Zones,
    report: PhaseReporter,
) -> Vec<ReceiverAnalysis> {
    let mut per_zone = vec![Vec::new(); zones.count()];
    for (k, lamp) in area_lights.iter().enumerate() {
        if let Some(&surface) = lamp.surfaces.first() {
            per_zone[zones.of(surface)].push(k);
        }
    }
    for (k, luminaire) in scene.luminaires.iter().enumerate() {
        let index = area_lights.len() + k;
        match &luminaire.body {
            Some(body) => per_zone[zones.of(body.surfaces[0])].push(index),
            None => per_zone.iter_mut().for_each(|lights| lights.push(index)),
        }
    }
    let room_of = |receiver| {
        let zone = zones.of(receiver);
        let inside = zones.visibility(zone).unwrap_or(visibility);
        (inside, per_zone[zone].clone())
    };
    analyse_receivers_reporting(scene, area_lights, settings, &room_of, report)
}
