//! The shadow boundaries each receiver's mesh follows: those the lights of
//! its own closed zone cast on it through that zone's occluders
//! (`lighting::shadow_boundaries` finds them on one receiver).

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::analyses::closed_zones;
use super::resolved::ResolvedMeshSettings;
use super::zones::{ZoneLabels, Zones};
use crate::lighting::{
    AreaLight, BoundaryLimits, EdgeNeighbours, ShadowReceiver, light_reaches, shadow_boundaries,
};
use crate::phase::{Phase, PhaseCounter, PhaseReporter};
use crate::scene::{Scene, SurfaceBoxes, SurfaceId, Visibility};

/// Every surface's shadow boundaries, indexed by surface, in its plane
/// coordinates, as `settings` meshes them: merged where closer than 3/16
/// of an element, at most `max_shadow_boundaries` per receiver, longest
/// first ([`ResolvedMeshSettings::shadow_boundaries`]). Empty for
/// emitters, for surfaces smaller than one element (a line across would
/// only split them into slivers), and for all when the settings ask for
/// none. Only the lights that reach a receiver cast boundaries on it
/// ([`light_reaches`]), and only the lights and occluders of its own
/// closed zone (a room whose doors are shut, `Zones`) are tried: a lamp
/// in another closed room adds none, and a building of separate rooms
/// costs what its rooms cost alone. Computed in parallel; `report` hears
/// [`Phase::ClosedRooms`], then [`Phase::ShadowBoundaries`] receiver by
/// receiver.
#[must_use]
pub fn scene_shadow_boundaries(
    scene: &Scene,
    visibility: &Visibility,
    area_lights: &[AreaLight],
    settings: &ResolvedMeshSettings,
    report: PhaseReporter,
) -> Vec<Vec<[DVec2; 2]>> {
    if casting_limits(scene, area_lights, settings).is_none() {
        return vec![Vec::new(); scene.surfaces.len()];
    }
    let zones = closed_zones(scene, visibility, report);
    boundaries_in_zones(scene, visibility, area_lights, settings, &zones, report)
}

/// The shadow boundaries on one receiver, as [`scene_shadow_boundaries`]
/// finds them for every surface.
#[must_use]
pub fn receiver_shadow_boundaries(
    scene: &Scene,
    visibility: &Visibility,
    area_lights: &[AreaLight],
    settings: &ResolvedMeshSettings,
    receiver: SurfaceId,
) -> Vec<[DVec2; 2]> {
    let Some(limits) = casting_limits(scene, area_lights, settings) else {
        return Vec::new();
    };
    let zones = Zones::new(scene, visibility);
    let zone = zones.of(receiver);
    let caster = BoundaryCaster::new(scene, area_lights, zones.labels(), limits, settings);
    caster.boundaries_on(
        scene,
        zones.visibility(zone).unwrap_or(visibility),
        receiver,
    )
}

/// [`scene_shadow_boundaries`] with the scene's closed zones found,
/// reporting its progress receiver by receiver.
pub(super) fn boundaries_in_zones(
    scene: &Scene,
    visibility: &Visibility,
    area_lights: &[AreaLight],
    settings: &ResolvedMeshSettings,
    zones: &Zones,
    report: PhaseReporter,
) -> Vec<Vec<[DVec2; 2]>> {
    let Some(limits) = casting_limits(scene, area_lights, settings) else {
        return vec![Vec::new(); scene.surfaces.len()];
    };
    let counter = PhaseCounter::start(Phase::ShadowBoundaries, scene.surfaces.len(), report);
    let caster = BoundaryCaster::new(scene, area_lights, zones.labels(), limits, settings);
    let ids: Vec<SurfaceId> = scene.surfaces_with_ids().map(|(id, _)| id).collect();
    let boundaries = ids
        .par_iter()
        .map(|&id| {
            let zone = zones.of(id);
            let found =
                caster.boundaries_on(scene, zones.visibility(zone).unwrap_or(visibility), id);
            counter.add(1);
            found
        })
        .collect();
    counter.finish();
    boundaries
}

