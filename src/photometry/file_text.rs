//! A photometric file's text, as the readers take it: from a regular file
//! of at most [`MAX_FILE_BYTES`], without a byte-order mark, UTF-8 or
//! Latin-1.
//!
//! A luminaire file names a device (`/dev/zero`), a FIFO or a directory by
//! mistake, or is something else renamed `.ies`: such names are refused
//! before a byte is read, and a file is read only up to the limit, so that
//! memory stays bounded whatever a scene file names.

use std::io::Read;
use std::path::Path;

use crate::error::{Error, Result};

/// The largest photometric file isorad reads, bytes: 16 MiB. A web of
/// every 1° in C and γ (361 × 181 values, finer than real files) is
/// about 0.5 MB, so a larger file is not a luminaire's.
pub const MAX_FILE_BYTES: u64 = 16 * 1024 * 1024;

/// The UTF-8 byte-order mark some editors write at a file's start.
const BOM: &[u8] = b"\xEF\xBB\xBF";

/// The text of the photometric file at `path` (see the module docs).
///
/// # Errors
/// [`Error::Photometry`] naming the file: it cannot be opened, it is a
/// directory or not a regular file, or it is larger than
/// [`MAX_FILE_BYTES`].
pub(super) fn read_file_text(path: &Path) -> Result<String> {
    let fail = |message: String| Error::Photometry {
        path: path.to_owned(),
        line: None,
        message,
    };
    // Only regular files, checked before opening: opening a FIFO blocks.
    let kind = std::fs::metadata(path)
        .map_err(|e| fail(format!("cannot be read: {e}")))?
        .file_type();
    if kind.is_dir() {
        return Err(fail(
            "cannot be read: a directory, not a photometric file".into(),
        ));
    }
    if !kind.is_file() {
        return Err(fail(
            "cannot be read: not a regular file (a device, a pipe or a socket): \
             expected an IES LM-63 or EULUMDAT file"
                .into(),
        ));
    }
    // At most the limit, and one byte more to tell that it is over.
    let file = std::fs::File::open(path).map_err(|e| fail(format!("cannot be read: {e}")))?;
    let mut bytes = Vec::new();
    file.take(MAX_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| fail(format!("cannot be read: {e}")))?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(fail(format!(
            "larger than {} MiB: not a luminaire's photometric file \
             (real ones are well under 1 MB)",
            MAX_FILE_BYTES >> 20
        )));
    }
    Ok(decode_text(&bytes))
}

/// A photometric file's bytes as text: a leading UTF-8 byte-order mark
/// dropped, then UTF-8 where the bytes are, Latin-1 otherwise (older
/// files' manufacturers' names). Bytes beyond ASCII only ever sit in text
/// fields, so either reading gives the same numbers.
#[must_use]
pub fn decode_text(bytes: &[u8]) -> String {
    let bytes = bytes.strip_prefix(BOM).unwrap_or(bytes);
    match std::str::from_utf8(bytes) {
        Ok(text) => text.to_owned(),
        Err(_) => bytes.iter().map(|&b| char::from(b)).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_byte_order_mark_is_dropped_and_latin_1_still_reads() {
        assert_eq!(
            decode_text(b"\xEF\xBB\xBFIESNA:LM-63-2002"),
            "IESNA:LM-63-2002"
        );
        assert_eq!(decode_text(b"Lumi\xE8re"), "Lumière");
        assert_eq!(decode_text("Lumière".as_bytes()), "Lumière");
    }

    #[test]
    fn directories_devices_and_huge_files_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let error = read_file_text(dir.path()).unwrap_err().to_string();
        assert!(error.contains("a directory"), "{error}");
        let error = read_file_text(Path::new("/dev/zero"))
            .unwrap_err()
            .to_string();
        assert!(error.contains("not a regular file"), "{error}");
        let huge = dir.path().join("huge.ies");
        let file = std::fs::File::create(&huge).unwrap();
        file.set_len(MAX_FILE_BYTES + 1).unwrap();
        let error = read_file_text(&huge).unwrap_err().to_string();
        assert!(error.contains("larger than 16 MiB"), "{error}");
        file.set_len(MAX_FILE_BYTES).unwrap();
        assert_eq!(read_file_text(&huge).unwrap().len() as u64, MAX_FILE_BYTES);
    }
}
