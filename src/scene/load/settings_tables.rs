//! A scene file's settings tables (`[mesh]`, `[solver]`) deserialized, with
//! the file, the line and the field path of any bad value.
//!
//! The scene loader keeps the file's text (see [`SceneOptions`]); here it is
//! deserialized through `serde_path_to_error`, so a type error (a string
//! where a number belongs, an unknown key, an unknown mesh kind) knows its
//! field path, and toml's span gives its line. Range errors, found by the
//! caller's check, carry their field path as the setting's name; the line
//! is that key's in the file. The tables' types belong to the layers that
//! use them (the meshing layer's `MeshSettings`, the solver's `Settings`).

use std::ops::Range;
use std::path::Path;

use serde::de::DeserializeOwned;
use toml::de::{DeTable, DeValue};

use super::source::line_at;
use crate::error::{Error, Result};
use crate::scene::SceneOptions;

impl SceneOptions {
    /// The scene file's text deserialized into `T` (whose fields are the
    /// tables it reads; other keys are the scene loader's and `T` skips
    /// them) and turned by `check` into the settings it validates, or
    /// `None` for a scene without a file.
    ///
    /// A wrong type or an unknown key, and an [`Error::InvalidSetting`]
    /// from `check` (named by its field path, `mesh.max_edge`), are an
    /// [`Error::SceneSetting`] naming the file, the line and the field path.
    pub fn read_settings<T: DeserializeOwned, R>(
        &self,
        check: impl FnOnce(T) -> Result<R>,
    ) -> Result<Option<R>> {
        let Some(path) = self.path() else {
            return Ok(None);
        };
        let text = self.text();
        let error =
            |name: String, span: Option<Range<usize>>, message: String| Error::SceneSetting {
                path: path.to_path_buf(),
                line: span.map(|span| line_at(text, span.start)),
                name,
                message,
            };
        // Types and keys: serde knows the field path, toml the span.
        let deserializer = toml::Deserializer::parse(text).map_err(|e| syntax_error(path, &e))?;
        let tables: T = serde_path_to_error::deserialize(deserializer).map_err(|e| {
            let name = e.path().to_string();
            let inner = e.into_inner();
            error(name, inner.span(), inner.message().trim().to_owned())
        })?;
        // Ranges: the error names the field, the file gives its line.
        let settings = check(tables).map_err(|e| match e {
            Error::InvalidSetting { name, message } => {
                let span = span_of(text, &name);
                error(name, span, message)
            }
            other => other,
        })?;
        Ok(Some(settings))
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
