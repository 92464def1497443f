//! The daylight a scene stands in: its sky, its sun and the ground, placed
//! in the scene's coordinates.
//!
//! Every luminance here is photometric (cd/m², lux); isorad's radiometric
//! grey is 179 times less ([`LUMENS_PER_WATT`]): a sky of 1,790 cd/m² is a
//! radiance of 10 W/(m²·sr).

use std::f64::consts::PI;

use glam::DVec3;

use crate::photometry::LUMENS_PER_WATT;

use super::{Sky, SkyDirection};

/// The solar disc's angular diameter, degrees: its penumbrae.
pub const SUN_DIAMETER_DEG: f64 = 0.53;

/// Up, north and east in the scene's coordinates (unit, right-handed:
/// east = north × up).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SkyFrame {
    /// The zenith's direction.
    pub up: DVec3,
    /// North, on the horizon.
    pub north: DVec3,
    /// East, on the horizon.
    pub east: DVec3,
}

impl SkyFrame {
    /// The frame of unit `up` and a `north` not parallel to it (made
    /// horizontal); `None` when north is zero, not finite or vertical.
    #[must_use]
    pub fn new(up: DVec3, north: DVec3) -> Option<SkyFrame> {
        let up = up.try_normalize()?;
        let north = (north - up * north.dot(up)).try_normalize()?;
        (north.is_finite() && north.length() > 0.5).then(|| SkyFrame {
            up,
            north,
            east: north.cross(up),
        })
    }

    /// A scene direction (unit) on the sky.
    #[must_use]
    pub fn to_sky(&self, direction: DVec3) -> SkyDirection {
        SkyDirection::from_local(
            direction.dot(self.east),
            direction.dot(self.north),
            direction.dot(self.up),
        )
    }

    /// A direction on the sky as a scene direction (unit).
    #[must_use]
    pub fn to_scene(&self, at: SkyDirection) -> DVec3 {
        let local = at.to_local();
        self.east * local.x + self.north * local.y + self.up * local.z
    }

    /// A scene vector in local (east, north, up) coordinates.
    #[must_use]
    pub fn to_local(&self, v: DVec3) -> DVec3 {
        DVec3::new(v.dot(self.east), v.dot(self.north), v.dot(self.up))
    }
}

/// The sun: its direction and its direct normal illuminance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sun {
    /// Where it stands on the sky.
    pub position: SkyDirection,
    /// Direct normal illuminance, lux; 0 keeps the sky's pattern without
    /// the beam.
    pub normal_illuminance: f64,
}

/// The radiance of the sky and the ground toward any direction.
#[derive(Clone, Debug, PartialEq)]
pub struct SkyRadiance {
    sky: Sky,
    frame: SkyFrame,
    /// The ground's radiance, W/(m²·sr).
    ground: f64,
}

impl SkyRadiance {
    /// The radiance (W/(m²·sr), isorad's grey) seen looking along the unit
    /// scene `direction` with nothing in the way: the sky above the
    /// horizon, the ground below it. The sun's disc is not in it: the sun
    /// is a source of its own ([`Daylight::sun_direction`]).
    #[must_use]
    pub fn toward(&self, direction: DVec3) -> f64 {
        let at = self.frame.to_sky(direction);
        if at.altitude > 0.0 {
            self.sky.luminance(at) / LUMENS_PER_WATT
        } else {
            self.ground
        }
    }
}

/// A scene's daylight: the sky, the sun, the ground below the horizon.
#[derive(Clone, Debug, PartialEq)]
pub struct Daylight {
    /// The sky's luminance pattern and scale.
    pub sky: Sky,
    /// The sun, if the scene has one.
    pub sun: Option<Sun>,
    /// The ground's reflectance: below the horizon, a Lambertian plane
    /// lit by the sky and the sun.
    pub ground_reflectance: f64,
    /// Up, north and east.
    pub frame: SkyFrame,
}

