//! Round numbers for lighting pictures: the iso-lux levels of a plot
//! ([`nice_levels`]), the top of a false-colour scale ([`nice_ceiling`]) and
//! the text of a value ([`format_lux`]).
//!
//! A nice number is m · 10^k with m one of 1, 2, 2.5 or 5 and k an integer.

/// The mantissas of nice numbers, increasing.
const MANTISSAS: [f64; 4] = [1.0, 2.0, 2.5, 5.0];

/// At most this many levels, whatever the target.
const MAX_LEVELS: usize = 1000;

/// A nice number m · 10^k, kept as its parts so that its multiples can be
/// computed without rounding drift.
#[derive(Clone, Copy, Debug)]
struct NiceStep {
    mantissa: f64,
    exponent: i32,
}

impl NiceStep {
    /// The nice step closest to `raw` (finite, positive) on a log scale.
    fn nearest(raw: f64) -> NiceStep {
        let exponent = raw.log10().floor() as i32;
        let candidates = MANTISSAS
            .iter()
            .map(|&mantissa| NiceStep { mantissa, exponent })
            .chain(std::iter::once(NiceStep {
                mantissa: 1.0,
                exponent: exponent + 1,
            }));
        candidates
            .min_by(|a, b| {
                let distance = |s: &NiceStep| (s.value() / raw).ln().abs();
                distance(a).total_cmp(&distance(b))
            })
            .unwrap_or(NiceStep {
                mantissa: 1.0,
                exponent,
            })
    }

    /// m · 10^k.
    fn value(self) -> f64 {
        self.times(1.0)
    }

    /// n · m · 10^k, divided rather than multiplied by 10^(−k) when k < 0,
    /// so that 3 × 0.1 is 0.3, the double nearest the decimal.
    fn times(self, n: f64) -> f64 {
        let count = n * self.mantissa;
        if self.exponent < 0 {
            count / 10_f64.powi(-self.exponent)
        } else {
            count * 10_f64.powi(self.exponent)
        }
    }
}

/// About `target` round iso-lux levels strictly between `min` and `max`,
/// increasing: the multiples n · s of the nice step s (1, 2, 2.5 or 5 ×
/// 10^k) nearest to (max − min′) / target on a log scale, with
/// min′ = max(min, 0).
///
/// Illuminance is not negative, so only positive levels are given: a
/// negative `min` counts as 0. Empty when `target` is 0, when either bound
/// is not finite, when max ≤ min′, and when the range is too narrow
/// to tell its ends apart (max − min′ ≤ 10⁻¹² max). At most 1000 levels.
///
/// ```
/// use isorad::calculation::nice_levels;
/// assert_eq!(nice_levels(12.0, 830.0, 8), vec![100.0, 200.0, 300.0, 400.0, 500.0, 600.0, 700.0, 800.0]);
/// assert_eq!(nice_levels(0.0, 1.0, 4), vec![0.25, 0.5, 0.75]);
/// ```
#[must_use]
pub fn nice_levels(min: f64, max: f64, target: usize) -> Vec<f64> {
    if target == 0 || !min.is_finite() || !max.is_finite() {
        return Vec::new();
    }
    let min = min.max(0.0);
    if max <= min {
        return Vec::new();
    }
    let target = target.min(MAX_LEVELS);
    let step = NiceStep::nearest((max - min) / target as f64);
    if !step.value().is_normal() || max - min <= 1e-12 * max {
        return Vec::new();
    }

    // Multiples of the step from the first above `min`, while below `max`.
    let first = (min / step.value()).floor() + 1.0;
    (0..=2 * target + 2)
        .map(|i| step.times(first + i as f64))
        .skip_while(|&level| level <= min)
        .take_while(|&level| level < max)
        .take(MAX_LEVELS)
        .collect()
}

/// The round maxima a scale may end at, per decade: fine enough that the
/// top band is never much emptier than the others.
const CEILING_MANTISSAS: [f64; 10] = [1.0, 1.2, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0];

/// The smallest round number (1, 1.2, 1.5, 2, 2.5, 3, 4, 5, 6 or 8 × 10^k)
/// at or above `value`, e.g. 512 → 600, 480 → 500, 0.18 → 0.2. None when `value` is not finite
/// and positive.
///
/// ```
/// use isorad::calculation::nice_ceiling;
/// assert_eq!(nice_ceiling(480.0), Some(500.0));
/// assert_eq!(nice_ceiling(553.0), Some(600.0));
/// assert_eq!(nice_ceiling(2100.0), Some(2500.0));
/// assert_eq!(nice_ceiling(0.0), None);
/// ```
#[must_use]
pub fn nice_ceiling(value: f64) -> Option<f64> {
    if !value.is_finite() || value <= 0.0 {
        return None;
    }
    let exponent = value.log10().floor() as i32;
    // The decade's round numbers and the next decade's 1, from the one
    // below (log10 may round across a power of ten).
    (exponent - 1..=exponent + 1)
        .flat_map(|exponent| {
            CEILING_MANTISSAS
                .iter()
                .map(move |&mantissa| mantissa * 10f64.powi(exponent))
        })
        .find(|&nice| nice >= value * (1.0 - 1e-12))
        .filter(|nice| nice.is_finite())
}

