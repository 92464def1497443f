//! A scene file's `[[luminaire]]` tables: each checked, its photometric
//! file read once however many tables name it.
//!
//! ```toml
//! [[luminaire]]
//! ies = "downlight.ies"        # required: IES LM-63, or EULUMDAT (.ldt, .eul)
//! position = [1.5, 2.75, 2.0]  # required: the photometric centre
//! aim = [0.0, -1.0, 0.0]       # required: the direction of γ = 0
//! c0 = [1.0, 0.0, 0.0]         # required: towards the C0 half-plane
//! multiplier = 0.8             # default 1: dimming, maintenance factor
//! color = [1.0, 0.92, 0.82]    # default white: a tint, normalised to unit luminance
//! ```
//!
//! Every fault is an [`Error::SceneLuminaire`] naming the scene file, the
//! line of the value, the table's index and the key. A photometric file
//! that cannot be read or parsed is such a fault of `ies`, its own error
//! (the photometric file, its line) the message.
//!
//! Tables that name one file share one [`PreparedDistribution`]: the file
//! is read, parsed and its flux integrated once, so 10,000 luminaires of a
//! car park cost one file, not 10,000.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::DVec3;
use serde::Deserialize;
use toml::Spanned;

use super::source::line_at;
use crate::error::{Error, Result};
use crate::photometry::{PreparedDistribution, read_photometric_file};
use crate::rgb::Rgb;
use crate::scene::PhotometricLuminaire;

/// One `[[luminaire]]` table, each value with its place in the file.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct LuminaireToml {
    ies: Spanned<PathBuf>,
    position: Spanned<[f64; 3]>,
    aim: Spanned<[f64; 3]>,
    c0: Spanned<[f64; 3]>,
    multiplier: Option<Spanned<f64>>,
    color: Option<Spanned<[f64; 3]>>,
}

/// Reads the `[[luminaire]]` tables of one scene file.
pub(super) struct LuminaireTables<'a> {
    /// The scene file, for messages.
    pub scene_path: &'a Path,
    /// Its text, for the lines of values.
    pub text: &'a str,
    /// Its folder: `ies` paths are relative to it.
    pub folder: &'a Path,
    /// The distributions read so far, by the photometric file's path.
    prepared: HashMap<PathBuf, PreparedDistribution>,
}

impl<'a> LuminaireTables<'a> {
    /// A reader for the scene file at `scene_path` holding `text`.
    pub fn new(scene_path: &'a Path, text: &'a str, folder: &'a Path) -> LuminaireTables<'a> {
        LuminaireTables {
            scene_path,
            text,
            folder,
            prepared: HashMap::new(),
        }
    }

    /// The luminaire of table `index` (1-based): its frame checked (finite,
    /// `aim` non-zero, `c0` not along it, then made perpendicular), the
    /// multiplier finite and non-negative, the colour non-negative with a
    /// positive luminance (normalised to unit luminance), its photometric
    /// file read or taken from an earlier table.
    pub fn read(&mut self, index: usize, t: &LuminaireToml) -> Result<PhotometricLuminaire> {
        let fault = |key: &str, span: std::ops::Range<usize>, message: String| {
            self.fault(index, key, span, message)
        };
        for (key, value) in [("position", &t.position), ("aim", &t.aim), ("c0", &t.c0)] {
            if !value.get_ref().iter().all(|x| x.is_finite()) {
                return Err(fault(key, value.span(), "must be finite".into()));
            }
        }
        let Some(aim) = DVec3::from_array(*t.aim.get_ref()).try_normalize() else {
            let message = "gives no direction: it must be a non-zero vector".into();
            return Err(fault("aim", t.aim.span(), message));
        };
        let Some(c0_unit) = DVec3::from_array(*t.c0.get_ref()).try_normalize() else {
            return Err(fault("c0", t.c0.span(), "gives no direction".into()));
        };
        let c0 = c0_unit - aim * c0_unit.dot(aim);
        if c0.length() < 1e-6 {
            let message = "runs along aim: it must point away from it, to the C0 half-plane";
            return Err(fault("c0", t.c0.span(), message.into()));
        }
        let multiplier = t.multiplier.as_ref().map_or(1.0, |m| *m.get_ref());
        if let Some(m) = &t.multiplier
            && !(multiplier.is_finite() && multiplier >= 0.0)
        {
            return Err(fault("multiplier", m.span(), "must be a number ≥ 0".into()));
        }
        let color = t.color.as_ref().map_or(Rgb::ONE, |c| {
            let [r, g, b] = *c.get_ref();
            Rgb::new(r, g, b)
        });
        if let Some(c) = &t.color
            && !(color.is_finite() && color.min_element() >= 0.0 && color.luminance() > 0.0)
        {
            let message = "components must be ≥ 0 with a positive luminance".into();
            return Err(fault("color", c.span(), message));
        }
        let prepared = self.prepared(index, &t.ies)?;
        Ok(PhotometricLuminaire::placed(
            t.ies.get_ref().display().to_string(),
            prepared,
            [
                DVec3::from_array(*t.position.get_ref()),
                aim,
                c0.normalize(),
            ],
            multiplier,
            color / color.luminance(),
        ))
    }

    /// The distribution of the file `ies` names (relative to the scene
    /// file's folder), read and prepared on its first use.
    fn prepared(&mut self, index: usize, ies: &Spanned<PathBuf>) -> Result<&PreparedDistribution> {
        if ies.get_ref().as_os_str().is_empty() {
            let message = "names no file: give the path of an IES LM-63 or EULUMDAT file".into();
            return Err(self.fault(index, "ies", ies.span(), message));
        }
        let path = self.folder.join(ies.get_ref());
        // One entry per file, however the tables spell its path.
        let key = std::fs::canonicalize(&path).unwrap_or_else(|_| path.clone());
        if !self.prepared.contains_key(&key) {
            let file = read_photometric_file(&path)
                .map_err(|e| self.fault(index, "ies", ies.span(), e.to_string()))?;
            let distribution = std::sync::Arc::new(file.distribution().clone());
            self.prepared
                .insert(key.clone(), PreparedDistribution::new(distribution));
        }
        Ok(&self.prepared[&key])
    }

    /// The error of table `index`'s `key`, whose value is the file's text
    /// at `span`.
    fn fault(
        &self,
        index: usize,
        key: &str,
        span: std::ops::Range<usize>,
        message: String,
    ) -> Error {
        let value = self.text.get(span.clone()).unwrap_or("?").trim();
        Error::SceneLuminaire {
            path: self.scene_path.to_path_buf(),
            line: line_at(self.text, span.start),
            index,
            key: key.to_owned(),
            value: value.to_owned(),
            message,
        }
    }
}
