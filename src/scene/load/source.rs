//! Where loaders read their text from: the file system, or files embedded in
//! the binary (the built-in scenes), so both go through the same parsers;
//! and the line of a place in that text, for messages.

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
        read_text(path)
    }
}

/// Reads a text file as exporters write them: a UTF-8 byte-order mark is
/// dropped, and bytes that are not UTF-8 (a Latin-1 comment or object name)
/// become U+FFFD instead of failing the load. A file holding NUL bytes is
/// binary, not text, and is an error saying so; so is anything but a
/// regular file (a directory, a device, a pipe).
pub(crate) fn read_text(path: &Path) -> Result<String> {
    let io = |source| Error::Io {
        path: path.to_path_buf(),
        source,
    };
    // Only regular files: a scene naming /dev/zero or a FIFO must not hang.
    let kind = std::fs::metadata(path).map_err(io)?.file_type();
    if !kind.is_file() {
        let what = if kind.is_dir() {
            "a directory"
        } else {
            "not a regular file"
        };
        return Err(io(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("{what}: expected a text file"),
        )));
    }
    let bytes = std::fs::read(path).map_err(io)?;
    if bytes.contains(&0) {
        return Err(io(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            "not a text file (it holds NUL bytes): expected a text OBJ, MTL, TOML or CSV file",
        )));
    }
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(&bytes);
    Ok(String::from_utf8_lossy(bytes).into_owned())
}

/// The 1-based line of `text` holding byte `offset`.
pub(crate) fn line_at(text: &str, offset: usize) -> usize {
    let before = text.get(..offset.min(text.len())).unwrap_or(text);
    before.matches('\n').count() + 1
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
