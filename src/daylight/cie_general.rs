//! The CIE standard general sky's table: the gradation and indicatrix
//! parameters a–e of its fifteen types.
//!
//! ```text
//!   gradation   φ(Z) = 1 + a exp(b / cos Z)        (φ = 1 at the horizon, Z = 90°)
//!   indicatrix  f(χ) = 1 + c (exp(d χ) − exp(d π/2)) + e cos² χ
//!   L / L_z    = f(χ) φ(Z) / (f(Z_s) φ(0))
//! ```
//!
//! Z is the zenith angle of the sky element, χ its angle to the sun and Z_s
//! the sun's zenith angle. The fifteen types combine six gradation groups
//! (I–VI: a, b) with six indicatrix groups (1–6: c, d, e), Table 1 of the
//! standard; types 1, 3 and 5 (indicatrix group 1: c = 0, e = 0) do not
//! depend on the sun.
//!
//! # References
//! - ISO 15469:2004(E) / CIE S 011/E:2003, *Spatial distribution of daylight
//!   — CIE standard general sky*, Table 1 (the parameters) and eqs. 1–3.
//! - S. Darula, R. Kittler, "CIE general sky standard defining luminance
//!   distributions", Proc. eSim 2002, Montréal (the same table, by groups).
//! - R. Kittler, R. Perez, S. Darula, "A set of standard skies
//!   characterizing daylight conditions for computer and energy conscious
//!   design", US SK 92 052 final report, 1998.

/// The parameters of one type of the CIE standard general sky.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CieGeneralParameters {
    /// Gradation: the horizon-to-zenith contrast (a > 0 darker at the horizon).
    pub a: f64,
    /// Gradation: how fast it changes with zenith angle (b < 0).
    pub b: f64,
    /// Indicatrix: the weight of the circumsolar term.
    pub c: f64,
    /// Indicatrix: the circumsolar term's decay with angle to the sun (d < 0).
    pub d: f64,
    /// Indicatrix: the weight of the scattering term cos² χ.
    pub e: f64,
    /// The standard's description of the type.
    pub description: &'static str,
}

/// Shorthand for the table below.
const fn row(
    a: f64,
    b: f64,
    c: f64,
    d: f64,
    e: f64,
    description: &'static str,
) -> CieGeneralParameters {
    CieGeneralParameters {
        a,
        b,
        c,
        d,
        e,
        description,
    }
}

/// Types 1–15 of ISO 15469:2004 / CIE S 011/E:2003, Table 1.
const TYPES: [CieGeneralParameters; 15] = [
    row(
        4.0,
        -0.70,
        0.0,
        -1.0,
        0.00,
        "CIE standard overcast sky, steep gradation towards the zenith, azimuthal uniformity",
    ),
    row(
        4.0,
        -0.70,
        2.0,
        -1.5,
        0.15,
        "overcast, steep gradation and slight brightening towards the sun",
    ),
    row(
        1.1,
        -0.80,
        0.0,
        -1.0,
        0.00,
        "overcast, moderately graded, azimuthal uniformity",
    ),
    row(
        1.1,
        -0.80,
        2.0,
        -1.5,
        0.15,
        "overcast, moderately graded, slight brightening towards the sun",
    ),
    row(0.0, -1.00, 0.0, -1.0, 0.00, "sky of uniform luminance"),
    row(
        0.0,
        -1.00,
        2.0,
        -1.5,
        0.15,
        "partly cloudy, no gradation towards the zenith, slight brightening towards the sun",
    ),
    row(
        0.0,
        -1.00,
        5.0,
        -2.5,
        0.30,
        "partly cloudy, no gradation towards the zenith, brighter circumsolar region",
    ),
    row(
        0.0,
        -1.00,
        10.0,
        -3.0,
        0.45,
        "partly cloudy, no gradation towards the zenith, distinct solar corona",
    ),
    row(
        -1.0,
        -0.55,
        2.0,
        -1.5,
        0.15,
        "partly cloudy, the sun obscured",
    ),
    row(
        -1.0,
        -0.55,
        5.0,
        -2.5,
        0.30,
        "partly cloudy, brighter circumsolar region",
    ),
    row(
        -1.0,
        -0.55,
        10.0,
        -3.0,
        0.45,
        "white-blue sky with distinct solar corona",
    ),
    row(
        -1.0,
        -0.32,
        10.0,
        -3.0,
        0.45,
        "CIE standard clear sky, low illuminance turbidity",
    ),
    row(
        -1.0,
        -0.32,
        16.0,
        -3.0,
        0.30,
        "CIE standard clear sky, polluted atmosphere",
    ),
    row(
        -1.0,
        -0.15,
        16.0,
        -3.0,
        0.30,
        "cloudless turbid sky with broad solar corona",
    ),
    row(
        -1.0,
        -0.15,
        24.0,
        -2.8,
        0.15,
        "white-blue turbid sky with broad solar corona",
    ),
];

