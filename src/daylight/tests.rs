//! The skies against references computed here independently of the
//! module's own code: hand-written formulas in altitude and azimuth, and
//! brute-force midpoint sums over an (altitude, azimuth) grid.

use glam::DVec3;
use std::f64::consts::{FRAC_PI_2, TAU};

use super::quadrature::integrate_in_front_of;
use super::{Sky, SkyDirection, SkyModel};

fn sky(model: SkyModel, sun: Option<SkyDirection>) -> Sky {
    Sky::new(model, 1.0, sun).unwrap_or_else(|e| panic!("{e}"))
}

/// The angle between two sky directions by the spherical law of cosines:
/// cos χ = sin γ sin γ_s + cos γ cos γ_s cos(A − A_s).
fn angle_to(a: SkyDirection, b: SkyDirection) -> f64 {
    let cos = a.altitude.sin() * b.altitude.sin()
        + a.altitude.cos() * b.altitude.cos() * (a.azimuth - b.azimuth).cos();
    cos.clamp(-1.0, 1.0).acos()
}

/// ∫ L(ω) max(0, n·ω) dω over the upper hemisphere by the midpoint rule on
/// an `rows` × 4·`rows` grid in (altitude, azimuth), dω = cos γ dγ dA.
fn midpoint_sum(sky: &Sky, normal: DVec3, rows: u32) -> f64 {
    let columns = 4 * rows;
    let (h_alt, h_az) = (FRAC_PI_2 / f64::from(rows), TAU / f64::from(columns));
    let mut sum = 0.0;
    for i in 0..rows {
        let altitude = (f64::from(i) + 0.5) * h_alt;
        for j in 0..columns {
            let at = SkyDirection {
                altitude,
                azimuth: (f64::from(j) + 0.5) * h_az,
            };
            let cosine = normal.dot(at.to_local()).max(0.0);
            sum += sky.relative_luminance(at) * cosine * altitude.cos();
        }
    }
    sum * h_alt * h_az
}

/// Every model and every CIE general type, with a sun where one is needed.
fn all_models() -> Vec<SkyModel> {
    let mut models = vec![
        SkyModel::CieOvercast,
        SkyModel::CieClear,
        SkyModel::CieIntermediate,
        SkyModel::Uniform,
    ];
    models.extend((1..=15).map(SkyModel::CieGeneral));
    models
}

#[test]
fn every_model_and_type_is_exactly_one_at_the_zenith() {
    for model in all_models() {
        for (alt, az) in [
            (0.0, 0.0),
            (5.0, 100.0),
            (30.0, 180.0),
            (60.0, 250.0),
            (89.0, 10.0),
            (90.0, 0.0),
        ] {
            let s = sky(model, Some(SkyDirection::from_degrees(alt, az)));
            assert_eq!(
                s.relative_luminance(SkyDirection::ZENITH),
                1.0,
                "{model:?}, sun at {alt}°, {az}°"
            );
            assert_eq!(s.luminance(SkyDirection::ZENITH), 1.0);
        }
    }
}

#[test]
fn clear_sky_against_the_cie_1973_formula() {
    // (0.91 + 10 e^(−3χ) + 0.45 cos² χ)(1 − e^(−0.32/cos Z))
    //   / ((0.91 + 10 e^(−3 Z_s) + 0.45 cos² Z_s)(1 − e^(−0.32)))
    let indicatrix = |chi: f64| 0.91 + 10.0 * (-3.0 * chi).exp() + 0.45 * chi.cos().powi(2);
    for (sun_alt, sun_az) in [(10.0, 120.0), (35.0, 180.0), (70.0, 200.0)] {
        let sun = SkyDirection::from_degrees(sun_alt, sun_az);
        let s = sky(SkyModel::CieClear, Some(sun));
        let sun_zenith = FRAC_PI_2 - sun.altitude;
        for (alt, az) in [
            (2.0, 0.0),
            (15.0, 90.0),
            (sun_alt, sun_az + 3.0),
            (45.0, 300.0),
            (80.0, 45.0),
        ] {
            let at = SkyDirection::from_degrees(alt, az);
            let zenith = FRAC_PI_2 - at.altitude;
            let expected = indicatrix(angle_to(at, sun)) * (1.0 - (-0.32 / zenith.cos()).exp())
                / (indicatrix(sun_zenith) * (1.0 - (-0.32f64).exp()));
            let got = s.relative_luminance(at);
            assert!(
                (got / expected - 1.0).abs() < 1e-9,
                "sun {sun_alt}°: at ({alt}, {az}): {got} vs {expected}"
            );
        }
        // At the sun itself the indicatrix's peak: 10.91 + 0.45 = 11.36 before the gradation.
        assert!(s.relative_luminance(sun) > 1.5);
    }
}

