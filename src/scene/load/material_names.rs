//! The hint an error about a material name gives: the model's materials.

use crate::scene::Scene;

/// How many of the model's material names a message lists.
const LISTED: usize = 12;

/// "no material of the model is called so; its materials: a, b, …" (the
/// first twelve), for a name that a scene file's table or key gives and
/// no material has.
pub(super) fn no_such_material(scene: &Scene) -> String {
    let names: Vec<&str> = scene
        .materials
        .iter()
        .map(|m| m.name.as_str())
        .take(LISTED)
        .collect();
    format!(
        "no material of the model is called so; its materials: {}",
        names.join(", ")
    )
}
