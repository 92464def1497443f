//! A clear glass pane as Radiance's `glass` material treats it: two parallel
//! faces of refractive index n = 1.52, Fresnel reflection averaged over the
//! two polarisations, the reflections between the faces summed, and
//! absorption over the path inside.
//!
//! # The model
//!
//! For incidence at cos θ = μ, the refracted cosine is
//! μ_t = √(1 − (1 − μ²)/n²), and per polarisation the single-face
//! reflectances are
//!
//! ```text
//!   r_s = ((μ − n μ_t) / (μ + n μ_t))²       r_p = ((μ_t − n μ) / (μ_t + n μ))²
//! ```
//!
//! (Radiance writes r_p with 1/μ and n/μ_t; multiplied through by μ μ_t it is
//! the same and stays finite at grazing). With t the transmissivity (the
//! fraction not absorbed in one traversal at normal incidence) the path
//! inside transmits d = t^(1/μ_t), and the pane, its multiple reflections
//! summed as a geometric series, transmits and reflects
//!
//! ```text
//!   τ = ½ Σ_{r ∈ {r_s, r_p}} (1 − r)² d / (1 − r² d²)
//!   ρ = ½ Σ_{r ∈ {r_s, r_p}} r (1 + (1 − 2r) d²) / (1 − r² d²)
//! ```
//!
//! The transmissivity comes from the transmittance T_n at normal incidence
//! (the value glass makers quote) by the manual's inversion of τ(μ = 1),
//!
//! ```text
//!   t = (√(0.840 252 843 5 + 0.007 252 223 9 T_n²) − 0.916 653 066 1) / 0.003 626 111 9 / T_n
//! ```
//!
//! whose constants are (1 − r₀)⁴, 4 r₀², (1 − r₀)² and 2 r₀² for
//! r₀ = ((n − 1)/(n + 1))² (tested). T_n = 0.88 gives t ≈ 0.96.
//!
//! # References
//! - G. Ward, Radiance `src/rt/glass.c` (`m_glass`; older releases
//!   `m_glass.c`), LBNL-ETA/Radiance.
//! - *The RADIANCE 5.x Reference Manual*, `doc/ray.html`, "Glass".
//! - M. Born, E. Wolf, *Principles of Optics*, §1.5 (Fresnel's formulae).

use super::quadrature::{Tolerance, integrate};

/// The refractive index Radiance's `glass` assumes.
pub const GLASS_REFRACTIVE_INDEX: f64 = 1.52;

/// The transmittance at normal incidence of a pane that absorbs nothing,
/// (1 − r₀)/(1 + r₀) = 2n/(n² + 1) ≈ 0.9183: the most a pane can have.
#[must_use]
pub fn lossless_pane_transmittance() -> f64 {
    let n = GLASS_REFRACTIVE_INDEX;
    2.0 * n / (n * n + 1.0)
}

/// Radiance's transmissivity t (not absorbed in one normal traversal) from
/// the transmittance `tn` at normal incidence (see the module docs),
/// clamped to [0, 1]: `tn` ≤ 0 or NaN gives 0, and `tn` at or above
/// [`lossless_pane_transmittance`] gives 1.
#[must_use]
pub fn transmissivity_from_transmittance(tn: f64) -> f64 {
    if tn.is_nan() || tn <= 0.0 {
        return 0.0;
    }
    let t = ((0.840_252_843_5 + 0.007_252_223_9 * tn * tn).sqrt() - 0.916_653_066_1)
        / 0.003_626_111_9
        / tn;
    t.clamp(0.0, 1.0)
}

/// The fractions a pane transmits and reflects at one incidence.
#[derive(Clone, Copy, Debug, PartialEq)]
struct PaneOptics {
    transmittance: f64,
    reflectance: f64,
}

/// τ and ρ of a pane of transmissivity `transmissivity` at incidence
/// `cos_theta` (see the module docs): grazing or worse (cos θ ≤ 0, or NaN)
/// transmits nothing and reflects all; cos θ above 1 counts as 1.
fn pane_optics(transmissivity: f64, cos_theta: f64) -> PaneOptics {
    if cos_theta.is_nan() || cos_theta <= 0.0 {
        return PaneOptics {
            transmittance: 0.0,
            reflectance: 1.0,
        };
    }
    let n = GLASS_REFRACTIVE_INDEX;
    let mu = cos_theta.min(1.0);
    let mu_t = (1.0 - (1.0 - mu * mu) / (n * n)).sqrt();
    let d = transmissivity.powf(1.0 / mu_t);
    let r_s = ((mu - n * mu_t) / (mu + n * mu_t)).powi(2);
    let r_p = ((mu_t - n * mu) / (mu_t + n * mu)).powi(2);
    let mut optics = PaneOptics {
        transmittance: 0.0,
        reflectance: 0.0,
    };
    for r in [r_s, r_p] {
        let series = 1.0 - r * r * d * d;
        optics.transmittance += 0.5 * (1.0 - r) * (1.0 - r) * d / series;
        optics.reflectance += 0.5 * r * (1.0 + (1.0 - 2.0 * r) * d * d) / series;
    }
    optics
}

