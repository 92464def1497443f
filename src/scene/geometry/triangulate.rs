//! Ear-clipping triangulation of simple planar polygons, in plane coordinates.
//!
//! Used by the loaders to split non-planar faces, and by the meshers for
//! n-gons. The input may be convex or not, clockwise or counter-clockwise,
//! and may carry collinear or repeated vertices; self-intersecting input
//! gets a best-effort answer, never a panic or an endless loop.

use glam::DVec2;

/// Relative tolerance on cross products, in units of the polygon's squared size.
const CROSS_TOLERANCE: f64 = 1e-12;

/// Twice the signed area of the triangle (a, b, c): positive when it turns
/// counter-clockwise, (b − a) × (c − a).
#[must_use]
fn cross(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    (b - a).perp_dot(c - a)
}

/// Signed area of a polygon by the shoelace formula,
/// A = ½ Σ (x_i y_{i+1} − x_{i+1} y_i): positive when counter-clockwise.
#[must_use]
pub fn signed_area_2d(points: &[DVec2]) -> f64 {
    let Some(&base) = points.first() else {
        return 0.0;
    };
    let n = points.len();
    let twice: f64 = (0..n)
        .map(|i| (points[i] - base).perp_dot(points[(i + 1) % n] - base))
        .sum();
    0.5 * twice
}

/// Triangulates a simple polygon by ear clipping.
///
/// Returns index triples into `points`, one per triangle, with the same
/// winding as the polygon (counter-clockwise triangles for a
/// counter-clockwise polygon, clockwise ones for a clockwise polygon). A
/// simple polygon of n vertices without collinear runs gives n − 2
/// triangles whose areas sum to the polygon's area.
///
/// Robustness:
/// - collinear vertices are kept when an ear can use them; when no ear
///   exists, a collinear vertex (zero-area corner) is dropped without a
///   triangle, which keeps the area exact;
/// - on self-intersecting input, when no ear remains, the most convex corner
///   is clipped regardless of containment: every step removes a vertex, so
///   the loop always ends, but triangles may overlap;
/// - fewer than three points, a non-finite coordinate or zero total area
///   give an empty list.
///
/// # References
/// Meisters, "Polygons have ears", *American Mathematical Monthly* 82 (1975);
/// Eberly, "Triangulation by Ear Clipping", Geometric Tools (2002).
#[must_use]
pub fn triangulate_polygon(points: &[DVec2]) -> Vec<[usize; 3]> {
    let n = points.len();
    if n < 3 || points.iter().any(|p| !p.is_finite()) {
        return Vec::new();
    }
    // Scale for tolerances: the bounding box diagonal.
    let (min, max) = points.iter().fold((points[0], points[0]), |(lo, hi), &p| {
        (lo.min(p), hi.max(p))
    });
    let eps = CROSS_TOLERANCE * (max - min).length_squared();
    let area = signed_area_2d(points);
    if area.is_nan() || area.abs() <= eps {
        return Vec::new();
    }
    if n == 3 {
        return vec![[0, 1, 2]];
    }
    // Work on a counter-clockwise ring of indices.
    let ring: Vec<usize> = if area > 0.0 {
        (0..n).collect()
    } else {
        (0..n).rev().collect()
    };
    let mut triangles = clip_ears(points, ring, eps);
    // Give the triangles the input's winding.
    if area < 0.0 {
        for t in &mut triangles {
            t.swap(1, 2);
        }
    }
    triangles
}

/// Ear clipping on a counter-clockwise ring of indices into `points`.
fn clip_ears(points: &[DVec2], mut ring: Vec<usize>, eps: f64) -> Vec<[usize; 3]> {
    let mut triangles = Vec::with_capacity(ring.len().saturating_sub(2));
    let mut i = 0;
    let mut misses = 0;
    while ring.len() > 3 {
        let m = ring.len();
        i %= m;
        if is_ear(points, &ring, i, eps) {
            // Clip the ear and step back to re-examine the previous corner.
            triangles.push(corner(&ring, i));
            ring.remove(i);
            i = (i + ring.len() - 1) % ring.len();
            misses = 0;
        } else {
            i += 1;
            misses += 1;
        }
        if misses >= m {
            // A full turn without an ear: remove a vertex anyway, so the loop ends.
            remove_without_ear(points, &mut ring, &mut triangles, eps);
            misses = 0;
        }
    }
    // The last triangle, unless it is degenerate.
    if ring.len() == 3 {
        let [a, b, c] = corner(&ring, 1);
        if cross(points[a], points[b], points[c]) > eps {
            triangles.push([a, b, c]);
        }
    }
    triangles
}

/// The indices (previous, current, next) of corner `i` of the ring.
fn corner(ring: &[usize], i: usize) -> [usize; 3] {
    let m = ring.len();
    [ring[(i + m - 1) % m], ring[i], ring[(i + 1) % m]]
}

