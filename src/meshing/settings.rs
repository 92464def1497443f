//! How a scene is meshed: which mesher, how fine, and the guard against
//! meshes too large to hold.

use serde::ser::SerializeMap;
use serde::{Deserialize, Serialize, de};

use super::refinement_settings::RefinementSettings;
use super::scene_mesh::{LAYOUT_EXTRA_POINTS, MAX_LAYOUT_GRID_RATIO};
use crate::error::Result;
use crate::lighting::DominanceSettings;
use crate::mesh::{
    ContourSettings, SquareMeshSettings, check_element_budget, estimate_contour_elements,
    estimate_square_elements,
};
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

/// A length in scene units, given outright or as a fraction of the scene's
/// bounding diagonal (so that settings can be written before a scene exists).
///
/// In a file, a bare number is an absolute length and a one-key table
/// `{ of_diagonal = F }` a fraction of the diagonal:
///
/// ```toml
/// max_edge = 50.0                          # Length::Absolute(50.0)
/// patch_max_edge = { of_diagonal = 0.125 } # Length::OfDiagonal(0.125)
/// ```
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

    /// Fails unless the number is positive and finite; the error is named
    /// `name`.
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

/// The key of [`Length::OfDiagonal`] in a file.
const OF_DIAGONAL: &str = "of_diagonal";

impl Serialize for Length {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match *self {
            Length::Absolute(length) => serializer.serialize_f64(length),
            Length::OfDiagonal(fraction) => {
                let mut map = serializer.serialize_map(Some(1))?;
                map.serialize_entry(OF_DIAGONAL, &fraction)?;
                map.end()
            }
        }
    }
}

impl<'de> Deserialize<'de> for Length {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_any(LengthVisitor)
    }
}

/// Reads a [`Length`]: a number, or `{ of_diagonal = F }`.
struct LengthVisitor;

impl<'de> de::Visitor<'de> for LengthVisitor {
    type Value = Length;

    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("a length in scene units or { of_diagonal = fraction }")
    }

    fn visit_f64<E: de::Error>(self, length: f64) -> Result<Length, E> {
        Ok(Length::Absolute(length))
    }

    fn visit_i64<E: de::Error>(self, length: i64) -> Result<Length, E> {
        Ok(Length::Absolute(length as f64))
    }

    fn visit_u64<E: de::Error>(self, length: u64) -> Result<Length, E> {
        Ok(Length::Absolute(length as f64))
    }

    fn visit_map<A: de::MapAccess<'de>>(self, mut map: A) -> Result<Length, A::Error> {
        let mut fraction = None;
        while let Some(key) = map.next_key::<String>()? {
            if key != OF_DIAGONAL {
                return Err(de::Error::unknown_field(&key, &[OF_DIAGONAL]));
            }
            if fraction.is_some() {
                return Err(de::Error::duplicate_field(OF_DIAGONAL));
            }
            fraction = Some(map.next_value::<f64>()?);
        }
        fraction
            .map(Length::OfDiagonal)
            .ok_or_else(|| de::Error::missing_field(OF_DIAGONAL))
    }
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
    /// Element edges along the shadow boundaries that the luminaires cast
    /// through the scene's occluders, for every mesher (discontinuity
    /// meshing; see `lighting::shadow_boundaries`). On by default.
    pub shadow_boundaries: bool,
    /// The most shadow boundaries one receiver gets, longest first (256).
    /// A floor under many lamps and chairs casts thousands; each kept one
    /// adds a row of vertices that every shot reaches. More follow small
    /// objects' shadows better at a cost in time: on `scenes/office` 1024
    /// gave 3.91 % per pixel against a path tracer instead of 4.49 %, for
    /// 17 % more time (measured once by hand; README, Accuracy), but on
    /// the furnished office of `bench/generate_building.py` keeping every
    /// one gave 1.70 % instead of 1.89 % for 81 % more time.
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

    /// The elements [`super::mesh_scene`] would make at most (see
    /// `mesh/budget.rs`): the square grid's count, plus for the contour
    /// meshers the triangles of the largest layouts they keep on every
    /// receiver.
    #[must_use]
    pub fn estimate_elements(&self, scene: &Scene) -> f64 {
        let square = estimate_square_elements(scene, &self.square_for(scene));
        let contour = match self.kind {
            // Adaptive meshing starts from the square grid; its splits stop
            // at `refinement.max_vertices`.
            MeshKind::Square | MeshKind::Adaptive => 0.0,
            MeshKind::Contour => {
                estimate_contour_elements(scene, square, MAX_LAYOUT_GRID_RATIO, LAYOUT_EXTRA_POINTS)
            }
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
