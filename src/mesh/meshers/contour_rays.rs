//! The contour mesher's rays from the field's centre: sampled over the
//! polygon, and solved for where they cross a level.

use std::ops::Range;

use glam::DVec2;

use super::scalar_field::ScalarField;
use crate::scene::polygon_contains;

/// Samples per ray for the level rule and for bracketing.
const RAY_SAMPLES: usize = 96;

/// A ray from the centre, sampled, with its extent over the polygon.
pub(super) struct Ray {
    pub(super) origin: DVec2,
    pub(super) angle: f64,
    pub(super) direction: DVec2,
    /// Where the ray last leaves the polygon (None: it never meets it).
    pub(super) exit: Option<f64>,
    /// Where it first enters, when the centre is outside.
    pub(super) entry: f64,
    /// (t, B) samples from 0 to the exit.
    pub(super) samples: Vec<(f64, f64)>,
}

impl Ray {
    pub(super) fn new(outline: &[DVec2], origin: DVec2, angle: f64, field: &ScalarField) -> Ray {
        Ray::sampled(
            outline,
            origin,
            angle,
            field,
            0.0..f64::INFINITY,
            RAY_SAMPLES,
        )
    }

    /// A ray sampled at `count` + 1 points over `span` (clipped to where it
    /// leaves the polygon): a whole ray, or the stretch where a level is
    /// expected to cross.
    pub(super) fn sampled(
        outline: &[DVec2],
        origin: DVec2,
        angle: f64,
        field: &ScalarField,
        span: Range<f64>,
        count: usize,
    ) -> Ray {
        let direction = DVec2::new(angle.cos(), angle.sin());
        let crossings = ray_polygon_crossings(outline, origin, direction);
        let exit = crossings
            .iter()
            .copied()
            .fold(None, |m: Option<f64>, t| Some(m.map_or(t, |m| m.max(t))));
        let entry = if polygon_contains(outline, origin) {
            0.0
        } else {
            crossings.iter().copied().fold(f64::INFINITY, f64::min)
        };
        let samples = exit
            .map(|end| {
                let (start, stop) = (span.start.clamp(0.0, end), span.end.min(end));
                (0..=count)
                    .map(|i| start + (stop - start) * i as f64 / count as f64)
                    .map(|t| (t, field(origin + direction * t).0))
                    .collect()
            })
            .unwrap_or_default();
        Ray {
            origin,
            angle,
            direction,
            exit,
            entry,
            samples,
        }
    }

    pub(super) fn at(&self, t: f64) -> DVec2 {
        self.origin + self.direction * t
    }

    /// Solves B(c + t u) = level for t in (0, exit] by Newton's method on
    /// f(t) = B − level with f'(t) = ∇B·u, safeguarded by the bracket the
    /// samples give (a bisection step whenever Newton leaves it). Returns t
    /// and the iterations taken, or None when the level is not crossed.
    pub(super) fn solve(&self, field: &ScalarField, level: f64) -> Option<(f64, usize)> {
        // Bracket: the first sample interval where B drops through the level.
        let k = self
            .samples
            .windows(2)
            .position(|w| w[0].1 >= level && w[1].1 < level)?;
        let (mut lo, mut hi) = (self.samples[k].0, self.samples[k + 1].0);
        let (b_lo, b_hi) = (self.samples[k].1, self.samples[k + 1].1);
        let mut t = lo + (hi - lo) * (b_lo - level) / (b_lo - b_hi);
        let tolerance = 1e-9 * level.abs().max(f64::MIN_POSITIVE);
        for iteration in 1..=60 {
            let (value, gradient) = field(self.at(t));
            let f = value - level;
            if f.abs() <= tolerance {
                return Some((t, iteration));
            }
            if f > 0.0 {
                lo = t
            } else {
                hi = t
            }
            let slope = gradient.dot(self.direction);
            let newton = t - f / slope;
            t = if slope.is_finite() && slope != 0.0 && newton > lo && newton < hi {
                newton
            } else {
                0.5 * (lo + hi)
            };
            if hi - lo <= 1e-15 * hi.abs().max(1.0) {
                return Some((t, iteration));
            }
        }
        Some((t, 60))
    }
}

/// Parameters t ≥ 0 where the ray origin + t·direction crosses the polygon's edges.
fn ray_polygon_crossings(outline: &[DVec2], origin: DVec2, direction: DVec2) -> Vec<f64> {
    let mut crossings = Vec::new();
    for k in 0..outline.len() {
        let (p, q) = (outline[k], outline[(k + 1) % outline.len()]);
        let denominator = direction.perp_dot(q - p);
        if denominator.abs() <= f64::MIN_POSITIVE {
            continue;
        }
        let t = (p - origin).perp_dot(q - p) / denominator;
        let s = (p - origin).perp_dot(direction) / denominator;
        if t >= 0.0 && (0.0..=1.0).contains(&s) {
            crossings.push(t);
        }
    }
    crossings
}

/// Parameter along a→b where the segment crosses a ray, if it does strictly inside.
pub(super) fn segment_ray_crossing(a: DVec2, b: DVec2, ray: &Ray) -> Option<f64> {
    let denominator = ray.direction.perp_dot(b - a);
    if denominator.abs() <= f64::MIN_POSITIVE {
        return None;
    }
    let t = (a - ray.origin).perp_dot(b - a) / denominator;
    let s = (a - ray.origin).perp_dot(ray.direction) / denominator;
    (t > ray.entry && s > 0.0 && s < 1.0).then_some(s)
}
