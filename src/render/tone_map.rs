//! From linear radiance to 8-bit sRGB: exposure, the sRGB transfer curve,
//! and an automatic exposure.

use super::image::Image;

/// Maps linear radiance to 8-bit sRGB display values.
///
/// For each channel: v = L · 2^exposure, then the sRGB transfer curve
/// ([`srgb_encode`]), clamped to [0, 1], and rounded to the nearest of 0..=255.
/// No other curve (no filmic shoulder): a radiance of 2^−exposure is white.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ToneMap {
    /// Exposure in stops: radiance is multiplied by 2^exposure. Default 0.
    pub exposure: f64,
}

impl ToneMap {
    /// A tone map with the given exposure in stops.
    #[must_use]
    pub fn new(exposure: f64) -> ToneMap {
        ToneMap { exposure }
    }

    /// The 8-bit value of one channel of linear radiance:
    /// round(255 · clamp(srgb(L · 2^exposure), 0, 1)). NaN maps to 0,
    /// +∞ to 255.
    #[must_use]
    pub fn map_channel(&self, radiance: f64) -> u8 {
        let encoded = srgb_encode(radiance * self.exposure.exp2());
        // `as` saturates; NaN is sent to 0 first.
        if encoded.is_nan() {
            0
        } else {
            (255.0 * encoded.clamp(0.0, 1.0)).round() as u8
        }
    }

    /// The 8-bit sRGB value of a linear RGB radiance.
    #[must_use]
    pub fn map_pixel(&self, radiance: [f32; 3]) -> [u8; 3] {
        radiance.map(|l| self.map_channel(f64::from(l)))
    }
}

/// The sRGB transfer curve (IEC 61966-2-1), linear → encoded:
///
/// - 12.92 · x for x ≤ 0.0031308,
/// - 1.055 · x^(1/2.4) − 0.055 otherwise.
///
/// Not clamped: values above 1 stay above 1, negative values are scaled by
/// 12.92.
///
/// # References
///
/// IEC 61966-2-1:1999, *Default RGB colour space — sRGB*.
#[must_use]
pub fn srgb_encode(linear: f64) -> f64 {
    if linear <= 0.003_130_8 {
        12.92 * linear
    } else {
        1.055 * linear.powf(1.0 / 2.4) - 0.055
    }
}

/// Luminance percentile that [`auto_exposure`] maps to [`AUTO_EXPOSURE_TARGET`].
const AUTO_EXPOSURE_PERCENTILE: f64 = 0.97;

/// Linear value (before the sRGB curve) the percentile is mapped to.
const AUTO_EXPOSURE_TARGET: f64 = 0.8;

/// An exposure, in stops, for an image given without one.
///
/// Takes the luminance Y = 0.2126 R + 0.7152 G + 0.0722 B (Rec. 709) of every
/// pixel with a finite Y > 0, picks its 97th percentile Y₉₇ (nearest rank),
/// and returns log₂(0.8 / Y₉₇), so that Y₉₇ is shown at linear 0.8 (sRGB
/// ≈ 0.91) and the brightest 3 % — typically the emitters — may saturate.
/// Returns 0 when no pixel is lit.
#[must_use]
pub fn auto_exposure(image: &Image) -> f64 {
    // Luminance of the lit pixels.
    let mut luminance: Vec<f64> = image
        .pixels()
        .iter()
        .map(|p| 0.2126 * f64::from(p[0]) + 0.7152 * f64::from(p[1]) + 0.0722 * f64::from(p[2]))
        .filter(|y| y.is_finite() && *y > 0.0)
        .collect();
    if luminance.is_empty() {
        return 0.0;
    }
    // Nearest-rank percentile.
    let rank = ((AUTO_EXPOSURE_PERCENTILE * luminance.len() as f64).ceil() as usize)
        .clamp(1, luminance.len());
    let (_, percentile, _) = luminance.select_nth_unstable_by(rank - 1, f64::total_cmp);
    (AUTO_EXPOSURE_TARGET / *percentile).log2()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_curve_is_continuous_at_the_knee() {
        let knee = 0.003_130_8;
        let below = srgb_encode(knee);
        let above = 1.055 * f64::powf(knee, 1.0 / 2.4) - 0.055;
        assert!((below - above).abs() < 1e-7, "{below} vs {above}");
        assert!((srgb_encode(1.0) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn exposure_scales_by_powers_of_two() {
        let tone_map = ToneMap::new(1.0);
        assert_eq!(tone_map.map_channel(0.5), 255);
        assert_eq!(tone_map.map_channel(f64::NAN), 0);
        assert_eq!(tone_map.map_channel(f64::INFINITY), 255);
        assert_eq!(tone_map.map_channel(-1.0), 0);
    }

    #[test]
    fn auto_exposure_maps_the_percentile_to_the_target() {
        // 100 pixels of luminance 1..=100 (grey), plus black ones ignored.
        let mut pixels: Vec<[f32; 3]> = (1..=100).map(|k| [k as f32; 3]).collect();
        pixels.extend([[0.0; 3]; 50]);
        let image = Image::from_pixels(150, 1, pixels).expect("150 pixels");
        let exposure = auto_exposure(&image);
        assert!(
            (exposure - (0.8_f64 / 97.0).log2()).abs() < 1e-6,
            "{exposure}"
        );
        assert_eq!(auto_exposure(&Image::new(4, 4)), 0.0);
    }
}
