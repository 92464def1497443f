//! The one entry point for loading a scene: a scene file, an OBJ file, or a
//! built-in scene's name.

use std::path::Path;

use crate::error::{Error, Result};

use super::builtin::{builtin_names, load_builtin};
use super::loaded::{LoadSettings, LoadedScene};
use super::obj::load_obj_from;
use super::scene_file::load_scene_file_with;
use super::source::Disk;
use crate::scene::SceneOptions;

/// Loads a scene from `spec`: a `.toml` scene file, an `.obj` file (with its
/// MTL libraries), or the name of a built-in scene (see [`builtin_names`]).
///
/// A file takes precedence over a built-in name. Anything else is
/// [`Error::UnknownScene`].
///
/// ```
/// let loaded = isorad::load_scene("cornell")?;
/// assert_eq!(loaded.scene.surfaces.len(), 16);
/// # Ok::<(), isorad::Error>(())
/// ```
pub fn load_scene(spec: &str) -> Result<LoadedScene> {
    load_scene_with(spec, &LoadSettings::default())
}

/// [`load_scene`] with settings.
pub fn load_scene_with(spec: &str, settings: &LoadSettings) -> Result<LoadedScene> {
    let path = Path::new(spec);
    if path.is_file() {
        let extension = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        return match extension.as_deref() {
            Some("toml") => {
                load_scene_file_with(path, &Disk, spec.to_owned(), settings.merge_coplanar)
            }
            Some("obj") => Ok(LoadedScene {
                scene: load_obj_from(path, &Disk, settings.merge_coplanar, false)?,
                options: SceneOptions::default(),
                source: spec.to_owned(),
            }),
            _ => Err(Error::SceneFile {
                path: path.to_path_buf(),
                message: "expected a `.toml` scene file or an `.obj` file".into(),
            }),
        };
    }
    load_builtin(spec).unwrap_or_else(|| {
        Err(Error::UnknownScene {
            name: spec.to_owned(),
            builtins: builtin_names().join(", "),
        })
    })
}
