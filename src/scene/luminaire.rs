//! Photometric luminaires: a manufacturer's intensity distribution placed
//! in the scene, shooting from its photometric centre.

use std::sync::Arc;

use glam::DVec3;

use super::{Rgb, SurfaceId, Visibility};
use crate::photometry::{IntensityDistribution, LUMENS_PER_WATT};

/// A luminaire from a photometric file (a scene file's `[[luminaire]]`):
/// its distribution I(C, γ) in candela, placed at `position` with γ = 0
/// along `aim` and the C0 half-plane towards `c0`.
///
/// Seen from behind the luminaire, looking along `aim`, C increases
/// counter-clockwise: the C90 direction is (−aim) × c0 (with aim −y and c0
/// +x, C90 is −z).
#[derive(Clone, Debug, PartialEq)]
pub struct PhotometricLuminaire {
    /// Where it came from (the photometric file), for messages.
    pub name: String,
    /// I(C, γ), candela, before `multiplier`.
    pub distribution: Arc<IntensityDistribution>,
    /// The photometric centre.
    pub position: DVec3,
    /// Unit direction of γ = 0.
    pub aim: DVec3,
    /// Unit direction of the C0 half-plane, perpendicular to `aim`.
    pub c0: DVec3,
    /// Scales the intensities (dimming, maintenance factor).
    pub multiplier: f64,
    /// Tint, with unit luminance (Rec. 709 weights, isorad's primaries).
    pub color: Rgb,
    /// Its radiant power per channel, W (see [`PhotometricLuminaire::power`]).
    power: Rgb,
}

impl PhotometricLuminaire {
    /// A luminaire of `distribution` at `position`, γ = 0 along the unit
    /// `aim`, C0 along the unit `c0` (perpendicular to it), intensities
    /// times `multiplier`, tinted by `color` (unit luminance). Its power is
    /// integrated here, once.
    #[must_use]
    pub fn new(
        name: String,
        distribution: Arc<IntensityDistribution>,
        [position, aim, c0]: [DVec3; 3],
        multiplier: f64,
        color: Rgb,
    ) -> PhotometricLuminaire {
        let power = color * (distribution.flux(8) * multiplier / LUMENS_PER_WATT);
        PhotometricLuminaire {
            name,
            distribution,
            position,
            aim,
            c0,
            multiplier,
            color,
            power,
        }
    }

    /// The (C, γ) angles of the unit direction `direction` from the
    /// luminaire, degrees: γ from `aim`, C from `c0` towards C90.
    #[must_use]
    pub fn angles(&self, direction: DVec3) -> (f64, f64) {
        let c90 = (-self.aim).cross(self.c0);
        let gamma = direction.dot(self.aim).clamp(-1.0, 1.0).acos().to_degrees();
        let c = direction
            .dot(c90)
            .atan2(direction.dot(self.c0))
            .to_degrees()
            .rem_euclid(360.0);
        (c, gamma)
    }

    /// The radiant intensity towards the unit `direction`, W/sr per
    /// channel: I(C, γ) × multiplier / 179 lm/W × colour.
    #[must_use]
    pub fn radiant_intensity(&self, direction: DVec3) -> Rgb {
        let (c, gamma) = self.angles(direction);
        self.color * (self.distribution.intensity(c, gamma) * self.multiplier / LUMENS_PER_WATT)
    }

    /// Its radiant power per channel, W: the distribution's flux × the
    /// multiplier / 179 lm/W × colour.
    #[must_use]
    pub fn power(&self) -> Rgb {
        self.power
    }

    /// The irradiance it gives a point `x` on `surface` with unit normal
    /// `normal` (the front side), W/m²: E = I(ω) cos θ / r² when nothing
    /// blocks the segment to the photometric centre, else zero. The shadow
    /// ray stops a surface offset short of the centre, so a recessed
    /// fitting whose centre lies on the ceiling's plane does not shadow
    /// itself.
    #[must_use]
    pub fn irradiance_at(
        &self,
        x: DVec3,
        normal: DVec3,
        surface: SurfaceId,
        visibility: &Visibility,
    ) -> Rgb {
        let to_light = self.position - x;
        let r2 = to_light.length_squared();
        if r2 <= 0.0 {
            return Rgb::ZERO;
        }
        let r = r2.sqrt();
        let cos = normal.dot(to_light) / r;
        if cos <= 0.0 {
            return Rgb::ZERO;
        }
        let intensity = self.radiant_intensity(-to_light / r);
        if intensity == Rgb::ZERO {
            return Rgb::ZERO;
        }
        let start = x + normal * visibility.surface_offset();
        let end = self.position + (to_light / r) * -visibility.surface_offset();
        if !visibility.is_unblocked(start, end, [surface, surface]) {
            return Rgb::ZERO;
        }
        intensity * (cos / r2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::photometry::{IntensityDistribution, LuminousOpening, Symmetry};

    /// A web with I = C (degrees) on every γ: reads the C angle back.
    fn c_reader() -> PhotometricLuminaire {
        let cs: Vec<f64> = (0..=36).map(|k| 10.0 * k as f64).collect();
        let planes: Vec<Vec<f64>> = cs.iter().map(|&c| vec![c, c]).collect();
        let distribution = IntensityDistribution::from_planes(
            Symmetry::None,
            &cs,
            &[0.0, 180.0],
            &planes,
            LuminousOpening::default(),
        );
        PhotometricLuminaire::new(
            "test".into(),
            Arc::new(distribution),
            [DVec3::ZERO, -DVec3::Y, DVec3::X],
            1.0,
            Rgb::ONE,
        )
    }

    #[test]
    fn c90_is_minus_z_for_a_downlight_with_c0_along_x() {
        let luminaire = c_reader();
        let toward = |d: DVec3| luminaire.angles(d.normalize());
        let (c, gamma) = toward(DVec3::new(0.0, -1.0, -1.0));
        assert!((c - 90.0).abs() < 1e-9 && (gamma - 45.0).abs() < 1e-9);
        let (c, _) = toward(DVec3::new(1.0, -1.0, 0.0));
        assert!(c.abs() < 1e-9);
        let (c, _) = toward(DVec3::new(0.0, -1.0, 1.0));
        assert!((c - 270.0).abs() < 1e-9);
        let (_, gamma) = toward(-DVec3::Y);
        assert!(gamma.abs() < 1e-9);
    }
}
