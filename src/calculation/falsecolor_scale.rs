//! The false-colour scale of [`write_falsecolor_image`] and
//! [`write_falsecolor_grid`]: each value painted with the colour of its band
//! on a scale from 0 to a maximum, as Radiance's `falsecolor` paints it.
//!
//! **The palette** is viridis (van der Walt and Smith, matplotlib 2.0), a
//! ramp from dark blue-violet through teal and green to yellow whose
//! lightness rises evenly, so equal steps of value read as equal steps of
//! colour and the picture survives printing in grey; it is kept as nine
//! colours 1/8 apart and interpolated linearly between them. Radiance's
//! default blue–green–yellow–red palette is not used.
//!
//! **The scale** ([`FalseColorScale`]) has `steps` bands of equal width,
//! on a linear scale from 0 to `maximum`, or on a log scale over the
//! [`LOG_DECADES`] decades below `maximum`. A value v falls in band
//!
//! b = ⌊t · steps⌋, clamped to 0 … steps − 1, with t = v / maximum
//! (linear) or t = 1 + log₁₀(v / maximum) / [`LOG_DECADES`] (log),
//!
//! and gets the palette's colour at b / (steps − 1): the lowest band the
//! palette's first colour, the band holding the maximum its last. Values
//! above the maximum get the top band's colour, values at or below the
//! bottom the lowest band's; missing values (NaN) are painted dark grey
//! `[40, 40, 40]`, the colour of the picture's background.
//!
//! # References
//! - S. van der Walt, N. Smith, "A Better Default Colormap for Matplotlib",
//!   SciPy 2015 (viridis).
//! - G. Ward, `falsecolor`(1), Radiance (the banded scale and its `-log`
//!   decades).
//!
//! [`write_falsecolor_image`]: super::write_falsecolor_image
//! [`write_falsecolor_grid`]: super::write_falsecolor_grid

use super::levels::nice_ceiling;

/// The decades below the maximum a logarithmic scale spans: its bottom is
/// maximum / 10³.
pub const LOG_DECADES: f64 = 3.0;

/// Viridis at 0, 1/8, …, 1 (matplotlib's values, as R's `viridis(9)`).
pub(super) const VIRIDIS: [[u8; 3]; 9] = [
    [68, 1, 84],
    [71, 45, 123],
    [59, 82, 139],
    [44, 114, 142],
    [33, 144, 140],
    [39, 173, 129],
    [93, 200, 99],
    [170, 220, 50],
    [253, 231, 37],
];

/// Missing values and the picture's background.
pub(super) const NO_DATA: [u8; 3] = [40, 40, 40];

/// Steps a scale may have.
const STEPS: std::ops::RangeInclusive<usize> = 2..=32;

/// The viridis colour at `t` in [0, 1] (clamped; NaN counts as 0).
fn viridis(t: f64) -> [u8; 3] {
    let scaled = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) } * 8.0;
    let below = (scaled.floor() as usize).min(7);
    let f = scaled - below as f64;
    std::array::from_fn(|channel| {
        let (a, b) = (
            f64::from(VIRIDIS[below][channel]),
            f64::from(VIRIDIS[below + 1][channel]),
        );
        (a + f * (b - a)).round() as u8
    })
}

/// A banded false-colour scale from 0 (or, logarithmic, from
/// maximum / 10^[`LOG_DECADES`]) to `maximum`; see the module notes for the
/// bands and the palette.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FalseColorScale {
    /// The top of the scale, in the values' unit (lux, cd/m²); finite and
    /// positive for the writers.
    pub maximum: f64,
    /// Whether the bands are equal on a log scale over the
    /// [`LOG_DECADES`] decades below the maximum (else equal in value).
    pub logarithmic: bool,
    /// The number of bands and swatches; held within 2 … 32.
    pub steps: usize,
}

impl FalseColorScale {
    /// A linear scale of 8 bands (Radiance's default) up to the largest
    /// finite value rounded up to a round number ([`nice_ceiling`]), or up
    /// to 1 when no value is finite and positive.
    #[must_use]
    pub fn fitted(values: &[f64]) -> FalseColorScale {
        FalseColorScale::fitted_to_quantile(values, 1.0)
    }

    /// As [`FalseColorScale::fitted`], up to the `quantile` (0 … 1) of the
    /// finite values rather than their largest: a camera view with a lamp
    /// in it keeps its bands for the room (0.99 clips the brightest 1 %
    /// of pixels into the top band, as Radiance's fixed scale would).
    #[must_use]
    pub fn fitted_to_quantile(values: &[f64], quantile: f64) -> FalseColorScale {
        let mut finite: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
        let top = if finite.is_empty() {
            f64::NAN
        } else {
            let rank = ((quantile.clamp(0.0, 1.0) * finite.len() as f64).ceil() as usize)
                .clamp(1, finite.len());
            *finite.select_nth_unstable_by(rank - 1, f64::total_cmp).1
        };
        FalseColorScale {
            maximum: nice_ceiling(top).unwrap_or(1.0),
            logarithmic: false,
            steps: 8,
        }
    }

