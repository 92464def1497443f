//! Point queries on polygons in plane coordinates.

use glam::DVec2;

/// Even-odd test: is `p` inside the polygon?
#[must_use]
pub fn polygon_contains(polygon: &[DVec2], p: DVec2) -> bool {
    let mut inside = false;
    for k in 0..polygon.len() {
        let (a, b) = (polygon[k], polygon[(k + 1) % polygon.len()]);
        if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x) {
            inside = !inside;
        }
    }
    inside
}

/// Distance from `p` to the polygon's boundary.
#[must_use]
pub fn distance_to_boundary(polygon: &[DVec2], p: DVec2) -> f64 {
    (0..polygon.len())
        .map(|k| distance_to_segment(p, polygon[k], polygon[(k + 1) % polygon.len()]))
        .fold(f64::INFINITY, f64::min)
}

/// Distance from `p` to the segment ab (to a when a = b).
#[must_use]
pub fn distance_to_segment(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    p.distance(a + (b - a) * segment_parameter(p, a, b))
}

/// The parameter t in [0, 1] of the point a + t (b − a) of the segment ab
/// nearest `p` (0 when a = b).
#[must_use]
pub fn segment_parameter(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    ((p - a).dot(b - a) / (b - a).length_squared().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0)
}

/// The part of a segment inside a polygon (counter-clockwise, simple),
/// assuming it is one piece: the segment's parameter range between its first
/// entry and last exit. `None` when it misses the polygon.
#[must_use]
pub fn clip_segment_to_polygon(ends: [DVec2; 2], polygon: &[DVec2]) -> Option<[DVec2; 2]> {
    let [a, b] = ends;
    let inside = |p: DVec2| polygon_contains(polygon, p);
    // Parameters where the segment crosses the polygon's edges, plus its ends.
    let mut cuts = vec![0.0, 1.0];
    for k in 0..polygon.len() {
        let (p, q) = (polygon[k], polygon[(k + 1) % polygon.len()]);
        let denominator = (b - a).perp_dot(q - p);
        if denominator.abs() <= f64::MIN_POSITIVE {
            continue;
        }
        let t = (p - a).perp_dot(q - p) / denominator;
        let s = (p - a).perp_dot(b - a) / denominator;
        if (0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&s) {
            cuts.push(t);
        }
    }
    cuts.sort_by(f64::total_cmp);
    // Keep the pieces whose middle is inside (or on the boundary).
    let mut range: Option<(f64, f64)> = None;
    for pair in cuts.windows(2) {
        let middle = a.lerp(b, 0.5 * (pair[0] + pair[1]));
        if pair[1] > pair[0]
            && (inside(middle) || distance_to_boundary(polygon, middle) < 1e-9 * (b - a).length())
        {
            range = Some(range.map_or((pair[0], pair[1]), |(lo, _)| (lo, pair[1])));
        }
    }
    range.map(|(lo, hi)| [a.lerp(b, lo), a.lerp(b, hi)])
}

/// An L-shaped hexagon, the unit squares at (0, 0), (1, 0) and (0, 1),
/// counter-clockwise: the unit tests' non-convex polygon.
#[cfg(test)]
pub(crate) const L_SHAPE: [DVec2; 6] = [
    DVec2::new(0.0, 0.0),
    DVec2::new(2.0, 0.0),
    DVec2::new(2.0, 1.0),
    DVec2::new(1.0, 1.0),
    DVec2::new(1.0, 2.0),
    DVec2::new(0.0, 2.0),
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn l_shape() {
        let l = L_SHAPE;
        assert!(polygon_contains(&l, DVec2::new(0.5, 1.5)));
        assert!(!polygon_contains(&l, DVec2::new(1.5, 1.5)));
        assert!((distance_to_boundary(&l, DVec2::new(1.5, 1.5)) - 0.5).abs() < 1e-15);
        assert!((distance_to_boundary(&l, DVec2::new(0.5, 0.25)) - 0.25).abs() < 1e-15);
    }
}