/// Transmittance of a clear glass pane at incidence `cos_theta` (the
/// cosine of the angle to the pane's normal, in 0..=1) given its visible
/// transmittance `tn` at normal incidence, as Radiance's `glass` material
/// computes it: τ of the module docs with the transmissivity from
/// [`transmissivity_from_transmittance`]. 0 at grazing (cos θ ≤ 0); 1 at
/// normal incidence gives back `tn` (to the manual's 10 digits).
#[must_use]
pub fn pane_transmittance(tn: f64, cos_theta: f64) -> f64 {
    pane_optics(transmissivity_from_transmittance(tn), cos_theta).transmittance
}

/// Reflectance of the same pane at that incidence: both faces and the
/// reflections between them, as `m_glass` computes its reflected ray (ρ of
/// the module docs). 1 at grazing (cos θ ≤ 0).
#[must_use]
pub fn pane_reflectance(tn: f64, cos_theta: f64) -> f64 {
    pane_optics(transmissivity_from_transmittance(tn), cos_theta).reflectance
}

/// ∫₀¹ f(μ) 2μ dμ, the hemispherical average under uniform diffuse light.
fn diffuse_average(f: impl Fn(f64) -> f64) -> f64 {
    let tolerance = Tolerance {
        absolute: 1e-14,
        relative: 1e-12,
        max_segments: 200,
    };
    integrate(|mu| f(mu) * 2.0 * mu, 0.0, 1.0, tolerance)
}

/// Hemispherical (diffuse-incidence) transmittance 2∫ τ(θ) cos θ sin θ dθ = ∫₀¹ τ(μ) 2μ dμ.
#[must_use]
pub fn pane_diffuse_transmittance(tn: f64) -> f64 {
    let t = transmissivity_from_transmittance(tn);
    diffuse_average(|mu| pane_optics(t, mu).transmittance)
}