impl Daylight {
    /// The sky's unobstructed horizontal illuminance, lux: E_h of the
    /// daylight factor.
    #[must_use]
    pub fn sky_horizontal_illuminance(&self) -> f64 {
        self.sky.horizontal_illuminance()
    }

    /// The sun's direct illuminance on the unobstructed horizontal plane,
    /// lux: E_n sin(altitude), 0 below the horizon.
    #[must_use]
    pub fn sun_horizontal_illuminance(&self) -> f64 {
        self.sun.map_or(0.0, |sun| {
            sun.normal_illuminance * sun.position.altitude.sin().max(0.0)
        })
    }

    /// The ground's luminance, cd/m²: L_g = ρ_g (E_sky + E_sun) / π on the
    /// unobstructed horizontal plane.
    #[must_use]
    pub fn ground_luminance(&self) -> f64 {
        self.ground_reflectance
            * (self.sky_horizontal_illuminance() + self.sun_horizontal_illuminance())
            / PI
    }

    /// The radiance seen in each direction with nothing in the way, ready
    /// to look up ([`SkyRadiance::toward`]): the ground's luminance is
    /// integrated here, once.
    #[must_use]
    pub fn radiance(&self) -> SkyRadiance {
        SkyRadiance {
            sky: self.sky.clone(),
            frame: self.frame,
            ground: self.ground_luminance() / LUMENS_PER_WATT,
        }
    }

    /// The unit scene direction toward the sun when it shines (above the
    /// horizon, with a beam).
    #[must_use]
    pub fn sun_direction(&self) -> Option<DVec3> {
        let sun = self.sun?;
        (sun.normal_illuminance > 0.0 && sun.position.altitude > 0.0)
            .then(|| self.frame.to_scene(sun.position))
    }

    /// The sun's direct normal irradiance, W/m² (isorad's grey).
    #[must_use]
    pub fn sun_normal_irradiance(&self) -> f64 {
        self.sun.map_or(0.0, |s| s.normal_illuminance) / LUMENS_PER_WATT
    }

    /// The irradiance (W/m²) on an unobstructed plane of unit scene
    /// `normal` from the sky and the ground (not the sun): the sky's part
    /// by [`Sky::plane_illuminance`], the ground's L_g π (1 − n·up) / 2.
    #[must_use]
    pub fn unobstructed_irradiance(&self, normal: DVec3) -> f64 {
        let local = self.frame.to_local(normal);
        let sky = self.sky.plane_illuminance(local);
        let ground = self.ground_luminance() * PI * (1.0 - local.z.clamp(-1.0, 1.0)) / 2.0;
        (sky + ground) / LUMENS_PER_WATT
    }

    /// The same daylight under the CIE standard overcast sky of the same
    /// horizontal illuminance and no sun: the daylight factor's sky.
    #[must_use]
    pub fn overcast(&self) -> Daylight {
        let e_h = self.sky_horizontal_illuminance();
        let model = super::SkyModel::CieOvercast;
        // L_z = 9 E_h / (7π) exactly for the overcast sky.
        let zenith = 9.0 * e_h / (7.0 * PI);
        Daylight {
            sky: Sky {
                model,
                zenith_luminance: zenith,
                sun: None,
            },
            sun: None,
            ground_reflectance: self.ground_reflectance,
            frame: self.frame,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn east_is_north_cross_up() {
        let frame = SkyFrame::new(DVec3::Y, DVec3::NEG_Z).unwrap();
        assert!((frame.east - DVec3::X).length() < 1e-15);
        let at = frame.to_sky(DVec3::X);
        assert!((at.azimuth - PI / 2.0).abs() < 1e-12 && at.altitude.abs() < 1e-12);
        assert!((frame.to_scene(at) - DVec3::X).length() < 1e-12);
        assert!(SkyFrame::new(DVec3::Y, DVec3::Y).is_none());
        assert!(SkyFrame::new(DVec3::Y, DVec3::ZERO).is_none());
    }
}
