//! Which receiver gets which mesher, and the contour layouts of those lit by
//! a dominant small emitter.

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::mesh_settings::{MeshKind, MeshSettings};
use super::zones::{ZoneLabels, Zones};
use crate::lighting::{
    BoundaryLimits, ContourMesher, DirectField, DominanceSettings, EdgeNeighbours, Luminaire,
    OccludersIn, ReceiverAnalysis, analyse_receivers, analyse_receivers_among, dominant_field,
    light_reaches, luminaires, shadow_boundaries,
};
use crate::mesh::{
    ContourLayout, ContourSettings, Mesh, SquareMeshSettings, SurfaceGuides, contour_layout,
    level_line_layout, mesh_surfaces_counted,
};
use crate::phase::{Phase, PhaseCounter, PhaseReporter, silent};
use crate::scene::{Scene, SurfaceBoxes, SurfaceId, Visibility};

/// What meshing found: the luminaires, each receiver's analysis, and where
/// the contour mesher was used.
#[derive(Clone, Debug, Default)]
pub struct MeshAnalysis {
    /// One analysis per non-emitting surface (empty for square meshing).
    pub receivers: Vec<ReceiverAnalysis>,
    /// The luminaires the analysis grouped.
    pub luminaires: Vec<Luminaire>,
    /// Surfaces meshed by the radial contour mesher.
    pub contour_surfaces: Vec<SurfaceId>,
    /// Surfaces meshed along the level lines of their total direct light.
    pub level_line_surfaces: Vec<SurfaceId>,
    /// Newton iterations spent on contour vertices, over all receivers.
    pub newton_iterations: usize,
    /// Contour vertices placed by Newton's method.
    pub newton_solves: usize,
    /// Shadow boundaries given to the meshers, over all receivers.
    pub shadow_boundaries: usize,
    /// Receivers with at least one shadow boundary.
    pub shadow_receivers: usize,
}

/// A meshed scene, with what the analysis found on each receiver.
pub struct SceneMesh {
    /// The mesh.
    pub mesh: Mesh,
    /// What the analysis found (empty for square meshing).
    pub analysis: MeshAnalysis,
    /// How far each surface's boundary vertices gather inside it, by
    /// surface index: a ten-thousandth of its room's diagonal
    /// (`Mesh::inset_boundary_receivers_by`); probes on a surface gather as
    /// far inside.
    pub receiver_insets: Vec<f64>,
}

/// Meshes a scene as `settings` asks: for [`MeshKind::Contour`], every
/// receiver whose direct light comes mostly from one small luminaire gets a
/// radial contour layout of that luminaire's direct radiosity (with its
/// shadow boundaries refined), every other receiver that direct light
/// reaches (several luminaires, or a large one) a level-line layout of the
/// total direct field ([`level_line_layout`]); receivers smaller than
/// 16 elements, and the rest, get the square grid. With
/// `settings.shadow_boundaries`, every mesher's elements follow the shadow
/// boundaries the luminaires cast (see [`scene_shadow_boundaries`]).
#[must_use]
pub fn mesh_scene(scene: &Scene, visibility: &Visibility, settings: &MeshSettings) -> SceneMesh {
    let lit = !luminaires(scene).is_empty() || !scene.luminaires.is_empty();
    let zones = lit.then(|| Zones::new(scene, visibility));
    mesh_scene_in_zones(scene, visibility, settings, zones.as_ref(), &silent)
}

