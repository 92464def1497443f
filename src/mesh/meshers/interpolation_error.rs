//! How well a mesh's piecewise-linear interpolation reproduces a field.

use glam::DVec2;
use rayon::prelude::*;

use super::constrained::PlaneTriangulation;
use crate::scene::polygon_contains;

/// Points below this fraction of the field's maximum are left out of the
/// mean relative error (as the golden-image tests leave out dark pixels).
const MEAN_FLOOR: f64 = 0.01;

/// The error of a mesh's Gouraud (piecewise-linear) interpolation against
/// the exact field, over a dense uniform grid of points inside the polygon.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InterpolationError {
    /// √mean((B_h − B)²) / √mean(B²): error energy over signal energy, what
    /// a viewer sees.
    pub rms_rel_error: f64,
    /// max |B_h − B| / max B.
    pub max_rel_error: f64,
    /// mean |B_h − B| / B over the points where B is above 1 % of its
    /// maximum: the relative difference a viewer sees in a tone-mapped
    /// image, which the RMS figure hides in the dim periphery.
    pub mean_rel_error: f64,
    /// Grid points inside the polygon (and inside a triangle) that were compared.
    pub samples: usize,
}

/// The exact field at the centres of an n × n lattice over a polygon's
/// bounding box, for the points inside the polygon: computed once, then
/// compared with any number of meshes.
#[derive(Clone, Debug, PartialEq)]
pub struct ErrorGrid {
    min: DVec2,
    step: DVec2,
    n: usize,
    /// The exact value at each lattice point inside the polygon.
    exact: Vec<Option<f64>>,
}

impl ErrorGrid {
    /// Evaluates `exact` (in parallel) at the n × n lattice points inside
    /// `outline`. A point where `exact` is NaN is left out (a point inside
    /// an object standing on the receiver, where no mesh has elements).
    #[must_use]
    pub fn new(outline: &[DVec2], n: usize, exact: &(dyn Fn(DVec2) -> f64 + Sync)) -> ErrorGrid {
        let n = n.max(2);
        let (min, max) = outline.iter().fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(lo, hi), &p| (lo.min(p), hi.max(p)),
        );
        let step = (max - min) / n as f64;
        let exact = (0..n * n)
            .into_par_iter()
            .map(|k| {
                let p = min + step * DVec2::new((k % n) as f64 + 0.5, (k / n) as f64 + 0.5);
                polygon_contains(outline, p)
                    .then(|| exact(p))
                    .filter(|value| !value.is_nan())
            })
            .collect();
        ErrorGrid {
            min,
            step,
            n,
            exact,
        }
    }

    /// The error of `values` (one per triangulation point) interpolated over
    /// the triangulation, against the exact field. Each lattice point is
    /// interpolated in the triangle containing it.
    #[must_use]
    pub fn measure(
        &self,
        triangulation: &PlaneTriangulation,
        values: &[f64],
    ) -> InterpolationError {
        let interpolated = self.interpolate(triangulation, values);
        let peak = self.exact.iter().flatten().copied().fold(0.0, f64::max);
        let (mut relative_sum, mut relative_count) = (0.0, 0usize);
        let (mut error_sq, mut signal_sq, mut max_error, mut max_value, mut samples) =
            (0.0, 0.0, 0.0f64, 0.0f64, 0);
        for (shown, truth) in interpolated.iter().zip(&self.exact) {
            let (Some(shown), Some(truth)) = (shown, truth) else {
                continue;
            };
            error_sq += (shown - truth).powi(2);
            signal_sq += truth * truth;
            max_error = max_error.max((shown - truth).abs());
            max_value = max_value.max(truth.abs());
            if *truth > MEAN_FLOOR * peak {
                relative_sum += (shown - truth).abs() / truth;
                relative_count += 1;
            }
            samples += 1;
        }
        InterpolationError {
            rms_rel_error: if signal_sq > 0.0 {
                (error_sq / signal_sq).sqrt()
            } else {
                0.0
            },
            max_rel_error: if max_value > 0.0 {
                max_error / max_value
            } else {
                0.0
            },
            mean_rel_error: if relative_count > 0 {
                relative_sum / relative_count as f64
            } else {
                0.0
            },
            samples,
        }
    }

    /// The interpolated value at each lattice point, scanning each
    /// triangle's bounding box.
    fn interpolate(&self, triangulation: &PlaneTriangulation, values: &[f64]) -> Vec<Option<f64>> {
        let n = self.n;
        let cell = |p: DVec2| ((p - self.min) / self.step).floor();
        let mut interpolated: Vec<Option<f64>> = vec![None; n * n];
        let points = &triangulation.points;
        for &[a, b, c] in &triangulation.triangles {
            let (pa, pb, pc) = (points[a], points[b], points[c]);
            let twice_area = (pb - pa).perp_dot(pc - pa);
            if twice_area.abs() <= f64::MIN_POSITIVE {
                continue;
            }
            let lo = cell(pa.min(pb).min(pc)).max(DVec2::ZERO);
            let hi = cell(pa.max(pb).max(pc)).min(DVec2::splat((n - 1) as f64));
            if lo.x > hi.x || lo.y > hi.y {
                continue;
            }
            for j in lo.y as usize..=hi.y as usize {
                for i in lo.x as usize..=hi.x as usize {
                    let p = self.min + self.step * DVec2::new(i as f64 + 0.5, j as f64 + 0.5);
                    let wa = (pc - pb).perp_dot(p - pb) / twice_area;
                    let wb = (pa - pc).perp_dot(p - pc) / twice_area;
                    let wc = 1.0 - wa - wb;
                    if wa >= -1e-12 && wb >= -1e-12 && wc >= -1e-12 {
                        interpolated[j * n + i] =
                            Some(wa * values[a] + wb * values[b] + wc * values[c]);
                    }
                }
            }
        }
        interpolated
    }
}

