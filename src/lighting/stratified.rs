//! Stratified points on planar polygons, for shadow rays and for estimating
//! a receiver's direct light.

use glam::DVec2;

use super::sample_stream::SampleStream;
use crate::scene::triangulate_polygon;

/// The golden ratio's fractional part: consecutive multiples of it spread
/// evenly over [0, 1) (a Kronecker sequence).
const GOLDEN_FRACTION: f64 = 0.618_033_988_749_894_9;

/// `count` points inside a polygon given in plane coordinates, each with the
/// area it stands for (the weights sum to the polygon's area).
///
/// The polygon is triangulated by ear clipping; the i-th point takes the
/// area coordinate a_i = (i + ξ)/count · A along the triangles' cumulative
/// areas (systematic sampling: each triangle gets its share of points, to
/// within one). Within its triangle (A, B, C) the point is
///
/// ```text
///   P = (1 − √s) A + √s (1 − t) B + √s t C
/// ```
///
/// where s is the point's position within the triangle's slice of a
/// (uniform on it, so the strips between consecutive points have equal
/// area) and t = frac(i φ + ξ′) with φ the golden ratio: stratified across
/// the strips and spread evenly along them. `shrink` ∈ [0, 1) pulls each
/// point that fraction of the way towards its triangle's centroid, keeping it
/// off the boundary. ξ, ξ′ come from `random`, so the points are
/// deterministic. Degenerate polygons (fewer than three points, zero area,
/// non-finite coordinates) give no points.
///
/// # References
/// J. Arvo, "Stratified Sampling of Spherical Triangles", SIGGRAPH 1995
/// (the √s map, in its planar form); P. Shirley, "Nonuniform Random Point
/// Sets via Warping", Graphics Gems III (1992).
pub fn stratified_points(
    polygon: &[DVec2],
    count: usize,
    shrink: f64,
    random: &mut SampleStream,
) -> Vec<(DVec2, f64)> {
    // Triangles and their cumulative areas.
    let triangles: Vec<[DVec2; 3]> = triangulate_polygon(polygon)
        .into_iter()
        .map(|[a, b, c]| [polygon[a], polygon[b], polygon[c]])
        .collect();
    let areas: Vec<f64> = triangles
        .iter()
        .map(|[a, b, c]| 0.5 * (*b - *a).perp_dot(*c - *a).abs())
        .collect();
    let total: f64 = areas.iter().sum();
    if count == 0 || !(total > 0.0 && total.is_finite()) {
        return Vec::new();
    }
    let weight = total / count as f64;
    let (xi, xi_along) = (random.next_f64(), random.next_f64());
    let mut points = Vec::with_capacity(count);
    let (mut triangle, mut below) = (0, 0.0);
    for i in 0..count {
        // Systematic position along the cumulative area; find its triangle.
        let a = (i as f64 + xi) * weight;
        while triangle + 1 < triangles.len() && a >= below + areas[triangle] {
            below += areas[triangle];
            triangle += 1;
        }
        let s = ((a - below) / areas[triangle].max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
        let t = (i as f64 * GOLDEN_FRACTION + xi_along).fract();
        let [pa, pb, pc] = triangles[triangle];
        let root = s.sqrt();
        let p = pa * (1.0 - root) + pb * (root * (1.0 - t)) + pc * (root * t);
        let centroid = (pa + pb + pc) / 3.0;
        points.push((p + (centroid - p) * shrink.clamp(0.0, 1.0), weight));
    }
    points
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::geometry::plane_polygon::L_SHAPE;
    use crate::scene::polygon_contains;

    #[test]
    fn points_lie_inside_and_weights_sum_to_the_area() {
        let l = L_SHAPE;
        for count in [1, 3, 16, 100] {
            let points = stratified_points(&l, count, 0.01, &mut SampleStream::new(1, 2));
            assert_eq!(points.len(), count);
            assert!(points.iter().all(|(p, _)| polygon_contains(&l, *p)));
            let area: f64 = points.iter().map(|(_, w)| w).sum();
            assert!((area - 3.0).abs() < 1e-12, "{area}");
        }
        // The mean of many points is the centroid of the L: (5/6, 5/6).
        let points = stratified_points(&l, 4000, 0.0, &mut SampleStream::new(3, 4));
        let mean = points.iter().map(|(p, _)| *p).sum::<DVec2>() / 4000.0;
        assert!((mean - DVec2::splat(5.0 / 6.0)).length() < 2e-3, "{mean}");
    }

    #[test]
    fn degenerate_polygons_give_no_points() {
        let mut random = SampleStream::new(0, 0);
        let line = [DVec2::ZERO, DVec2::X, DVec2::new(2.0, 0.0)];
        let nan = [DVec2::ZERO, DVec2::X, DVec2::new(f64::NAN, 1.0)];
        for polygon in [&[][..], &line[..], &nan[..]] {
            assert!(stratified_points(polygon, 8, 0.0, &mut random).is_empty());
        }
        assert!(stratified_points(&line[..2], 8, 0.0, &mut random).is_empty());
    }
}