#[test]
fn intermediate_sky_against_radiance_skybright_cal() {
    // skybright.cal's intersky with gensky's F2 as A4: equal to ours up to
    // the rounding of F2's constants (0.1 %).
    let f2 = |alt: f64| {
        (2.739 + 0.9891 * (0.3119 + 2.6 * alt).sin())
            * (-(FRAC_PI_2 - alt) * (0.4441 + 1.48 * alt)).exp()
    };
    for (sun_alt, sun_az) in [(15.0, 100.0), (40.0, 180.0), (75.0, 260.0)] {
        let sun = SkyDirection::from_degrees(sun_alt, sun_az);
        let s = sky(SkyModel::CieIntermediate, Some(sun));
        let zt = FRAC_PI_2 - sun.altitude;
        for (alt, az) in [
            (1.0, 0.0),
            (20.0, 90.0),
            (sun_alt + 2.0, sun_az),
            (50.0, 330.0),
            (85.0, 45.0),
        ] {
            let at = SkyDirection::from_degrees(alt, az);
            let (eta, gamma) = (FRAC_PI_2 - at.altitude, angle_to(at, sun));
            let radiance = ((1.35 * (5.631 - 3.59 * eta).sin() + 3.12) * (4.396 - 2.6 * zt).sin()
                + 6.37
                - eta)
                / 2.326
                * (gamma * -0.563 * ((2.629 - eta) * (1.562 - zt) + 0.812)).exp()
                / f2(sun.altitude);
            let got = s.relative_luminance(at);
            assert!(
                (got / radiance - 1.0).abs() < 1e-3,
                "sun {sun_alt}°: at ({alt}, {az}): {got} vs {radiance}"
            );
        }
    }
}

#[test]
fn horizontal_illuminance_against_a_midpoint_sum() {
    let mut cases = vec![
        (SkyModel::CieClear, 30.0),
        (SkyModel::CieIntermediate, 50.0),
        (SkyModel::CieOvercast, 0.0),
    ];
    for t in [1, 3, 7, 12, 13, 15] {
        cases.extend([10.0, 45.0, 75.0].map(|alt| (SkyModel::CieGeneral(t), alt)));
    }
    for (model, sun_alt) in cases {
        let s = sky(model, Some(SkyDirection::from_degrees(sun_alt, 163.0)));
        let ratio = s.horizontal_illuminance() / s.zenith_luminance;
        let brute = midpoint_sum(&s, DVec3::Z, 200);
        assert!(
            (ratio / brute - 1.0).abs() < 1e-4,
            "{model:?}, sun {sun_alt}°: {ratio} vs {brute}"
        );
    }
}

#[test]
fn the_sun_centred_integral_converges() {
    // The same integral about the zenith instead of the sun (the cusp at
    // the sun left to the adaptive bisection) and at a tighter tolerance.
    for (model, sun_alt) in [
        (SkyModel::CieClear, 20.0),
        (SkyModel::CieIntermediate, 60.0),
        (SkyModel::CieGeneral(15), 5.0),
    ] {
        let sun = SkyDirection::from_degrees(sun_alt, 200.0);
        let s = sky(model, Some(sun));
        let about_sun = s.horizontal_illuminance();
        let about_zenith = integrate_in_front_of(DVec3::Z, &[DVec3::Z], 1e-12, |w| {
            s.relative_luminance(SkyDirection::from_local(w.x, w.y, w.z)) * w.z
        });
        assert!(
            (about_sun / about_zenith - 1.0).abs() < 1e-8,
            "{model:?}: {about_sun} vs {about_zenith}"
        );
    }
}

#[test]
fn plane_illuminance_of_clear_and_intermediate_skies() {
    for (model, sun) in [
        (SkyModel::CieClear, SkyDirection::from_degrees(25.0, 135.0)),
        (
            SkyModel::CieIntermediate,
            SkyDirection::from_degrees(50.0, 200.0),
        ),
        (
            SkyModel::CieGeneral(13),
            SkyDirection::from_degrees(0.0, 270.0),
        ),
    ] {
        let s = sky(model, Some(sun));
        // The upward normal is the horizontal illuminance.
        let up = s.plane_illuminance(DVec3::Z * 2.0);
        assert!(
            (up / s.horizontal_illuminance() - 1.0).abs() < 1e-12,
            "{model:?}"
        );
        // Vertical and tilted planes, facing the sun and away, against the grid.
        let toward = sun.to_local() * DVec3::new(1.0, 1.0, 0.0);
        for normal in [
            toward,
            -toward,
            DVec3::new(0.3, -0.2, 0.9),
            DVec3::new(0.5, 0.5, -0.3),
            DVec3::new(-1.0, 0.1, 0.0),
        ] {
            let normal = normal.normalize();
            let e = s.plane_illuminance(normal);
            let brute = midpoint_sum(&s, normal, 200);
            assert!(
                (e / brute - 1.0).abs() < 2e-4,
                "{model:?}, {normal}: {e} vs {brute}"
            );
        }
    }
}

#[test]
fn zenith_luminance_for_inverts_horizontal_illuminance() {
    let sun = Some(SkyDirection::from_degrees(40.0, 180.0));
    for model in [
        SkyModel::CieClear,
        SkyModel::CieIntermediate,
        SkyModel::CieGeneral(8),
    ] {
        let lz = Sky::zenith_luminance_for(model, sun, 20_000.0).unwrap_or_else(|e| panic!("{e}"));
        let s = Sky::new(model, lz, sun).unwrap_or_else(|e| panic!("{e}"));
        assert!(
            (s.horizontal_illuminance() / 20_000.0 - 1.0).abs() < 1e-12,
            "{model:?}"
        );
    }
}

#[test]
fn a_sky_is_dark_below_the_horizon() {
    for model in all_models() {
        let s = sky(model, Some(SkyDirection::from_degrees(30.0, 90.0)));
        assert_eq!(
            s.luminance(SkyDirection::from_degrees(-0.1, 90.0)),
            0.0,
            "{model:?}"
        );
        assert_eq!(
            s.luminance(SkyDirection {
                altitude: f64::NAN,
                azimuth: 0.0
            }),
            0.0,
            "{model:?}"
        );
        assert!(s.horizontal_illuminance() > 0.0 && s.horizontal_illuminance().is_finite());
    }
}
