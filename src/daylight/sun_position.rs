//! The sun's apparent position by NOAA's solar calculator: Meeus's
//! low-accuracy solar coordinates, the equation of time, and refraction.
//!
//! # The algorithm (NOAA's spreadsheet, column by column)
//!
//! With T the Julian centuries from J2000.0 (UT taken for TT; ΔT ≈ 70 s
//! moves the sun by 0.001°) and angles in degrees:
//!
//! ```text
//!   L0 = 280.46646 + T (36000.76983 + 0.0003032 T)            mean longitude
//!   M  = 357.52911 + T (35999.05029 − 0.0001537 T)            mean anomaly
//!   e  = 0.016708634 − T (0.000042037 + 0.0000001267 T)       eccentricity
//!   C  = (1.914602 − T (0.004817 + 0.000014 T)) sin M
//!      + (0.019993 − 0.000101 T) sin 2M + 0.000289 sin 3M      equation of centre
//!   λ  = L0 + C − 0.00569 − 0.00478 sin Ω,  Ω = 125.04 − 1934.136 T
//!   ε  = 23° 26′ (21.448 − T (46.815 + T (0.00059 − 0.001813 T)))″ + 0.00256 cos Ω
//!   δ  = asin(sin ε sin λ)                                    declination
//!   E  = 4 · deg(y sin 2L0 − 2e sin M + 4ey sin M cos 2L0 − y²/2 sin 4L0 − 5e²/4 sin 2M),
//!        y = tan²(ε/2)                                         equation of time, min
//!   H  = (UTC minutes + E + 4 · longitude) / 4 − 180           hour angle
//! ```
//!
//! The sun's local direction is east = −cos δ sin H,
//! north = cos φ sin δ − sin φ cos δ cos H, up = sin φ sin δ + cos φ cos δ cos H
//! (φ the latitude); its azimuth atan2(east, north) is the angle NOAA gets
//! from acos, without acos's trouble at the zenith and the poles. NOAA's
//! refraction (standard atmosphere, 1010 hPa and 10 °C), with h the true
//! elevation, is, in arc seconds,
//!
//! ```text
//!   h > 85°:            0
//!   5° < h ≤ 85°:       58.1 / tan h − 0.07 / tan³ h + 0.000086 / tan⁵ h
//!   −0.575° < h ≤ 5°:   1735 − 518.2 h + 103.4 h² − 12.79 h³ + 0.711 h⁴
//!   h ≤ −0.575°:        −20.772 / tan h
//! ```
//!
//! # Accuracy
//!
//! Meeus gives the low-accuracy solar coordinates as good to 0.01° (for
//! dates within a few centuries of 2000); NOAA states its sunrise and
//! sunset times are theoretically accurate to within a minute between ±72°
//! latitude (its spreadsheet's Julian-day shortcut limits it to 1901–2099;
//! the Julian day here is exact for any Gregorian date). On NREL SPA's
//! example (SPA itself ±0.0003°) this position is off by 0.003° in zenith
//! angle and 0.002° in azimuth; the tests allow 0.01°. Near the horizon,
//! refraction, which varies with the weather by a tenth of a degree or
//! more, dominates the error.
//!
//! # References
//! - J. Meeus, *Astronomical Algorithms*, 2nd ed., Willmann-Bell 1998,
//!   ch. 25 (solar coordinates, low accuracy), ch. 28 (equation of time).
//! - NOAA Global Monitoring Laboratory, *Solar Calculation Details* and the
//!   spreadsheet `NOAA_Solar_Calculations_day.xls`.
//! - I. Reda, A. Andreas, *Solar Position Algorithm for Solar Radiation
//!   Applications*, NREL/TP-560-34302, 2003, rev. 2008 (the test example).

use super::direction::SkyDirection;
use super::instant::Instant;

/// The Julian day of J2000.0.
const J2000: f64 = 2_451_545.0;
/// Days in a Julian century.
const JULIAN_CENTURY: f64 = 36_525.0;

