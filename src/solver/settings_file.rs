//! A scene file's `[mesh]` and `[solver]` tables read into [`Settings`],
//! with the file, the line and the field path of any bad value.
//!
//! The scene loader keeps the file's text (see [`SceneOptions`]); here it is
//! deserialized through `serde_path_to_error`, so a type error (a string
//! where a number belongs, an unknown key, an unknown mesh kind) knows its
//! field path, and toml's span gives its line. Range errors found by
//! [`Settings::validate`] carry their field path as the setting's name; the
//! line is that key's in the file.

use std::ops::Range;
use std::path::Path;

use serde::Deserialize;
use toml::de::{DeTable, DeValue};

use super::settings::{Settings, SolverSettings};
use crate::error::{Error, Result};
use crate::meshing::MeshSettings;
use crate::scene::{SceneOptions, line_at};

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
    /// [`Error::SceneSetting`] naming the file, the line and the field path
    /// (`mesh.max_edge`).
    ///
    /// ```
    /// let loaded = isorad::load_scene("cornell")?;
    /// let settings = isorad::Settings::from_scene_options(&loaded.options)?;
    /// assert_eq!(settings, isorad::Settings::default());
    /// # Ok::<(), isorad::Error>(())
    /// ```
    pub fn from_scene_options(options: &SceneOptions) -> Result<Settings> {
        let Some(path) = options.path() else {
            return Ok(Settings::default());
        };
        let text = options.text();
        let error =
            |name: String, span: Option<Range<usize>>, message: String| Error::SceneSetting {
                path: path.to_path_buf(),
                line: span.map(|span| line_at(text, span.start)),
                name,
                message,
            };
        // Types and keys: serde knows the field path, toml the span.
        let deserializer = toml::Deserializer::parse(text).map_err(|e| syntax_error(path, &e))?;
        let tables: SettingsTables =
            serde_path_to_error::deserialize(deserializer).map_err(|e| {
                let name = e.path().to_string();
                let inner = e.into_inner();
                error(name, inner.span(), inner.message().trim().to_owned())
            })?;
        let settings = Settings {
            mesh: tables.mesh,
            solver: tables.solver,
        };
        // Ranges: the error names the field, the file gives its line.
        settings.validate().map_err(|e| match e {
            Error::InvalidSetting { name, message } => {
                let span = span_of(text, &name);
                error(name, span, message)
            }
            other => other,
        })?;
        Ok(settings)
    }
}

/// A file that is not TOML (the scene loader refuses those first).
fn syntax_error(path: &Path, error: &toml::de::Error) -> Error {
    Error::SceneFile {
        path: path.to_path_buf(),
        message: error.message().trim().to_owned(),
    }
}

/// The byte range of the value at the dotted `field_path` in the TOML
/// `text`, if the file sets it.
fn span_of(text: &str, field_path: &str) -> Option<Range<usize>> {
    let root = DeTable::parse(text).ok()?;
    let mut table = root.get_ref();
    let mut keys = field_path.split('.').peekable();
    while let Some(key) = keys.next() {
        let value = table.get(key)?;
        if keys.peek().is_none() {
            return Some(value.span());
        }
        let DeValue::Table(inner) = value.get_ref() else {
            return None;
        };
        table = inner;
    }
    None
}
