//! What a calculation grid reports: illuminance (EN 12464-1's statistics,
//! and under daylight EN 17037's shares of the grid reaching 300, 500 and
//! 750 lx), or the daylight factor (BREEAM Hea 01's mean, median, minimum,
//! uniformity and share reaching a target).

/// The illuminances EN 17037 asks a share of the area to reach, lx.
pub const EN17037_TARGETS: [f64; 3] = [300.0, 500.0, 750.0];

/// The daylight factor BREEAM Hea 01 asks for, percent.
pub const DEFAULT_DF_TARGET: f64 = 2.0;

/// The quantity a grid's values are.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GridQuantity {
    /// Illuminance, lx; `daylight` adds the shares reaching
    /// [`EN17037_TARGETS`].
    Illuminance {
        /// The scene is lit by daylight.
        daylight: bool,
    },
    /// Daylight factor DF = 100 E / E_h, percent, under the CIE overcast
    /// sky.
    DaylightFactor {
        /// E_h, the sky's unobstructed horizontal illuminance, lx.
        sky_illuminance: f64,
        /// The DF a point should reach, percent.
        target: f64,
    },
}

/// Statistics of a grid's illuminance, lx, over its points inside the outline.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IlluminanceStatistics {
    /// Points counted.
    pub points: usize,
    /// Emin, Eavg, Emax, lx.
    pub minimum: f64,
    /// The arithmetic mean over the points.
    pub average: f64,
    /// The largest value.
    pub maximum: f64,
}

impl IlluminanceStatistics {
    /// The statistics of the finite values of `lux` (NaN marks points
    /// outside the outline); `None` when there are none.
    #[must_use]
    pub fn of(lux: &[f64]) -> Option<IlluminanceStatistics> {
        let finite: Vec<f64> = lux.iter().copied().filter(|e| e.is_finite()).collect();
        if finite.is_empty() {
            return None;
        }
        Some(IlluminanceStatistics {
            points: finite.len(),
            minimum: finite.iter().copied().fold(f64::INFINITY, f64::min),
            average: finite.iter().sum::<f64>() / finite.len() as f64,
            maximum: finite.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        })
    }

    /// Uniformity U₀ = Emin / Eavg (EN 12464-1); 0 when Eavg is 0.
    #[must_use]
    pub fn uniformity(&self) -> f64 {
        ratio(self.minimum, self.average)
    }

    /// Diversity Emin / Emax; 0 when Emax is 0.
    #[must_use]
    pub fn diversity(&self) -> f64 {
        ratio(self.minimum, self.maximum)
    }
}

fn ratio(a: f64, b: f64) -> f64 {
    if b > 0.0 { a / b } else { 0.0 }
}

/// Statistics of a grid's values over its counted points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridStatistics {
    /// Minimum, mean and maximum.
    pub extremes: IlluminanceStatistics,
    /// The median (the mean of the middle two for an even count).
    pub median: f64,
}

impl GridStatistics {
    /// The statistics of the finite values; `None` when there are none.
    #[must_use]
    pub fn of(values: &[f64]) -> Option<GridStatistics> {
        let extremes = IlluminanceStatistics::of(values)?;
        let mut finite: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
        finite.sort_by(f64::total_cmp);
        let n = finite.len();
        let median = if n % 2 == 1 {
            finite[n / 2]
        } else {
            (finite[n / 2 - 1] + finite[n / 2]) / 2.0
        };
        Some(GridStatistics { extremes, median })
    }
}

/// The share (0 to 1) of the finite values at or above `target`.
#[must_use]
pub fn share_reaching(values: &[f64], target: f64) -> f64 {
    let finite = values.iter().filter(|v| v.is_finite()).count();
    if finite == 0 {
        return 0.0;
    }
    values
        .iter()
        .filter(|v| v.is_finite() && **v >= target)
        .count() as f64
        / finite as f64
}

impl GridQuantity {
    /// The CSV column of the values.
    #[must_use]
    pub fn column(&self) -> &'static str {
        match self {
            GridQuantity::Illuminance { .. } => "illuminance_lux",
            GridQuantity::DaylightFactor { .. } => "daylight_factor_percent",
        }
    }

    /// The values' unit: "lx" or "%".
    #[must_use]
    pub fn unit(&self) -> &'static str {
        match self {
            GridQuantity::Illuminance { .. } => "lx",
            GridQuantity::DaylightFactor { .. } => "%",
        }
    }

    /// The statistics of `values` as `name = value` lines.
    #[must_use]
    pub fn statistics_lines(&self, values: &[f64]) -> Vec<String> {
        let Some(stats) = GridStatistics::of(values) else {
            return vec!["points = 0".into()];
        };
        let e = stats.extremes;
        let mut lines = vec![format!("points = {}", e.points)];
        match *self {
            GridQuantity::Illuminance { daylight } => {
                lines.extend([
                    format!("Emin = {:.6} lx", e.minimum),
                    format!("Eavg = {:.6} lx", e.average),
                    format!("Emax = {:.6} lx", e.maximum),
                    format!("U0 = Emin/Eavg = {:.6}", e.uniformity()),
                    format!("Emin/Emax = {:.6}", e.diversity()),
                ]);
                if daylight {
                    lines.push(format!("Emedian = {:.6} lx", stats.median));
                    for target in EN17037_TARGETS {
                        let share = 100.0 * share_reaching(values, target);
                        lines.push(format!("share >= {target} lx = {share:.2} %"));
                    }
                }
            }
            GridQuantity::DaylightFactor {
                sky_illuminance,
                target,
            } => {
                let share = 100.0 * share_reaching(values, target);
                lines.extend([
                    "sky = CIE standard overcast".into(),
                    format!("Eh = {sky_illuminance:.6} lx"),
                    format!("DFmin = {:.6} %", e.minimum),
                    format!("DFavg = {:.6} %", e.average),
                    format!("DFmedian = {:.6} %", stats.median),
                    format!("DFmax = {:.6} %", e.maximum),
                    format!("U0 = DFmin/DFavg = {:.6}", e.uniformity()),
                    format!("share >= {target} % = {share:.2} %"),
                ]);
            }
        }
        lines
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_and_shares_count_finite_values_only() {
        let values = [1.0, f64::NAN, 3.0, 2.0, 4.0];
        let stats = GridStatistics::of(&values).unwrap();
        assert_eq!(stats.median, 2.5);
        assert_eq!(GridStatistics::of(&[5.0, 1.0, 3.0]).unwrap().median, 3.0);
        assert_eq!(share_reaching(&values, 2.0), 0.75);
        assert_eq!(share_reaching(&[f64::NAN], 2.0), 0.0);
        let lines = GridQuantity::DaylightFactor {
            sky_illuminance: 10_000.0,
            target: 2.0,
        }
        .statistics_lines(&values);
        assert!(
            lines.contains(&"DFmedian = 2.500000 %".to_string()),
            "{lines:?}"
        );
        assert!(
            lines.contains(&"share >= 2 % = 75.00 %".to_string()),
            "{lines:?}"
        );
    }
}
