//! A sky: a luminance model, its zenith luminance and the sun, with the
//! illuminance it gives an unobstructed plane.
//!
//! # Illuminance
//!
//! ```text
//!   E_h = ∫ L(ω) sin γ dω              over the upper hemisphere
//!   E_n = ∫ L(ω) max(0, n·ω) dω        over the upper hemisphere
//! ```
//!
//! Both are integrated in polar coordinates about the sun (about the zenith
//! for models that need no sun), where the circumsolar peak e^(−3χ) is
//! smooth, over the arc of each half great circle above the horizon and in
//! front of the plane, by adaptive Gauss–Kronrod in both angles to 1e-9
//! relative by its error estimates (the results agree with integrals to
//! 1e-12 within about 1e-10; see `quadrature.rs`). A call takes a few
//! milliseconds (release build): 10⁴–10⁵ evaluations of the pattern, most
//! for the steep gradation near the horizon. For the overcast sky
//! E_h = 7π L_z / 9 exactly; for the uniform sky π L_z.
//!
//! # The sun below the horizon, and near the zenith
//!
//! Radiance's `gensky` keeps the clear and intermediate patterns for a sun
//! below the horizon (it only drops the solar source; its default zenith
//! luminance then falls towards 0), and it moves a sun above 87° down to 87°
//! because its normalisation `normsc()` is a polynomial fit. We refuse a sun
//! below the horizon for the models that need one (the CIE formulas are
//! defined for 0 ≤ Z_s ≤ 90°; twilight is outside the standards) and we do
//! not clamp near the zenith, as our normalisations are exact. The models
//! that need no sun accept any finite sun and ignore it.
//!
//! Radiance's `skybright.cal` also blends the sky toward the ground's
//! brightness near the horizon (weights (Dz + 1.01)^±10); that is the
//! ground's business and is left out here: these are the CIE patterns.
//!
//! # References
//! - P. Moon, D. E. Spencer, "Illumination from a non-uniform sky", 1942.
//! - ISO 15469:2004 / CIE S 011/E:2003; CIE 110-1994.
//! - Radiance `src/gen/gensky.c`, `src/gen/skybright.cal` (LBNL-ETA/Radiance).

use glam::DVec3;

use super::direction::SkyDirection;
use super::model::{SkyModel, SkyPattern};
use super::quadrature::integrate_in_front_of;

/// Relative accuracy the illuminance integrals aim at.
const INTEGRAL_TOLERANCE: f64 = 1e-9;

/// A sky: a model, its zenith luminance (cd/m²) and, for models with a
/// sun-dependent pattern, the sun's direction.
#[derive(Clone, Debug, PartialEq)]
pub struct Sky {
    /// The luminance distribution.
    pub model: SkyModel,
    /// The luminance at the zenith, cd/m².
    pub zenith_luminance: f64,
    /// The sun's direction; needed above the horizon when
    /// [`SkyModel::needs_sun`], ignored otherwise.
    pub sun: Option<SkyDirection>,
}

impl Sky {
    /// Builds a sky; Err(String) naming the problem when the model needs a
    /// sun and has none (the clear and intermediate skies, general types
    /// other than 1, 3 and 5), when a general type is outside 1..=15, when
    /// the zenith luminance is not a finite number above 0, or when a
    /// needed sun is below the horizon or not finite.
    ///
    /// A sun below the horizon is refused, not clamped (the module docs say
    /// why, and what gensky does instead); models that need no sun accept
    /// any finite sun and ignore it.
    pub fn new(
        model: SkyModel,
        zenith_luminance: f64,
        sun: Option<SkyDirection>,
    ) -> Result<Sky, String> {
        let sky = Sky {
            model,
            zenith_luminance,
            sun,
        };
        sky.validate()?;
        Ok(sky)
    }

    /// Err naming the first broken invariant of a sky (see [`Sky::new`]).
    pub fn validate(&self) -> Result<(), String> {
        self.model.check()?;
        if !(self.zenith_luminance.is_finite() && self.zenith_luminance > 0.0) {
            return Err(format!(
                "the zenith luminance of {} must be a finite number above 0 cd/m², not {}",
                self.model.name(),
                self.zenith_luminance
            ));
        }
        check_sun(self.model, self.sun)
    }

    /// L/L_z at a direction above the horizon (0 below it).
    ///
    /// The horizon itself (altitude 0) counts as above; NaN counts as below.
    #[must_use]
    pub fn relative_luminance(&self, at: SkyDirection) -> f64 {
        if at.altitude.is_nan() || at.altitude < 0.0 {
            return 0.0;
        }
        self.model
            .relative_luminance_toward(self.sun_local(), at.to_local())
    }

    /// Luminance (cd/m²) at a direction above the horizon; 0 below.
    ///
    /// For many directions under one sky, [`Sky::pattern`] computes the
    /// pattern's normalisation once.
    #[must_use]
    pub fn luminance(&self, at: SkyDirection) -> f64 {
        self.zenith_luminance * self.relative_luminance(at)
    }

