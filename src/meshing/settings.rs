//! How a scene is meshed, as written before the scene exists: which
//! mesher, how fine, and the guard against meshes too large to hold.

use serde::{Deserialize, Serialize};

use super::length::Length;

use super::refinement_settings::RefinementSettings;
use crate::lighting::DominanceSettings;
use crate::mesh::{ContourSettings, SquareMeshSettings};
use crate::scene::Scene;

/// Which mesher meshes the receivers. In a scene file: `kind = "square"`,
/// `"contour"` or `"adaptive"`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
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

/// How a scene is meshed. Lengths may be relative to the scene's size, so
/// the defaults and presets need no scene. A scene file's `[mesh]` table is
/// read into this struct, field by field (see `scene/load/scene_file.rs`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct MeshSettings {
    /// Square, contour or adaptive.
    pub kind: MeshKind,
    /// Longest element edge (default: 1/40 of the scene's diagonal).
    pub max_edge: Length,
    /// N for an N × N grid on every quad (and N divisions of every triangle
    /// edge), instead of `max_edge`.
    #[serde(skip_serializing_if = "Option::is_none")]
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
    /// Element edges along the shadow boundaries that the lights cast
    /// through the scene's occluders, for every mesher (discontinuity
    /// meshing; see `lighting::shadow_boundaries`). On by default.
    pub shadow_boundaries: bool,
    /// The most shadow boundaries one receiver gets, longest first (256).
    /// A floor under many lamps and chairs casts thousands; each kept one
    /// adds a row of vertices that every shot reaches. More follow small
    /// objects' shadows better, at a cost in time.
    pub max_shadow_boundaries: usize,
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
            shadow_boundaries: true,
            max_shadow_boundaries: 256,
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

    /// Checks every field is in range; returns the first problem, an
    /// [`crate::Error::InvalidSetting`] named by its field path below the
    /// mesh settings (`max_edge`, `refinement.threshold`;
    /// [`crate::Settings::validate`] puts it under `mesh.`).
    pub fn validate(&self) -> crate::Result<()> {
        self.max_edge.validate("max_edge")?;
        self.patch_max_edge.validate("patch_max_edge")?;
        let counts = [
            ("elements_per_side", self.elements_per_side.unwrap_or(1)),
            ("contour.directions", self.contour.directions),
            ("contour.levels", self.contour.levels),
        ];
        for (name, value) in counts {
            if !(1..=1000).contains(&value) {
                return Err(crate::Error::InvalidSetting {
                    name: name.into(),
                    message: format!("{value} is not in 1..=1000"),
                });
            }
        }
        if !(1..=1_000_000).contains(&self.max_shadow_boundaries) {
            return Err(crate::Error::InvalidSetting {
                name: "max_shadow_boundaries".into(),
                message: format!("{} is not in 1..=1000000", self.max_shadow_boundaries),
            });
        }
        let error = self.contour.max_relative_error;
        if !(0.0..1.0).contains(&error) {
            return Err(crate::Error::InvalidSetting {
                name: "contour.max_relative_error".into(),
                message: format!("{error} is not in [0, 1)"),
            });
        }
        self.dominance
            .validate()
            .map_err(|e| e.within("dominance"))?;
        self.refinement
            .validate()
            .map_err(|e| e.within("refinement"))
    }
}

impl MeshSettings {
    /// The default of [`MeshSettings::max_elements`]: five million elements,
    /// about a gigabyte for mesh and solver together and hours of solving
    /// on a small machine; the Cornell box at default settings has 4 000.
    pub const DEFAULT_MAX_ELEMENTS: usize = 5_000_000;
}
