//! A scene file's `[mesh]` table read into [`MeshSettings`], for what meshes
//! a scene without solving it (`isorad info`, `isorad compare`).

use serde::Deserialize;

use super::settings::MeshSettings;
use crate::error::Result;
use crate::scene::SceneOptions;

/// The one table of a scene file that holds mesh settings; its other keys
/// (`obj`, `[camera]`, `[solver]`, …) are skipped here.
#[derive(Deserialize)]
struct MeshTable {
    #[serde(default)]
    mesh: MeshSettings,
}

impl MeshSettings {
    /// The defaults, overridden by the scene file's `[mesh]` table, and
    /// validated; a scene without a file gives the defaults. Errors name
    /// the file, the line and the field path (`mesh.max_edge`), as
    /// [`crate::Settings::from_scene_options`]'s do.
    ///
    /// ```
    /// let loaded = isorad::load_scene("cornell")?;
    /// let mesh = isorad::MeshSettings::from_scene_options(&loaded.options)?;
    /// assert_eq!(mesh, isorad::MeshSettings::default());
    /// # Ok::<(), isorad::Error>(())
    /// ```
    pub fn from_scene_options(options: &SceneOptions) -> Result<MeshSettings> {
        let read = options.read_settings(|table: MeshTable| {
            table.mesh.validate().map_err(|e| e.within("mesh"))?;
            Ok(table.mesh)
        })?;
        Ok(read.unwrap_or_default())
    }
}
