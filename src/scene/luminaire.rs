//! Photometric luminaires: a manufacturer's intensity distribution placed
//! in the scene, shooting from its photometric centre.

use std::sync::Arc;

use glam::DVec3;

use super::emitting_body::EmittingBody;
use super::{ShadowCache, SurfaceId, Visibility};
use crate::photometry::{IntensityDistribution, LUMENS_PER_WATT, PreparedDistribution};
use crate::rgb::Rgb;

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
    /// The emitting faces it stands for, when it is a lamp modelled as
    /// faces on many planes ([`PhotometricLuminaire::of_body`]); `None`
    /// for a photometric file's luminaire.
    pub body: Option<Arc<EmittingBody>>,
    /// Its radiant power per channel, W (see [`PhotometricLuminaire::power`]).
    power: Rgb,
}

impl PhotometricLuminaire {
    /// A luminaire of `distribution` at `position`, γ = 0 along the unit
    /// `aim`, C0 along the unit `c0` (perpendicular to it), intensities
    /// times `multiplier`, tinted by `color` (unit luminance). Its power is
    /// integrated here; to place one distribution many times, prepare it
    /// once and use [`PhotometricLuminaire::placed`].
    #[must_use]
    pub fn new(
        name: String,
        distribution: Arc<IntensityDistribution>,
        frame: [DVec3; 3],
        multiplier: f64,
        color: Rgb,
    ) -> PhotometricLuminaire {
        let prepared = PreparedDistribution::new(distribution);
        PhotometricLuminaire::placed(name, &prepared, frame, multiplier, color)
    }

    /// A luminaire of the `prepared` distribution (shared, its flux
    /// integrated once), placed as [`PhotometricLuminaire::new`] says.
    #[must_use]
    pub fn placed(
        name: String,
        prepared: &PreparedDistribution,
        [position, aim, c0]: [DVec3; 3],
        multiplier: f64,
        color: Rgb,
    ) -> PhotometricLuminaire {
        let power = color * (prepared.flux * multiplier / LUMENS_PER_WATT);
        PhotometricLuminaire {
            name,
            distribution: Arc::clone(&prepared.distribution),
            position,
            aim,
            c0,
            multiplier,
            color,
            body: None,
            power,
        }
    }

    /// The luminaire a lamp modelled as faces on many planes makes: its
    /// distribution computed from the faces
    /// ([`EmittingBody::intensity_distribution`]), its centre the faces'
    /// area centroid, γ = 0 along [`EmittingBody::aim`], tinted by the
    /// exitance's chromaticity. Its light near the body is the faces'
    /// exact field, its shadows are cast from points on its faces
    /// (see `scene/emitting_body.rs`). `None` for a body that emits no
    /// luminance.
    #[must_use]
    pub fn of_body(body: EmittingBody) -> Option<PhotometricLuminaire> {
        let luminance = body.exitance.luminance();
        if !(luminance > 0.0 && luminance.is_finite()) {
            return None;
        }
        let aim = body.aim();
        let c0 = aim.any_orthonormal_vector();
        let distribution = Arc::new(body.intensity_distribution(aim, c0));
        let prepared = PreparedDistribution::new(distribution);
        let name = format!(
            "emitting body `{}` ({} faces)",
            body.material,
            body.face_count()
        );
        let color = body.exitance / luminance;
        let mut luminaire =
            PhotometricLuminaire::placed(name, &prepared, [body.centre, aim, c0], 1.0, color);
        luminaire.body = Some(Arc::new(body));
        Some(luminaire)
    }