/// The parameters of type `sky_type` (1–15); None outside 1..=15.
#[must_use]
pub fn cie_general_parameters(sky_type: u8) -> Option<CieGeneralParameters> {
    TYPES.get(usize::from(sky_type).checked_sub(1)?).copied()
}

impl CieGeneralParameters {
    /// φ(Z) = 1 + a exp(b / cos Z), given cos Z; 1 at and below the horizon
    /// (the limit as cos Z → 0⁺, b being negative).
    #[must_use]
    pub fn gradation(&self, cos_zenith: f64) -> f64 {
        if cos_zenith > 0.0 {
            1.0 + self.a * (self.b / cos_zenith).exp()
        } else {
            1.0
        }
    }

    /// f(χ) = 1 + c (exp(d χ) − exp(d π/2)) + e cos² χ, χ in radians.
    #[must_use]
    pub fn indicatrix(&self, chi: f64) -> f64 {
        let cos = chi.cos();
        1.0 + self.c * ((self.d * chi).exp() - (self.d * std::f64::consts::FRAC_PI_2).exp())
            + self.e * cos * cos
    }

    /// Whether the indicatrix varies (c ≠ 0 or e ≠ 0), so that the pattern
    /// depends on the sun: every type but 1, 3 and 5.
    #[must_use]
    pub fn needs_sun(&self) -> bool {
        self.c != 0.0 || self.e != 0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn types_outside_one_to_fifteen_are_refused() {
        assert!(cie_general_parameters(0).is_none());
        assert!(cie_general_parameters(16).is_none());
        assert!(cie_general_parameters(255).is_none());
        assert!((1..=15).all(|t| cie_general_parameters(t).is_some()));
    }

    #[test]
    fn spot_checks_against_the_standard() {
        // ISO 15469:2004 Table 1: (type, a, b, c, d, e).
        let published = [
            (1, 4.0, -0.70, 0.0, -1.0, 0.00),
            (5, 0.0, -1.00, 0.0, -1.0, 0.00),
            (7, 0.0, -1.00, 5.0, -2.5, 0.30),
            (9, -1.0, -0.55, 2.0, -1.5, 0.15),
            (12, -1.0, -0.32, 10.0, -3.0, 0.45),
            (13, -1.0, -0.32, 16.0, -3.0, 0.30),
            (15, -1.0, -0.15, 24.0, -2.8, 0.15),
        ];
        for (t, a, b, c, d, e) in published {
            let p = cie_general_parameters(t).unwrap_or_else(|| panic!("type {t}"));
            assert_eq!([p.a, p.b, p.c, p.d, p.e], [a, b, c, d, e], "type {t}");
        }
    }

    #[test]
    fn the_table_is_six_gradation_groups_by_six_indicatrix_groups() {
        // Darula & Kittler 2002: type → (gradation group, indicatrix group).
        let gradation = [
            (4.0, -0.70),
            (1.1, -0.80),
            (0.0, -1.00),
            (-1.0, -0.55),
            (-1.0, -0.32),
            (-1.0, -0.15),
        ];
        let indicatrix = [
            (0.0, -1.0, 0.0),
            (2.0, -1.5, 0.15),
            (5.0, -2.5, 0.30),
            (10.0, -3.0, 0.45),
            (16.0, -3.0, 0.30),
            (24.0, -2.8, 0.15),
        ];
        let groups = [
            (1, 1),
            (1, 2),
            (2, 1),
            (2, 2),
            (3, 1),
            (3, 2),
            (3, 3),
            (3, 4),
            (4, 2),
            (4, 3),
            (4, 4),
            (5, 4),
            (5, 5),
            (6, 5),
            (6, 6),
        ];
        for (t, (g, i)) in (1u8..).zip(groups) {
            let p = cie_general_parameters(t).unwrap_or_else(|| panic!("type {t}"));
            assert_eq!((p.a, p.b), gradation[g - 1], "type {t}");
            assert_eq!((p.c, p.d, p.e), indicatrix[i - 1], "type {t}");
            assert_eq!(p.needs_sun(), i != 1, "type {t}");
        }
    }

    #[test]
    fn gradation_is_one_at_the_horizon() {
        for t in 1..=15 {
            let p = cie_general_parameters(t).unwrap_or_else(|| panic!("type {t}"));
            assert_eq!(p.gradation(0.0), 1.0);
            assert!((p.gradation(1e-3) - 1.0).abs() < 1e-30);
            assert_eq!(
                p.indicatrix(std::f64::consts::FRAC_PI_2),
                1.0 + p.e * std::f64::consts::FRAC_PI_2.cos().powi(2)
            );
        }
    }
}
