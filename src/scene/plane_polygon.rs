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
    let t = ((p - a).dot(b - a) / (b - a).length_squared().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
    p.distance(a + (b - a) * t)
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