/// The limits of the boundaries a receiver keeps, or `None` where none are
/// cast: the settings ask for none, or the scene has no light.
fn casting_limits(
    scene: &Scene,
    area_lights: &[AreaLight],
    settings: &ResolvedMeshSettings,
) -> Option<BoundaryLimits> {
    let lit = !area_lights.is_empty() || !scene.luminaires.is_empty();
    settings.shadow_boundaries.filter(|_| lit)
}

/// What casts every receiver's shadow boundaries: each light with the
/// points it is seen from (an area light's centre and vertices, a
/// photometric one's opening outline), the scene's edges for the
/// silhouettes, the zones and every surface's box for the occluders of a
/// receiver's own zone, and what a receiver keeps.
struct BoundaryCaster<'a> {
    area_lights: &'a [AreaLight],
    area_points: Vec<Vec<DVec3>>,
    photometric_points: Vec<Vec<DVec3>>,
    neighbours: EdgeNeighbours,
    zones: &'a ZoneLabels,
    boxes: SurfaceBoxes,
    limits: BoundaryLimits,
    /// The element edge: a receiver smaller than one element gets none.
    element: f64,
}

impl<'a> BoundaryCaster<'a> {
    fn new(
        scene: &Scene,
        area_lights: &'a [AreaLight],
        zones: &'a ZoneLabels,
        limits: BoundaryLimits,
        settings: &ResolvedMeshSettings,
    ) -> BoundaryCaster<'a> {
        let neighbours = EdgeNeighbours::new(scene);
        let area_points = area_lights
            .iter()
            .map(|lamp| {
                let corners = lamp
                    .surfaces
                    .iter()
                    .flat_map(|&s| scene.surface(s).vertices());
                std::iter::once(lamp.centre)
                    .chain(corners.copied())
                    .collect()
            })
            .collect();
        let photometric_points = scene
            .luminaires
            .iter()
            .map(|l| l.opening_corners())
            .collect();
        BoundaryCaster {
            area_lights,
            area_points,
            photometric_points,
            neighbours,
            zones,
            boxes: SurfaceBoxes::new(scene),
            limits,
            element: settings.square.max_edge,
        }
    }

    /// The boundaries the lights that reach `id` cast on it through the
    /// surfaces of its zone (`visibility`: its zone's BVH, or the scene's);
    /// none on an emitter or a surface smaller than one element.
    fn boundaries_on(
        &self,
        scene: &Scene,
        visibility: &Visibility,
        id: SurfaceId,
    ) -> Vec<[DVec2; 2]> {
        let (zones, boxes) = (self.zones, &self.boxes);
        let occluders = |low, high| {
            let mut near = boxes.near(low, high, 0.0);
            near.retain(|&other| zones.together(id, other));
            near
        };
        let surface = scene.surface(id);
        let emitting = scene.material_of(surface).is_emitter();
        if emitting || surface.area() < self.element * self.element {
            return Vec::new();
        }
        // Only the lights that reach the receiver cast boundaries on it.
        let lit: Vec<AreaLight> = self
            .area_lights
            .iter()
            .zip(&self.area_points)
            .filter(|(lamp, from)| {
                zones.together(id, lamp.surfaces[0])
                    && light_reaches(scene, visibility, id, from, lamp.surfaces[0])
            })
            .map(|(lamp, _)| lamp.clone())
            .collect();
        let points: Vec<DVec3> = self
            .photometric_points
            .iter()
            .filter(|from| light_reaches(scene, visibility, id, from, id))
            .flatten()
            .copied()
            .collect();
        let receiver = ShadowReceiver {
            surface: id,
            occluders: &occluders,
        };
        shadow_boundaries(
            scene,
            visibility,
            &self.neighbours,
            receiver,
            &lit,
            &points,
            self.limits,
        )
    }
}
