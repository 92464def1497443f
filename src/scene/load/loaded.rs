//! What loading gives: the scene with its file's settings, and how loading
//! treats geometry.

use crate::scene::{Scene, SceneOptions};

/// A loaded scene with the settings its file carries.
#[derive(Clone, Debug)]
pub struct LoadedScene {
    /// The scene.
    pub scene: Scene,
    /// The scene file's `[solver]` and `[mesh]` settings as written, for
    /// [`crate::Settings::from_scene_options`] to read (none for an OBJ file
    /// or a scene built in code).
    pub options: SceneOptions,
    /// Where the scene came from, for messages: the path as given, or the
    /// built-in scene's name.
    pub source: String,
}

/// How [`super::load_scene_with`] treats the geometry it reads.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct LoadSettings {
    /// Merge adjacent coplanar faces of one object and material into
    /// polygons (see [`crate::scene::merge_coplanar_faces`]); default true. A scene
    /// file's `merge_coplanar = false` turns it off as well. Built-in scenes
    /// have no such faces.
    pub merge_coplanar: bool,
}

impl Default for LoadSettings {
    fn default() -> Self {
        LoadSettings {
            merge_coplanar: true,
        }
    }
}
