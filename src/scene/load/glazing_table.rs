//! A scene file's `[glazing]` table: materials made glazing by name, for
//! models whose MTL has no `Tf` (most exporters write glass as a colour
//! and a dissolve).
//!
//! ```toml
//! [glazing]                 # material name = visible transmittance at normal incidence
//! "Glass_Clear" = 0.78
//! window = 0.6
//! ```
//!
//! The value overrides an MTL `Tf`. Every fault is an
//! [`Error::SceneDaylight`] naming the scene file, the line and the key.

use std::collections::BTreeMap;
use std::path::Path;

use toml::Spanned;

use super::material_names::no_such_material;
use super::source::line_at;
use crate::daylight::pane_diffuse_reflectance;
use crate::error::{Error, Result};
use crate::rgb::Rgb;
use crate::scene::Scene;

/// The `[glazing]` table as written: material name → transmittance.
pub(super) type GlazingToml = BTreeMap<Spanned<String>, Spanned<f64>>;

/// Makes the materials `table` names glazing of the transmittance it
/// gives (0 < τ_n < 1), reflecting as a clear pane does; an error for a
/// name no material has, or a value out of range.
pub(super) fn apply_glazing(
    scene: &mut Scene,
    table: &GlazingToml,
    path: &Path,
    text: &str,
) -> Result<()> {
    for (name, value) in table {
        let fault = |span: std::ops::Range<usize>, message: String| Error::SceneDaylight {
            path: path.to_path_buf(),
            line: line_at(text, span.start),
            table: "glazing",
            key: name.get_ref().clone(),
            value: value.get_ref().to_string(),
            message,
        };
        let tau = *value.get_ref();
        if !(tau.is_finite() && tau > 0.0 && tau < 1.0) {
            let message = "the transmittance must be above 0 and below 1".to_owned();
            return Err(fault(value.span(), message));
        }
        let Some(material) = scene
            .materials
            .iter_mut()
            .find(|m| m.name == *name.get_ref())
        else {
            return Err(fault(name.span(), no_such_material(scene)));
        };
        material.transmittance = tau;
        material.reflectance = Rgb::splat(pane_diffuse_reflectance(tau));
    }
    Ok(())
}