    /// Illuminance on an unobstructed horizontal plane from the sky alone
    /// (lux): E_h = ∫ L sin γ dω over the upper hemisphere.
    ///
    /// Polar coordinates about the sun, adaptive Gauss–Kronrod in both
    /// angles (see the module docs); about 1e-9 relative. The overcast sky
    /// gives 7π L_z / 9, the uniform sky π L_z.
    #[must_use]
    pub fn horizontal_illuminance(&self) -> f64 {
        self.zenith_luminance * self.relative_illuminance(&[DVec3::Z], DVec3::Z)
    }

    /// The zenith luminance (cd/m²) that gives horizontal illuminance `e_h`
    /// (lux) from the sky, for this model and sun.
    ///
    /// L_z = e_h / (E_h / L_z), the ratio integrated for a sky of L_z = 1.
    /// Err when the model and sun would be refused by [`Sky::new`] or
    /// `e_h` is not a finite number above 0.
    pub fn zenith_luminance_for(
        model: SkyModel,
        sun: Option<SkyDirection>,
        e_h: f64,
    ) -> Result<f64, String> {
        if !(e_h.is_finite() && e_h > 0.0) {
            return Err(format!(
                "the horizontal illuminance of {} must be a finite number above 0 lx, not {e_h}",
                model.name()
            ));
        }
        let unit = Sky::new(model, 1.0, sun)?;
        Ok(e_h / unit.horizontal_illuminance())
    }

    /// Illuminance (lux) on an unobstructed plane whose unit normal in local
    /// (east, north, up) coordinates is `normal_local`, from the sky above
    /// the horizon only (no ground): E_n = ∫ L max(0, n·ω) dω.
    ///
    /// The normal is normalised first; a zero or non-finite normal gives 0.
    /// Integrated over the directions above both the horizon and the plane
    /// (see the module docs); about 1e-9 relative.
    #[must_use]
    pub fn plane_illuminance(&self, normal_local: DVec3) -> f64 {
        let Some(normal) = normal_local.try_normalize() else {
            return 0.0;
        };
        let planes: &[DVec3] = if normal == DVec3::Z {
            &[DVec3::Z]
        } else {
            &[DVec3::Z, normal]
        };
        self.zenith_luminance * self.relative_illuminance(planes, normal)
    }

    /// ∫ (L/L_z) (n·ω) dω over the directions in front of every plane.
    fn relative_illuminance(&self, planes: &[DVec3], normal: DVec3) -> f64 {
        let pole = match self.sun_local() {
            Some(sun) if self.model.needs_sun() => sun,
            _ => DVec3::Z,
        };
        let pattern = self.pattern();
        integrate_in_front_of(pole, planes, INTEGRAL_TOLERANCE, |to| {
            pattern.relative_luminance(to) * normal.dot(to)
        })
    }

    /// The pattern L/L_z of this sky, to evaluate in many directions
    /// (local unit vectors) with its normalisation computed once.
    #[must_use]
    pub fn pattern(&self) -> SkyPattern {
        SkyPattern::new(self.model, self.sun_local())
    }

    /// The sun as a local unit vector.
    fn sun_local(&self) -> Option<DVec3> {
        self.sun.map(SkyDirection::to_local)
    }
}