/// Measures the interpolation error of `values` (one per triangulation
/// point) against `exact`, at the centres of a `grid` × `grid` lattice over
/// the polygon's bounding box, keeping the points inside the polygon. For
/// several meshes of one field, build an [`ErrorGrid`] once instead.
#[must_use]
pub fn interpolation_error(
    outline: &[DVec2],
    triangulation: &PlaneTriangulation,
    values: &[f64],
    exact: &(dyn Fn(DVec2) -> f64 + Sync),
    grid: usize,
) -> InterpolationError {
    ErrorGrid::new(outline, grid, exact).measure(triangulation, values)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_ten_percent_high_everywhere_err_by_ten_percent_on_average() {
        // B = 1 + x + 99 y on the unit square (1 to 101: every point above
        // 1 % of the maximum), two triangles carrying 1.1 B at the corners:
        // the interpolant is 1.1 B exactly, so |B_h − B| / B = 0.1.
        let square = [DVec2::ZERO, DVec2::X, DVec2::ONE, DVec2::Y];
        let triangulation = PlaneTriangulation {
            points: square.to_vec(),
            triangles: vec![[0, 1, 2], [0, 2, 3]],
        };
        let field = |p: DVec2| 1.0 + p.x + 99.0 * p.y;
        let values: Vec<f64> = square.iter().map(|&p| 1.1 * field(p)).collect();
        let error = interpolation_error(&square, &triangulation, &values, &field, 64);
        assert!((error.mean_rel_error - 0.1).abs() < 1e-9, "{error:?}");
        // The RMS figure weighs the bright top: also 0.1 here, as the error
        // is proportional everywhere.
        assert!((error.rms_rel_error - 0.1).abs() < 1e-9, "{error:?}");
    }

    #[test]
    fn the_mean_relative_error_leaves_out_points_below_one_percent_of_the_peak() {
        // B = y² · 1000 + 0.001: the bottom tenth of the square is below 1 %
        // of the peak; the corners carry B + 0.5, an error that is huge
        // relative to the dark bottom and small at the top.
        let square = [DVec2::ZERO, DVec2::X, DVec2::ONE, DVec2::Y];
        let triangulation = PlaneTriangulation {
            points: square.to_vec(),
            triangles: vec![[0, 1, 2], [0, 2, 3]],
        };
        let field = |p: DVec2| 1000.0 * p.y * p.y + 0.001;
        let values: Vec<f64> = square.iter().map(|&p| field(p) + 0.5).collect();
        let error = interpolation_error(&square, &triangulation, &values, &field, 100);
        // The interpolant is 1000 y + 0.501; over y in (0.1, 1], where B is
        // above 10, the mean of (y − y²)/y² is (ln 10 − 0.9)/0.9 = 1.558.
        // The points below (relative errors up to 500) are left out.
        assert!((error.mean_rel_error - 1.558).abs() < 0.05, "{error:?}");
    }
}
