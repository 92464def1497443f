//! The sky luminance models: the pattern L/L_z of each, as a function of a
//! direction and the sun's, in local (east, north, up) unit vectors.
//!
//! Angles are computed from the vectors with atan2 (χ = atan2(|ω × s|, ω·s),
//! and the zenith angle likewise with the zenith for s), which keeps them
//! exact near the sun and the zenith where acos loses half the digits.

use glam::DVec3;

use super::cie_general::{CieGeneralParameters, cie_general_parameters};

/// The sky luminance distributions: each gives L/L_z, the luminance relative
/// to the zenith's, above the horizon.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SkyModel {
    /// CIE standard overcast sky (Moon & Spencer 1942, CIE 1955):
    /// L(γ) = L_z (1 + 2 sin γ) / 3, γ the altitude; 1/3 at the horizon.
    ///
    /// # References
    /// P. Moon, D. E. Spencer, "Illumination from a non-uniform sky", Illum.
    /// Eng. 37, 1942; CIE, *Natural Daylight, Official Recommendation*, 1955.
    CieOvercast,
    /// CIE clear sky (CIE 110-1994; ISO 15469 / CIE S 011 type 12 but for
    /// a rounded constant), as Radiance's `gensky +s` uses it.
    ///
    /// ```text
    ///   L/L_z = (0.91 + 10 e^(−3χ) + 0.45 cos² χ)(1 − e^(−0.32 / cos Z))
    ///         / ((0.91 + 10 e^(−3 Z_s) + 0.45 cos² Z_s)(1 − e^(−0.32)))
    /// ```
    ///
    /// χ the angle to the sun, Z the zenith angle, Z_s the sun's. Type 12 of
    /// the general sky writes the indicatrix's constant as
    /// 1 − 10 e^(−3π/2) = 0.910 17 instead of 0.91: the two patterns differ
    /// by less than 0.02 %. Radiance's `skybright.cal` (`sunnysky`)
    /// evaluates the same expression but divides by gensky's
    /// F2 = 0.274 (0.91 + 10 e^(−3 Z_s) + 0.45 cos² Z_s), 1 − e^(−0.32) =
    /// 0.273 85 rounded: its L/L_z at the zenith is 0.9995. Here it is 1.
    ///
    /// # References
    /// CIE 110-1994, *Spatial distribution of daylight — luminance
    /// distributions of various reference skies*; CIE Publication 22,
    /// *Standardization of luminance distribution on clear skies*, 1973;
    /// Radiance `src/gen/skybright.cal`
    /// and `src/gen/gensky.c` (LBNL-ETA/Radiance).
    CieClear,
    /// CIE intermediate sky, as Radiance's `gensky +i` computes it.
    ///
    /// With η the zenith angle, χ the angle to the sun and Z_s the sun's
    /// zenith angle (radians), Radiance's `skybright.cal` (`intersky`) is
    ///
    /// ```text
    ///   g(η, χ) = [(1.35 sin(5.631 − 3.59 η) + 3.12) sin(4.396 − 2.6 Z_s) + 6.37 − η] / 2.326
    ///             · exp(−0.563 χ ((2.629 − η)(1.562 − Z_s) + 0.812))
    ///   L/L_z  = g(η, χ) / g(0, Z_s)
    /// ```
    ///
    /// gensky divides by its F2 = (2.739 + 0.9891 sin(0.3119 + 2.6 α_s))
    /// · exp(−(π/2 − α_s)(0.4441 + 1.48 α_s)), α_s = π/2 − Z_s: g(0, Z_s)
    /// multiplied out with its constants rounded to four digits (within
    /// 0.1 %, tested). Here the exact g(0, Z_s) normalises, so L/L_z = 1
    /// at the zenith. The pattern has a cusp at the zenith (it is linear
    /// in η) as well as at the sun.
    ///
    /// # References
    /// Radiance `src/gen/skybright.cal` (`intersky`, rev. 2.7) and
    /// `src/gen/gensky.c` (`S_INTER`, F2; rev. 2.31), LBNL-ETA/Radiance.
    CieIntermediate,
    /// ISO 15469:2004 / CIE S 011/E:2003 general sky, types 1–15.
    ///
    /// ```text
    ///   gradation   φ(Z) = 1 + a exp(b / cos Z)        (φ(90°) = 1 at the horizon)
    ///   indicatrix  f(χ) = 1 + c (exp(d χ) − exp(d π/2)) + e cos² χ
    ///   L/L_z      = f(χ) φ(Z) / (f(Z_s) φ(0))
    /// ```
    ///
    /// a–e per type are in [`cie_general_parameters`]; types 1, 3 and 5
    /// (c = e = 0) need no sun.
    ///
    /// # References
    /// ISO 15469:2004(E) / CIE S 011/E:2003, *Spatial distribution of
    /// daylight — CIE standard general sky*.
    CieGeneral(u8),
    /// Uniform luminance L_z everywhere above the horizon.
    Uniform,
}

