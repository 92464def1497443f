//! Which receiver gets which mesher, and the contour layouts of those lit by
//! a dominant small emitter.

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::mesh_settings::{MeshKind, MeshSettings};
use crate::lighting::{
    BoundaryLimits, DirectField, EdgeNeighbours, Luminaire, ReceiverAnalysis, analyse_receivers,
    dominant_field, light_reaches, luminaires, shadow_boundaries,
};
use crate::mesh::{
    ContourLayout, ContourSettings, Mesh, SurfaceGuides, contour_layout, mesh_surfaces,
};
use crate::scene::{Scene, SurfaceId, Visibility};

/// What meshing found: the luminaires, each receiver's analysis, and where
/// the contour mesher was used.
#[derive(Clone, Debug, Default)]
pub struct MeshAnalysis {
    /// One analysis per non-emitting surface (empty for square meshing).
    pub receivers: Vec<ReceiverAnalysis>,
    /// The luminaires the analysis grouped.
    pub luminaires: Vec<Luminaire>,
    /// Surfaces meshed by the contour mesher.
    pub contour_surfaces: Vec<SurfaceId>,
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
}

/// Meshes a scene as `settings` asks: for [`MeshKind::Contour`], every
/// receiver whose direct light comes mostly from one small luminaire gets a
/// contour layout of that luminaire's direct radiosity (with its shadow
/// boundaries refined), the rest the square grid. With
/// `settings.shadow_boundaries`, every mesher's elements follow the shadow
/// boundaries the luminaires cast (see [`scene_shadow_boundaries`]).
#[must_use]
pub fn mesh_scene(scene: &Scene, visibility: &Visibility, settings: &MeshSettings) -> SceneMesh {
    let square = settings.square_for(scene);
    let mut analysis = MeshAnalysis {
        luminaires: luminaires(scene),
        ..MeshAnalysis::default()
    };
    let boundaries = scene_shadow_boundaries(scene, visibility, &analysis.luminaires, settings);
    analysis.shadow_boundaries = boundaries.iter().map(Vec::len).sum();
    analysis.shadow_receivers = boundaries.iter().filter(|b| !b.is_empty()).count();
    if matches!(settings.kind, MeshKind::Square | MeshKind::Adaptive) {
        let mesh = mesh_surfaces(scene, &square, &|surface| SurfaceGuides {
            layout: None,
            boundaries: boundaries[surface.index()].clone(),
        });
        return SceneMesh { mesh, analysis };
    }
    analysis.receivers =
        analyse_receivers(scene, visibility, &analysis.luminaires, &settings.dominance);
    let layouts: Vec<Option<ContourLayout>> = scene
        .surfaces_with_ids()
        .map(|(surface, _)| {
            let found = analysis
                .receivers
                .iter()
                .find(|a| a.receiver == surface && a.qualifies)?;
            let field = dominant_field(scene, surface, &analysis.luminaires, found.dominant?)?;
            field_layout(scene, visibility, surface, field, &settings.contour)
        })
        .collect();
    for ((surface, _), layout) in scene.surfaces_with_ids().zip(&layouts) {
        if let Some(layout) = layout {
            analysis.contour_surfaces.push(surface);
            analysis.newton_iterations += layout.newton_iterations;
            analysis.newton_solves += layout.newton_solves;
        }
    }
    let mesh = mesh_surfaces(scene, &square, &|surface| SurfaceGuides {
        layout: layouts[surface.index()].clone(),
        boundaries: boundaries[surface.index()].clone(),
    });
    SceneMesh { mesh, analysis }
}

/// Shadow boundaries closer than this fraction of the element spacing are
/// one: the mesh cannot tell them apart.
const BOUNDARY_MIN_FEATURE: f64 = 0.25;

/// The most shadow boundaries one receiver gets, longest first.
const MAX_BOUNDARIES_PER_RECEIVER: usize = 256;

/// Every surface's shadow boundaries, indexed by surface, in its plane
/// coordinates, as `settings` meshes them: merged where closer than a
/// quarter of an element, at most 256 per receiver, longest first. Empty
/// for emitters, for surfaces smaller than one element (a line across would
/// only split them into slivers), and for all when
/// `settings.shadow_boundaries` is off. Only the lights that reach a
/// receiver cast boundaries on it ([`light_reaches`]): a lamp in another
/// closed room adds none. Computed in parallel.
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
    let square = settings.square_for(scene);
    let neighbours = EdgeNeighbours::new(scene);
    let limits = BoundaryLimits {
        min_feature: BOUNDARY_MIN_FEATURE * square.max_edge,
        max_per_receiver: MAX_BOUNDARIES_PER_RECEIVER,
    };
    // Each light with the points it is seen from: an area luminaire's
    // centre and vertices, a photometric one's opening outline.
    let area_points: Vec<Vec<DVec3>> = luminaires
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
    let photometric_points: Vec<Vec<DVec3>> = scene
        .luminaires
        .iter()
        .map(|l| l.opening_corners())
        .collect();
    let ids: Vec<SurfaceId> = scene.surfaces_with_ids().map(|(id, _)| id).collect();
    ids.par_iter()
        .map(|&id| {
            let surface = scene.surface(id);
            let emitting = scene.material_of(surface).is_emitter();
            if emitting || surface.area() < square.max_edge * square.max_edge {
                return Vec::new();
            }
            // Only the lights that reach the receiver cast boundaries on it.
            let lit: Vec<Luminaire> = luminaires
                .iter()
                .zip(&area_points)
                .filter(|(lamp, from)| light_reaches(scene, visibility, id, from, lamp.surfaces[0]))
                .map(|(lamp, _)| lamp.clone())
                .collect();
            let points: Vec<DVec3> = photometric_points
                .iter()
                .filter(|from| light_reaches(scene, visibility, id, from, id))
                .flatten()
                .copied()
                .collect();
            shadow_boundaries(scene, &neighbours, id, &lit, &points, limits)
        })
        .collect()
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
    let diameter = outline
        .iter()
        .flat_map(|a| outline.iter().map(move |b| a.distance(*b)))
        .fold(0.0, f64::max);
    let kink: Vec<[DVec2; 2]> = field
        .kink_line()
        .map(|(point, direction)| {
            vec![[
                point - direction * 2.0 * diameter,
                point + direction * 2.0 * diameter,
            ]]
        })
        .unwrap_or_default();
    let value = |p: DVec2| field.value_and_gradient(p);
    let mut layout = contour_layout(&outline, &value, centre, &settings, &kink);
    layout.refine_shadows(&|p: DVec2| field.visible_fraction(visibility, p, SHADOW_RAYS));
    Some(layout)
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
