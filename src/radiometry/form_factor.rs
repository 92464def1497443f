//! Point-to-area form factors: Wallace's disc kernel and Lambert's exact
//! polygon formula.

use glam::DVec3;
use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

/// Form factor from a differential receiver to a small source area, modelled
/// as a disc of area `source_area` (Wallace, Elmquist, Haines 1989, eq. 3.1 of
/// the seed paper):
///
/// ```text
///            A · cosθ_r · cosθ_s
///   F ≈  ─────────────────────────
///            π r² + A
/// ```
///
/// `cos_receiver` and `cos_source` are the cosines between each normal and
/// the line joining the two points; `distance_squared` is r². The `+ A` term
/// keeps the kernel bounded as r → 0 (it is exact for a coaxial parallel disc).
///
/// # References
/// J. R. Wallace, K. A. Elmquist, E. A. Haines, "A Ray Tracing Algorithm for
/// Progressive Radiosity", SIGGRAPH 1989.
#[must_use]
#[inline]
pub fn disc_form_factor(
    source_area: f64,
    cos_receiver: f64,
    cos_source: f64,
    distance_squared: f64,
) -> f64 {
    if cos_receiver <= 0.0 || cos_source <= 0.0 {
        return 0.0;
    }
    source_area * cos_receiver * cos_source / (PI * distance_squared + source_area)
}

/// Exact, unoccluded form factor from a differential area at `point` with unit
/// `normal` to a planar polygon (Lambert's formula):
///
/// ```text
///   F = 1/(2π) · Σ_e γ_e · n · (R_e × R_{e+1}) / |R_e × R_{e+1}|
/// ```
///
/// where R_e are unit vectors from the point to the polygon's vertices and
/// γ_e = angle(R_e, R_{e+1}). The polygon is first clipped to the half-space
/// in front of the receiver (n · (x − point) ≥ 0), so a source partly behind
/// the receiver's plane is handled. The result does not depend on the
/// polygon's winding; one-sidedness of the source is the caller's concern.
/// Edges whose end points coincide as seen from the point contribute nothing,
/// so points on or near the polygon's edges give finite values.
///
/// # References
/// J. H. Lambert, *Photometria* (1760); J. Arvo, "The Irradiance Jacobian for
/// Partially Occluded Polyhedral Sources", SIGGRAPH 1994 (eq. 1).
#[must_use]
pub fn polygon_form_factor(point: DVec3, normal: DVec3, polygon: &[DVec3]) -> f64 {
    with_clipped(point, normal, polygon, |clipped| {
        if clipped.len() < 3 {
            return 0.0;
        }
        let mut sum = 0.0;
        for i in 0..clipped.len() {
            let a = clipped[i] - point;
            let b = clipped[(i + 1) % clipped.len()] - point;
            let cross = a.cross(b);
            let cross_length = cross.length();
            // Coincident or collinear directions: the edge subtends no angle.
            if cross_length <= 1e-300 {
                continue;
            }
            let gamma = angle_from_sine_cosine(cross_length, a.dot(b));
            sum += gamma * normal.dot(cross) / cross_length;
        }
        (sum.abs() / (2.0 * PI)).min(1.0)
    })
}

/// tan(π/8): above it, atan(t) = π/4 + atan((t − 1)/(t + 1)).
const TAN_FRAC_PI_8: f64 = 0.414_213_562_373_095_03;

/// atan(t)/t as a polynomial in t² on |t| ≤ tan(π/8): a least-squares fit on
/// Chebyshev nodes, within 1e-15 of atan(t) there.
const ATAN_COEFFICIENTS: [f64; 10] = [
    0.999_999_999_999_998_9,
    -0.333_333_333_332_242_47,
    0.199_999_999_788_624_07,
    -0.142_857_126_890_905_35,
    0.111_110_496_662_216_34,
    -0.090_895_435_289_025_86,
    0.076_736_688_926_340_14,
    -0.065_067_486_815_382_57,
    0.050_271_322_541_548_21,
    -0.025_347_060_640_100_28,
];

/// The angle atan2(y, x) ∈ [0, π] for y ≥ 0 (a sine and a cosine times the
/// same positive length), to within 2e-15: reduced to atan(t) with
/// |t| ≤ tan(π/8) and a polynomial there. Lambert's formula needs one per
/// edge, and libm's general `atan2` would take about a sixth of the
/// solver's time.
#[inline]
fn angle_from_sine_cosine(y: f64, x: f64) -> f64 {
    let ax = x.abs();
    // atan of the smaller over the larger, in [0, π/4].
    let (small, large) = if y <= ax { (y, ax) } else { (ax, y) };
    if large == 0.0 {
        return 0.0;
    }
    let t = small / large;
    let (t, base) = if t > TAN_FRAC_PI_8 {
        ((t - 1.0) / (t + 1.0), FRAC_PI_4)
    } else {
        (t, 0.0)
    };
    let u = t * t;
    let polynomial = ATAN_COEFFICIENTS
        .iter()
        .rev()
        .fold(0.0, |sum, &c| sum * u + c);
    let octant = base + t * polynomial;
    let quadrant = if y <= ax { octant } else { FRAC_PI_2 - octant };
    if x < 0.0 { PI - quadrant } else { quadrant }
}

