//! A scene file's `[mesh]` and `[solver]` tables read into [`Settings`],
//! with the file, the line and the field path of any bad value (see
//! [`SceneOptions::read_settings`]).

use serde::Deserialize;

use super::settings::{Settings, SolverSettings};
use crate::error::Result;
use crate::meshing::MeshSettings;
use crate::scene::SceneOptions;

/// The two tables of a scene file that hold settings; its other keys
/// (`obj`, `[camera]`, …) are the scene loader's and are skipped here.
#[derive(Deserialize)]
struct SettingsTables {
    #[serde(default)]
    mesh: MeshSettings,
    #[serde(default)]
    solver: SolverSettings,
}

impl Settings {
    /// The defaults, overridden by the scene file's `[mesh]` and `[solver]`
    /// tables (see `scene/load/scene_file.rs` for their keys), and
    /// validated. A scene without a file gives the defaults.
    ///
    /// A wrong type, an unknown key or a value out of range is an
    /// [`crate::Error::SceneSetting`] naming the file, the line and the
    /// field path (`mesh.max_edge`).
    ///
    /// ```
    /// let loaded = isorad::load_scene("cornell")?;
    /// let settings = isorad::Settings::from_scene_options(&loaded.options)?;
    /// assert_eq!(settings, isorad::Settings::default());
    /// # Ok::<(), isorad::Error>(())
    /// ```
    pub fn from_scene_options(options: &SceneOptions) -> Result<Settings> {
        let read = options.read_settings(|tables: SettingsTables| {
            let settings = Settings {
                mesh: tables.mesh,
                solver: tables.solver,
            };
            settings.validate()?;
            Ok(settings)
        })?;
        Ok(read.unwrap_or_default())
    }
}
