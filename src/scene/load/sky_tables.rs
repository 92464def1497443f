//! A scene file's `[sky]` and `[sun]` tables: the daylight outside.
//!
//! ```toml
//! [sky]
//! model = "cie_overcast"            # required: cie_overcast | cie_clear | cie_intermediate
//!                                   #   | cie_general (with type = 1…15) | uniform
//! horizontal_illuminance = 10000.0  # lux on the open horizontal plane, sky alone (default 10,000)
//! # zenith_luminance = 3000.0       # cd/m², instead of horizontal_illuminance
//! ground_reflectance = 0.2          # default 0.2: the ground below the horizon
//! north = [0.0, 0.0, -1.0]          # default −z
//! up = [0.0, 1.0, 0.0]              # default +y
//! [sun]                             # optional
//! altitude_deg = 40.0               # with azimuth_deg, clockwise from north …
//! azimuth_deg = 180.0
//! # latitude = 51.5                 # … or a place and a time (NOAA's algorithm)
//! # longitude = -0.13
//! # time = "2026-06-21T12:00:00+01:00"
//! normal_illuminance = 80000.0      # required: direct normal lux; 0 keeps only the sky's pattern
//! ```
//!
//! Every fault is an [`Error::SceneDaylight`] naming the scene file, the
//! line, the table and the key.

use std::ops::Range;
use std::path::Path;

use glam::DVec3;
use serde::Deserialize;
use toml::Spanned;

use super::source::line_at;
use crate::daylight::{
    Daylight, Instant, Sky, SkyDirection, SkyFrame, SkyModel, Sun, solar_position,
};
use crate::error::{Error, Result};

/// The horizontal illuminance of a `[sky]` that gives no scale, lux.
pub const DEFAULT_HORIZONTAL_ILLUMINANCE: f64 = 10_000.0;

/// The `[sky]` table as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SkyToml {
    model: Spanned<String>,
    #[serde(rename = "type")]
    general_type: Option<Spanned<i64>>,
    horizontal_illuminance: Option<Spanned<f64>>,
    zenith_luminance: Option<Spanned<f64>>,
    ground_reflectance: Option<Spanned<f64>>,
    north: Option<Spanned<[f64; 3]>>,
    up: Option<Spanned<[f64; 3]>>,
}

/// The `[sun]` table as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SunToml {
    altitude_deg: Option<Spanned<f64>>,
    azimuth_deg: Option<Spanned<f64>>,
    latitude: Option<Spanned<f64>>,
    longitude: Option<Spanned<f64>>,
    time: Option<Spanned<String>>,
    normal_illuminance: Option<Spanned<f64>>,
}

/// Reads the two tables of the scene file at `path`, whose text is `text`.
pub(super) struct SkyTables<'a> {
    pub path: &'a Path,
    pub text: &'a str,
}