/// A polygon none of whose vertices rises above the receiver's plane by
/// more than this fraction of its farthest vertex's distance lies in that
/// plane (or behind it), to rounding.
const IN_PLANE: f64 = 1e-9;

/// Calls `body` with the polygon clipped to the half-space in front of the
/// receiver, n · (x − point) ≥ 0; with no vertex at all when it lies in
/// the receiver's plane or behind it (see [`IN_PLANE`]).
pub(super) fn with_clipped<R>(
    point: DVec3,
    normal: DVec3,
    polygon: &[DVec3],
    body: impl FnOnce(&[DVec3]) -> R,
) -> R {
    // Wholly behind, or lying in the receiver's plane: seen edge-on, it
    // subtends no projected solid angle. (Lambert's sum would give a point
    // inside a coplanar polygon F = 1, its limit from the front: a face
    // and its back-to-back twin would light each other fully.)
    let reach = polygon
        .iter()
        .map(|&p| (p - point).length())
        .fold(0.0, f64::max);
    if polygon
        .iter()
        .all(|&p| normal.dot(p - point) <= IN_PLANE * reach)
    {
        return body(&[]);
    }
    // Wholly in front (the usual case): nothing to clip.
    if polygon.iter().all(|&p| normal.dot(p - point) >= 0.0) {
        return body(polygon);
    }
    // Clipping adds at most one vertex per edge: a stack buffer serves the
    // cells the solver integrates, a heap one any larger polygon.
    let mut small = [DVec3::ZERO; 16];
    let mut large = Vec::new();
    let buffer: &mut [DVec3] = if 2 * polygon.len() <= small.len() {
        &mut small
    } else {
        large.resize(2 * polygon.len(), DVec3::ZERO);
        &mut large
    };
    let count = clip_to_half_space(point, normal, polygon, buffer);
    body(&buffer[..count])
}