/// [`mesh_scene`] with the scene's closed zones already found (`None`
/// for a scene without light, which gets no shadow boundaries nor
/// analyses): the solver finds them once, for meshing and for its shots.
/// Reports the shadow boundaries' and the meshing's progress to `report`.
pub(crate) fn mesh_scene_in_zones(
    scene: &Scene,
    visibility: &Visibility,
    settings: &MeshSettings,
    zones: Option<&Zones>,
    report: PhaseReporter,
) -> SceneMesh {
    let square = settings.square_for(scene);
    let mut analysis = MeshAnalysis {
        luminaires: luminaires(scene),
        ..MeshAnalysis::default()
    };
    let boundaries = match zones {
        Some(zones) => {
            let luminaires = &analysis.luminaires;
            boundaries_in_zones(scene, visibility, luminaires, settings, zones, report)
        }
        None => vec![Vec::new(); scene.surfaces.len()],
    };
    let contact_scales = contact_scales(scene, zones);
    analysis.shadow_boundaries = boundaries.iter().map(Vec::len).sum();
    analysis.shadow_receivers = boundaries.iter().filter(|b| !b.is_empty()).count();
    if matches!(settings.kind, MeshKind::Square | MeshKind::Adaptive) {
        let guides = |surface: SurfaceId| SurfaceGuides {
            layout: None,
            boundaries: boundaries[surface.index()].clone(),
            contact_scale: contact_scales[surface.index()],
        };
        let (mesh, receiver_insets) =
            mesh_surfaces_counted(scene, Some(visibility), &square, &guides, report);
        return SceneMesh {
            mesh,
            analysis,
            receiver_insets,
        };
    }
    let counter = PhaseCounter::start(Phase::ContourLayouts, scene.surfaces.len(), report);
    analysis.receivers = match zones {
        Some(zones) => analyses_in_zones(
            scene,
            visibility,
            &analysis.luminaires,
            &settings.dominance,
            zones,
        ),
        None => analyse_receivers(scene, visibility, &analysis.luminaires, &settings.dominance),
    };
    let mut analysed = vec![None; scene.surfaces.len()];
    for (k, receiver) in analysis.receivers.iter().enumerate() {
        analysed[receiver.receiver.index()] = Some(k);
    }
    let layouts: Vec<Option<ContourLayout>> = scene
        .surfaces_with_ids()
        .map(|(surface, _)| {
            let found = &analysis.receivers[analysed[surface.index()]?];
            // A receiver of a few elements: its grid follows the light as
            // well as contours would.
            let spacing = square.max_edge;
            if scene.surface(surface).area() < MIN_CONTOUR_ELEMENTS * spacing * spacing {
                return None;
            }
            let fields: Vec<DirectField> = found
                .contour_lights()
                .into_iter()
                .filter_map(|k| dominant_field(scene, surface, &analysis.luminaires, k))
                .collect();
            let layout = match found.contour_mesher() {
                ContourMesher::Radial => {
                    let field = fields.into_iter().next()?;
                    field_layout(scene, visibility, surface, field, &settings.contour)
                }
                ContourMesher::LevelLines => {
                    total_field_layout(scene, surface, &fields, &settings.contour, &square)
                }
                ContourMesher::Square => None,
            }?;
            // A layout that would cost more than a finer square grid does
            // not pay: the square grid then.
            let budget = layout_budget(scene, surface, spacing);
            (layout.points.len() <= budget).then_some(layout)
        })
        .inspect(|_| counter.add(1))
        .collect();
    counter.finish();
    for ((surface, _), layout) in scene.surfaces_with_ids().zip(&layouts) {
        let Some(layout) = layout else { continue };
        let radial = analysed[surface.index()].is_some_and(|k| analysis.receivers[k].qualifies);
        if radial {
            analysis.contour_surfaces.push(surface);
        } else {
            analysis.level_line_surfaces.push(surface);
        }
        analysis.newton_iterations += layout.newton_iterations;
        analysis.newton_solves += layout.newton_solves;
    }
    let guides = |surface: SurfaceId| SurfaceGuides {
        layout: layouts[surface.index()].clone(),
        boundaries: boundaries[surface.index()].clone(),
        contact_scale: contact_scales[surface.index()],
    };
    let (mesh, receiver_insets) =
        mesh_surfaces_counted(scene, Some(visibility), &square, &guides, report);
    SceneMesh {
        mesh,
        analysis,
        receiver_insets,
    }
}

/// The diagonal of each surface's zone (`None` without zones): the length
/// its contact tolerance is a fraction of, so that the rooms of a building
/// mesh as each would alone (`mesh::SurfaceGuides::contact_scale`).
fn contact_scales(scene: &Scene, zones: Option<&Zones>) -> Vec<Option<f64>> {
    let Some(zones) = zones else {
        return vec![None; scene.surfaces.len()];
    };
    let mut bounds = vec![(DVec3::INFINITY, DVec3::NEG_INFINITY); zones.count().max(1)];
    for (id, surface) in scene.surfaces_with_ids() {
        let (lo, hi) = surface.bounds();
        if let Some(zone) = bounds.get_mut(zones.of(id)) {
            *zone = (zone.0.min(lo), zone.1.max(hi));
        }
    }
    scene
        .surfaces_with_ids()
        .map(|(id, _)| {
            let (lo, hi) = bounds.get(zones.of(id))?;
            let diagonal = (*hi - *lo).length();
            (diagonal.is_finite() && diagonal > 0.0).then_some(diagonal)
        })
        .collect()
}

/// Receivers smaller than this many square elements keep the square grid
/// under the contour meshers.
const MIN_CONTOUR_ELEMENTS: f64 = 16.0;