    /// The number of bands used: `steps` held within 2 … 32.
    pub(super) fn bands(&self) -> usize {
        self.steps.clamp(*STEPS.start(), *STEPS.end())
    }

    /// The band of a value that is not NaN: ⌊t · steps⌋ clamped to the
    /// bands, t as in the module notes.
    fn band(&self, value: f64) -> usize {
        let t = if self.logarithmic {
            1.0 + (value / self.maximum).log10() / LOG_DECADES
        } else {
            value / self.maximum
        };
        let bands = self.bands();
        if t.is_nan() {
            return 0;
        }
        ((t * bands as f64).floor().max(0.0) as usize).min(bands - 1)
    }

    /// The colour of band `band`: viridis at band / (steps − 1).
    pub(super) fn band_colour(&self, band: usize) -> [u8; 3] {
        viridis(band as f64 / (self.bands() - 1) as f64)
    }

    /// The colour of `value`: its band's, or dark grey `[40, 40, 40]` when
    /// it is NaN.
    #[must_use]
    pub fn colour(&self, value: f64) -> [u8; 3] {
        if value.is_nan() {
            NO_DATA
        } else {
            self.band_colour(self.band(value))
        }
    }

    /// The values between the bands, from the bottom of the scale to its
    /// maximum (steps + 1 of them): maximum · i / steps (linear), or
    /// maximum · 10^(−[`LOG_DECADES`] · (1 − i / steps)) (log).
    #[must_use]
    pub fn boundaries(&self) -> Vec<f64> {
        let bands = self.bands();
        (0..=bands)
            .map(|i| {
                let t = i as f64 / bands as f64;
                if self.logarithmic {
                    self.maximum * 10_f64.powf(-LOG_DECADES * (1.0 - t))
                } else {
                    self.maximum * t
                }
            })
            .collect()
    }

    /// Why the writers cannot use the scale, if they cannot.
    pub(super) fn check(&self) -> std::result::Result<(), String> {
        if self.maximum.is_finite() && self.maximum > 0.0 {
            Ok(())
        } else {
            Err(format!(
                "the false-colour scale's maximum {} is not finite and positive",
                self.maximum
            ))
        }
    }
}

/// A linear scale of eight bands up to 1000, for the false-colour tests.
#[cfg(test)]
pub(crate) const TEST_SCALE: FalseColorScale = FalseColorScale {
    maximum: 1000.0,
    logarithmic: false,
    steps: 8,
};

#[cfg(test)]
mod tests {
    use super::*;

    const SCALE: FalseColorScale = TEST_SCALE;

    #[test]
    fn colours_follow_the_bands() {
        assert_eq!(SCALE.colour(0.0), VIRIDIS[0]);
        assert_eq!(SCALE.colour(-5.0), VIRIDIS[0]);
        assert_eq!(SCALE.colour(1000.0), VIRIDIS[8]);
        assert_eq!(SCALE.colour(5000.0), VIRIDIS[8]);
        assert_eq!(SCALE.colour(f64::INFINITY), VIRIDIS[8]);
        assert_eq!(SCALE.colour(f64::NAN), NO_DATA);
        // 8 bands of 125: 499 is in band 3, 500 in band 4.
        assert_eq!(SCALE.colour(499.0), viridis(3.0 / 7.0));
        assert_eq!(SCALE.colour(500.0), viridis(4.0 / 7.0));
        assert_ne!(SCALE.colour(499.0), SCALE.colour(500.0));
        assert_eq!(SCALE.boundaries()[4], 500.0);
    }

    #[test]
    fn log_scales_span_three_decades() {
        let scale = FalseColorScale {
            logarithmic: true,
            steps: 6,
            ..SCALE
        };
        let boundaries = scale.boundaries();
        assert!((boundaries[0] - 1.0).abs() < 1e-9);
        assert!((boundaries[2] - 10.0).abs() < 1e-9);
        assert!((boundaries[6] - 1000.0).abs() < 1e-9);
        assert_eq!(scale.colour(0.0), VIRIDIS[0]);
        assert_eq!(scale.colour(10.5), viridis(2.0 / 5.0));
        assert_eq!(scale.colour(999.0), VIRIDIS[8]);
    }

    #[test]
    fn fitted_scales_round_the_maximum_up() {
        assert_eq!(
            FalseColorScale::fitted(&[3.0, 412.0, f64::NAN]).maximum,
            500.0
        );
        assert_eq!(FalseColorScale::fitted(&[f64::NAN]).maximum, 1.0);
        assert_eq!(FalseColorScale::fitted(&[]).maximum, 1.0);
        assert_eq!(FalseColorScale::fitted(&[-3.0]).maximum, 1.0);
    }
}