/// Sutherland–Hodgman clip of a polygon to n · (x − point) ≥ 0. `out` must
/// hold twice the polygon's vertex count. Returns the vertices written.
fn clip_to_half_space(point: DVec3, normal: DVec3, polygon: &[DVec3], out: &mut [DVec3]) -> usize {
    let mut count = 0;
    let n = polygon.len();
    for i in 0..n {
        let a = polygon[i];
        let b = polygon[(i + 1) % n];
        let ha = normal.dot(a - point);
        let hb = normal.dot(b - point);
        if ha >= 0.0 {
            out[count] = a;
            count += 1;
        }
        if (ha >= 0.0) != (hb >= 0.0) {
            let t = ha / (ha - hb);
            out[count] = a + (b - a) * t;
            count += 1;
        }
    }
    count
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Parallel coaxial disc of radius R at height h, point at horizontal
    /// distance x (DESIGN.md).
    fn disc_reference(radius: f64, height: f64, x: f64) -> f64 {
        let (r2, h2, x2) = (radius * radius, height * height, x * x);
        0.5 * (1.0 - (x2 + h2 - r2) / ((x2 + h2 + r2).powi(2) - 4.0 * r2 * x2).sqrt())
    }

    fn regular_polygon(sides: usize, radius: f64, height: f64) -> Vec<DVec3> {
        (0..sides)
            .map(|k| {
                let a = 2.0 * PI * k as f64 / sides as f64;
                DVec3::new(radius * a.cos(), radius * a.sin(), height)
            })
            .collect()
    }

    #[test]
    fn polygon_matches_coaxial_disc() {
        let polygon = regular_polygon(256, 1.0, 2.0);
        // A 256-gon inscribed in the disc has area smaller by (1 − sin(2π/n)/(2π/n)) ≈ 1e-4.
        for x in [0.0, 0.5, 1.0, 2.0, 4.0] {
            let f = polygon_form_factor(DVec3::new(x, 0.0, 0.0), DVec3::Z, &polygon);
            let reference = disc_reference(1.0, 2.0, x);
            assert!(
                (f - reference).abs() < 3e-4 * reference,
                "x={x}: {f} vs {reference}"
            );
        }
    }

    #[test]
    fn a_polygon_in_the_receivers_plane_gives_nothing() {
        // A face and its back-to-back twin (a shade, a panel modelled each
        // way): a point of one lies inside the other, in its plane, tilted
        // and off the origin so that its heights are rounding noise. Seen
        // edge-on, it subtends nothing, whichever way the point faces;
        // raised clearly off the plane, it sees all of it from the front.
        let (u, v) = (DVec3::new(0.6, 0.3, -0.2), DVec3::new(-0.1, 0.5, 0.7));
        let normal = u.cross(v).normalize();
        let origin = DVec3::new(3.1, -1.7, 12.9);
        let polygon: Vec<DVec3> = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
            .iter()
            .map(|&(a, b)| origin + u * a + v * b)
            .collect();
        let inside = origin + u * 0.3 - v * 0.1;
        for facing in [normal, -normal] {
            assert_eq!(polygon_form_factor(inside, facing, &polygon), 0.0);
        }
        let above = polygon_form_factor(inside - normal * 1e-6, normal, &polygon);
        assert!((above - 1.0).abs() < 1e-4, "{above}");
    }

    #[test]
    fn winding_does_not_matter() {
        let mut polygon = regular_polygon(6, 1.0, 1.0);
        let p = DVec3::new(0.3, -0.2, 0.0);
        let f = polygon_form_factor(p, DVec3::Z, &polygon);
        polygon.reverse();
        assert!((f - polygon_form_factor(p, DVec3::Z, &polygon)).abs() < 1e-15);
    }

    #[test]
    fn perpendicular_wall_at_a_corner_sees_half() {
        // An unbounded wall x = 0 seen from a floor point just beside it: F → 1/2.
        let wall = [
            DVec3::new(0.0, -1e4, 0.0),
            DVec3::new(0.0, 1e4, 0.0),
            DVec3::new(0.0, 1e4, 1e4),
            DVec3::new(0.0, -1e4, 1e4),
        ];
        let f = polygon_form_factor(DVec3::new(1e-3, 0.0, 0.0), DVec3::Z, &wall);
        assert!((f - 0.5).abs() < 1e-3, "{f}");
    }

    #[test]
    fn clipped_source_behind_the_receiver_plane() {
        // A square straddling the receiver's plane: only its upper half counts.
        let square = [
            DVec3::new(-1.0, 2.0, -1.0),
            DVec3::new(1.0, 2.0, -1.0),
            DVec3::new(1.0, 2.0, 1.0),
            DVec3::new(-1.0, 2.0, 1.0),
        ];
        let upper = [
            DVec3::new(-1.0, 2.0, 0.0),
            DVec3::new(1.0, 2.0, 0.0),
            DVec3::new(1.0, 2.0, 1.0),
            DVec3::new(-1.0, 2.0, 1.0),
        ];
        let f = polygon_form_factor(DVec3::ZERO, DVec3::Z, &square);
        let g = polygon_form_factor(DVec3::ZERO, DVec3::Z, &upper);
        assert!(f > 0.0 && (f - g).abs() < 1e-15);
    }

    #[test]
    fn angle_matches_atan2() {
        // SplitMix64, so a failure reproduces.
        let mut state: u64 = 11;
        let mut random = || {
            state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut worst: f64 = 0.0;
        for k in 0..200_000 {
            // Lengths over many decades, both signs of the cosine.
            let scale = 10f64.powf(40.0 * random() - 20.0);
            let (y, x) = (random() * scale, (2.0 * random() - 1.0) * scale);
            let (y, x) = match k % 4 {
                0 => (y, x),
                1 => (y * 1e-9, x),
                2 => (y, x * 1e-9),
                _ => (y, -y * (1.0 + 1e-12 * random())),
            };
            worst = worst.max((angle_from_sine_cosine(y, x) - y.atan2(x)).abs());
        }
        assert!(worst < 2e-15, "{worst:e}");
        assert_eq!(angle_from_sine_cosine(0.0, 0.0), 0.0);
        assert_eq!(angle_from_sine_cosine(0.0, -1.0), PI);
        assert!((angle_from_sine_cosine(1.0, 0.0) - FRAC_PI_2).abs() < 1e-16);
    }

    #[test]
    fn disc_kernel_is_exact_on_axis() {
        // For a coaxial parallel disc the kernel reduces to A/(πh² + A) = R²/(h² + R²).
        let (radius, height) = (0.7, 1.3);
        let area = PI * radius * radius;
        let f = disc_form_factor(area, 1.0, 1.0, height * height);
        assert!((f - disc_reference(radius, height, 0.0)).abs() < 1e-14);
    }

    #[test]
    fn point_on_a_vertex_or_edge_is_finite() {
        let square = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 1.0),
            DVec3::new(0.0, 0.0, 1.0),
        ];
        for p in [DVec3::ZERO, DVec3::new(0.5, 0.0, 0.0)] {
            let f = polygon_form_factor(p, DVec3::Y, &square);
            assert!(f.is_finite() && (0.0..=1.0).contains(&f));
        }
    }
}