/// The sun's apparent position, from NOAA's solar calculator algorithm
/// (Meeus, *Astronomical Algorithms*; NOAA Global Monitoring Laboratory
/// spreadsheet), with refraction.
///
/// Accurate to about 0.01° in both angles for the sun a few degrees or more
/// above the horizon and dates within a few centuries of 2000 (see the
/// module docs); nearer the horizon, to the accuracy of a standard
/// atmosphere's refraction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolarPosition {
    /// Apparent altitude above the horizon, refraction included, degrees.
    pub altitude_deg: f64,
    /// Azimuth clockwise from north, degrees in [0, 360).
    pub azimuth_deg: f64,
}

impl SolarPosition {
    /// The same direction as a [`SkyDirection`] (radians).
    #[must_use]
    pub fn direction(&self) -> SkyDirection {
        SkyDirection::from_degrees(self.altitude_deg, self.azimuth_deg)
    }
}

/// The sun's declination and the equation of time at an instant, the two
/// quantities of the algorithm that do not depend on the site.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolarGeometry {
    /// Declination δ, degrees north of the celestial equator.
    pub declination_deg: f64,
    /// Right ascension α, degrees in [0, 360).
    pub right_ascension_deg: f64,
    /// Equation of time E = apparent − mean solar time, minutes.
    pub equation_of_time_min: f64,
}

/// Sine and cosine of an angle in degrees.
fn sin_deg(x: f64) -> f64 {
    x.to_radians().sin()
}

fn cos_deg(x: f64) -> f64 {
    x.to_radians().cos()
}

/// Declination, right ascension and equation of time at `time` (see the
/// module docs for the formulas).
#[must_use]
pub fn solar_geometry(time: &Instant) -> SolarGeometry {
    let t = (time.julian_day() - J2000) / JULIAN_CENTURY;
    let mean_longitude = (280.466_46 + t * (36_000.769_83 + t * 0.000_303_2)).rem_euclid(360.0);
    let mean_anomaly = 357.529_11 + t * (35_999.050_29 - 0.000_153_7 * t);
    let eccentricity = 0.016_708_634 - t * (0.000_042_037 + 0.000_000_126_7 * t);
    let centre = sin_deg(mean_anomaly) * (1.914_602 - t * (0.004_817 + 0.000_014 * t))
        + sin_deg(2.0 * mean_anomaly) * (0.019_993 - 0.000_101 * t)
        + sin_deg(3.0 * mean_anomaly) * 0.000_289;
    let node = 125.04 - 1934.136 * t;
    let apparent_longitude = mean_longitude + centre - 0.005_69 - 0.004_78 * sin_deg(node);
    let mean_obliquity =
        23.0 + (26.0 + (21.448 - t * (46.815 + t * (0.000_59 - t * 0.001_813))) / 60.0) / 60.0;
    let obliquity = mean_obliquity + 0.002_56 * cos_deg(node);
    let declination = (sin_deg(obliquity) * sin_deg(apparent_longitude))
        .asin()
        .to_degrees();
    let right_ascension = (cos_deg(obliquity) * sin_deg(apparent_longitude))
        .atan2(cos_deg(apparent_longitude))
        .to_degrees()
        .rem_euclid(360.0);
    let y = (obliquity / 2.0).to_radians().tan().powi(2);
    let (l0, m, e) = (mean_longitude, mean_anomaly, eccentricity);
    let equation_of_time = 4.0
        * (y * sin_deg(2.0 * l0) - 2.0 * e * sin_deg(m)
            + 4.0 * e * y * sin_deg(m) * cos_deg(2.0 * l0)
            - 0.5 * y * y * sin_deg(4.0 * l0)
            - 1.25 * e * e * sin_deg(2.0 * m))
        .to_degrees();
    SolarGeometry {
        declination_deg: declination,
        right_ascension_deg: right_ascension,
        equation_of_time_min: equation_of_time,
    }
}

/// NOAA's atmospheric refraction (degrees) at true elevation
/// `elevation_deg` (see the module docs).
#[must_use]
pub fn refraction_deg(elevation_deg: f64) -> f64 {
    let h = elevation_deg;
    let tan = h.to_radians().tan();
    let arc_seconds = if h > 85.0 {
        0.0
    } else if h > 5.0 {
        58.1 / tan - 0.07 / tan.powi(3) + 0.000_086 / tan.powi(5)
    } else if h > -0.575 {
        1735.0 + h * (-518.2 + h * (103.4 + h * (-12.79 + h * 0.711)))
    } else {
        -20.772 / tan
    };
    arc_seconds / 3600.0
}

