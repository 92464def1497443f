//! How a scene is meshed: which mesher, how fine, and the guard against
//! meshes too large to hold.

use super::refinement::RefinementSettings;
use crate::error::Result;
use crate::lighting::DominanceSettings;
use crate::mesh::{
    ContourSettings, SquareMeshSettings, check_element_budget, estimate_contour_elements,
    estimate_square_elements,
};
use crate::scene::Scene;

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

impl MeshSettings {
    /// The default of [`MeshSettings::max_elements`]: five million elements,
    /// about a gigabyte for mesh and solver together and hours of solving
    /// on a small machine; the Cornell box at default settings has 4 000.
    pub const DEFAULT_MAX_ELEMENTS: usize = 5_000_000;

    /// The elements [`super::mesh_scene`] would make at most (see
    /// `mesh/budget.rs`): the square grid's count, plus for the contour
    /// mesher its triangles on every receiver that might qualify.
    #[must_use]
    pub fn estimate_elements(&self, scene: &Scene) -> f64 {
        let square = estimate_square_elements(scene, &self.square_for(scene));
        let contour = match self.kind {
            // Adaptive meshing starts from the square grid; its splits stop
            // at `refinement.max_vertices`.
            MeshKind::Square | MeshKind::Adaptive => 0.0,
            MeshKind::Contour => estimate_contour_elements(scene, &self.contour),
        };
        square + contour
    }

    /// Refuses settings that would mesh `scene` into more than
    /// [`MeshSettings::max_elements`] elements, with an error that says how
    /// to ask for fewer or allow more. [`crate::Solver::new`] calls it before
    /// meshing; call it before [`super::mesh_scene`] when meshing yourself.
    pub fn check_budget(&self, scene: &Scene) -> Result<()> {
        check_element_budget(
            scene,
            self.estimate_elements(scene),
            self.max_elements,
            &self.square_for(scene),
        )
    }
}
