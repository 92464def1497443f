//! Which receiver gets which mesher, and the contour layouts of those lit by
//! a dominant small emitter.

use glam::DVec2;

use super::direct_field::DirectField;
use super::dominance::{DominanceSettings, ReceiverAnalysis, analyse_receivers};
use super::emitters::{Luminaire, luminaires};
use super::refinement::RefinementSettings;
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
    /// A coarser square grid whose elements split while solving wherever
    /// their vertices' radiosities disagree (see [`RefinementSettings`]).
    Adaptive,
}

impl std::str::FromStr for MeshKind {
    type Err = crate::Error;

    fn from_str(name: &str) -> crate::Result<Self> {
        match name {
            "square" => Ok(MeshKind::Square),
            "contour" => Ok(MeshKind::Contour),
            "adaptive" => Ok(MeshKind::Adaptive),
            other => Err(crate::Error::InvalidSetting {
                name: "mesh".into(),
                message: format!("`{other}` is not one of square, contour, adaptive"),
            }),
        }
    }
}

/// A length in scene units, given outright or as a fraction of the scene's
/// bounding diagonal (so that settings can be written before a scene exists).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Length {
    /// This many scene units.
    Absolute(f64),
    /// This fraction of the scene's bounding diagonal.
    OfDiagonal(f64),
}

impl Length {
    /// The length in scene units, for a scene whose diagonal is `diagonal`.
    #[must_use]
    pub fn resolve(self, diagonal: f64) -> f64 {
        match self {
            Length::Absolute(length) => length,
            Length::OfDiagonal(fraction) => fraction * diagonal,
        }
    }

    fn validate(self, name: &str) -> crate::Result<()> {
        let (Length::Absolute(x) | Length::OfDiagonal(x)) = self;
        if x > 0.0 && x.is_finite() {
            Ok(())
        } else {
            Err(crate::Error::InvalidSetting {
                name: name.into(),
                message: format!("{x} is not positive"),
            })
        }
    }
}

/// How a scene is meshed. Lengths may be relative to the scene's size, so
/// the defaults and presets need no scene.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct MeshSettings {
    /// Square or contour.
    pub kind: MeshKind,
    /// Longest element edge (default: 1/40 of the scene's diagonal).
    pub max_edge: Length,
    /// N for an N × N grid on every quad (and N divisions of every triangle
    /// edge), instead of `max_edge`.
    pub elements_per_side: Option<usize>,
    /// Longest shooting-patch edge (default: 1/8 of the scene's diagonal);
    /// never shorter than `max_edge`.
    pub patch_max_edge: Length,
    /// D and K of the contour mesher.
    pub contour: ContourSettings,
    /// What makes a receiver qualify for the contour mesher.
    pub dominance: DominanceSettings,
    /// How adaptive meshing starts and how far it splits.
    pub refinement: RefinementSettings,
    /// The most elements [`MeshSettings::check_budget`] allows (estimated
    /// before meshing): a guard against settings that would exhaust memory.
    /// Raise it to mesh a scene that truly needs more.
    pub max_elements: usize,
}

impl Default for MeshSettings {
    /// Square meshing, elements of 1/40 and patches of 1/8 of the scene's
    /// diagonal.
    fn default() -> Self {
        MeshSettings {
            kind: MeshKind::Square,
            max_edge: Length::OfDiagonal(1.0 / 40.0),
            elements_per_side: None,
            patch_max_edge: Length::OfDiagonal(1.0 / 8.0),
            contour: ContourSettings::default(),
            dominance: DominanceSettings::default(),
            refinement: RefinementSettings::default(),
            max_elements: MeshSettings::DEFAULT_MAX_ELEMENTS,
        }
    }
}

impl MeshSettings {
    /// Coarser elements for quick images: 1/20 of the scene's diagonal.
    #[must_use]
    pub fn preview() -> Self {
        MeshSettings {
            max_edge: Length::OfDiagonal(1.0 / 20.0),
            ..Self::default()
        }
    }

    /// Finer elements for smooth images: 1/80 of the scene's diagonal.
    #[must_use]
    pub fn final_quality() -> Self {
        MeshSettings {
            max_edge: Length::OfDiagonal(1.0 / 80.0),
            ..Self::default()
        }
    }

    /// The square mesher's settings for `scene`, lengths resolved. For
    /// adaptive meshing, elements start `refinement.coarsening` times longer.
    #[must_use]
    pub fn square_for(&self, scene: &Scene) -> SquareMeshSettings {
        let diagonal = scene.diagonal();
        let mut square = SquareMeshSettings::for_scene(scene);
        square.max_edge = self.max_edge.resolve(diagonal);
        if self.kind == MeshKind::Adaptive {
            square.max_edge *= self.refinement.coarsening;
        }
        square.patch_max_edge = self.patch_max_edge.resolve(diagonal).max(square.max_edge);
        square.elements_per_side = self.elements_per_side;
        square
    }

    /// Checks every field is in range; returns the first problem.
    pub fn validate(&self) -> crate::Result<()> {
        self.max_edge.validate("max-edge")?;
        self.patch_max_edge.validate("patch-max-edge")?;
        let counts = [
            ("elements-per-side", self.elements_per_side.unwrap_or(1)),
            ("directions", self.contour.directions),
            ("levels", self.contour.levels),
        ];
        for (name, value) in counts {
            if !(1..=1000).contains(&value) {
                return Err(crate::Error::InvalidSetting {
                    name: name.into(),
                    message: format!("{value} is not in 1..=1000"),
                });
            }
        }
        self.dominance.validate()?;
        self.refinement.validate()
    }
}

/// What meshing found: the luminaires, each receiver's analysis, and where
/// the contour mesher was used.
#[derive(Clone, Debug, Default)]
pub struct MeshAnalysis {
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
/// boundaries refined), the rest the square grid.
#[must_use]
pub fn mesh_scene(scene: &Scene, visibility: &Visibility, settings: &MeshSettings) -> SceneMesh {
    let square = settings.square_for(scene);
    let mut analysis = MeshAnalysis::default();
    if matches!(settings.kind, MeshKind::Square | MeshKind::Adaptive) {
        let mesh = mesh_surfaces(scene, &square, &|_| None);
        return SceneMesh { mesh, analysis };
    }
    analysis.luminaires = luminaires(scene);
    analysis.receivers =
        analyse_receivers(scene, visibility, &analysis.luminaires, &settings.dominance);
    let layouts: Vec<Option<ContourLayout>> = (0..scene.surfaces.len())
        .map(|surface| {
            let found = analysis
                .receivers
                .iter()
                .find(|a| a.receiver == surface && a.qualifies)?;
            let luminaire = &analysis.luminaires[found.dominant?];
            receiver_layout(scene, visibility, surface, luminaire, &settings.contour)
        })
        .collect();
    for (surface, layout) in layouts.iter().enumerate() {
        if let Some(layout) = layout {
            analysis.contour_surfaces.push(surface);
            analysis.newton_iterations += layout.newton_iterations;
            analysis.newton_solves += layout.newton_solves;
        }
    }
    let mesh = mesh_surfaces(scene, &square, &|surface| layouts[surface].clone());
    SceneMesh { mesh, analysis }
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