impl SkyModel {
    /// Whether the pattern depends on the sun's direction: the clear and
    /// intermediate skies and the general types whose indicatrix varies
    /// (every type but 1, 3 and 5). A general type outside 1..=15 counts
    /// as needing none (it is refused by [`SkyModel::check`] anyway).
    #[must_use]
    pub fn needs_sun(self) -> bool {
        match self {
            SkyModel::CieClear | SkyModel::CieIntermediate => true,
            SkyModel::CieGeneral(t) => cie_general_parameters(t).is_some_and(|p| p.needs_sun()),
            SkyModel::CieOvercast | SkyModel::Uniform => false,
        }
    }

    /// The model's name, as messages use it.
    #[must_use]
    pub fn name(self) -> String {
        match self {
            SkyModel::CieOvercast => "the CIE overcast sky".to_string(),
            SkyModel::CieClear => "the CIE clear sky".to_string(),
            SkyModel::CieIntermediate => "the CIE intermediate sky".to_string(),
            SkyModel::CieGeneral(t) => format!("CIE general sky type {t}"),
            SkyModel::Uniform => "the uniform sky".to_string(),
        }
    }

    /// Err naming the problem when the model itself is invalid (a general
    /// type outside 1..=15).
    pub fn check(self) -> Result<(), String> {
        match self {
            SkyModel::CieGeneral(t) if cie_general_parameters(t).is_none() => Err(format!(
                "CIE general sky type {t} does not exist: the standard's types are 1 to 15"
            )),
            _ => Ok(()),
        }
    }

    /// L/L_z toward the unit local direction `to`, for the unit sun
    /// direction `sun` (ignored by models that need none; a model that
    /// needs one and has none gives NaN). 0 below the horizon (z < 0).
    /// For many directions under one sun, [`SkyPattern`] computes the
    /// normalisation once.
    #[must_use]
    pub fn relative_luminance_toward(self, sun: Option<DVec3>, to: DVec3) -> f64 {
        SkyPattern::new(self, sun).relative_luminance(to)
    }
}

/// What a pattern evaluates, with the model's table row looked up.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Shape {
    Uniform,
    Overcast,
    Clear,
    Intermediate,
    /// A general type, with or without its sun-dependent indicatrix.
    General {
        parameters: CieGeneralParameters,
        with_sun: bool,
    },
    /// A general type outside 1..=15, or a needed sun missing.
    Invalid,
}

/// A model's pattern under one sun, its value at the zenith computed once:
/// L/L_z = pattern(ω) / pattern(zenith), the two by the same arithmetic so
/// that the zenith gives exactly 1. Built from a model [`SkyModel::check`]
/// refuses, or without a sun the model needs, it gives NaN above the
/// horizon ([`Sky::new`](super::Sky::new) refuses both).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SkyPattern {
    shape: Shape,
    sun: DVec3,
    sun_zenith: f64,
    zenith_value: f64,
}