/// A contour layout with more points than this many times the square
/// grid's (plus 256) is dropped for the grid: near a luminaire's plane,
/// where the light of several lamps fans out along the receiver's edge,
/// level lines can crowd without bound.
pub(crate) const MAX_LAYOUT_GRID_RATIO: f64 = 4.0;

/// Points a contour layout may have beyond [`MAX_LAYOUT_GRID_RATIO`] times
/// its grid's: room for the levels on a receiver of a few elements.
pub(crate) const LAYOUT_EXTRA_POINTS: f64 = 256.0;

/// Shadow boundaries closer than this fraction (3/16) of the element
/// spacing are one: the mesh cannot tell them apart. A table leg's shadow
/// is a strip whose edges converge towards the leg's foot; merged at a
/// quarter of an element, the strip kept one edge over most of its length,
/// and the triangles from that edge's dark vertices across the lit side
/// left a dark wedge beside each leg's shadow in `scenes/room` (the room's
/// per-pixel error against Mitsuba 1.99 %, and 1.82 % at 3/16, by
/// `bench/compare_images.py`; the golden test's 1.97 % and 1.83 %). Finer
/// merging costs vertices for little (measured once each, by hand): an
/// eighth gives the room 1.86 % and the gather probes in the table's umbra
/// 1.5 % too much light (0.5 % at 3/16, the golden test's figure), a
/// twentieth 1.74 % for twice the office's time.
const BOUNDARY_MIN_FEATURE: f64 = 0.1875;

/// Every surface's shadow boundaries, indexed by surface, in its plane
/// coordinates, as `settings` meshes them: merged where closer than 3/16
/// of an element, at most `settings.max_shadow_boundaries` per receiver,
/// longest first. Empty
/// for emitters, for surfaces smaller than one element (a line across would
/// only split them into slivers), and for all when
/// `settings.shadow_boundaries` is off. Only the lights that reach a
/// receiver cast boundaries on it ([`light_reaches`]), and only the
/// luminaires and occluders of its own closed zone (a room whose doors are
/// shut, `zones.rs`) are tried: a lamp in another closed room adds none,
/// and a building of separate rooms costs what its rooms cost alone.
/// Computed in parallel.
#[must_use]
pub fn scene_shadow_boundaries(
    scene: &Scene,
    visibility: &Visibility,
    luminaires: &[Luminaire],
    settings: &MeshSettings,
) -> Vec<Vec<[DVec2; 2]>> {
    if (luminaires.is_empty() && scene.luminaires.is_empty()) || !settings.shadow_boundaries {
        return vec![Vec::new(); scene.surfaces.len()];
    }
    let zones = Zones::new(scene, visibility);
    boundaries_in_zones(scene, visibility, luminaires, settings, &zones, &silent)
}

/// [`scene_shadow_boundaries`] with the scene's closed zones found,
/// reporting its progress receiver by receiver.
fn boundaries_in_zones(
    scene: &Scene,
    visibility: &Visibility,
    luminaires: &[Luminaire],
    settings: &MeshSettings,
    zones: &Zones,
    report: PhaseReporter,
) -> Vec<Vec<[DVec2; 2]>> {
    if (luminaires.is_empty() && scene.luminaires.is_empty()) || !settings.shadow_boundaries {
        return vec![Vec::new(); scene.surfaces.len()];
    }
    let counter = PhaseCounter::start(Phase::ShadowBoundaries, scene.surfaces.len(), report);
    let square = settings.square_for(scene);
    let neighbours = EdgeNeighbours::new(scene);
    let limits = BoundaryLimits {
        min_feature: BOUNDARY_MIN_FEATURE * square.max_edge,
        max_per_receiver: settings.max_shadow_boundaries,
    };
    let ids: Vec<SurfaceId> = scene.surfaces_with_ids().map(|(id, _)| id).collect();
    let lights = LightPoints::new(scene, luminaires);
    let boxes = SurfaceBoxes::new(scene);
    let boundaries = ids
        .par_iter()
        .map(|&id| {
            let zone = zones.of(id);
            let receiver = (id, (zones.labels(), &boxes));
            let found = lights.boundaries_on(
                scene,
                zones.visibility(zone).unwrap_or(visibility),
                &neighbours,
                receiver,
                limits,
                square.max_edge,
            );
            counter.add(1);
            found
        })
        .collect();
    counter.finish();
    boundaries
}

