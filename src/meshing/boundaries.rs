//! The shadow boundaries each receiver's mesh follows: those the lights of
//! its own closed zone cast on it through that zone's occluders
//! (`lighting::shadow_boundaries` finds them on one receiver).

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::analyses::closed_zones;
use super::resolved::ResolvedMeshSettings;
use super::zones::{ZoneLabels, Zones};
use crate::lighting::{
    AreaLight, BoundaryLimits, EdgeNeighbours, OccludersIn, ShadowReceiver, light_reaches,
    shadow_boundaries,
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
    let sunlit = scene
        .daylight
        .as_ref()
        .and_then(|d| d.sun_direction())
        .is_some();
    let lit = !area_lights.is_empty() || !scene.luminaires.is_empty() || sunlit;
    settings.shadow_boundaries.filter(|_| lit)
}

/// How far toward the sun its point stands, in scene diagonals: its rays
/// across the scene are then parallel to 0.006°, well inside the sun's own
/// 0.53°.
const SUN_DISTANCE: f64 = 1e4;

/// The sun as a caster of shadow boundaries: a point far along its
/// direction, and what it shines through. Glazing does not stop it: the
/// scene's BVH without the panes, when there are any.
struct SunCaster {
    point: [DVec3; 1],
    /// The BVH and edges without the panes, when there are any.
    clear: Option<ClearOfGlazing>,
}

/// A scene's BVH and edge index without its glazing.
struct ClearOfGlazing {
    visibility: Visibility,
    neighbours: EdgeNeighbours,
}

impl SunCaster {
    /// The scene's sun, if it shines.
    fn of_scene(scene: &Scene) -> Option<SunCaster> {
        let direction = scene.daylight.as_ref()?.sun_direction()?;
        let bounds = scene.bounds();
        let centre = (bounds.min + bounds.max) / 2.0;
        let glazing = |id: SurfaceId| scene.material_of(scene.surface(id)).is_glazing();
        let glazed = scene.surfaces_with_ids().any(|(id, _)| glazing(id));
        Some(SunCaster {
            point: [centre + direction * (SUN_DISTANCE * scene.diagonal().max(1e-9))],
            clear: glazed.then(|| ClearOfGlazing {
                visibility: Visibility::of_surfaces(scene, |id| !glazing(id)),
                neighbours: EdgeNeighbours::of_surfaces(scene, |id| !glazing(id)),
            }),
        })
    }
}

/// A receiver of the sun's boundaries: its surface, its zone's BVH (the
/// sun's own when glazing is in the way) and its zone's occluders.
#[derive(Clone, Copy)]
struct SunReceiver<'a> {
    surface: SurfaceId,
    visibility: &'a Visibility,
    occluders: OccludersIn<'a>,
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
    /// The sun, when it shines.
    sun: Option<SunCaster>,
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
            sun: SunCaster::of_scene(scene),
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
        let mut found = shadow_boundaries(
            scene,
            visibility,
            &self.neighbours,
            receiver,
            &lit,
            &points,
            self.limits,
        );
        if let Some(sun) = &self.sun {
            let place = SunReceiver {
                surface: id,
                visibility,
                occluders: &occluders,
            };
            self.add_sun_boundaries(scene, sun, place, &mut found);
        }
        found
    }

    /// The sun's boundaries on `id`, through every occluder but glazing,
    /// added to `found`, the longest kept to the receiver's limit.
    fn add_sun_boundaries(
        &self,
        scene: &Scene,
        sun: &SunCaster,
        place: SunReceiver<'_>,
        found: &mut Vec<[DVec2; 2]>,
    ) {
        let (id, occluders) = (place.surface, place.occluders);
        let (visibility, neighbours) = match &sun.clear {
            Some(clear) => (&clear.visibility, &clear.neighbours),
            None => (place.visibility, &self.neighbours),
        };
        if !light_reaches(scene, visibility, id, &sun.point, id) {
            return;
        }
        let opaque = |low, high| {
            let mut near = occluders(low, high);
            near.retain(|&o| !scene.material_of(scene.surface(o)).is_glazing());
            near
        };
        let receiver = ShadowReceiver {
            surface: id,
            occluders: &opaque,
        };
        let sunlit = shadow_boundaries(
            scene,
            visibility,
            neighbours,
            receiver,
            &[],
            &sun.point,
            self.limits,
        );
        if sunlit.is_empty() {
            return;
        }
        found.extend(sunlit);
        let length = |s: &[DVec2; 2]| s[0].distance(s[1]);
        found.sort_by(|a, b| length(b).total_cmp(&length(a)));
        found.truncate(self.limits.max_per_receiver);
    }
}