impl SkyPattern {
    /// The pattern of `model` for the unit local sun direction `sun`.
    #[must_use]
    pub fn new(model: SkyModel, sun: Option<DVec3>) -> SkyPattern {
        let shape = match (model, sun) {
            (SkyModel::Uniform, _) => Shape::Uniform,
            (SkyModel::CieOvercast, _) => Shape::Overcast,
            (SkyModel::CieClear, Some(_)) => Shape::Clear,
            (SkyModel::CieIntermediate, Some(_)) => Shape::Intermediate,
            (SkyModel::CieGeneral(t), _) => match cie_general_parameters(t) {
                Some(p) if p.needs_sun() && sun.is_none() => Shape::Invalid,
                Some(p) => Shape::General {
                    parameters: p,
                    with_sun: p.needs_sun(),
                },
                None => Shape::Invalid,
            },
            (SkyModel::CieClear | SkyModel::CieIntermediate, None) => Shape::Invalid,
        };
        let sun = sun.unwrap_or(DVec3::Z);
        let mut pattern = SkyPattern {
            shape,
            sun,
            sun_zenith: zenith_angle(sun),
            zenith_value: 1.0,
        };
        pattern.zenith_value = pattern.unnormalised(DVec3::Z);
        pattern
    }

    /// L/L_z toward the unit local direction `to`; 0 below the horizon.
    #[must_use]
    pub fn relative_luminance(&self, to: DVec3) -> f64 {
        if to.z.is_nan() || to.z < 0.0 {
            return 0.0;
        }
        self.unnormalised(to) / self.zenith_value
    }

    /// The pattern before normalisation (see [`SkyModel`]'s variants).
    fn unnormalised(&self, to: DVec3) -> f64 {
        match self.shape {
            Shape::Uniform => 1.0,
            Shape::Overcast => (1.0 + 2.0 * to.z) / 3.0,
            Shape::Clear => {
                let gradation = if to.z > 0.0 {
                    1.0 - (-0.32 / to.z).exp()
                } else {
                    1.0
                };
                clear_indicatrix(angle_between(to, self.sun)) * gradation
            }
            Shape::Intermediate => intermediate_pattern(
                zenith_angle(to),
                angle_between(to, self.sun),
                self.sun_zenith,
            ),
            Shape::General {
                parameters: p,
                with_sun,
            } => {
                let gradation = p.gradation(to.z);
                if with_sun {
                    gradation * p.indicatrix(angle_between(to, self.sun))
                } else {
                    gradation
                }
            }
            Shape::Invalid => f64::NAN,
        }
    }
}

/// The angle between two unit vectors, exact near 0 and π.
fn angle_between(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}

/// The zenith angle of a unit local vector (the same arithmetic as
/// [`angle_between`] with the zenith, so that a pattern's value at the
/// zenith and its normalisation agree to the last bit).
fn zenith_angle(v: DVec3) -> f64 {
    angle_between(DVec3::Z, v)
}

/// The CIE 1973 clear sky's indicatrix 0.91 + 10 e^(−3χ) + 0.45 cos² χ.
fn clear_indicatrix(chi: f64) -> f64 {
    let cos = chi.cos();
    0.91 + 10.0 * (-3.0 * chi).exp() + 0.45 * cos * cos
}

/// Radiance's intermediate-sky function g(η, χ) for the sun at zenith
/// angle `sun_zenith` (see [`SkyModel::CieIntermediate`]).
fn intermediate_pattern(eta: f64, chi: f64, sun_zenith: f64) -> f64 {
    let graded = ((1.35 * (5.631 - 3.59 * eta).sin() + 3.12) * (4.396 - 2.6 * sun_zenith).sin()
        + 6.37
        - eta)
        / 2.326;
    graded * (-0.563 * chi * ((2.629 - eta) * (1.562 - sun_zenith) + 0.812)).exp()
}