/// True when corner `i` is strictly convex and no other reflex or collinear
/// vertex of the ring lies inside or on its triangle.
fn is_ear(points: &[DVec2], ring: &[usize], i: usize, eps: f64) -> bool {
    let [ia, ib, ic] = corner(ring, i);
    let (a, b, c) = (points[ia], points[ib], points[ic]);
    if cross(a, b, c) <= eps {
        return false;
    }
    let m = ring.len();
    (0..m).all(|j| {
        let [jp, jv, jn] = corner(ring, j);
        let p = points[jv];
        // Only non-convex vertices can block an ear of a simple polygon;
        // a vertex repeating a corner's position does not block it either.
        jv == ia
            || jv == ib
            || jv == ic
            || p == a
            || p == b
            || p == c
            || cross(points[jp], p, points[jn]) > eps
            || !in_triangle(a, b, c, p, eps)
    })
}

/// True when p is inside or on the counter-clockwise triangle (a, b, c).
fn in_triangle(a: DVec2, b: DVec2, c: DVec2, p: DVec2, eps: f64) -> bool {
    cross(a, b, p) >= -eps && cross(b, c, p) >= -eps && cross(c, a, p) >= -eps
}

/// Fallback when no corner is an ear: drop a collinear corner (no area
/// lost), else clip the most convex corner (self-intersecting input), else
/// drop the first corner.
fn remove_without_ear(
    points: &[DVec2],
    ring: &mut Vec<usize>,
    triangles: &mut Vec<[usize; 3]>,
    eps: f64,
) {
    let crosses: Vec<f64> = (0..ring.len())
        .map(|i| {
            let [a, b, c] = corner(ring, i);
            cross(points[a], points[b], points[c])
        })
        .collect();
    if let Some(i) = crosses.iter().position(|x| x.abs() <= eps) {
        ring.remove(i);
        return;
    }
    let best = crosses
        .iter()
        .enumerate()
        .max_by(|x, y| x.1.total_cmp(y.1))
        .map_or(0, |(i, _)| i);
    if crosses[best] > eps {
        triangles.push(corner(ring, best));
    }
    ring.remove(best);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// SplitMix64: a small seeded generator for property-style tests.
    struct Rng(u64);

    impl Rng {
        fn next_f64(&mut self) -> f64 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^= z >> 31;
            (z >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    fn triangle_area(points: &[DVec2], t: [usize; 3]) -> f64 {
        0.5 * cross(points[t[0]], points[t[1]], points[t[2]])
    }

    /// Even-odd point-in-polygon test.
    fn inside(polygon: &[DVec2], p: DVec2) -> bool {
        let n = polygon.len();
        let mut inside = false;
        for i in 0..n {
            let (a, b) = (polygon[i], polygon[(i + 1) % n]);
            if (a.y > p.y) != (b.y > p.y) {
                let x = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
                if p.x < x {
                    inside = !inside;
                }
            }
        }
        inside
    }

    /// Checks a triangulation of a simple polygon: n − 2 triangles when
    /// `full`, the polygon's winding, areas summing to its area, and every
    /// triangle's centroid inside the polygon.
    fn check(points: &[DVec2], full: bool) {
        let triangles = triangulate_polygon(points);
        let area = signed_area_2d(points);
        if full {
            assert_eq!(triangles.len(), points.len() - 2, "{points:?}");
        }
        let mut sum = 0.0;
        for &t in &triangles {
            assert!(t.iter().all(|&i| i < points.len()));
            assert!(t[0] != t[1] && t[1] != t[2] && t[0] != t[2]);
            let a = triangle_area(points, t);
            assert!(a * area > 0.0, "triangle {t:?} has the wrong winding");
            let centroid = (points[t[0]] + points[t[1]] + points[t[2]]) / 3.0;
            assert!(inside(points, centroid), "triangle {t:?} outside");
            sum += a;
        }
        assert!(
            (sum - area).abs() <= 1e-9 * area.abs(),
            "areas sum to {sum}, polygon {area}"
        );
    }

    fn reversed(points: &[DVec2]) -> Vec<DVec2> {
        points.iter().rev().copied().collect()
    }

    fn star(rng: &mut Rng, n: usize) -> Vec<DVec2> {
        // Strictly increasing angles, random radii: star-shaped about the origin.
        let mut angles: Vec<f64> = (0..n)
            .map(|k| (k as f64 + 0.1 + 0.8 * rng.next_f64()) / n as f64)
            .collect();
        angles.sort_by(f64::total_cmp);
        angles
            .iter()
            .map(|t| {
                let r = 0.2 + 0.8 * rng.next_f64();
                DVec2::from_angle(std::f64::consts::TAU * t) * r
            })
            .collect()
    }

    fn comb(teeth: usize, depth: f64) -> Vec<DVec2> {
        // Base along y = 0, teeth pointing up between x = 2k and 2k + 1.
        let mut p = vec![DVec2::new(0.0, -1.0), DVec2::new(2.0 * teeth as f64, -1.0)];
        for k in (0..teeth).rev() {
            let x = 2.0 * k as f64;
            p.push(DVec2::new(x + 2.0, 0.0));
            p.push(DVec2::new(x + 1.0, depth));
            p.push(DVec2::new(x + 0.5, depth));
        }
        p.push(DVec2::new(0.0, 0.0));
        p
    }

    #[test]
    fn convex_and_simple_shapes() {
        let square = [
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(0.0, 1.0),
        ];
        check(&square, true);
        check(&reversed(&square), true);
        let l_shape: Vec<DVec2> = [(0., 0.), (2., 0.), (2., 1.), (1., 1.), (1., 2.), (0., 2.)]
            .iter()
            .map(|&(x, y)| DVec2::new(x, y))
            .collect();
        check(&l_shape, true);
        check(&reversed(&l_shape), true);
    }

    #[test]
    fn random_star_polygons_both_windings() {
        let mut rng = Rng(7);
        for trial in 0..300 {
            let n = 3 + trial % 40;
            let p = star(&mut rng, n);
            check(&p, true);
            check(&reversed(&p), true);
            // Far from the origin and large: tolerances are relative.
            let far: Vec<DVec2> = p.iter().map(|&q| q * 1e4 + DVec2::new(3e6, -2e6)).collect();
            check(&far, true);
        }
    }

    #[test]
    fn combs_and_spirals() {
        for teeth in 1..20 {
            let p = comb(teeth, 0.5 + teeth as f64);
            check(&p, true);
            check(&reversed(&p), true);
        }
        // A square spiral corridor: many reflex vertices.
        let spiral: Vec<DVec2> = [
            (0., 0.),
            (6., 0.),
            (6., 6.),
            (1., 6.),
            (1., 2.),
            (4., 2.),
            (4., 4.),
            (3., 4.),
            (3., 3.),
            (2., 3.),
            (2., 5.),
            (5., 5.),
            (5., 1.),
            (0., 1.),
        ]
        .iter()
        .map(|&(x, y)| DVec2::new(x, y))
        .collect();
        check(&spiral, true);
        check(&reversed(&spiral), true);
    }

    #[test]
    fn collinear_and_repeated_vertices() {
        // A rectangle with five extra points on its bottom edge.
        let mut p: Vec<DVec2> = (0..=6).map(|k| DVec2::new(k as f64, 0.0)).collect();
        p.push(DVec2::new(6.0, 1.0));
        p.push(DVec2::new(0.0, 1.0));
        check(&p, true);
        check(&reversed(&p), true);
        // A triangle with a midpoint on every edge.
        let t: Vec<DVec2> = [(0., 0.), (1., 0.), (2., 0.), (1.5, 1.), (1., 2.), (0.5, 1.)]
            .iter()
            .map(|&(x, y)| DVec2::new(x, y))
            .collect();
        check(&t, false);
        // A repeated vertex: area still exact.
        let mut d = p.clone();
        d.insert(3, d[3]);
        check(&d, false);
    }

    #[test]
    fn degenerate_input_gives_nothing() {
        assert!(triangulate_polygon(&[]).is_empty());
        assert!(triangulate_polygon(&[DVec2::ZERO, DVec2::X]).is_empty());
        let line = [
            DVec2::ZERO,
            DVec2::X,
            DVec2::new(2.0, 0.0),
            DVec2::new(3.0, 0.0),
        ];
        assert!(triangulate_polygon(&line).is_empty());
        let nan = [DVec2::ZERO, DVec2::X, DVec2::new(f64::NAN, 1.0)];
        assert!(triangulate_polygon(&nan).is_empty());
        assert_eq!(
            triangulate_polygon(&[DVec2::ZERO, DVec2::Y, DVec2::X]),
            vec![[0, 1, 2]]
        );
    }

    #[test]
    fn self_intersecting_input_terminates() {
        let bow_tie = [
            DVec2::new(0.0, 0.0),
            DVec2::new(2.0, 2.0),
            DVec2::new(2.0, 0.0),
            DVec2::new(0.0, 3.0),
        ];
        let t = triangulate_polygon(&bow_tie);
        assert!(t.len() <= 2);
        // Random point soups: valid indices, bounded output, no panic.
        let mut rng = Rng(11);
        for trial in 0..200 {
            let n = 3 + trial % 30;
            let p: Vec<DVec2> = (0..n)
                .map(|_| DVec2::new(rng.next_f64(), rng.next_f64()))
                .collect();
            let t = triangulate_polygon(&p);
            assert!(t.len() <= n - 2);
            assert!(t.iter().flatten().all(|&i| i < n));
        }
    }
}
