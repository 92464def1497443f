//! How well a mesh's piecewise-linear interpolation reproduces a field.

use glam::DVec2;

use super::constrained::PlaneTriangulation;
use crate::scene::polygon_contains;

/// The error of a mesh's Gouraud (piecewise-linear) interpolation against
/// the exact field, over a dense uniform grid of points inside the polygon.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InterpolationError {
    /// √mean((B_h − B)²) / √mean(B²): error energy over signal energy, what
    /// a viewer sees.
    pub rms_rel_error: f64,
    /// max |B_h − B| / max B.
    pub max_rel_error: f64,
    /// Grid points inside the polygon (and inside a triangle) that were compared.
    pub samples: usize,
}

/// Measures the interpolation error of `values` (one per triangulation
/// point) against `exact`, at the centres of a `grid` × `grid` lattice over
/// the polygon's bounding box, keeping the points inside the polygon.
/// Each point is interpolated in the triangle containing it.
#[must_use]
pub fn interpolation_error(
    outline: &[DVec2],
    triangulation: &PlaneTriangulation,
    values: &[f64],
    exact: &(dyn Fn(DVec2) -> f64 + Sync),
    grid: usize,
) -> InterpolationError {
    let grid = grid.max(2);
    let (min, max) = outline.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    let step = (max - min) / grid as f64;
    let cell = |p: DVec2| ((p - min) / step).floor();
    // Interpolated value at each grid point, by scanning each triangle's box.
    let mut interpolated: Vec<Option<f64>> = vec![None; grid * grid];
    let points = &triangulation.points;
    for &[a, b, c] in &triangulation.triangles {
        let (pa, pb, pc) = (points[a], points[b], points[c]);
        let twice_area = (pb - pa).perp_dot(pc - pa);
        if twice_area.abs() <= f64::MIN_POSITIVE {
            continue;
        }
        let lo = cell(pa.min(pb).min(pc)).max(DVec2::ZERO);
        let hi = cell(pa.max(pb).max(pc)).min(DVec2::splat((grid - 1) as f64));
        for j in lo.y as usize..=hi.y as usize {
            for i in lo.x as usize..=hi.x as usize {
                let p = min + step * DVec2::new(i as f64 + 0.5, j as f64 + 0.5);
                let wa = (pc - pb).perp_dot(p - pb) / twice_area;
                let wb = (pa - pc).perp_dot(p - pc) / twice_area;
                let wc = 1.0 - wa - wb;
                if wa >= -1e-12 && wb >= -1e-12 && wc >= -1e-12 {
                    interpolated[j * grid + i] =
                        Some(wa * values[a] + wb * values[b] + wc * values[c]);
                }
            }
        }
    }
    // Accumulate the error over the points inside the polygon.
    let (mut error_sq, mut signal_sq, mut max_error, mut max_value, mut samples) =
        (0.0, 0.0, 0.0f64, 0.0f64, 0);
    for j in 0..grid {
        for i in 0..grid {
            let p = min + step * DVec2::new(i as f64 + 0.5, j as f64 + 0.5);
            let Some(shown) = interpolated[j * grid + i] else {
                continue;
            };
            if !polygon_contains(outline, p) {
                continue;
            }
            let truth = exact(p);
            error_sq += (shown - truth).powi(2);
            signal_sq += truth * truth;
            max_error = max_error.max((shown - truth).abs());
            max_value = max_value.max(truth.abs());
            samples += 1;
        }
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
        samples,
    }
}