/// Hemispherical (diffuse-incidence) reflectance 2∫ ρ(θ) cos θ sin θ dθ = ∫₀¹ ρ(μ) 2μ dμ.
#[must_use]
pub fn pane_diffuse_reflectance(tn: f64) -> f64 {
    let t = transmissivity_from_transmittance(tn);
    diffuse_average(|mu| pane_optics(t, mu).reflectance)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// r₀ = ((n − 1)/(n + 1))², one face at normal incidence.
    fn face_reflectance() -> f64 {
        let n = GLASS_REFRACTIVE_INDEX;
        ((n - 1.0) / (n + 1.0)).powi(2)
    }

    #[test]
    fn the_manuals_constants_come_from_n_1_52() {
        let r0 = face_reflectance();
        assert!((r0 - 0.042_580).abs() < 1e-6, "{r0}");
        assert!(((1.0 - r0).powi(4) - 0.840_252_843_5).abs() < 1e-9);
        assert!((4.0 * r0 * r0 - 0.007_252_223_9).abs() < 1e-9);
        assert!(((1.0 - r0).powi(2) - 0.916_653_066_1).abs() < 1e-9);
        assert!((2.0 * r0 * r0 - 0.003_626_111_9).abs() < 1e-9);
    }

    #[test]
    fn normal_incidence_gives_back_the_transmittance() {
        for tn in [0.05, 0.3, 0.6, 0.88, 0.9] {
            let tau = pane_transmittance(tn, 1.0);
            assert!((tau - tn).abs() < 1e-6, "{tn}: {tau}");
        }
        // The manual: "Standard 88% transmittance glass has a transmissivity of 0.96."
        assert!((transmissivity_from_transmittance(0.88) - 0.96).abs() < 0.005);
        let lossless = lossless_pane_transmittance();
        assert!((transmissivity_from_transmittance(lossless) - 1.0).abs() < 1e-7);
        assert_eq!(transmissivity_from_transmittance(0.95), 1.0);
        assert_eq!(transmissivity_from_transmittance(0.0), 0.0);
        assert_eq!(transmissivity_from_transmittance(f64::NAN), 0.0);
    }

    #[test]
    fn transmittance_falls_with_angle_to_zero_at_grazing() {
        for tn in [0.3, 0.88] {
            let mut last = f64::INFINITY;
            for i in (0..=200).rev() {
                let mu = f64::from(i) / 200.0;
                let tau = pane_transmittance(tn, mu);
                let rho = pane_reflectance(tn, mu);
                assert!(
                    tau < last || (tau == 0.0 && last == 0.0),
                    "{tn} at μ {mu}: {tau} after {last}"
                );
                assert!(
                    tau + rho <= 1.0 + 1e-12 && tau >= 0.0 && rho >= 0.0,
                    "{tn} at μ {mu}"
                );
                last = tau;
            }
            assert_eq!(pane_transmittance(tn, 0.0), 0.0);
            assert_eq!(pane_reflectance(tn, 0.0), 1.0);
            assert!(pane_transmittance(tn, 1e-9) < 1e-7);
        }
    }

    #[test]
    fn a_clear_pane_reflects_about_eight_percent_at_normal_incidence() {
        // One face: r₀ = 0.0426; two faces of a lossless pane with their
        // interreflections: r₀ + (1 − r₀)² r₀ / (1 − r₀²) = 2r₀/(1 + r₀).
        let r0 = face_reflectance();
        let lossless = pane_optics(1.0, 1.0);
        assert!((lossless.reflectance - 2.0 * r0 / (1.0 + r0)).abs() < 1e-12);
        assert!((lossless.reflectance - 0.0817).abs() < 1e-3);
        let rho = pane_reflectance(0.88, 1.0);
        assert!(rho > 0.075 && rho < 0.0817, "{rho}");
    }

    #[test]
    fn sixty_degrees_against_fresnels_formulae_in_angles() {
        // Snell: sin θ_t = sin θ / n; Fresnel: r_s = sin²(θ − θ_t)/sin²(θ + θ_t),
        // r_p = tan²(θ − θ_t)/tan²(θ + θ_t); path d = t^(1/cos θ_t); the pane
        // as the sum of the series r + (1−r)² r d² Σ (r² d²)^k, (1−r)² d Σ (r² d²)^k.
        let tn = 0.88;
        let t = transmissivity_from_transmittance(tn);
        let theta = 60f64.to_radians();
        let theta_t = (theta.sin() / GLASS_REFRACTIVE_INDEX).asin();
        let r_s = ((theta - theta_t).sin() / (theta + theta_t).sin()).powi(2);
        let r_p = ((theta - theta_t).tan() / (theta + theta_t).tan()).powi(2);
        let d = t.powf(1.0 / theta_t.cos());
        let (mut tau, mut rho) = (0.0, 0.0);
        for r in [r_s, r_p] {
            let bounces: f64 = (0..200).map(|k| (r * r * d * d).powi(k)).sum();
            tau += 0.5 * (1.0 - r).powi(2) * d * bounces;
            rho += 0.5 * (r + (1.0 - r).powi(2) * r * d * d * bounces);
        }
        assert!(
            (pane_transmittance(tn, theta.cos()) - tau).abs() < 1e-12,
            "{tau}"
        );
        assert!(
            (pane_reflectance(tn, theta.cos()) - rho).abs() < 1e-12,
            "{rho}"
        );
    }

    #[test]
    fn diffuse_averages() {
        // A lossless pane conserves light: τ + ρ = 1 at every angle, so on average.
        let lossless = lossless_pane_transmittance();
        let sum = pane_diffuse_transmittance(lossless) + pane_diffuse_reflectance(lossless);
        assert!((sum - 1.0).abs() < 1e-6, "{sum}");
        // Against a midpoint sum in θ of 2 τ cos θ sin θ.
        let n = 20_000;
        let h = std::f64::consts::FRAC_PI_2 / f64::from(n);
        let midpoint: f64 = (0..n)
            .map(|i| {
                let theta = (f64::from(i) + 0.5) * h;
                2.0 * pane_transmittance(0.88, theta.cos()) * theta.cos() * theta.sin() * h
            })
            .sum();
        let diffuse = pane_diffuse_transmittance(0.88);
        assert!((diffuse - midpoint).abs() < 1e-8, "{diffuse} vs {midpoint}");
        assert!(diffuse > 0.7 && diffuse < 0.88, "{diffuse}");
        let rho = pane_diffuse_reflectance(0.88);
        assert!(rho > 0.08 && rho < 0.2 && diffuse + rho < 1.0, "{rho}");
    }
}
