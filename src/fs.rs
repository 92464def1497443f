//! Files written atomically: a temporary file `.<name>.tmp-<pid>-<n>` next
//! to the target is written, synced and renamed over the target, so an
//! existing file is either left as it was or replaced whole. On failure the
//! temporary file is removed and the error names the target path. Every
//! writer of isorad (images, exports, plots, records) goes through here.

use std::fs::{self, File};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use crate::error::{Error, Result};

/// Distinguishes temporary files written concurrently by one process.
static TEMPORARY_COUNTER: AtomicU64 = AtomicU64::new(0);

/// Runs `encode` on a temporary file beside `path`, syncs it, and renames it
/// over `path`; removes the temporary file on any failure.
pub(crate) fn write_atomically(
    path: &Path,
    encode: impl FnOnce(&mut BufWriter<File>) -> Result<()>,
) -> Result<()> {
    let temporary = temporary_path(path)?;
    let result = write_then_rename(path, &temporary, encode);
    if result.is_err() {
        // Nothing to report if it was never created.
        let _ = fs::remove_file(&temporary);
    }
    result
}

/// The steps of [`write_atomically`], any of which may fail.
fn write_then_rename(
    path: &Path,
    temporary: &Path,
    encode: impl FnOnce(&mut BufWriter<File>) -> Result<()>,
) -> Result<()> {
    let io = |source| io_error(path, source);
    let mut writer = BufWriter::new(File::create(temporary).map_err(io)?);
    encode(&mut writer)?;
    writer.flush().map_err(io)?;
    let file = writer.into_inner().map_err(|e| io(e.into_error()))?;
    file.sync_all().map_err(io)?;
    fs::rename(temporary, path).map_err(io)
}

/// `.<name>.tmp-<pid>-<n>` in the directory of `path`.
fn temporary_path(path: &Path) -> Result<PathBuf> {
    let name = path
        .file_name()
        .ok_or_else(|| output_error(path, "the path does not name a file"))?;
    let count = TEMPORARY_COUNTER.fetch_add(1, Ordering::Relaxed);
    let temporary = format!(
        ".{}.tmp-{}-{count}",
        name.to_string_lossy(),
        std::process::id()
    );
    Ok(path.with_file_name(temporary))
}

/// [`Error::Io`] naming `path`.
pub(crate) fn io_error(path: &Path, source: std::io::Error) -> Error {
    Error::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// [`Error::Output`] naming `path`.
pub(crate) fn output_error(path: &Path, message: impl ToString) -> Error {
    Error::Output {
        path: path.to_path_buf(),
        message: message.to_string(),
    }
}
