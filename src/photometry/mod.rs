//! Photometry: real luminaires' intensity distributions, read from IES
//! LM-63 and EULUMDAT files into one [`IntensityDistribution`] I(C, γ) in
//! candela.
//!
//! isorad's photometric unit is Radiance's white efficacy: 179 lm/W, so
//! 1 cd is 1/179 W/sr of isorad's radiometric grey (docs/guide.md, units).
//!
//! We read both formats ourselves. `lidrs` (MIT) reads them too, but, as
//! checked for its 0.2 releases: it predates LM-63-2019, converts only type C
//! files to its photometric web, and brings about 3.5 MB of dependencies;
//! `eulumdat` is AGPL-3.0, which isorad's licence cannot take.

mod distribution;
mod eulumdat;
mod file_text;
mod ies;
mod ies_numbers;
mod prepared;
mod problem;

use std::path::Path;

pub use distribution::{
    IntensityDistribution, IntensityWithDerivatives, LuminousOpening, Symmetry,
};
pub use eulumdat::{EulumdatFile, parse_eulumdat};
pub use file_text::{MAX_FILE_BYTES, decode_text};
pub use ies::{IesFile, parse_ies};
pub use prepared::{FLUX_REFINEMENT, PreparedDistribution};
pub use problem::ParseProblem;

use crate::error::{Error, Result};

/// Lumens per watt of isorad's radiometric grey: a radiance of
/// 1 W/(m²·sr) is 179 cd/m², an irradiance of 1 W/m² is 179 lx.
pub const LUMENS_PER_WATT: f64 = 179.0;

/// A photometric file as read: either format, with what it says of itself.
#[derive(Clone, Debug, PartialEq)]
pub enum PhotometricFile {
    /// An IES LM-63 file.
    Ies(IesFile),
    /// An EULUMDAT file.
    Eulumdat(EulumdatFile),
}

impl PhotometricFile {
    /// The intensity distribution, candela.
    #[must_use]
    pub fn distribution(&self) -> &IntensityDistribution {
        match self {
            PhotometricFile::Ies(file) => &file.distribution,
            PhotometricFile::Eulumdat(file) => &file.distribution,
        }
    }

    /// What the file says of itself, as (field, value) pairs for a report:
    /// the format and, for LM-63, its keywords; for EULUMDAT, the company,
    /// luminaire, lamp flux and light output ratio.
    #[must_use]
    pub fn description(&self) -> Vec<(String, String)> {
        match self {
            PhotometricFile::Ies(file) => {
                let mut fields = vec![("format".to_owned(), file.format.clone())];
                fields.extend(file.keywords.iter().cloned());
                let lumens = if file.lumens_per_lamp < 0.0 {
                    "absolute photometry".to_owned()
                } else {
                    format!("{} lm per lamp", file.lumens_per_lamp)
                };
                fields.push(("lamps".to_owned(), format!("{} ({lumens})", file.lamps)));
                fields.push(("input watts".to_owned(), file.input_watts.to_string()));
                fields
            }
            PhotometricFile::Eulumdat(file) => vec![
                ("format".to_owned(), "EULUMDAT".to_owned()),
                ("company".to_owned(), file.company.clone()),
                ("luminaire".to_owned(), file.luminaire.clone()),
                ("lamp flux".to_owned(), format!("{} lm", file.lamp_flux)),
                (
                    "light output ratio".to_owned(),
                    format!("{} %", file.light_output_ratio),
                ),
            ],
        }
    }
}

/// The two formats isorad reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PhotometricFormat {
    /// IES LM-63.
    Ies,
    /// EULUMDAT.
    Eulumdat,
}

impl PhotometricFormat {
    /// The format a file's name says: EULUMDAT for `.ldt` and `.eul` (any
    /// case), IES LM-63 otherwise.
    #[must_use]
    pub fn of_path(path: &Path) -> PhotometricFormat {
        let extension = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match extension.as_deref() {
            Some("ldt" | "eul") => PhotometricFormat::Eulumdat,
            _ => PhotometricFormat::Ies,
        }
    }
}

/// Reads a photometric file's bytes in `format`, decoded as
/// [`decode_text`] says (a byte-order mark dropped, UTF-8 or Latin-1).
///
/// # Errors
/// The reader's [`ParseProblem`], naming the line.
pub fn parse_photometric_bytes(
    bytes: &[u8],
    format: PhotometricFormat,
) -> std::result::Result<PhotometricFile, ParseProblem> {
    parse_text(&decode_text(bytes), format)
}

/// Reads a photometric file's text in `format`.
fn parse_text(
    text: &str,
    format: PhotometricFormat,
) -> std::result::Result<PhotometricFile, ParseProblem> {
    match format {
        PhotometricFormat::Eulumdat => parse_eulumdat(text).map(PhotometricFile::Eulumdat),
        PhotometricFormat::Ies => parse_ies(text).map(PhotometricFile::Ies),
    }
}

/// Reads a photometric file: EULUMDAT for `.ldt` and `.eul`, IES LM-63
/// otherwise. Only a regular file of at most [`MAX_FILE_BYTES`] is read.
///
/// # Errors
/// [`Error::Photometry`] naming the file, and the line where the fault
/// lies, when it cannot be read (missing, a directory, a device or pipe,
/// too large) or is not a file isorad can use.
pub fn read_photometric_file(path: &Path) -> Result<PhotometricFile> {
    let text = file_text::read_file_text(path)?;
    parse_text(&text, PhotometricFormat::of_path(path)).map_err(|problem| Error::Photometry {
        path: path.to_owned(),
        line: problem.line,
        message: problem.message,
    })
}
