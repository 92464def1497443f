//! When and how far an adaptive solve splits elements: the settings of
//! [`crate::meshing::MeshKind::Adaptive`], part of the mesh settings (the
//! splitting itself is the solver's).

/// When and how far elements are split during an adaptive solve. In a scene
/// file: `[mesh.refinement]`.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct RefinementSettings {
    /// Split an element when the jump of the radiosity gradient across it
    /// times its size, η_e = h_e · max_v |G_e − G_v| (Zienkiewicz and Zhu's
    /// recovery estimator, with G_e the gradient of the element's linear
    /// interpolant and G_v its area-weighted mean around vertex v), exceeds
    /// `threshold` times its mean radiosity.
    pub threshold: f64,
    /// Differences in elements darker than `floor` times the scene's mean
    /// radiosity are measured against that floor instead: deep shadows are
    /// not refined for differences nobody can see.
    pub floor: f64,
    /// How many times an element of the starting mesh may be halved.
    pub max_levels: u32,
    /// The starting mesh's element edge, as a multiple of the square
    /// mesher's: adaptive meshing starts coarser and refines where needed.
    pub coarsening: f64,
    /// Stop splitting once the mesh holds this many vertices.
    pub max_vertices: usize,
}

impl Default for RefinementSettings {
    fn default() -> Self {
        RefinementSettings {
            threshold: 1.0,
            floor: 0.05,
            max_levels: 3,
            coarsening: 1.0,
            max_vertices: 2_000_000,
        }
    }
}

impl RefinementSettings {
    /// Checks every field is in range. An [`crate::Error::InvalidSetting`]
    /// names the field (`threshold`).
    pub fn validate(&self) -> crate::Result<()> {
        let invalid = |name: &str, message: String| {
            Err(crate::Error::InvalidSetting {
                name: name.into(),
                message,
            })
        };
        if !(self.threshold > 0.0 && self.threshold.is_finite()) {
            return invalid(
                "threshold",
                format!("{} must be a positive number", self.threshold),
            );
        }
        if !(self.floor >= 0.0 && self.floor.is_finite()) {
            return invalid("floor", format!("{} must be ≥ 0", self.floor));
        }
        if self.max_levels > 16 {
            return invalid(
                "max_levels",
                format!("{} is more than 16 levels", self.max_levels),
            );
        }
        if !(self.coarsening >= 1.0 && self.coarsening.is_finite()) {
            return invalid("coarsening", format!("{} must be ≥ 1", self.coarsening));
        }
        Ok(())
    }
}