    /// The (C, γ) angles of the unit direction `direction` from the
    /// luminaire, degrees: γ from `aim`, C from `c0` towards C90.
    #[must_use]
    pub fn angles(&self, direction: DVec3) -> (f64, f64) {
        let c90 = self.c90();
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
    ///
    /// An emitting body's luminaire gives, within a few of its radii, its
    /// faces' exact field instead of the far-field law
    /// ([`EmittingBody::near_factor`], blended as
    /// [`EmittingBody::far_weight`] says), and its shadows are weighed over
    /// points of its faces ([`EmittingBody::visible_share`]).
    #[must_use]
    pub fn irradiance_at(
        &self,
        x: DVec3,
        normal: DVec3,
        surface: SurfaceId,
        visibility: &Visibility,
    ) -> Rgb {
        let unoccluded = self.unoccluded_irradiance(x, normal);
        if unoccluded == Rgb::ZERO {
            return Rgb::ZERO;
        }
        let seen = self.visible_share(x, normal, surface, visibility);
        if seen == 0.0 {
            return Rgb::ZERO;
        }
        unoccluded * seen
    }

    /// The irradiance it gives `x` facing the unit `normal` with nothing in
    /// the way, W/m²: E = I(ω) cos θ / r² from the centre, or, near an
    /// emitting body, its faces' exact field blended into that
    /// ([`EmittingBody::near_factor`], [`EmittingBody::far_weight`]). Zero
    /// behind `x`'s plane or at the centre.
    #[must_use]
    pub fn unoccluded_irradiance(&self, x: DVec3, normal: DVec3) -> Rgb {
        let to_light = self.position - x;
        let r2 = to_light.length_squared();
        if r2 <= 0.0 || r2.is_nan() {
            return Rgb::ZERO;
        }
        let r = r2.sqrt();
        let cos = normal.dot(to_light) / r;
        let far_weight = self.body.as_ref().map_or(1.0, |body| body.far_weight(x));
        let far = if cos > 0.0 {
            self.radiant_intensity(-to_light / r) * (cos / r2)
        } else {
            Rgb::ZERO
        };
        match &self.body {
            Some(body) if far_weight < 1.0 => {
                let near = body.exitance * body.near_factor(x, normal);
                near * (1.0 - far_weight) + far * far_weight
            }
            _ => far,
        }
    }

    /// The share of the luminous opening that `x` (on `surface`, whose
    /// front normal is `normal`; [`SurfaceId::NONE`] in free space) sees:
    /// the fraction of [`PhotometricLuminaire::opening_samples`] whose
    /// shadow ray, lifted a surface offset off `x` along `normal` and
    /// stopping that far short of its sample, is unblocked. An emitting
    /// body weighs its points by the light each sends `x`
    /// ([`EmittingBody::visible_share`]).
    #[must_use]
    pub fn visible_share(
        &self,
        x: DVec3,
        normal: DVec3,
        surface: SurfaceId,
        visibility: &Visibility,
    ) -> f64 {
        if let Some(body) = &self.body {
            return body.visible_share(x, normal, surface, visibility);
        }
        let offset = visibility.surface_offset();
        let start = x + normal * offset;
        let samples = self.opening_samples();
        // The samples' rays are nearly parallel: what blocks one mostly
        // blocks the next.
        let mut cache = ShadowCache::default();
        let seen = samples
            .iter()
            .filter(|&&target| {
                let back = (x - target).normalize_or_zero() * offset;
                visibility.is_unblocked_cached(start, target + back, [surface, surface], &mut cache)
            })
            .count();
        seen as f64 / samples.len() as f64
    }

    /// The direction of the C90 half-plane, (−aim) × c0.
    #[must_use]
    pub fn c90(&self) -> DVec3 {
        (-self.aim).cross(self.c0)
    }

    /// Whether the file gives no luminous opening (or none that is finite):
    /// a point source.
    fn is_point(&self) -> bool {
        if self.body.is_some() {
            return false;
        }
        let opening = self.distribution.opening;
        let (width, length) = (opening.width, opening.length.max(0.0));
        width == 0.0 && length == 0.0 || !(width.is_finite() && length.is_finite())
    }

    /// The opening's radius: the largest distance from the centre to its
    /// outline ([`PhotometricLuminaire::opening_corners`]); 0 for a point.
    #[must_use]
    pub fn opening_radius(&self) -> f64 {
        self.opening_corners()
            .iter()
            .map(|c| c.distance(self.position))
            .fold(0.0, f64::max)
    }

    /// The unoccluded illuminance it gives a point `x` facing the unit
    /// `normal`, lx, E = I(C, γ) · multiplier · cos θ / r², and its
    /// gradient with respect to `x` (the normal held fixed), lx per unit
    /// length. With d = x − c, r = |d|, ω = d / r and cos θ = −n·d / r:
    ///
    /// ```text
    ///   ∇E = (−n·d / r³) (∂I/∂C ∇C + ∂I/∂γ ∇γ) + I (−n / r³ + 3 (n·d) d / r⁵)
    ///   ∇γ = −(a − cos γ ω) / (r sin γ)
    ///   ∇C = (ω·c₀ (c₉₀ − (ω·c₉₀) ω) − ω·c₉₀ (c₀ − (ω·c₀) ω)) / (r ((ω·c₀)² + (ω·c₉₀)²))
    /// ```
    ///
    /// with a the aim, the angle derivatives from the bilinear web
    /// ([`IntensityDistribution::intensity_with_derivatives`], per degree,
    /// times 180/π). On the aim (sin γ = 0) the terms in ∇C and ∇γ are left
    /// out, as the web's planes meet there. Zero, with a zero gradient,
    /// behind the point's plane or at the centre.
    #[must_use]
    pub fn illuminance_with_gradient(&self, x: DVec3, normal: DVec3) -> (f64, DVec3) {
        let d = x - self.position;
        let r2 = d.length_squared();
        let facing = -normal.dot(d);
        if !(r2 > 0.0 && facing > 0.0 && r2.is_finite()) {
            return (0.0, DVec3::ZERO);
        }
        let r = r2.sqrt();
        let omega = d / r;
        let (c, gamma) = self.angles(omega);
        let crate::photometry::IntensityWithDerivatives {
            intensity,
            d_c,
            d_gamma,
        } = self.distribution.intensity_with_derivatives(c, gamma);
        let (intensity, d_c, d_gamma) = (
            intensity * self.multiplier,
            d_c * self.multiplier * (180.0 / std::f64::consts::PI),
            d_gamma * self.multiplier * (180.0 / std::f64::consts::PI),
        );
        let r3 = r2 * r;
        let value = intensity * facing / r3;
        let mut gradient = intensity * (-normal / r3 + d * (3.0 * normal.dot(d) / (r3 * r2)));
        let c90 = self.c90();
        let (along_c0, along_c90, cos_gamma) =
            (omega.dot(self.c0), omega.dot(c90), omega.dot(self.aim));
        let sine_squared = along_c0 * along_c0 + along_c90 * along_c90;
        if sine_squared > 1e-24 {
            let transverse = |e: DVec3, along: f64| (e - omega * along) / r;
            let grad_gamma = -transverse(self.aim, cos_gamma) / sine_squared.sqrt();
            let grad_c = (transverse(c90, along_c90) * along_c0
                - transverse(self.c0, along_c0) * along_c90)
                / sine_squared;
            gradient += (grad_c * d_c + grad_gamma * d_gamma) * (facing / r3);
        }
        (value, gradient)
    }

    /// Shadow rays' targets on the luminous opening: an emitting body's
    /// points on its faces ([`EmittingBody::shadow_samples`]); the centre
    /// alone for a point source; otherwise [`OPENING_SAMPLES`] points of a Hammersley
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
        let c90 = self.c90();
        let (width, length) = (opening.width, opening.length.max(0.0));
        if let Some(body) = &self.body {
            return body.shadow_samples().iter().map(|s| s.position).collect();
        }
        if self.is_point() {
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
    /// the outline of the luminous opening (its rectangle's corners, or
    /// eight points on its disc's rim), or an emitting body's extreme
    /// vertices ([`EmittingBody::outline`]).
    #[must_use]
    pub fn opening_corners(&self) -> Vec<DVec3> {
        let opening = self.distribution.opening;
        let c90 = self.c90();
        let (width, length) = (opening.width, opening.length.max(0.0));
        if let Some(body) = &self.body {
            return body.outline();
        }
        if self.is_point() {
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

    /// An asymmetric web on coarse steps: I = 500 + 300 cos γ + 2 C, with
    /// every plane different.
    fn asymmetric() -> PhotometricLuminaire {
        let cs: Vec<f64> = (0..=12).map(|k| 30.0 * k as f64).collect();
        let gammas: Vec<f64> = (0..=12).map(|k| 15.0 * k as f64).collect();
        let planes: Vec<Vec<f64>> = cs
            .iter()
            .map(|&c| {
                let c = if c == 360.0 { 0.0 } else { c };
                gammas
                    .iter()
                    .map(|&g: &f64| 500.0 + 300.0 * g.to_radians().cos() + 2.0 * c)
                    .collect()
            })
            .collect();
        let distribution = IntensityDistribution::from_planes(
            Symmetry::None,
            &cs,
            &gammas,
            &planes,
            LuminousOpening::default(),
        );
        let aim = DVec3::new(0.3, -1.0, 0.2).normalize();
        let c0 = (DVec3::X - aim * aim.x).normalize();
        PhotometricLuminaire::new(
            "asymmetric".into(),
            Arc::new(distribution),
            [DVec3::new(0.2, 2.5, -0.4), aim, c0],
            0.8,
            Rgb::ONE,
        )
    }

    #[test]
    fn the_illuminance_gradient_agrees_with_finite_differences() {
        let luminaire = asymmetric();
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut checked = 0;
        for _ in 0..400 {
            let x = DVec3::new(6.0 * next() - 3.0, 0.0, 6.0 * next() - 3.0);
            let normal = DVec3::new(0.2 * next() - 0.1, 1.0, 0.0).normalize();
            let (value, gradient) = luminaire.illuminance_with_gradient(x, normal);
            assert!(value > 0.0);
            let h = 1e-6;
            let mut numeric = DVec3::ZERO;
            for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
                let plus = luminaire.illuminance_with_gradient(x + axis * h, normal).0;
                let minus = luminaire.illuminance_with_gradient(x - axis * h, normal).0;
                numeric += axis * ((plus - minus) / (2.0 * h));
            }
            // The value matches the plain law.
            let d = luminaire.position - x;
            let (c, gamma) = luminaire.angles(-d.normalize());
            let law = luminaire.distribution.intensity(c, gamma) * 0.8 * normal.dot(d)
                / d.length().powi(3);
            assert!((value - law).abs() <= 1e-12 * law);
            // A difference straddling a tabulated angle sees the kink: skip
            // points whose six difference points are not all in (C, γ)'s cell.
            let cell = |p: DVec3| {
                let (c, gamma) = luminaire.angles((p - luminaire.position).normalize());
                ((c / 30.0).floor(), (gamma / 15.0).floor())
            };
            let home = cell(x);
            let straddles = [DVec3::X, DVec3::Y, DVec3::Z]
                .into_iter()
                .flat_map(|axis| [x + axis * h, x - axis * h])
                .any(|p| cell(p) != home);
            if straddles {
                continue;
            }
            checked += 1;
            let error = (gradient - numeric).length() / gradient.length().max(1e-9);
            assert!(
                error < 1e-5,
                "at {x}: analytic {gradient}, numeric {numeric}"
            );
        }
        assert!(checked > 300, "only {checked} points checked");
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
