//! Built-in scenes, usable by name without any file.
//!
//! Each built-in scene is the text of files shipped in `scenes/`, compiled
//! into the binary and read through the same loaders as files on disk, so
//! the built-in `cornell` and `scenes/cornell/cornell.toml` are one scene.
//!
//! - `cornell`: the Cornell box (Cornell University Program of Computer
//!   Graphics, "Cornell Box Data"), in millimetres, with the measured camera;
//!   the 130 × 105 mm light sits just below the ceiling, facing down, with
//!   Ke = (17, 12, 4).

use std::path::Path;

use crate::error::Result;

use super::loaded::LoadedScene;
use super::scene_file::load_scene_file_from;
use super::source::Embedded;

/// Built-in scenes: (name, scene file path, the files it needs).
const BUILTINS: [(&str, &str, Embedded); 1] = [(
    "cornell",
    "builtin:cornell/cornell.toml",
    Embedded(&[
        (
            "builtin:cornell/cornell.toml",
            include_str!("../../../scenes/cornell/cornell.toml"),
        ),
        (
            "builtin:cornell/cornell.obj",
            include_str!("../../../scenes/cornell/cornell.obj"),
        ),
        (
            "builtin:cornell/cornell.mtl",
            include_str!("../../../scenes/cornell/cornell.mtl"),
        ),
    ]),
)];

/// The names of the built-in scenes, for [`crate::load_scene`].
#[must_use]
pub fn builtin_names() -> &'static [&'static str] {
    &["cornell"]
}

/// Loads the built-in scene `name`, or `None` when there is no such scene.
pub(crate) fn load_builtin(name: &str) -> Option<Result<LoadedScene>> {
    let (_, path, files) = BUILTINS.iter().find(|(n, _, _)| *n == name)?;
    Some(load_scene_file_from(
        Path::new(path),
        files,
        name.to_owned(),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_loads() {
        assert_eq!(builtin_names().len(), BUILTINS.len());
        for name in builtin_names() {
            let loaded = load_builtin(name).unwrap().unwrap();
            assert_eq!(loaded.source, *name);
            assert!(
                loaded.scene.warnings.is_empty(),
                "{:?}",
                loaded.scene.warnings
            );
        }
        assert!(load_builtin("nope").is_none());
    }
}