/// The sun's apparent position (refraction added to the true elevation)
/// seen from latitude `latitude_deg` (degrees, north positive) and
/// longitude `longitude_deg` (degrees, east positive) at `time`, by
/// NOAA's algorithm; see the module docs for the formulas and accuracy.
/// Latitudes outside ±90° and non-finite inputs give meaningless or NaN
/// angles: the caller checks its site.
#[must_use]
pub fn solar_position(latitude_deg: f64, longitude_deg: f64, time: &Instant) -> SolarPosition {
    let geometry = solar_geometry(time);
    let true_solar_minutes =
        (time.utc_minutes_of_day() + geometry.equation_of_time_min + 4.0 * longitude_deg)
            .rem_euclid(1440.0);
    let hour_angle = true_solar_minutes / 4.0 - 180.0;
    let (sin_lat, cos_lat) = latitude_deg.to_radians().sin_cos();
    let (sin_dec, cos_dec) = geometry.declination_deg.to_radians().sin_cos();
    let (sin_h, cos_h) = hour_angle.to_radians().sin_cos();
    let east = -cos_dec * sin_h;
    let north = cos_lat * sin_dec - sin_lat * cos_dec * cos_h;
    let up = sin_lat * sin_dec + cos_lat * cos_dec * cos_h;
    let elevation = up.atan2(east.hypot(north)).to_degrees();
    let azimuth = east.atan2(north).to_degrees().rem_euclid(360.0);
    SolarPosition {
        altitude_deg: elevation + refraction_deg(elevation),
        azimuth_deg: if azimuth >= 360.0 { 0.0 } else { azimuth },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(text: &str) -> Instant {
        text.parse().unwrap_or_else(|e| panic!("{e}"))
    }

    /// The smallest difference of two azimuths, degrees.
    fn azimuth_gap(a: f64, b: f64) -> f64 {
        let d = (a - b).rem_euclid(360.0);
        d.min(360.0 - d)
    }

    #[test]
    fn nrel_spa_example() {
        // Reda & Andreas, NREL/TP-560-34302, Table A5.1: Golden, Colorado,
        // 2003-10-17 12:30:30 at UTC−7: topocentric zenith 50.11162°,
        // azimuth 194.34024° (for 820 hPa and 11 °C; the refraction's
        // difference from NOAA's standard atmosphere is about 0.004°).
        let sun = solar_position(39.742_476, -105.1786, &at("2003-10-17T12:30:30-07:00"));
        assert!(
            ((90.0 - sun.altitude_deg) - 50.111_62).abs() < 0.01,
            "{sun:?}"
        );
        assert!(azimuth_gap(sun.azimuth_deg, 194.340_24) < 0.01, "{sun:?}");
        let geometry = solar_geometry(&at("2003-10-17T12:30:30-07:00"));
        assert!(
            (geometry.declination_deg - -9.314_34).abs() < 0.005,
            "{geometry:?}"
        );
        assert!(
            (geometry.equation_of_time_min - 14.641_503).abs() < 0.02,
            "{geometry:?}"
        );
    }

    #[test]
    fn meeus_example_25a() {
        // Meeus, Astronomical Algorithms, example 25.a: 1992 October 13.0 TD
        // (JD 2448908.5): δ = −7.78507°, α = 198.38083° (13h 13m 31.4s).
        let geometry = solar_geometry(&Instant::from_unix_seconds(
            (2_448_908.5 - 2_440_587.5) * 86_400.0,
        ));
        assert!(
            (geometry.declination_deg - -7.785_07).abs() < 2e-5,
            "{geometry:?}"
        );
        assert!(
            (geometry.right_ascension_deg - 198.380_83).abs() < 2e-5,
            "{geometry:?}"
        );
        // Example 28.b, the same date: E = 13m 42.7s by the low-accuracy formula.
        assert!(
            (geometry.equation_of_time_min - 13.71).abs() < 0.02,
            "{geometry:?}"
        );
    }

    #[test]
    fn noaa_spreadsheet_row() {
        // NOAA's NOAA_Solar_Calculations_day.xls, its example row: 2010-06-21
        // 00:06 at UTC−7, latitude 40°, longitude −105° (JD 2455368.7958333).
        let time = at("2010-06-21T00:06:00-07:00");
        assert!((time.julian_day() - 2_455_368.795_833_33).abs() < 1e-7);
        let geometry = solar_geometry(&time);
        assert!(
            (geometry.declination_deg - 23.438_370_619_286_9).abs() < 1e-8,
            "{geometry:?}"
        );
        assert!(
            (geometry.right_ascension_deg - 89.809_480_084_421_4).abs() < 1e-8,
            "{geometry:?}"
        );
        assert!(
            (geometry.equation_of_time_min - -1.715_367_578_469_53).abs() < 1e-8,
            "{geometry:?}"
        );
        let sun = solar_position(40.0, -105.0, &time);
        assert!((refraction_deg(-26.553_762_119_181_3) - 0.011_545_686_591_924_2).abs() < 1e-10);
        assert!(
            (sun.altitude_deg - -26.542_216_432_589_3).abs() < 1e-7,
            "{sun:?}"
        );
        assert!(
            azimuth_gap(sun.azimuth_deg, 1.098_671_183_884_45) < 1e-7,
            "{sun:?}"
        );
    }

    /// The highest altitude of the day at a site, by the minute.
    fn noon_altitude(latitude: f64, longitude: f64, midnight: &str) -> SolarPosition {
        let start = at(midnight).unix_seconds();
        (0..1440)
            .map(|minute| {
                solar_position(
                    latitude,
                    longitude,
                    &Instant::from_unix_seconds(start + 60.0 * f64::from(minute)),
                )
            })
            .fold(
                SolarPosition {
                    altitude_deg: -90.0,
                    azimuth_deg: 0.0,
                },
                |best, p| {
                    if p.altitude_deg > best.altitude_deg {
                        p
                    } else {
                        best
                    }
                },
            )
    }

    #[test]
    fn solstice_and_equinox_noons() {
        // Noon altitude 90° − φ + δ (north of the sun) or 90° + φ − δ. The
        // 2026 June solstice is on the 21st at 08:24 UTC (δ = ε = 23.436°),
        // the March equinox on the 20th at 14:46 UTC (δ = 0); the longitudes
        // put local noon near those instants. Refraction adds 0.005° at 73°,
        // 0.06° at 15°.
        let june = noon_altitude(40.0, 54.4, "2026-06-21T00:00+03:38");
        assert!(
            (june.altitude_deg - (90.0 - 40.0 + 23.436)).abs() < 0.1,
            "{june:?}"
        );
        assert!(azimuth_gap(june.azimuth_deg, 180.0) < 1.0, "{june:?}");
        let south = noon_altitude(-40.0, 54.4, "2026-06-21T00:00+03:38");
        assert!(
            (south.altitude_deg - (90.0 - 40.0 - 23.436)).abs() < 0.1,
            "{south:?}"
        );
        assert!(azimuth_gap(south.azimuth_deg, 0.0) < 1.0, "{south:?}");
        let march = noon_altitude(30.0, -39.6, "2026-03-20T00:00-02:38");
        assert!((march.altitude_deg - 60.0).abs() < 0.1, "{march:?}");
        let december = noon_altitude(51.48, 0.0, "2026-12-21T00:00Z");
        assert!(
            (december.altitude_deg - (90.0 - 51.48 - 23.436)).abs() < 0.1,
            "{december:?}"
        );
    }

    #[test]
    fn refraction_is_continuous_enough_and_vanishes_overhead() {
        assert_eq!(refraction_deg(89.0), 0.0);
        assert!((refraction_deg(0.0) - 1735.0 / 3600.0).abs() < 1e-12);
        assert!((refraction_deg(5.0 + 1e-9) - refraction_deg(5.0)).abs() < 0.001);
        assert!(refraction_deg(45.0) > 0.015 && refraction_deg(45.0) < 0.017);
    }

    #[test]
    fn the_direction_matches_the_angles() {
        let p = SolarPosition {
            altitude_deg: 30.0,
            azimuth_deg: 90.0,
        };
        let v = p.direction().to_local();
        assert!((v - glam::DVec3::new(30f64.to_radians().cos(), 0.0, 0.5)).length() < 1e-15);
    }
}
