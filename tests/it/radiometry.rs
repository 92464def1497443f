//! Radiometry against analytic references: catalogue form factors, finite
//! differences of every analytic gradient, the seed's closed-form maximum.
//!
//! Run with `--nocapture` to see the worst agreement of each check.

use crate::support::Rng;
use glam::DVec3;
use isorad::radiometry::{
    DiscModel, ReceiverPlane, SmallDisc, polygon_form_factor, polygon_form_factor_gradient,
    polygon_form_factor_with_gradient, tilt_line_maximum,
};
use std::f64::consts::PI;

/// A star-shaped polygon (3 to 8 vertices, not always convex) of size about
/// `size` around `centre`, in a random plane.
fn random_polygon(rng: &mut Rng, centre: DVec3, size: f64) -> Vec<DVec3> {
    let (u, v) = rng.direction().any_orthonormal_pair();
    let count = 3 + (rng.next_f64() * 6.0) as usize;
    let mut angles: Vec<f64> = (0..count).map(|_| rng.range(0.0, 2.0 * PI)).collect();
    angles.sort_by(f64::total_cmp);
    angles
        .into_iter()
        .map(|a| centre + (u * a.cos() + v * a.sin()) * (size * rng.range(0.4, 1.2)))
        .collect()
}

fn segment_distance(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let t = ((p - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
    (a + (b - a) * t - p).length()
}

/// Distance from `p` to where F is not smooth: the polygon's edges and its
/// plane (a conservative stand-in for the polygon itself).
fn singular_distance(p: DVec3, polygon: &[DVec3]) -> f64 {
    let n = polygon.len();
    let edges = (0..n)
        .map(|i| segment_distance(p, polygon[i], polygon[(i + 1) % n]))
        .fold(f64::INFINITY, f64::min);
    let plane_normal = (polygon[1] - polygon[0])
        .cross(polygon[2] - polygon[0])
        .normalize();
    edges.min(plane_normal.dot(p - polygon[0]).abs())
}

/// Central differences of `f` along the three axes.
fn central_gradient(f: impl Fn(DVec3) -> f64, p: DVec3, step: f64) -> DVec3 {
    let d = |axis: DVec3| (f(p + axis * step) - f(p - axis * step)) / (2.0 * step);
    DVec3::new(d(DVec3::X), d(DVec3::Y), d(DVec3::Z))
}

/// Tracks the worst |g − g_fd| / |g| and checks the norm-based tolerance.
#[derive(Default)]
struct Agreement {
    worst: f64,
    checked: usize,
}

impl Agreement {
    fn check(&mut self, what: &str, analytic: DVec3, numeric: DVec3, absolute: f64) {
        let error = (analytic - numeric).length();
        assert!(
            error <= 1e-4 * analytic.length() + absolute,
            "{what}: analytic {analytic} vs finite differences {numeric}"
        );
        self.worst = self.worst.max(error / analytic.length().max(absolute));
        self.checked += 1;
    }
}

/// Checks the polygon gradient at `p` against central differences; false
/// when the point sees nothing.
fn check_polygon(agreement: &mut Agreement, p: DVec3, normal: DVec3, polygon: &[DVec3]) -> bool {
    let (f, g) = polygon_form_factor_with_gradient(p, normal, polygon);
    if f <= 1e-12 {
        return false;
    }
    let scale = singular_distance(p, polygon);
    let numeric = central_gradient(|x| polygon_form_factor(x, normal, polygon), p, 1e-4 * scale);
    let what = format!("p={p} n={normal} polygon={polygon:?}");
    agreement.check(&what, g, numeric, 1e-9 * f / scale);
    true
}

#[test]
fn polygon_gradient_matches_finite_differences_in_front() {
    let mut rng = Rng(1);
    let mut agreement = Agreement::default();
    while agreement.checked < 300 {
        // A tilted receiver and a source somewhere in front of it.
        let normal = rng.direction();
        let p = rng.point(1.0);
        let centre = p + (normal + rng.direction() * 0.9) * rng.range(0.5, 3.0);
        let size = rng.range(0.1, 1.5);
        let polygon = random_polygon(&mut rng, centre, size);
        check_polygon(&mut agreement, p, normal, &polygon);
    }
    println!(
        "polygon in front: worst relative FD disagreement {:.2e}",
        agreement.worst
    );
}

#[test]
fn polygon_gradient_matches_finite_differences_when_clipped() {
    let mut rng = Rng(2);
    let mut agreement = Agreement::default();
    while agreement.checked < 300 {
        // A source centred on the receiver's plane: partly behind it.
        let normal = rng.direction();
        let p = rng.point(1.0);
        let (u, v) = normal.any_orthonormal_pair();
        let centre = p + (u * rng.range(-1.0, 1.0) + v * rng.range(-1.0, 1.0)) * 2.0;
        let size = rng.range(0.3, 1.5);
        let polygon = random_polygon(&mut rng, centre, size);
        let straddles = polygon.iter().any(|x| normal.dot(*x - p) < 0.0)
            && polygon.iter().any(|x| normal.dot(*x - p) > 0.0);
        if straddles {
            check_polygon(&mut agreement, p, normal, &polygon);
        }
    }
    println!(
        "clipped polygon: worst relative FD disagreement {:.2e}",
        agreement.worst
    );
}

#[test]
fn polygon_gradient_matches_finite_differences_near_edges() {
    let mut rng = Rng(3);
    let mut agreement = Agreement::default();
    while agreement.checked < 300 {
        // A point a hair off a random edge, on either side of the polygon.
        let polygon = random_polygon(&mut rng, DVec3::ZERO, 1.0);
        let i = (rng.next_f64() * polygon.len() as f64) as usize;
        let (a, b) = (polygon[i], polygon[(i + 1) % polygon.len()]);
        let along = a + (b - a) * rng.range(0.05, 0.95);
        let off = rng.direction().reject_from(b - a).normalize();
        let p = along + off * 10f64.powf(rng.range(-5.0, -2.0));
        // Receivers of any tilt, facing the polygon's centre more or less.
        let normal = (-p.normalize() + rng.direction() * 0.8).normalize();
        check_polygon(&mut agreement, p, normal, &polygon);
    }
    println!(
        "near edges: worst relative FD disagreement {:.2e}",
        agreement.worst
    );
}

#[test]
fn polygon_gradient_in_plane_part() {
    // Under the middle of a parallel square's edge, F changes only across it.
    let square = [
        DVec3::new(0.0, 0.0, 1.0),
        DVec3::new(1.0, 0.0, 1.0),
        DVec3::new(1.0, 1.0, 1.0),
        DVec3::new(0.0, 1.0, 1.0),
    ];
    let g = polygon_form_factor_gradient(DVec3::new(0.5, 0.0, 0.0), DVec3::Z, &square);
    let in_plane = g - DVec3::Z * g.dot(DVec3::Z);
    assert!(in_plane.x.abs() < 1e-15 && in_plane.y > 0.0, "{in_plane}");
}

/// Howell's catalogue: plane element parallel to a rectangle a × b at
/// distance c, its normal through a corner.
fn howell_parallel_corner(a: f64, b: f64, c: f64) -> f64 {
    let (x, y) = (a / c, b / c);
    let (sx, sy) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
    (x / sx * (y / sx).atan() + y / sy * (x / sy).atan()) / (2.0 * PI)
}

/// Howell's catalogue: plane element at distance c from the plane of a
/// perpendicular rectangle (b along the planes' intersection, a away from
/// the element's plane), opposite one of the rectangle's corners.
fn howell_perpendicular_corner(a: f64, b: f64, c: f64) -> f64 {
    let (x, y) = (a / b, c / b);
    let s = (x * x + y * y).sqrt();
    ((1.0 / y).atan() - y / s * (1.0 / s).atan()) / (2.0 * PI)
}

#[test]
fn exact_factor_matches_howell_rectangles() {
    for (a, b, c) in [
        (1.0, 1.0, 1.0),
        (1.0, 2.0, 0.5),
        (3.0, 0.2, 1.7),
        (0.01, 5.0, 0.3),
    ] {
        // Parallel rectangle [0, a] × [0, b] at height c over the origin.
        let parallel = [
            DVec3::new(0.0, 0.0, c),
            DVec3::new(a, 0.0, c),
            DVec3::new(a, b, c),
            DVec3::new(0.0, b, c),
        ];
        let f = polygon_form_factor(DVec3::ZERO, DVec3::Z, &parallel);
        let reference = howell_parallel_corner(a, b, c);
        assert!(
            (f - reference).abs() < 1e-13 * reference,
            "{f} vs {reference}"
        );
        // Perpendicular rectangle in the plane y = c, x ∈ [0, b], z ∈ [0, a].
        let wall = [
            DVec3::new(0.0, c, 0.0),
            DVec3::new(b, c, 0.0),
            DVec3::new(b, c, a),
            DVec3::new(0.0, c, a),
        ];
        let f = polygon_form_factor(DVec3::ZERO, DVec3::Z, &wall);
        let reference = howell_perpendicular_corner(a, b, c);
        assert!(
            (f - reference).abs() < 1e-13 * reference,
            "{f} vs {reference}"
        );
    }
}

/// A random disc and receiver plane with the disc in front of the plane.
fn random_disc(rng: &mut Rng) -> (SmallDisc, ReceiverPlane) {
    let plane = ReceiverPlane {
        point: rng.point(1.0),
        normal: rng.direction(),
    };
    let centre = plane.point + rng.point(2.0) + plane.normal * rng.range(0.2, 3.0);
    let disc = SmallDisc {
        centre,
        normal: rng.direction(),
        area: rng.range(1e-3, 0.5),
        exitance: rng.range(0.5, 2.0),
    };
    (disc, plane)
}

#[test]
fn disc_gradients_match_finite_differences() {
    let mut rng = Rng(4);
    for model in [DiscModel::PointSource, DiscModel::FiniteDisc] {
        let mut agreement = Agreement::default();
        while agreement.checked < 300 {
            let (disc, plane) = random_disc(&mut rng);
            let (u, v) = plane.normal.any_orthonormal_pair();
            let m = plane
                .project(plane.point + (u * rng.range(-1.0, 1.0) + v * rng.range(-1.0, 1.0)) * 4.0);
            let (f, g) = disc.form_factor_with_gradient(model, &plane, m);
            // Lit points away from the kink where the disc's plane cuts.
            let d = disc.centre - m;
            let kink_distance =
                -disc.normal.dot(d) / disc.normal.reject_from(plane.normal).length();
            if f <= 0.0 || kink_distance < 1e-3 {
                continue;
            }
            let step = 1e-4 * d.length().min(kink_distance);
            let value = |x: DVec3| disc.form_factor(model, &plane, x);
            let fd = |axis: DVec3| (value(m + axis * step) - value(m - axis * step)) / (2.0 * step);
            let numeric = u * fd(u) + v * fd(v);
            agreement.check(
                &format!("{disc:?} {plane:?} at {m}"),
                g,
                numeric,
                1e-9 * f / d.length(),
            );
        }
        println!(
            "{model:?}: worst relative FD disagreement {:.2e}",
            agreement.worst
        );
    }
}

/// The largest value of `f` on [lo, hi]: dense sampling, then golden section
/// around the best sample.
fn numerical_maximum(f: impl Fn(f64) -> f64, lo: f64, hi: f64) -> f64 {
    let samples = 20_000;
    let x = |i: usize| lo + (hi - lo) * i as f64 / samples as f64;
    let best = (0..=samples)
        .max_by(|&i, &j| f(x(i)).total_cmp(&f(x(j))))
        .unwrap_or(0);
    let (mut a, mut b) = (x(best.saturating_sub(1)), x((best + 1).min(samples)));
    let ratio = (5f64.sqrt() - 1.0) / 2.0;
    while b - a > 1e-13 * (hi - lo) {
        let (c, d) = (b - ratio * (b - a), a + ratio * (b - a));
        if f(c) > f(d) {
            b = d;
        } else {
            a = c;
        }
    }
    0.5 * (a + b)
}

#[test]
fn seed_maximum_matches_numerical_maximisation() {
    let plane = ReceiverPlane {
        point: DVec3::ZERO,
        normal: DVec3::Z,
    };
    let mut worst: f64 = 0.0;
    for degrees in 1..=80 {
        // A disc at height h leaning by φ towards +x.
        let (h, phi) = (1.7, f64::from(degrees).to_radians());
        let disc = SmallDisc {
            centre: DVec3::new(0.3, -0.2, h),
            normal: DVec3::new(phi.sin(), 0.0, -phi.cos()),
            area: 0.05,
            exitance: 1.0,
        };
        for model in [DiscModel::PointSource, DiscModel::FiniteDisc] {
            let along = |x: f64| disc.form_factor(model, &plane, DVec3::new(0.3 + x, -0.2, 0.0));
            let numeric = numerical_maximum(along, -2.0 * h, 10.0 * h);
            let peak = disc.maximum_on_plane(model, &plane).unwrap();
            let x = peak.x - 0.3;
            assert!(
                (peak.y + 0.2).abs() < 1e-12 && peak.z.abs() < 1e-12,
                "{peak}"
            );
            assert!(
                (x - numeric).abs() < 1e-6 * h,
                "{degrees}° {model:?}: {x} vs {numeric}"
            );
            worst = worst.max((x - numeric).abs() / h);
            if model == DiscModel::PointSource {
                // The seed's printed form, eq. (4.2).
                let t = phi.tan();
                let seed = h * (-4.0 + 2.0 * (4.0 + 3.0 * t * t).sqrt()) / (6.0 * t);
                assert!((x - seed).abs() < 1e-12 * h, "{degrees}°: {x} vs {seed}");
                assert!((tilt_line_maximum(h, phi).unwrap() - seed).abs() < 1e-12 * h);
            }
        }
    }
    println!("eq. 4.2 and the finite-disc peak vs numerical maximum: worst |Δx|/h {worst:.2e}");
}

#[test]
fn maximum_on_plane_for_any_orientation() {
    let mut rng = Rng(5);
    let mut found = 0;
    while found < 200 {
        let (disc, plane) = random_disc(&mut rng);
        for model in [DiscModel::PointSource, DiscModel::FiniteDisc] {
            let Some(peak) = disc.maximum_on_plane(model, &plane) else {
                continue;
            };
            found += 1;
            // On the plane, a stationary point, and no lower than its neighbours.
            let (f, g) = disc.form_factor_with_gradient(model, &plane, peak);
            let r = (disc.centre - peak).length();
            assert!(plane.normal.dot(peak - plane.point).abs() < 1e-12 * r);
            assert!(g.length() * r < 1e-9 * f, "{disc:?} {plane:?}: {g}");
            for _ in 0..20 {
                let nearby = plane.project(peak + rng.direction() * 0.01 * r);
                assert!(disc.form_factor(model, &plane, nearby) <= f);
            }
        }
    }
}

#[test]
fn finite_disc_tends_to_point_source_far_away() {
    let plane = ReceiverPlane {
        point: DVec3::ZERO,
        normal: DVec3::Z,
    };
    let normal = DVec3::new(0.4, 0.1, -1.0).normalize();
    for height in [1.0, 10.0, 100.0, 1000.0] {
        let disc = SmallDisc {
            centre: DVec3::new(0.0, 0.0, height),
            normal,
            area: 0.5,
            exitance: 1.0,
        };
        let m = DVec3::new(0.3 * height, 0.1 * height, 0.0);
        let point = disc.form_factor(DiscModel::PointSource, &plane, m);
        let finite = disc.form_factor(DiscModel::FiniteDisc, &plane, m);
        // F_disc / F_point = r² / (r² + A/π) exactly.
        let r2 = (disc.centre - m).length_squared();
        let expected = r2 / (r2 + 0.5 / PI);
        assert!((finite / point - expected).abs() < 1e-14, "h={height}");
        assert!(1.0 - finite / point < 0.2 / (height * height));
    }
}

#[test]
fn small_polygonal_disc_tends_to_finite_disc_form() {
    let plane = ReceiverPlane {
        point: DVec3::ZERO,
        normal: DVec3::Z,
    };
    let normal = DVec3::new(0.5, -0.3, -1.0).normalize();
    let (u, v) = normal.any_orthonormal_pair();
    let mut previous = f64::INFINITY;
    for radius in [0.2, 0.1, 0.05, 0.025, 0.0125] {
        // A 64-gon of the disc's area.
        let area = PI * radius * radius;
        let sides = 64;
        let wedge = 2.0 * PI / f64::from(sides);
        let circumradius = (2.0 * area / (f64::from(sides) * wedge.sin())).sqrt();
        let centre = DVec3::new(0.2, 0.1, 1.0);
        let polygon: Vec<DVec3> = (0..sides)
            .map(|k| {
                let a = wedge * f64::from(k);
                centre + (u * a.cos() + v * a.sin()) * circumradius
            })
            .collect();
        let disc = SmallDisc {
            centre,
            normal,
            area,
            exitance: 1.0,
        };
        // Relative difference over a few receiver points.
        let mut worst: f64 = 0.0;
        for m in [
            DVec3::ZERO,
            DVec3::new(0.7, 0.4, 0.0),
            DVec3::new(-0.5, 0.2, 0.0),
        ] {
            let exact = polygon_form_factor(m, DVec3::Z, &polygon);
            let finite = disc.form_factor(DiscModel::FiniteDisc, &plane, m);
            worst = worst.max((finite - exact).abs() / exact);
        }
        // The model error shrinks like (radius/distance)².
        assert!(worst < 2.0 * radius * radius, "radius {radius}: {worst}");
        assert!(worst < previous);
        previous = worst;
        println!("disc radius {radius}: finite-disc form vs 64-gon {worst:.2e}");
    }
}