/// Err when `model` needs a sun and `sun` is missing, not finite or below
/// the horizon (altitude < 0 or above π/2).
fn check_sun(model: SkyModel, sun: Option<SkyDirection>) -> Result<(), String> {
    if !model.needs_sun() {
        return match sun {
            Some(s) if !(s.altitude.is_finite() && s.azimuth.is_finite()) => Err(format!(
                "the sun's direction must be finite, not altitude {} azimuth {}",
                s.altitude, s.azimuth
            )),
            _ => Ok(()),
        };
    }
    let Some(sun) = sun else {
        return Err(format!("{} needs the sun's direction", model.name()));
    };
    if !(sun.altitude.is_finite() && sun.azimuth.is_finite()) {
        return Err(format!(
            "the sun's direction must be finite, not altitude {} azimuth {}",
            sun.altitude, sun.azimuth
        ));
    }
    if sun.altitude < 0.0 {
        return Err(format!(
            "the sun is below the horizon (altitude {:.3}°): {} is defined for the sun above it",
            sun.altitude.to_degrees(),
            model.name()
        ));
    }
    if sun.altitude > std::f64::consts::FRAC_PI_2 {
        return Err(format!(
            "the sun's altitude {:.3}° is beyond the zenith (90°)",
            sun.altitude.to_degrees()
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn new_refuses_what_it_must() {
        let sun = Some(SkyDirection::from_degrees(30.0, 180.0));
        let below = Some(SkyDirection::from_degrees(-2.0, 180.0));
        let no = |model, lz, sun| Sky::new(model, lz, sun).err().unwrap_or_default();
        assert!(no(SkyModel::CieClear, 1000.0, None).contains("needs the sun"));
        assert!(no(SkyModel::CieIntermediate, 1000.0, None).contains("needs the sun"));
        assert!(no(SkyModel::CieGeneral(2), 1000.0, None).contains("needs the sun"));
        assert!(no(SkyModel::CieGeneral(0), 1000.0, sun).contains("1 to 15"));
        assert!(no(SkyModel::CieGeneral(16), 1000.0, sun).contains("1 to 15"));
        assert!(no(SkyModel::Uniform, 0.0, None).contains("zenith luminance"));
        assert!(no(SkyModel::Uniform, f64::NAN, None).contains("zenith luminance"));
        assert!(no(SkyModel::CieOvercast, f64::INFINITY, None).contains("zenith luminance"));
        assert!(no(SkyModel::CieClear, 1000.0, below).contains("below the horizon"));
        assert!(
            no(
                SkyModel::CieGeneral(12),
                1000.0,
                Some(SkyDirection::from_degrees(91.0, 0.0))
            )
            .contains("zenith")
        );
        assert!(
            no(
                SkyModel::CieClear,
                1000.0,
                Some(SkyDirection {
                    altitude: f64::NAN,
                    azimuth: 0.0
                })
            )
            .contains("finite")
        );
        // Models without a sun-dependent pattern take none, or ignore one below the horizon.
        for t in [1, 3, 5] {
            assert!(
                Sky::new(SkyModel::CieGeneral(t), 1000.0, None).is_ok(),
                "type {t}"
            );
        }
        assert!(Sky::new(SkyModel::CieOvercast, 1000.0, below).is_ok());
        assert!(
            Sky::new(
                SkyModel::CieClear,
                1000.0,
                Some(SkyDirection::from_degrees(0.0, 90.0))
            )
            .is_ok()
        );
    }

    #[test]
    fn overcast_values_and_illuminance() {
        let lz = 3000.0;
        let sky = Sky::new(SkyModel::CieOvercast, lz, None).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(sky.relative_luminance(SkyDirection::ZENITH), 1.0);
        assert!(
            (sky.relative_luminance(SkyDirection::from_degrees(0.0, 77.0)) - 1.0 / 3.0).abs()
                < 1e-15
        );
        assert_eq!(sky.luminance(SkyDirection::from_degrees(-1.0, 0.0)), 0.0);
        let expected = 7.0 * PI * lz / 9.0;
        let e_h = sky.horizontal_illuminance();
        assert!((e_h / expected - 1.0).abs() < 1e-9, "{e_h} vs {expected}");
        let lz_back = Sky::zenith_luminance_for(SkyModel::CieOvercast, None, e_h)
            .unwrap_or_else(|e| panic!("{e}"));
        assert!((lz_back / lz - 1.0).abs() < 1e-9);
    }

    #[test]
    fn vertical_planes_under_the_overcast_and_uniform_skies() {
        // E_v = 2 ∫₀^{π/2} L(γ) cos² γ dγ (the azimuth integral ∫ cos A dA = 2
        // over the half facing the plane): with L = L_z (1 + 2 sin γ)/3,
        // ∫ cos² = π/4 and ∫ 2 sin γ cos² γ = 2/3, so E_v = L_z (π/6 + 4/9);
        // the uniform sky gives π L_z / 2.
        let overcast = Sky::new(SkyModel::CieOvercast, 1.0, None).unwrap_or_else(|e| panic!("{e}"));
        let uniform = Sky::new(SkyModel::Uniform, 1.0, None).unwrap_or_else(|e| panic!("{e}"));
        for normal in [DVec3::Y, DVec3::X, DVec3::new(-0.6, -0.8, 0.0)] {
            let e_v = overcast.plane_illuminance(normal);
            assert!(
                (e_v / (PI / 6.0 + 4.0 / 9.0) - 1.0).abs() < 1e-9,
                "{normal}: {e_v}"
            );
            let e_u = uniform.plane_illuminance(normal * 3.0);
            assert!((e_u / (PI / 2.0) - 1.0).abs() < 1e-9, "{normal}: {e_u}");
        }
        assert!((uniform.horizontal_illuminance() / PI - 1.0).abs() < 1e-12);
        assert_eq!(uniform.plane_illuminance(-DVec3::Z), 0.0);
        assert_eq!(uniform.plane_illuminance(DVec3::ZERO), 0.0);
        assert_eq!(uniform.plane_illuminance(DVec3::splat(f64::NAN)), 0.0);
    }

    #[test]
    fn zenith_luminance_for_refuses_bad_illuminance() {
        assert!(Sky::zenith_luminance_for(SkyModel::Uniform, None, 0.0).is_err());
        assert!(Sky::zenith_luminance_for(SkyModel::Uniform, None, f64::NAN).is_err());
        assert!(Sky::zenith_luminance_for(SkyModel::CieClear, None, 1e4).is_err());
        let lz = Sky::zenith_luminance_for(SkyModel::Uniform, None, 10_000.0)
            .unwrap_or_else(|e| panic!("{e}"));
        assert!((lz - 10_000.0 / PI).abs() < 1e-8);
    }
}