/// What [`analyse_receivers`] finds on every receiver, each paired only
/// with the luminaires of its own closed zone
/// ([`analyse_receivers_among`]): as `mesh_scene` analyses them.
#[must_use]
pub fn scene_receiver_analyses(
    scene: &Scene,
    visibility: &Visibility,
    luminaires: &[Luminaire],
    settings: &DominanceSettings,
) -> Vec<ReceiverAnalysis> {
    let zones = Zones::new(scene, visibility);
    analyses_in_zones(scene, visibility, luminaires, settings, &zones)
}

/// [`scene_receiver_analyses`] with the scene's closed zones found: each
/// receiver gets the area luminaires of its zone, and every photometric
/// one (a point, in no zone).
fn analyses_in_zones(
    scene: &Scene,
    visibility: &Visibility,
    luminaires: &[Luminaire],
    settings: &DominanceSettings,
    zones: &Zones,
) -> Vec<ReceiverAnalysis> {
    let mut per_zone = vec![Vec::new(); zones.count()];
    for (k, lamp) in luminaires.iter().enumerate() {
        if let Some(&surface) = lamp.surfaces.first() {
            per_zone[zones.of(surface)].push(k);
        }
    }
    let photometric = luminaires.len()..luminaires.len() + scene.luminaires.len();
    for lights in &mut per_zone {
        lights.extend(photometric.clone());
    }
    let room_of = |receiver| {
        let zone = zones.of(receiver);
        let inside = zones.visibility(zone).unwrap_or(visibility);
        (inside, per_zone[zone].clone())
    };
    analyse_receivers_among(scene, luminaires, settings, &room_of)
}

/// The shadow boundaries on one receiver, as [`scene_shadow_boundaries`]
/// finds them for every surface.
#[must_use]
pub fn receiver_shadow_boundaries(
    scene: &Scene,
    visibility: &Visibility,
    luminaires: &[Luminaire],
    settings: &MeshSettings,
    receiver: SurfaceId,
) -> Vec<[DVec2; 2]> {
    if (luminaires.is_empty() && scene.luminaires.is_empty()) || !settings.shadow_boundaries {
        return Vec::new();
    }
    let square = settings.square_for(scene);
    let limits = BoundaryLimits {
        min_feature: BOUNDARY_MIN_FEATURE * square.max_edge,
        max_per_receiver: settings.max_shadow_boundaries,
    };
    let zones = Zones::new(scene, visibility);
    let zone = zones.of(receiver);
    let boxes = SurfaceBoxes::new(scene);
    let room = (zones.labels(), &boxes);
    LightPoints::new(scene, luminaires).boundaries_on(
        scene,
        zones.visibility(zone).unwrap_or(visibility),
        &EdgeNeighbours::new(scene),
        (receiver, room),
        limits,
        square.max_edge,
    )
}

/// Each light with the points it is seen from: an area luminaire's centre
/// and vertices, a photometric one's opening outline.
struct LightPoints<'a> {
    luminaires: &'a [Luminaire],
    area_points: Vec<Vec<DVec3>>,
    photometric_points: Vec<Vec<DVec3>>,
}