/// gensky's normalisation F2 of the intermediate sky for the sun at
/// altitude `sun_altitude`: g(0, Z_s) with rounded constants (for tests).
#[cfg(test)]
pub(crate) fn gensky_intermediate_f2(sun_altitude: f64) -> f64 {
    (2.739 + 0.9891 * (0.3119 + 2.6 * sun_altitude).sin())
        * (-(std::f64::consts::FRAC_PI_2 - sun_altitude) * (0.4441 + 1.48 * sun_altitude)).exp()
}

/// The unit vector at altitude `altitude` (radians) due south, for tests.
#[cfg(test)]
pub(crate) fn south_at(altitude: f64) -> DVec3 {
    DVec3::new(0.0, -altitude.cos(), altitude.sin())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    #[test]
    fn every_model_is_one_at_the_zenith() {
        let suns = [0.0, 0.1, 0.5, 1.0, 1.4, FRAC_PI_2].map(south_at);
        let mut models = vec![
            SkyModel::CieOvercast,
            SkyModel::CieClear,
            SkyModel::CieIntermediate,
            SkyModel::Uniform,
        ];
        models.extend((1..=15).map(SkyModel::CieGeneral));
        for model in models {
            for sun in suns {
                let zenith = model.relative_luminance_toward(Some(sun), DVec3::Z);
                assert_eq!(zenith, 1.0, "{model:?}, sun {sun}");
            }
        }
    }

    #[test]
    fn below_the_horizon_is_dark_and_a_missing_sun_is_nan() {
        let down = DVec3::new(0.0, 0.6, -0.8);
        assert_eq!(SkyModel::Uniform.relative_luminance_toward(None, down), 0.0);
        assert_eq!(
            SkyModel::CieClear.relative_luminance_toward(Some(DVec3::Z), down),
            0.0
        );
        assert!(
            SkyModel::CieClear
                .relative_luminance_toward(None, DVec3::Y)
                .is_nan()
        );
        assert!(
            SkyModel::CieGeneral(12)
                .relative_luminance_toward(None, DVec3::Y)
                .is_nan()
        );
        assert!(
            SkyModel::CieGeneral(16)
                .relative_luminance_toward(None, DVec3::Y)
                .is_nan()
        );
        assert!(
            SkyModel::CieGeneral(3)
                .relative_luminance_toward(None, DVec3::Y)
                .is_finite()
        );
    }

    #[test]
    fn gensky_f2_is_the_exact_normalisation_rounded() {
        // gensky.c's F2 for S_INTER against g(0, Z_s) from skybright.cal.
        for altitude_deg in [2.0, 10.0, 25.0, 40.0, 60.0, 75.0, 87.0] {
            let altitude = f64::to_radians(altitude_deg);
            let exact = intermediate_pattern(0.0, FRAC_PI_2 - altitude, FRAC_PI_2 - altitude);
            let f2 = gensky_intermediate_f2(altitude);
            assert!(
                (f2 / exact - 1.0).abs() < 1e-3,
                "{altitude_deg}°: F2 {f2}, exact {exact}"
            );
        }
    }

    #[test]
    fn the_clear_sky_is_type_twelve_within_two_parts_in_ten_thousand() {
        let sun = south_at(0.6);
        for (alt, az) in [(0.05, 0.0), (0.3, 1.0), (0.6, 3.1), (1.2, 2.0), (0.9, 5.0)] {
            let to = DVec3::new(
                f64::cos(alt) * f64::sin(az),
                f64::cos(alt) * f64::cos(az),
                f64::sin(alt),
            );
            let clear = SkyModel::CieClear.relative_luminance_toward(Some(sun), to);
            let twelve = SkyModel::CieGeneral(12).relative_luminance_toward(Some(sun), to);
            assert!((clear / twelve - 1.0).abs() < 2e-4, "{clear} vs {twelve}");
        }
    }
}
