//! A scene meshed as its settings ask: which receiver gets which mesher,
//! each along its contour layout and shadow boundaries.

use crate::scene::Box3;
use glam::DVec3;

use super::analyses::analyses_in_zones;
use super::boundaries::boundaries_in_zones;
use super::layouts::{MIN_CONTOUR_ELEMENTS, field_layout, layout_budget, total_field_layout};
use super::resolved::ResolvedMeshSettings;
use super::settings::{MeshKind, MeshSettings};
use super::zones::Zones;
use crate::lighting::{
    AreaLight, ContourMesher, DirectField, ReceiverAnalysis, analyse_receivers, area_lights,
    dominant_field,
};
use crate::mesh::{ContourLayout, Mesh, SurfaceGuides, mesh_surfaces_counted};
use crate::phase::{Phase, PhaseCounter, PhaseReporter, silent};
use crate::scene::{Scene, SurfaceId, Visibility};

/// What meshing found: the area lights, each receiver's analysis, and where
/// the contour mesher was used.
#[derive(Clone, Debug, Default)]
pub struct MeshAnalysis {
    /// One analysis per non-emitting surface (empty for square meshing).
    pub receivers: Vec<ReceiverAnalysis>,
    /// The area lights: the scene's emitting surfaces grouped into lamps.
    pub area_lights: Vec<AreaLight>,
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
/// receiver whose direct light comes mostly from one small light gets a
/// radial contour layout of that light's direct radiosity (with its
/// shadow boundaries refined), every other receiver that direct light
/// reaches (several lights, or a large one) a level-line layout of the
/// total direct field ([`crate::mesh::level_line_layout`]); receivers smaller than
/// 16 elements, and the rest, get the square grid. With
/// `settings.shadow_boundaries`, every mesher's elements follow the shadow
/// boundaries the lights cast (see [`super::scene_shadow_boundaries`]).
#[must_use]
pub fn mesh_scene(scene: &Scene, visibility: &Visibility, settings: &MeshSettings) -> SceneMesh {
    let lit = !area_lights(scene).is_empty() || !scene.luminaires.is_empty();
    let zones = lit.then(|| Zones::new(scene, visibility));
    let settings = settings.resolve(scene);
    mesh_scene_in_zones(scene, visibility, &settings, zones.as_ref(), &silent)
}

/// [`mesh_scene`] with the scene's closed zones already found (`None`
/// for a scene without light, which gets no shadow boundaries nor
/// analyses): the solver finds them once, for meshing and for its shots.
/// Reports the shadow boundaries' and the meshing's progress to `report`.
pub(crate) fn mesh_scene_in_zones(
    scene: &Scene,
    visibility: &Visibility,
    settings: &ResolvedMeshSettings,
    zones: Option<&Zones>,
    report: PhaseReporter,
) -> SceneMesh {
    let mut analysis = MeshAnalysis {
        area_lights: area_lights(scene),
        ..MeshAnalysis::default()
    };
    // The shadow boundaries each receiver follows, found in its own zone.
    let boundaries = match zones {
        Some(zones) => {
            let area_lights = &analysis.area_lights;
            boundaries_in_zones(scene, visibility, area_lights, settings, zones, report)
        }
        None => vec![Vec::new(); scene.surfaces.len()],
    };
    let contact_scales = contact_scales(scene, zones);
    analysis.shadow_boundaries = boundaries.iter().map(Vec::len).sum();
    analysis.shadow_receivers = boundaries.iter().filter(|b| !b.is_empty()).count();
    // The contour layouts, under the contour meshers only.
    let layouts = match settings.kind {
        MeshKind::Square | MeshKind::Adaptive => vec![None; scene.surfaces.len()],
        MeshKind::Contour => {
            let layouts =
                contour_layouts(scene, visibility, settings, zones, &mut analysis, report);
            analysis.count_layouts(scene, &layouts);
            layouts
        }
    };
    // Every surface meshed along its layout and boundaries.
    let guides = |surface: SurfaceId| SurfaceGuides {
        layout: layouts[surface.index()].clone(),
        boundaries: boundaries[surface.index()].clone(),
        contact_scale: contact_scales[surface.index()],
    };
    let (mesh, receiver_insets) =
        mesh_surfaces_counted(scene, Some(visibility), &settings.square, &guides, report);
    SceneMesh {
        mesh,
        analysis,
        receiver_insets,
    }
}

/// Each surface's contour layout, by surface index (`None` for the square
/// grid), with the receivers' analyses stored in `analysis`; reports the
/// layouts' progress to `report`.
fn contour_layouts(
    scene: &Scene,
    visibility: &Visibility,
    settings: &ResolvedMeshSettings,
    zones: Option<&Zones>,
    analysis: &mut MeshAnalysis,
    report: PhaseReporter,
) -> Vec<Option<ContourLayout>> {
    let counter = PhaseCounter::start(Phase::ContourLayouts, scene.surfaces.len(), report);
    let lights = &analysis.area_lights;
    analysis.receivers = match zones {
        // Reported as part of the contour layouts.
        Some(zones) => analyses_in_zones(
            scene,
            visibility,
            lights,
            &settings.dominance,
            zones,
            &silent,
        ),
        None => analyse_receivers(scene, visibility, lights, &settings.dominance),
    };
    let analysed = analysed_index(scene, &analysis.receivers);
    let layouts = scene
        .surfaces_with_ids()
        .map(|(surface, _)| {
            let found = &analysis.receivers[analysed[surface.index()]?];
            receiver_contour_layout(scene, visibility, surface, found, lights, settings)
        })
        .inspect(|_| counter.add(1))
        .collect();
    counter.finish();
    layouts
}

/// Each surface's place in `receivers`, by surface index.
fn analysed_index(scene: &Scene, receivers: &[ReceiverAnalysis]) -> Vec<Option<usize>> {
    let mut analysed = vec![None; scene.surfaces.len()];
    for (k, receiver) in receivers.iter().enumerate() {
        analysed[receiver.receiver.index()] = Some(k);
    }
    analysed
}

/// The contour layout `found` asks for on `surface` (radial, level lines,
/// or none), or `None` where the square grid does as well: on a receiver
/// of a few elements, or where the layout would cost more than a finer
/// grid.
fn receiver_contour_layout(
    scene: &Scene,
    visibility: &Visibility,
    surface: SurfaceId,
    found: &ReceiverAnalysis,
    area_lights: &[AreaLight],
    settings: &ResolvedMeshSettings,
) -> Option<ContourLayout> {
    // A receiver of a few elements: its grid follows the light as well as
    // contours would.
    let spacing = settings.square.max_edge;
    if scene.surface(surface).area() < MIN_CONTOUR_ELEMENTS * spacing * spacing {
        return None;
    }
    let fields: Vec<DirectField> = found
        .contour_lights()
        .into_iter()
        .filter_map(|k| dominant_field(scene, surface, area_lights, k))
        .collect();
    let layout = match found.contour_mesher() {
        ContourMesher::Radial => {
            let field = fields.into_iter().next()?;
            field_layout(scene, visibility, surface, field, &settings.contour)
        }
        ContourMesher::LevelLines => {
            total_field_layout(scene, surface, &fields, &settings.contour, &settings.square)
        }
        ContourMesher::Square => None,
    }?;
    // A layout that would cost more than a finer square grid does not pay:
    // the square grid then.
    let budget = layout_budget(scene, surface, spacing);
    (layout.points.len() <= budget).then_some(layout)
}

impl MeshAnalysis {
    /// Records which surfaces got which contour layout (`layouts`, by
    /// surface index) and the Newton work their vertices took.
    fn count_layouts(&mut self, scene: &Scene, layouts: &[Option<ContourLayout>]) {
        let analysed = analysed_index(scene, &self.receivers);
        for ((surface, _), layout) in scene.surfaces_with_ids().zip(layouts) {
            let Some(layout) = layout else { continue };
            let radial = analysed[surface.index()].is_some_and(|k| self.receivers[k].qualifies);
            if radial {
                self.contour_surfaces.push(surface);
            } else {
                self.level_line_surfaces.push(surface);
            }
            self.newton_iterations += layout.newton_iterations;
            self.newton_solves += layout.newton_solves;
        }
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
        let Box3 { min: lo, max: hi } = surface.bounds();
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