/// A value as a label: whole numbers from 100 up, otherwise three
/// significant digits, trailing zeros dropped ("500", "12.5", "0.75",
/// "0.025"); below 0.001 in scientific notation ("2.5e-5").
///
/// ```
/// use isorad::calculation::format_lux;
/// assert_eq!(format_lux(500.0), "500");
/// assert_eq!(format_lux(12.5), "12.5");
/// assert_eq!(format_lux(0.75), "0.75");
/// ```
#[must_use]
pub fn format_lux(value: f64) -> String {
    let magnitude = value.abs();
    if !value.is_finite() || magnitude == 0.0 {
        return if value == 0.0 {
            "0".to_string()
        } else {
            value.to_string()
        };
    }
    if magnitude < 1e-3 {
        let text = format!("{value:.2e}");
        let (mantissa, exponent) = text.split_once('e').unwrap_or((&text, "0"));
        return format!("{}e{exponent}", trim_zeros(mantissa));
    }
    let decimals = (2 - magnitude.log10().floor() as i32).max(0) as usize;
    trim_zeros(&format!("{value:.decimals$}")).to_string()
}

/// `text` without the trailing zeros of its decimals, nor a bare point.
fn trim_zeros(text: &str) -> &str {
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.')
    } else {
        text
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_are_round_and_inside() {
        assert_eq!(
            nice_levels(12.0, 830.0, 8),
            vec![100.0, 200.0, 300.0, 400.0, 500.0, 600.0, 700.0, 800.0]
        );
        assert_eq!(nice_levels(0.0, 1.0, 4), vec![0.25, 0.5, 0.75]);
        assert_eq!(nice_levels(0.31, 0.72, 4), vec![0.4, 0.5, 0.6, 0.7]);
        // The ends themselves are not levels.
        assert_eq!(nice_levels(100.0, 500.0, 4), vec![200.0, 300.0, 400.0]);
        let many = nice_levels(3.0, 47_000.0, 10);
        assert!((7..=13).contains(&many.len()), "{many:?}");
        assert!(many.windows(2).all(|w| w[0] < w[1]));
    }

    #[test]
    fn levels_print_as_decimals() {
        let levels = nice_levels(0.0, 0.9, 9);
        let text: Vec<String> = levels.iter().map(|&v| format_lux(v)).collect();
        assert_eq!(
            text,
            ["0.1", "0.2", "0.3", "0.4", "0.5", "0.6", "0.7", "0.8"]
        );
        assert_eq!(nice_levels(0.0, 0.9, 9)[2], 0.3);
    }

    #[test]
    fn degenerate_ranges_give_no_levels() {
        assert!(nice_levels(5.0, 5.0, 8).is_empty());
        assert!(nice_levels(9.0, 5.0, 8).is_empty());
        assert!(nice_levels(f64::NAN, 5.0, 8).is_empty());
        assert!(nice_levels(0.0, f64::INFINITY, 8).is_empty());
        assert!(nice_levels(-10.0, -1.0, 8).is_empty());
        assert!(nice_levels(0.0, 10.0, 0).is_empty());
        assert!(nice_levels(1e300, 1e300 * (1.0 + 1e-15), 8).is_empty());
        assert!(nice_levels(0.0, f64::MAX, 8).len() <= 9);
        assert!(nice_levels(0.0, 1.0, usize::MAX).len() <= MAX_LEVELS);
    }

    #[test]
    fn negative_minimum_counts_as_zero() {
        assert_eq!(nice_levels(-100.0, 100.0, 4), vec![25.0, 50.0, 75.0]);
    }

    #[test]
    fn ceilings_are_nice() {
        assert_eq!(nice_ceiling(512.0), Some(600.0));
        assert_eq!(nice_ceiling(1150.0), Some(1200.0));
        assert_eq!(nice_ceiling(480.0), Some(500.0));
        assert_eq!(nice_ceiling(500.0), Some(500.0));
        assert_eq!(nice_ceiling(1000.0), Some(1000.0));
        assert_eq!(nice_ceiling(0.18), Some(0.2));
        assert_eq!(nice_ceiling(2100.0), Some(2500.0));
        assert_eq!(nice_ceiling(-1.0), None);
        assert_eq!(nice_ceiling(f64::NAN), None);
        assert_eq!(nice_ceiling(f64::MAX), None);
    }

    #[test]
    fn labels_are_short() {
        assert_eq!(format_lux(500.0), "500");
        assert_eq!(format_lux(1250.0), "1250");
        assert_eq!(format_lux(512.4), "512");
        assert_eq!(format_lux(12.5), "12.5");
        assert_eq!(format_lux(2.5), "2.5");
        assert_eq!(format_lux(0.75), "0.75");
        assert_eq!(format_lux(0.025), "0.025");
        assert_eq!(format_lux(0.0), "0");
        assert_eq!(format_lux(-20.0), "-20");
        assert_eq!(format_lux(2.5e-5), "2.5e-5");
        assert_eq!(format_lux(f64::NAN), "NaN");
    }
}