impl SkyTables<'_> {
    /// The daylight the tables give; `None` without a `[sky]`.
    pub fn read(
        &self,
        sky: Option<&Spanned<SkyToml>>,
        sun: Option<&Spanned<SunToml>>,
    ) -> Result<Option<Daylight>> {
        let Some(sky) = sky else {
            return match sun {
                Some(sun) => Err(self.fault(
                    "sun",
                    "(table)",
                    sun.span(),
                    "a [sun] needs a [sky]: add one (model = \"cie_clear\", say)",
                )),
                None => Ok(None),
            };
        };
        let table = sky.get_ref();
        let sun = sun.map(|sun| self.sun(sun)).transpose()?;
        let model = self.model(sky)?;
        let position = sun.map(|s| s.position);
        let zenith = self.zenith_luminance(table, model, position)?;
        let sky_model = Sky::new(model, zenith, position)
            .map_err(|message| self.fault("sky", "model", table.model.span(), &message))?;
        let ground_reflectance = match &table.ground_reflectance {
            Some(value) => {
                let rho = *value.get_ref();
                if !(rho.is_finite() && (0.0..1.0).contains(&rho)) {
                    return Err(self.fault(
                        "sky",
                        "ground_reflectance",
                        value.span(),
                        "must be at least 0 and below 1",
                    ));
                }
                rho
            }
            None => 0.2,
        };
        let vector = |value: &Option<Spanned<[f64; 3]>>, default: DVec3| {
            value
                .as_ref()
                .map_or(default, |v| DVec3::from_array(*v.get_ref()))
        };
        let up = vector(&table.up, DVec3::Y);
        let north = vector(&table.north, DVec3::NEG_Z);
        let frame = SkyFrame::new(up, north).filter(|_| up.is_finite() && north.is_finite());
        let Some(frame) = frame else {
            let (key, span) = match (&table.north, &table.up) {
                (Some(n), _) => ("north", n.span()),
                (None, Some(u)) => ("up", u.span()),
                (None, None) => ("north", sky.span()),
            };
            return Err(self.fault(
                "sky",
                key,
                span,
                "north and up must be finite, non-zero and not parallel",
            ));
        };
        Ok(Some(Daylight {
            sky: sky_model,
            sun,
            ground_reflectance,
            frame,
        }))
    }

    /// The sky model, with `type` for `cie_general` and only there.
    fn model(&self, sky: &Spanned<SkyToml>) -> Result<SkyModel> {
        let table = sky.get_ref();
        let name = table.model.get_ref().as_str();
        let model = match name {
            "cie_overcast" => SkyModel::CieOvercast,
            "cie_clear" => SkyModel::CieClear,
            "cie_intermediate" => SkyModel::CieIntermediate,
            "uniform" => SkyModel::Uniform,
            "cie_general" => {
                let Some(kind) = &table.general_type else {
                    return Err(self.missing(
                        "sky",
                        "type",
                        sky.span(),
                        "model = \"cie_general\" needs type = 1…15 (ISO 15469)",
                    ));
                };
                let value = *kind.get_ref();
                if !(1..=15).contains(&value) {
                    return Err(self.fault(
                        "sky",
                        "type",
                        kind.span(),
                        "must be an integer from 1 to 15 (ISO 15469)",
                    ));
                }
                SkyModel::CieGeneral(value as u8)
            }
            _ => {
                let message = "is not a sky model: use cie_overcast, cie_clear, cie_intermediate, cie_general or uniform";
                return Err(self.fault("sky", "model", table.model.span(), message));
            }
        };
        if let (Some(kind), false) = (&table.general_type, name == "cie_general") {
            return Err(self.fault(
                "sky",
                "type",
                kind.span(),
                "belongs to model = \"cie_general\" only",
            ));
        }
        Ok(model)
    }

    /// L_z from `zenith_luminance`, or for `horizontal_illuminance` (one,
    /// not both; 10,000 lx when neither).
    fn zenith_luminance(
        &self,
        table: &SkyToml,
        model: SkyModel,
        sun: Option<SkyDirection>,
    ) -> Result<f64> {
        let positive = |value: &Spanned<f64>, key: &str| {
            let v = *value.get_ref();
            if v.is_finite() && v > 0.0 {
                Ok(v)
            } else {
                Err(self.fault("sky", key, value.span(), "must be a number above 0"))
            }
        };
        match (&table.horizontal_illuminance, &table.zenith_luminance) {
            (Some(_), Some(zenith)) => Err(self.fault(
                "sky",
                "zenith_luminance",
                zenith.span(),
                "give horizontal_illuminance or zenith_luminance, not both",
            )),
            (None, Some(zenith)) => positive(zenith, "zenith_luminance"),
            (horizontal, None) => {
                let e_h = match horizontal {
                    Some(value) => positive(value, "horizontal_illuminance")?,
                    None => DEFAULT_HORIZONTAL_ILLUMINANCE,
                };
                let span = horizontal
                    .as_ref()
                    .map_or(table.model.span(), Spanned::span);
                Sky::zenith_luminance_for(model, sun, e_h)
                    .map_err(|message| self.fault("sky", "model", span, &message))
            }
        }
    }

    /// The sun: its position given or computed, its beam's illuminance.
    fn sun(&self, sun: &Spanned<SunToml>) -> Result<Sun> {
        let t = sun.get_ref();
        let number = |value: &Spanned<f64>, key: &str, range: Range<f64>| {
            let v = *value.get_ref();
            if v.is_finite() && v >= range.start && v <= range.end {
                Ok(v)
            } else {
                let message = format!("must be a number from {} to {}", range.start, range.end);
                Err(self.fault("sun", key, value.span(), &message))
            }
        };
        let given = (&t.altitude_deg, &t.azimuth_deg);
        let place = (&t.latitude, &t.longitude, &t.time);
        let position = match (given, place) {
            ((Some(altitude), Some(azimuth)), (None, None, None)) => {
                let altitude = number(altitude, "altitude_deg", -90.0..90.0)?;
                let azimuth = number(azimuth, "azimuth_deg", -360.0..360.0)?;
                SkyDirection {
                    altitude: altitude.to_radians(),
                    azimuth: azimuth.rem_euclid(360.0).to_radians(),
                }
            }
            ((None, None), (Some(latitude), Some(longitude), Some(time))) => {
                let latitude = number(latitude, "latitude", -90.0..90.0)?;
                let longitude = number(longitude, "longitude", -180.0..180.0)?;
                let instant: Instant = time
                    .get_ref()
                    .parse()
                    .map_err(|message: String| self.fault("sun", "time", time.span(), &message))?;
                let p = solar_position(latitude, longitude, &instant);
                SkyDirection {
                    altitude: p.altitude_deg.to_radians(),
                    azimuth: p.azimuth_deg.rem_euclid(360.0).to_radians(),
                }
            }
            _ => {
                let message = "give altitude_deg and azimuth_deg, or latitude, longitude and time";
                return Err(self.missing("sun", "altitude_deg", sun.span(), message));
            }
        };
        let Some(normal) = &t.normal_illuminance else {
            let message = "is required: the sun's direct normal illuminance in lux (0 for the sky's pattern without the beam)";
            return Err(self.missing("sun", "normal_illuminance", sun.span(), message));
        };
        let normal_illuminance = number(normal, "normal_illuminance", 0.0..f64::MAX)?;
        Ok(Sun {
            position,
            normal_illuminance,
        })
    }

    /// The error of `key` in `[table]`, whose value is the text at `span`.
    fn fault(&self, table: &'static str, key: &str, span: Range<usize>, message: &str) -> Error {
        let value = self.text.get(span.clone()).unwrap_or("?").trim();
        let value = value.lines().next().unwrap_or(value);
        Error::SceneDaylight {
            path: self.path.to_path_buf(),
            line: line_at(self.text, span.start),
            table,
            key: key.to_owned(),
            value: value.to_owned(),
            message: message.to_owned(),
        }
    }

    /// The error of a missing `key` in `[table]`, whose body is at `span`.
    fn missing(&self, table: &'static str, key: &str, span: Range<usize>, message: &str) -> Error {
        Error::SceneDaylight {
            path: self.path.to_path_buf(),
            line: line_at(self.text, span.start),
            table,
            key: key.to_owned(),
            value: "(missing)".to_owned(),
            message: message.to_owned(),
        }
    }
}