impl<'a> LightPoints<'a> {
    fn new(scene: &Scene, luminaires: &'a [Luminaire]) -> LightPoints<'a> {
        let area_points = luminaires
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
        LightPoints {
            luminaires,
            area_points,
            photometric_points,
        }
    }

    /// The boundaries the lights that reach `id` cast on it through the
    /// surfaces of its zone (`room`: the zones, and every surface's box);
    /// none on an emitter or a surface smaller than one element of
    /// `element` size.
    fn boundaries_on(
        &self,
        scene: &Scene,
        visibility: &Visibility,
        neighbours: &EdgeNeighbours,
        (id, room): (SurfaceId, (&ZoneLabels, &SurfaceBoxes)),
        limits: BoundaryLimits,
        element: f64,
    ) -> Vec<[DVec2; 2]> {
        let (zones, boxes) = room;
        let occluders = |low, high| {
            let mut near = boxes.near(low, high, 0.0);
            near.retain(|&other| zones.together(id, other));
            near
        };
        let surface = scene.surface(id);
        let emitting = scene.material_of(surface).is_emitter();
        if emitting || surface.area() < element * element {
            return Vec::new();
        }
        // Only the lights that reach the receiver cast boundaries on it.
        let lit: Vec<Luminaire> = self
            .luminaires
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
        let receiver = (id, &occluders as OccludersIn<'_>);
        shadow_boundaries(
            (scene, visibility),
            neighbours,
            receiver,
            &lit,
            &points,
            limits,
        )
    }
}

/// Shadow rays per luminaire polygon when looking for penumbrae.
const SHADOW_RAYS: usize = 16;

/// The contour layout of a luminaire's direct light on a receiver: centred
/// on the light's maximum, the first ray along the luminaire's tilt, the line
/// where its plane meets the receiver's kept as an edge, and penumbrae
/// (where 5 %, 50 % and 95 % of the luminaire is hidden) given vertices.
#[must_use]
pub fn receiver_layout(
    scene: &Scene,
    visibility: &Visibility,
    receiver: SurfaceId,
    luminaire: &Luminaire,
    settings: &ContourSettings,
) -> Option<ContourLayout> {
    let field = DirectField::new(scene, receiver, luminaire)?;
    field_layout(scene, visibility, receiver, field, settings)
}

/// The contour layout of `field` (an area or a photometric luminaire's
/// direct light) on `receiver`, as [`receiver_layout`] builds it.
#[must_use]
pub fn field_layout(
    scene: &Scene,
    visibility: &Visibility,
    receiver: SurfaceId,
    field: DirectField,
    settings: &ContourSettings,
) -> Option<ContourLayout> {
    let centre = field.maximum()?;
    let outline = scene.surface(receiver).plane_vertices();
    let mut settings = settings.clone();
    settings.orientation = tilt_angle(&field, centre);
    let kink: Vec<[DVec2; 2]> = horizon_segment(&field, &outline).into_iter().collect();
    let value = |p: DVec2| field.value_and_gradient(p);
    let mut layout = contour_layout(&outline, &value, centre, &settings, &kink);
    layout.refine_shadows(&|p: DVec2| field.visible_fraction(visibility, p, SHADOW_RAYS));
    Some(layout)
}

/// The level-line layout of the total direct field of `fields` on
/// `receiver` (the sum of their values and gradients), with each field's
/// horizon kept as an edge and points at the square grid's spacing filling
/// regions no level line comes near (the indirect light needs them); None
/// for a receiver smaller than 16 elements, whose grid already follows its
/// light as well as lines would, and where the lines would need more points
/// than four times its square grid.
#[must_use]
pub fn total_field_layout(
    scene: &Scene,
    receiver: SurfaceId,
    fields: &[DirectField],
    settings: &ContourSettings,
    square: &SquareMeshSettings,
) -> Option<ContourLayout> {
    let surface = scene.surface(receiver);
    let spacing = square.max_edge;
    if fields.is_empty() || surface.area() < MIN_CONTOUR_ELEMENTS * spacing * spacing {
        return None;
    }
    let outline = surface.plane_vertices();
    let horizons: Vec<[DVec2; 2]> = fields
        .iter()
        .filter_map(|field| horizon_segment(field, &outline))
        .collect();
    let total = |p: DVec2| {
        fields
            .iter()
            .fold((0.0, DVec2::ZERO), |(value, gradient), field| {
                let (v, g) = field.value_and_gradient(p);
                (value + v, gradient + g)
            })
    };
    let budget = layout_budget(scene, receiver, spacing);
    level_line_layout(&outline, &total, settings, &horizons, spacing, budget)
}

/// The line where the luminaire's plane cuts the receiver's, beyond which
/// its light ends, as a segment reaching past the receiver's `outline` on
/// both sides.
fn horizon_segment(field: &DirectField, outline: &[DVec2]) -> Option<[DVec2; 2]> {
    let (point, direction) = field.kink_line()?;
    let diameter = outline
        .iter()
        .flat_map(|a| outline.iter().map(move |b| a.distance(*b)))
        .fold(0.0, f64::max);
    Some([
        point - direction * 2.0 * diameter,
        point + direction * 2.0 * diameter,
    ])
}

/// The most points a contour layout of `receiver` may have:
/// [`MAX_LAYOUT_GRID_RATIO`] times its square grid's, plus
/// [`LAYOUT_EXTRA_POINTS`].
fn layout_budget(scene: &Scene, receiver: SurfaceId, spacing: f64) -> usize {
    let area = scene.surface(receiver).area();
    (MAX_LAYOUT_GRID_RATIO * area / (spacing * spacing) + LAYOUT_EXTRA_POINTS).min(1e9) as usize
}

/// The direction, in the receiver's plane, from the foot of the luminaire's
/// perpendicular to the light's maximum: where a tilted lamp leans.
fn tilt_angle(field: &DirectField, centre: DVec2) -> f64 {
    let foot = field.frame().to_plane(field.centre());
    let lean = centre - foot;
    if lean.length() > 1e-9 * field.length_scale() {
        lean.y.atan2(lean.x)
    } else {
        0.0
    }
}
