//! Directions on the sky: altitude and azimuth, and their local vectors.

use glam::DVec3;
use std::f64::consts::{FRAC_PI_2, TAU};

/// A direction on the sky: altitude above the horizon and azimuth clockwise from north, radians.
///
/// In local (east, north, up) = (x, y, z) coordinates,
///
/// ```text
///   east  = cos(altitude) sin(azimuth)
///   north = cos(altitude) cos(azimuth)
///   up    = sin(altitude)
/// ```
///
/// so azimuth 0 is north, π/2 east, π south and 3π/2 west, as NOAA's solar
/// calculator counts it. Radiance's `gensky -ang` counts azimuth west of
/// south: azimuth = azimuth_gensky + π.
///
/// # References
/// - NOAA Global Monitoring Laboratory, *Solar Calculation Details*
///   (azimuth "degrees clockwise from north").
/// - G. Ward, Radiance `gensky(1)` (azimuth "degrees west of South").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SkyDirection {
    /// Angle above the horizon, radians: 0 on it, π/2 at the zenith.
    pub altitude: f64,
    /// Angle clockwise from north seen from above, radians.
    pub azimuth: f64,
}

impl SkyDirection {
    /// The zenith.
    pub const ZENITH: SkyDirection = SkyDirection {
        altitude: FRAC_PI_2,
        azimuth: 0.0,
    };

    /// From degrees: altitude above the horizon, azimuth clockwise from north.
    #[must_use]
    pub fn from_degrees(altitude_deg: f64, azimuth_deg: f64) -> SkyDirection {
        SkyDirection {
            altitude: altitude_deg.to_radians(),
            azimuth: azimuth_deg.to_radians(),
        }
    }

    /// From a unit vector in local (east, north, up) coordinates.
    ///
    /// altitude = atan2(up, √(east² + north²)), azimuth = atan2(east, north)
    /// in [0, 2π); the vector need not be unit (only its direction counts).
    /// The zero vector gives the horizon due north.
    #[must_use]
    pub fn from_local(east: f64, north: f64, up: f64) -> SkyDirection {
        let altitude = up.atan2(east.hypot(north));
        let azimuth = east.atan2(north).rem_euclid(TAU);
        // rem_euclid may round −0⁻ up to exactly 2π.
        let azimuth = if azimuth >= TAU { 0.0 } else { azimuth };
        SkyDirection { altitude, azimuth }
    }

    /// Back to (east, north, up) unit components as glam::DVec3 (x = east, y = north, z = up).
    #[must_use]
    pub fn to_local(self) -> DVec3 {
        if self.altitude == FRAC_PI_2 {
            // Exactly up, not (0, 6e-17, 1): the zenith's patterns are exact.
            return DVec3::Z;
        }
        let (sin_alt, cos_alt) = self.altitude.sin_cos();
        let (sin_az, cos_az) = self.azimuth.sin_cos();
        DVec3::new(cos_alt * sin_az, cos_alt * cos_az, sin_alt)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn the_compass_points() {
        let north = SkyDirection::from_local(0.0, 1.0, 0.0);
        assert_eq!(
            north,
            SkyDirection {
                altitude: 0.0,
                azimuth: 0.0
            }
        );
        let east = SkyDirection::from_local(1.0, 0.0, 0.0);
        assert!((east.azimuth - FRAC_PI_2).abs() < 1e-15);
        let south = SkyDirection::from_local(0.0, -1.0, 0.0);
        assert!((south.azimuth - PI).abs() < 1e-15);
        let west = SkyDirection::from_local(-1.0, 0.0, 0.0);
        assert!((west.azimuth - 1.5 * PI).abs() < 1e-15);
        let zenith = SkyDirection::from_local(0.0, 0.0, 1.0);
        assert!((zenith.altitude - FRAC_PI_2).abs() < 1e-15);
        assert!((SkyDirection::ZENITH.to_local() - DVec3::Z).length() < 1e-15);
    }

    #[test]
    fn to_local_inverts_from_local() {
        for v in [
            DVec3::new(0.3, -0.4, 0.5),
            DVec3::new(-0.9, -0.1, 0.2),
            DVec3::new(0.0, 0.2, -0.7),
        ] {
            let unit = v.normalize();
            let back = SkyDirection::from_local(v.x, v.y, v.z).to_local();
            assert!((back - unit).length() < 1e-14, "{back} vs {unit}");
        }
        let d = SkyDirection::from_degrees(30.0, 135.0);
        let again = SkyDirection::from_local(d.to_local().x, d.to_local().y, d.to_local().z);
        assert!(
            (again.altitude - d.altitude).abs() < 1e-14
                && (again.azimuth - d.azimuth).abs() < 1e-14
        );
    }

    #[test]
    fn the_zero_vector_is_the_horizon_due_north() {
        assert_eq!(
            SkyDirection::from_local(0.0, 0.0, 0.0),
            SkyDirection {
                altitude: 0.0,
                azimuth: 0.0
            }
        );
    }
}
