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
    /// `normal` (the front side), W/m²: E = I(ω) cos θ / r² from the
    /// photometric centre (the far-field law the file was measured for),
    /// times the share of the luminous opening that `x` sees unblocked.
    ///
    /// A point source is one shadow ray to the centre. A luminous opening
    /// (see [`PhotometricLuminaire::opening_samples`]) is sampled at
    /// [`OPENING_SAMPLES`] points, so that its shadows have penumbrae; in
    /// the open the result is the point-source law exactly. Each shadow ray
    /// stops a surface offset short of its sample, so a recessed fitting
    /// whose opening lies on the ceiling's plane does not shadow itself.
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
        let offset = visibility.surface_offset();
        let start = x + normal * offset;
        let unblocked = |target: DVec3| {
            let back = (x - target).normalize_or_zero() * offset;
            visibility.is_unblocked(start, target + back, [surface, surface])
        };
        let samples = self.opening_samples();
        let seen = samples.iter().filter(|&&p| unblocked(p)).count();
        if seen == 0 {
            return Rgb::ZERO;
        }
        intensity * (cos / r2 * seen as f64 / samples.len() as f64)
    }

    /// Shadow rays' targets on the luminous opening: the centre alone for a
    /// point source; otherwise [`OPENING_SAMPLES`] points of a Hammersley
    /// set over the opening's face through the centre, perpendicular to the
    /// aim: a rectangle of the file's width (along C90) by its length (along
    /// C0), either of which may be zero (a line), or a disc of diameter
    /// −width (the concentric map of Shirley & Chiu 1997). The opening's
    /// height (along the aim) is not sampled: the face through the centre
    /// stands for it, so that a fitting whose centre sits on the ceiling
    /// puts no sample behind it.
    #[must_use]
    pub fn opening_samples(&self) -> Vec<DVec3> {
        let opening = self.distribution.opening;
        let c90 = (-self.aim).cross(self.c0);
        let (width, length) = (opening.width, opening.length.max(0.0));
        if width == 0.0 && length == 0.0 || !(width.is_finite() && length.is_finite()) {
            return vec![self.position];
        }
        (0..OPENING_SAMPLES)
            .map(|i| {
                let s = (i as f64 + 0.5) / OPENING_SAMPLES as f64;
                let t = radical_inverse(i as u32);
                let (along_c0, along_c90) = if width < 0.0 {
                    let (a, b) = concentric_disc(s, t);
                    (a * -width / 2.0, b * -width / 2.0)
                } else {
                    ((t - 0.5) * length, (s - 0.5) * width)
                };
                self.position + self.c0 * along_c0 + c90 * along_c90
            })
            .collect()
    }

    /// Points a shadow boundary is cast from: the centre of a point source,
    /// or the outline of the luminous opening (its rectangle's corners, or
    /// eight points on its disc's rim).
    #[must_use]
    pub fn opening_corners(&self) -> Vec<DVec3> {
        let opening = self.distribution.opening;
        let c90 = (-self.aim).cross(self.c0);
        let (width, length) = (opening.width, opening.length.max(0.0));
        if width == 0.0 && length == 0.0 || !(width.is_finite() && length.is_finite()) {
            return vec![self.position];
        }
        if width < 0.0 {
            return (0..8)
                .map(|k| {
                    let angle = f64::from(k) * std::f64::consts::FRAC_PI_4;
                    self.position + (self.c0 * angle.cos() + c90 * angle.sin()) * (-width / 2.0)
                })
                .collect();
        }
        [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
            .iter()
            .map(|&(a, b)| self.position + self.c0 * (a * length / 2.0) + c90 * (b * width / 2.0))
            .collect()
    }
}

/// Shadow rays per receiving point for a luminaire with a luminous opening.
pub const OPENING_SAMPLES: usize = 16;

/// The base-2 radical inverse of `i` (van der Corput): its bits mirrored
/// about the binary point.
fn radical_inverse(i: u32) -> f64 {
    f64::from(i.reverse_bits()) / 2f64.powi(32)
}

/// Shirley & Chiu's concentric map of the unit square onto the unit disc,
/// which keeps strata compact ("A Low Distortion Map Between Disk and
/// Square", JGT 2(3), 1997).
fn concentric_disc(s: f64, t: f64) -> (f64, f64) {
    let (a, b) = (2.0 * s - 1.0, 2.0 * t - 1.0);
    if a == 0.0 && b == 0.0 {
        return (0.0, 0.0);
    }
    let (r, phi) = if a.abs() > b.abs() {
        (a, std::f64::consts::FRAC_PI_4 * (b / a))
    } else {
        (
            b,
            std::f64::consts::FRAC_PI_2 - std::f64::consts::FRAC_PI_4 * (a / b),
        )
    };
    (r * phi.cos(), r * phi.sin())
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
    fn opening_samples_cover_the_rectangle_or_the_disc() {
        let mut luminaire = c_reader();
        assert_eq!(luminaire.opening_samples(), vec![DVec3::ZERO]);
        let mut distribution = (*luminaire.distribution).clone();
        distribution.opening = LuminousOpening {
            width: 0.4,
            length: 1.2,
            height: 0.1,
        };
        luminaire.distribution = Arc::new(distribution.clone());
        let samples = luminaire.opening_samples();
        assert_eq!(samples.len(), OPENING_SAMPLES);
        let mean = samples.iter().sum::<DVec3>() / samples.len() as f64;
        assert!(mean.length() < 0.05, "mean {mean}");
        // Length along C0 (x), width along C90 (−z), in the plane y = 0.
        for p in &samples {
            assert!(p.y == 0.0 && p.x.abs() <= 0.6 && p.z.abs() <= 0.2, "{p}");
        }
        assert_eq!(luminaire.opening_corners().len(), 4);
        distribution.opening.width = -0.5;
        luminaire.distribution = Arc::new(distribution);
        for p in luminaire.opening_samples() {
            assert!(p.length() <= 0.25 + 1e-12, "{p}");
        }
        for p in luminaire.opening_corners() {
            assert!((p.length() - 0.25).abs() < 1e-12, "{p}");
        }
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
