//! A scene file's `two_sided` key: materials whose faces are lit and seen
//! from both sides.
//!
//! ```toml
//! two_sided = ["WhitePaint", "shelf"]   # these materials' faces
//! two_sided = true                      # every face
//! ```
//!
//! isorad's surfaces are one-sided, as a path tracer's diffuse faces are: a
//! face emits and reflects on its front and is black from behind. A model
//! whose windings are not consistent (a ceiling written facing the sky, a
//! free-standing panel or a shelf board modelled as one face) needs its
//! faces lit from both sides. Each face of a two-sided material gets a twin
//! facing the other way, back to back with it: twice the surfaces, each
//! meshed and shot on its own. Faces back to back neither light each other
//! nor show their backs (see `radiometry/form_factor.rs` and the
//! renderer's depth test).

use std::collections::BTreeSet;
use std::path::Path;

use toml::Spanned;

use super::material_names::no_such_material;
use super::source::line_at;
use crate::error::{Error, Result};
use crate::scene::{Scene, Surface};

/// The `two_sided` key as written: `true`, `false` or a list of names.
pub(super) type TwoSidedToml = toml::Value;

/// Gives every face of the materials `spec` names a twin facing the other
/// way; returns how many faces were twinned. A name that no material has
/// is an [`Error::SceneFile`] naming the file, the line and the key, as is
/// a value that is neither a boolean nor a list of names.
pub(super) fn apply_two_sided(
    scene: &mut Scene,
    spec: &Spanned<TwoSidedToml>,
    path: &Path,
    text: &str,
) -> Result<usize> {
    let span = spec.span();
    let fault = |offset: usize, message: String| Error::SceneFile {
        path: path.to_path_buf(),
        message: format!("line {}: two_sided: {message}", line_at(text, offset)),
    };
    let chosen: BTreeSet<usize> = match spec.get_ref() {
        toml::Value::Boolean(true) => (0..scene.materials.len()).collect(),
        toml::Value::Boolean(false) => BTreeSet::new(),
        toml::Value::Array(names) => {
            let mut chosen = BTreeSet::new();
            for name in names {
                let toml::Value::String(name) = name else {
                    let message = format!("{name}: expected a material's name (a string)");
                    return Err(fault(span.start, message));
                };
                let Some(index) = scene.materials.iter().position(|m| m.name == *name) else {
                    // The name's own line, within the value.
                    let quoted = format!("\"{name}\"");
                    let at = text
                        .get(span.clone())
                        .and_then(|value| value.find(&quoted))
                        .map_or(span.start, |k| span.start + k);
                    return Err(fault(at, format!("{name:?}: {}", no_such_material(scene))));
                };
                chosen.insert(index);
            }
            chosen
        }
        other => {
            let message = format!("{other}: expected true, false or a list of material names");
            return Err(fault(span.start, message));
        }
    };
    let twins: Vec<Surface> = scene
        .surfaces
        .iter()
        .filter(|s| chosen.contains(&s.material))
        .filter_map(twin)
        .collect();
    let count = twins.len();
    scene.surfaces.extend(twins);
    Ok(count)
}

/// The face turned over: the same polygon, wound the other way.
fn twin(surface: &Surface) -> Option<Surface> {
    let reversed = |v: &[glam::DVec3]| v.iter().rev().copied().collect::<Vec<_>>();
    let turned = Surface::new(
        surface.name.clone(),
        surface.material,
        reversed(surface.vertices()),
    )?;
    Some(turned.with_occluder(reversed(surface.occluder_vertices())))
}
