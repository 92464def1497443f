//! Each receiver's dominant-emitter analysis, paired only with the lights
//! of its own closed zone.

use super::zones::Zones;
use crate::lighting::{AreaLight, DominanceSettings, ReceiverAnalysis, analyse_receivers_among};
use crate::scene::{Scene, Visibility};

/// What [`crate::lighting::analyse_receivers`] finds on every receiver, each paired only
/// with the lights of its own closed zone
/// ([`analyse_receivers_among`]): as `mesh_scene` analyses them.
#[must_use]
pub fn scene_receiver_analyses(
    scene: &Scene,
    visibility: &Visibility,
    area_lights: &[AreaLight],
    settings: &DominanceSettings,
) -> Vec<ReceiverAnalysis> {
    let zones = Zones::new(scene, visibility);
    analyses_in_zones(scene, visibility, area_lights, settings, &zones)
}

/// [`scene_receiver_analyses`] with the scene's closed zones found: each
/// receiver gets the area lights of its zone, and every photometric
/// one (a point, in no zone).
pub(super) fn analyses_in_zones(
    scene: &Scene,
    visibility: &Visibility,
    area_lights: &[AreaLight],
    settings: &DominanceSettings,
    zones: &Zones,
) -> Vec<ReceiverAnalysis> {
    let mut per_zone = vec![Vec::new(); zones.count()];
    for (k, lamp) in area_lights.iter().enumerate() {
        if let Some(&surface) = lamp.surfaces.first() {
            per_zone[zones.of(surface)].push(k);
        }
    }
    let photometric = area_lights.len()..area_lights.len() + scene.luminaires.len();
    for lights in &mut per_zone {
        lights.extend(photometric.clone());
    }
    let room_of = |receiver| {
        let zone = zones.of(receiver);
        let inside = zones.visibility(zone).unwrap_or(visibility);
        (inside, per_zone[zone].clone())
    };
    analyse_receivers_among(scene, area_lights, settings, &room_of)
}
