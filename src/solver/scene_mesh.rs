//! Which receiver gets which mesher, and the contour layouts of those lit by
//! a dominant small emitter.

use glam::DVec2;

use super::direct_field::DirectField;
use super::dominance::{DominanceSettings, ReceiverAnalysis, analyse_receivers};
use super::emitters::{Luminaire, luminaires};
use crate::mesh::{
    ContourLayout, ContourSettings, Mesh, SquareMeshSettings, contour_layout, mesh_surfaces,
};
use crate::scene::{Scene, Visibility};

/// Which mesher meshes the receivers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MeshKind {
    /// A uniform grid everywhere.
    #[default]
    Square,
    /// The radial contour-level mesher on receivers lit by a dominant small
    /// emitter, the square grid on the rest.
    Contour,
}

impl std::str::FromStr for MeshKind {
    type Err = crate::Error;

    fn from_str(name: &str) -> crate::Result<Self> {
        match name {
            "square" => Ok(MeshKind::Square),
            "contour" => Ok(MeshKind::Contour),
            other => Err(crate::Error::InvalidSetting {
                name: "mesh".into(),
                message: format!("`{other}` is not one of square, contour"),
            }),
        }
    }
}

/// How a scene is meshed.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct MeshSettings {
    /// Square or contour.
    pub kind: MeshKind,
    /// The square grid (also the patches of contour-meshed receivers).
    pub square: SquareMeshSettings,
    /// D and K of the contour mesher.
    pub contour: ContourSettings,
    /// What makes a receiver qualify for the contour mesher.
    pub dominance: DominanceSettings,
    /// The most elements [`MeshSettings::check_budget`] allows (estimated
    /// before meshing): a guard against settings that would exhaust memory.
    /// Raise it to mesh a scene that truly needs more.
    pub max_elements: usize,
}

impl MeshSettings {
    /// Square meshing with defaults scaled to the scene.
    #[must_use]
    pub fn for_scene(scene: &Scene) -> MeshSettings {
        MeshSettings {
            kind: MeshKind::Square,
            square: SquareMeshSettings::for_scene(scene),
            contour: ContourSettings::default(),
            dominance: DominanceSettings::default(),
            max_elements: MeshSettings::DEFAULT_MAX_ELEMENTS,
        }
    }
}

/// A meshed scene, with what the analysis found on each receiver.
pub struct SceneMesh {
    /// The mesh.
    pub mesh: Mesh,
    /// One analysis per non-emitting surface (empty for square meshing).
    pub receivers: Vec<ReceiverAnalysis>,
    /// The luminaires the analysis grouped.
    pub luminaires: Vec<Luminaire>,
    /// Surfaces meshed by the contour mesher.
    pub contour_surfaces: Vec<usize>,
    /// Newton iterations spent on contour vertices, over all receivers.
    pub newton_iterations: usize,
    /// Contour vertices placed by Newton's method.
    pub newton_solves: usize,
}

/// Meshes a scene as `settings` asks: for [`MeshKind::Contour`], every
/// receiver whose direct light comes mostly from one small luminaire gets a
/// contour layout of that luminaire's direct radiosity (with its shadow
/// boundaries refined), the rest the square grid.
#[must_use]
pub fn mesh_scene(scene: &Scene, visibility: &Visibility, settings: &MeshSettings) -> SceneMesh {
    let mut result = SceneMesh {
        mesh: Mesh::default(),
        receivers: Vec::new(),
        luminaires: Vec::new(),
        contour_surfaces: Vec::new(),
        newton_iterations: 0,
        newton_solves: 0,
    };
    if settings.kind == MeshKind::Square {
        result.mesh = mesh_surfaces(scene, &settings.square, &|_| None);
        return result;
    }
    result.luminaires = luminaires(scene);
    result.receivers =
        analyse_receivers(scene, visibility, &result.luminaires, &settings.dominance);
    let layouts: Vec<Option<ContourLayout>> = (0..scene.surfaces.len())
        .map(|surface| {
            let analysis = result
                .receivers
                .iter()
                .find(|a| a.receiver == surface && a.qualifies)?;
            let luminaire = &result.luminaires[analysis.dominant?];
            receiver_layout(scene, visibility, surface, luminaire, &settings.contour)
        })
        .collect();
    for (surface, layout) in layouts.iter().enumerate() {
        if let Some(layout) = layout {
            result.contour_surfaces.push(surface);
            result.newton_iterations += layout.newton_iterations;
            result.newton_solves += layout.newton_solves;
        }
    }
    result.mesh = mesh_surfaces(scene, &settings.square, &|surface| layouts[surface].clone());
    result
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
    receiver: usize,
    luminaire: &Luminaire,
    settings: &ContourSettings,
) -> Option<ContourLayout> {
    let field = DirectField::new(scene, receiver, luminaire)?;
    let centre = field.maximum()?;
    let outline = scene.surfaces[receiver].plane_vertices();
    let mut settings = settings.clone();
    settings.orientation = tilt_angle(&field, luminaire, centre);
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
fn tilt_angle(field: &DirectField, luminaire: &Luminaire, centre: DVec2) -> f64 {
    let foot = field.frame().to_plane(luminaire.centre);
    let lean = centre - foot;
    if lean.length() > 1e-9 * field.scale() {
        lean.y.atan2(lean.x)
    } else {
        0.0
    }
}
