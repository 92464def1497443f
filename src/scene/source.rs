//! Where loaders read their text from: the file system, or files embedded in
//! the binary (the built-in scenes), so both go through the same parsers.

use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

/// A read-only set of text files addressed by path.
pub(crate) trait SourceFiles {
    /// The whole text of the file at `path`.
    fn read_to_string(&self, path: &Path) -> Result<String>;
}

/// The file system.
pub(crate) struct Disk;

impl SourceFiles for Disk {
    fn read_to_string(&self, path: &Path) -> Result<String> {
        std::fs::read_to_string(path).map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })
    }
}

/// Files compiled into the binary, as (path, text) pairs.
pub(crate) struct Embedded(pub &'static [(&'static str, &'static str)]);

impl SourceFiles for Embedded {
    fn read_to_string(&self, path: &Path) -> Result<String> {
        self.0
            .iter()
            .find(|(p, _)| Path::new(p) == path)
            .map(|(_, text)| (*text).to_owned())
            .ok_or_else(|| Error::Io {
                path: PathBuf::from(path),
                source: std::io::Error::new(
                    std::io::ErrorKind::NotFound,
                    "no such file among the built-in scene's files",
                ),
            })
    }
}
