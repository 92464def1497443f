//! The seed paper's small-disc emitter: the direct light of a small, possibly
//! tilted disc on a receiver plane, its gradient, and where it peaks.
//!
//! # The model
//!
//! A disc of centre S, unit normal m (the side it emits from) and area A
//! lights a plane through O with unit normal n (its front). For a point M of
//! the plane, with d = S − M, r = |d|, the receiver's cosine n·d/r and the
//! source's −m·d/r, the form factor from M to the disc is, as a point source
//! (the seed's eq. 3.1 without `+ A`) or as Wallace's finite disc (eq. 3.1),
//!
//! ```text
//!   F_point(M) = A cosθ_r cosθ_s / (π r²)       = k h Q / r⁴
//!   F_disc(M)  = A cosθ_r cosθ_s / (π r² + A)   = k h Q / (r² (r² + k))
//! ```
//!
//! with k = A/π, h = n·d (the disc's height above the plane: the same for
//! every M of the plane) and Q = −m·d; F = 0 where h ≤ 0 or Q ≤ 0 (the disc
//! is behind the plane, or M behind the disc). Units: F is dimensionless;
//! the irradiance at M is E·F with E the disc's exitance (W/m²), and the
//! direct radiosity of a receiver of reflectance ρ is ρ·E·F.
//!
//! # The frame of the tilt
//!
//! Let the foot F₀ = S − h n, the tilt φ ∈ [0, π] the angle between m and
//! −n (cos φ = −m·n; φ = 0 for a disc facing straight down at the plane) and
//! the tilt direction t the unit in-plane part of m, m = −cos φ n + sin φ t:
//! the direction the disc leans towards. With b = n × t and
//! M = F₀ + x t + y b, R² = x² + y² + h², Q = h cos φ + x sin φ and
//!
//! ```text
//!   F_point(x, y) = k h (h cos φ + x sin φ) / R⁴
//!   F_disc(x, y)  = k h (h cos φ + x sin φ) / (R² (R² + k))
//! ```
//!
//! On the tilt line (y = 0) the first is the seed's eq. (4.1),
//! B(x) ∝ (h x sin φ + h² cos φ)/(x² + h²)². Light ends on the line
//! x = −h cot φ, where the disc's plane meets the receiver's (a kink in F).
//!
//! # The gradient (the seed's eq. 3.2, re-derived)
//!
//! With D = r²(r² + a) (a = 0 for the point source, a = k for the disc), on
//! the plane ∇h = 0, ∇Q = m and ∇r² = −2d, so
//!
//! ```text
//!   ∇F = k h [ m / D + 2 Q (2r² + a) d / D² ]   projected on the plane
//!   ∂F/∂x = k h [ sin φ / D − 2 x Q (2R² + a) / D² ],
//!   ∂F/∂y = −2 k h y Q (2R² + a) / D²
//! ```
//!
//! # The maximum
//!
//! ∂F/∂y = 0 only at y = 0, and for fixed x both denominators grow with y²,
//! so the maximum lies on the tilt line. There, for the point source,
//! ∂F/∂x = 0 ⇔ h sin φ (x² + h²) − 4x (h x sin φ + h² cos φ) = 0 ⇔
//! 3 sin φ x² + 4 h cos φ x − h² sin φ = 0, whose positive root is
//!
//! ```text
//!   x* = h (−4 + 2 √(4 + 3 tan² φ)) / (6 tan φ)       (seed eq. 4.2)
//!      = h sin φ / (2 cos φ + √(4 cos² φ + 3 sin² φ))
//! ```
//!
//! the second form free of cancellation for small φ and valid up to φ < π
//! (beyond 90° the disc leans away but still lights x > −h cot φ). For the
//! finite disc the condition is the quartic
//! sin φ u (u + k) − 2x (h cos φ + x sin φ)(2u + k) = 0 with u = x² + h²;
//! its root lies beyond the point source's x* (the factor u/(u + k) grows
//! with |x|) and is found by safeguarded Newton.
//!
//! # References
//! P. Arquès, V. Biri, S. Derpierre, "A new formulation of differential
//! radiosity and a rendering application", WSCG 2005 (eqs. 3.1, 3.2, 4.1,
//! 4.2). J. R. Wallace, K. A. Elmquist, E. A. Haines, "A Ray Tracing
//! Algorithm for Progressive Radiosity", SIGGRAPH 1989.

use glam::DVec3;
use std::f64::consts::PI;

/// Which kernel stands for the disc (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DiscModel {
    /// A · cosθ_r cosθ_s / (π r²): exact in the limit of a small disc.
    PointSource,
    /// Wallace's A · cosθ_r cosθ_s / (π r² + A): bounded as r → 0, exact on
    /// the axis of a parallel disc.
    FiniteDisc,
}

/// A plane through `point` with unit `normal`; its front is the side the
/// normal points to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReceiverPlane {
    /// Any point of the plane.
    pub point: DVec3,
    /// Unit normal, pointing to the lit side.
    pub normal: DVec3,
}

impl ReceiverPlane {
    /// The orthogonal projection of `world` onto the plane.
    #[must_use]
    pub fn project(&self, world: DVec3) -> DVec3 {
        world - self.normal * self.normal.dot(world - self.point)
    }
}

/// A small emitting disc: the seed paper's emitter model.
///
/// # References
/// P. Arquès, V. Biri, S. Derpierre, WSCG 2005, §3.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SmallDisc {
    /// Centre S.
    pub centre: DVec3,
    /// Unit normal m, on the emitting side.
    pub normal: DVec3,
    /// Area A (m²).
    pub area: f64,
    /// Exitance E (W/m²): irradiance = E · F, direct radiosity = ρ · E · F.
    pub exitance: f64,
}

/// The disc seen from a receiver plane: foot of the perpendicular, height
/// and tilt (see the module documentation for the conventions).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TiltFrame {
    /// F₀ = S − h n, the origin of the frame.
    pub foot: DVec3,
    /// h = n·(S − O) > 0.
    pub height: f64,
    /// φ ∈ [0, π], the angle between the disc's normal m and −n.
    pub tilt: f64,
    /// t, the unit in-plane direction the disc leans towards (x axis); any
    /// unit in-plane vector when φ = 0 or π.
    pub tilt_direction: DVec3,
}

impl SmallDisc {
    /// The form factor F(M) from the point of the plane nearest `point` to
    /// the disc: k h Q / r⁴ or k h Q / (r² (r² + k)), zero where the disc is
    /// behind the plane or the point behind the disc.
    ///
    /// # References
    /// Arquès, Biri, Derpierre, WSCG 2005, eq. 3.1; Wallace et al. 1989.
    #[must_use]
    pub fn form_factor(&self, model: DiscModel, plane: &ReceiverPlane, point: DVec3) -> f64 {
        self.form_factor_with_gradient(model, plane, point).0
    }

    /// F(M) and its gradient within the plane (a world-space vector
    /// orthogonal to n): ∇F = k h [m/D + 2Q(2r² + a) d/D²] projected on the
    /// plane, D = r²(r² + a). Zero where F is zero; finite always.
    ///
    /// # References
    /// Arquès, Biri, Derpierre, WSCG 2005, eq. 3.2 (re-derived, see the
    /// module documentation).
    #[must_use]
    pub fn form_factor_with_gradient(
        &self,
        model: DiscModel,
        plane: &ReceiverPlane,
        point: DVec3,
    ) -> (f64, DVec3) {
        // Unit normals; the receiver on its plane.
        let (n, m) = (
            plane.normal.normalize_or_zero(),
            self.normal.normalize_or_zero(),
        );
        let d = self.centre - plane.project(point);
        // Height of the disc and its cosine factor: no light unless both > 0.
        let (h, q) = (n.dot(d), -m.dot(d));
        let k = self.area / PI;
        let lit = h > 0.0 && q > 0.0 && k > 0.0;
        if !lit {
            return (0.0, DVec3::ZERO);
        }
        // F = k h Q / D with D = r² (r² + a).
        let r2 = d.length_squared();
        let a = match model {
            DiscModel::PointSource => 0.0,
            DiscModel::FiniteDisc => k,
        };
        let denominator = r2 * (r2 + a);
        let value = k * h * q / denominator;
        // ∇F from ∇Q = m and ∇r² = −2d, then its in-plane part.
        let gradient = (m / denominator
            + d * (2.0 * q * (2.0 * r2 + a) / (denominator * denominator)))
            * (k * h);
        let in_plane = gradient - n * n.dot(gradient);
        if value.is_finite() && in_plane.is_finite() {
            (value, in_plane)
        } else {
            (0.0, DVec3::ZERO)
        }
    }

    /// The in-plane gradient of [`form_factor`](Self::form_factor).
    ///
    /// # References
    /// Arquès, Biri, Derpierre, WSCG 2005, eq. 3.2 (re-derived).
    #[must_use]
    pub fn form_factor_gradient(
        &self,
        model: DiscModel,
        plane: &ReceiverPlane,
        point: DVec3,
    ) -> DVec3 {
        self.form_factor_with_gradient(model, plane, point).1
    }

    /// Irradiance E·F (W/m²) at the point of the plane nearest `point`, and
    /// its in-plane gradient.
    ///
    /// # References
    /// Arquès, Biri, Derpierre, WSCG 2005, eqs. 3.1–3.2.
    #[must_use]
    pub fn irradiance_with_gradient(
        &self,
        model: DiscModel,
        plane: &ReceiverPlane,
        point: DVec3,
    ) -> (f64, DVec3) {
        let (value, gradient) = self.form_factor_with_gradient(model, plane, point);
        (self.exitance * value, gradient * self.exitance)
    }

    /// The frame of the tilt: foot, height h, tilt φ and tilt direction t.
    /// `None` when the disc is on or behind the plane (h ≤ 0), or the input
    /// is degenerate (zero normal, non-finite coordinates).
    ///
    /// # References
    /// Arquès, Biri, Derpierre, WSCG 2005, §4 (the frame of eq. 4.1).
    #[must_use]
    pub fn tilt_frame(&self, plane: &ReceiverPlane) -> Option<TiltFrame> {
        // Height above the plane: the disc must be in front of it.
        let (n, m) = (
            plane.normal.normalize_or_zero(),
            self.normal.normalize_or_zero(),
        );
        let height = n.dot(self.centre - plane.point);
        let in_front = height > 0.0 && height.is_finite() && m != DVec3::ZERO;
        if !in_front {
            return None;
        }
        // m = −cos φ n + sin φ t.
        let cos_tilt = -m.dot(n);
        let lean = m + n * cos_tilt;
        let sin_tilt = lean.length();
        let tilt_direction = if sin_tilt > 1e-12 {
            lean / sin_tilt
        } else {
            n.any_orthonormal_vector()
        };
        Some(TiltFrame {
            foot: self.centre - n * height,
            height,
            tilt: sin_tilt.atan2(cos_tilt),
            tilt_direction,
        })
    }

    /// The point of the plane where F is largest, for any orientation of
    /// disc and plane. `None` when no light reaches the plane: the disc on or
    /// behind it, facing straight away (φ = π), or of zero area.
    ///
    /// The maximum lies on the tilt line at x* from the foot (module
    /// documentation): in closed form for the point source
    /// ([`tilt_line_maximum`], the seed's eq. 4.2), and for the finite disc
    /// by safeguarded Newton on the quartic ∂F/∂x = 0, bracketed between the
    /// point source's x* and a point beyond the peak.
    ///
    /// # References
    /// Arquès, Biri, Derpierre, WSCG 2005, eq. 4.2.
    #[must_use]
    pub fn maximum_on_plane(&self, model: DiscModel, plane: &ReceiverPlane) -> Option<DVec3> {
        // The frame of the tilt, and the point source's peak in closed form.
        let frame = self.tilt_frame(plane)?;
        let has_area = self.area > 0.0;
        if !has_area {
            return None;
        }
        let point_peak = tilt_line_maximum(frame.height, frame.tilt)?;
        // The finite disc's peak lies further along the tilt line.
        let x = match model {
            DiscModel::PointSource => point_peak,
            DiscModel::FiniteDisc => {
                finite_disc_peak(frame.height, frame.tilt, self.area / PI, point_peak)
            }
        };
        Some(frame.foot + frame.tilt_direction * x)
    }
}

/// The point source's peak on the tilt line: the distance x* ≥ 0 from the
/// foot along the tilt direction where h (h cos φ + x sin φ)/(x² + h²)² is
/// largest,
///
/// ```text
///   x* = h (−4 + 2 √(4 + 3 tan² φ)) / (6 tan φ)                (eq. 4.2)
///      = h sin φ / (2 cos φ + √(4 cos² φ + 3 sin² φ))       (cos φ ≥ 0)
///      = h (2 |cos φ| + √(4 cos² φ + 3 sin² φ)) / (3 sin φ)  (cos φ < 0)
/// ```
///
/// the positive root of 3 sin φ x² + 4 h cos φ x − h² sin φ = 0, written
/// without cancellation. x* = 0 at φ = 0. `None` for h ≤ 0, φ outside
/// [0, π) or non-finite input: no light on the plane.
///
/// # References
/// P. Arquès, V. Biri, S. Derpierre, "A new formulation of differential
/// radiosity and a rendering application", WSCG 2005, eqs. 4.1–4.2.
#[must_use]
pub fn tilt_line_maximum(height: f64, tilt: f64) -> Option<f64> {
    // A disc on or behind the plane, or facing straight away, lights nothing.
    let lit = height > 0.0 && height.is_finite() && (0.0..PI).contains(&tilt);
    if !lit {
        return None;
    }
    let (sin, cos) = tilt.sin_cos();
    let root = (4.0 * cos * cos + 3.0 * sin * sin).sqrt();
    // Pick the form of the root that does not cancel.
    let x = if cos >= 0.0 {
        height * sin / (2.0 * cos + root)
    } else {
        height * (-2.0 * cos + root) / (3.0 * sin)
    };
    x.is_finite().then_some(x)
}

/// The finite disc's peak on the tilt line: the root of
/// p(x) = sin φ u(u + k) − 2x (h cos φ + x sin φ)(2u + k), u = x² + h², which
/// has the sign of ∂F/∂x. p(lower) ≥ 0 at the point source's peak.
fn finite_disc_peak(height: f64, tilt: f64, k: f64, lower: f64) -> f64 {
    let (sin, cos) = tilt.sin_cos();
    let h = height;
    // p and p′.
    let p = |x: f64| {
        let u = x * x + h * h;
        let q = h * cos + x * sin;
        let value = sin * u * (u + k) - 2.0 * x * q * (2.0 * u + k);
        let slope = 2.0 * x * sin * (2.0 * u + k)
            - 2.0 * (h * cos + 2.0 * x * sin) * (2.0 * u + k)
            - 8.0 * x * x * q;
        (value, slope)
    };
    // At φ = 0 the peak is at the foot for both models.
    let beyond_lower = sin > 0.0 && p(lower).0 > 0.0;
    if !beyond_lower {
        return lower;
    }
    // Bracket: p < 0 far out (p ~ −3 sin φ x⁴).
    let mut upper = (2.0 * lower).max(lower + h);
    for _ in 0..200 {
        if p(upper).0 < 0.0 {
            break;
        }
        upper *= 2.0;
    }
    safeguarded_newton(p, lower, upper)
}

/// A root of f in [lo, hi] with f(lo) > 0 > f(hi): Newton steps kept inside
/// the bracket, bisection when a step leaves it; at most 100 iterations.
fn safeguarded_newton(f: impl Fn(f64) -> (f64, f64), mut lo: f64, mut hi: f64) -> f64 {
    let mut x = 0.5 * (lo + hi);
    for _ in 0..100 {
        // Shrink the bracket around the sign change.
        let (value, slope) = f(x);
        if value > 0.0 {
            lo = x;
        } else {
            hi = x;
        }
        // Newton if it stays inside the bracket, else bisect.
        let newton = x - value / slope;
        let next = if newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if (next - x).abs() <= 1e-15 * x.abs().max(hi - lo) || hi - lo <= 1e-15 * hi {
            return next;
        }
        x = next;
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    fn floor() -> ReceiverPlane {
        ReceiverPlane {
            point: DVec3::ZERO,
            normal: DVec3::Z,
        }
    }

    fn tilted_disc(tilt_degrees: f64) -> SmallDisc {
        let phi = tilt_degrees.to_radians();
        SmallDisc {
            centre: DVec3::new(0.0, 0.0, 2.0),
            normal: DVec3::new(phi.sin(), 0.0, -phi.cos()),
            area: 0.01,
            exitance: 1.0,
        }
    }

    #[test]
    fn frame_of_a_disc_leaning_along_x() {
        let frame = tilted_disc(30.0).tilt_frame(&floor()).unwrap();
        assert!((frame.height - 2.0).abs() < 1e-15);
        assert!((frame.tilt - 30f64.to_radians()).abs() < 1e-15);
        assert!((frame.tilt_direction - DVec3::X).length() < 1e-15);
        assert!(frame.foot.length() < 1e-15);
    }

    #[test]
    fn finite_disc_is_wallaces_kernel() {
        let disc = tilted_disc(40.0);
        let m = DVec3::new(0.8, -0.3, 0.0);
        let d = disc.centre - m;
        let r = d.length();
        let wallace =
            crate::radiometry::disc_form_factor(disc.area, d.z / r, -disc.normal.dot(d) / r, r * r);
        let f = disc.form_factor(DiscModel::FiniteDisc, &floor(), m);
        assert!((f - wallace).abs() < 1e-15 * wallace, "{f} vs {wallace}");
    }

    #[test]
    fn seed_formula_and_stable_form_agree() {
        for degrees in [1.0, 10.0, 45.0, 80.0, 89.0] {
            let phi = f64::to_radians(degrees);
            let t = phi.tan();
            let seed = 1.5 * (-4.0 + 2.0 * (4.0 + 3.0 * t * t).sqrt()) / (6.0 * t);
            let x = tilt_line_maximum(1.5, phi).unwrap();
            assert!((x - seed).abs() < 1e-12 * seed, "{degrees}°: {x} vs {seed}");
        }
    }

    #[test]
    fn untilted_disc_peaks_at_the_foot() {
        for model in [DiscModel::PointSource, DiscModel::FiniteDisc] {
            let peak = tilted_disc(0.0).maximum_on_plane(model, &floor()).unwrap();
            assert!(peak.length() < 1e-12, "{peak}");
        }
    }

    #[test]
    fn no_light_gives_none_and_zero() {
        let plane = floor();
        // Facing straight up, lying in the plane, below the plane, no area.
        let mut cases = vec![tilted_disc(180.0)];
        cases[0].normal = DVec3::Z;
        let mut in_plane = tilted_disc(30.0);
        in_plane.centre.z = 0.0;
        let mut below = tilted_disc(30.0);
        below.centre.z = -1.0;
        let mut no_area = tilted_disc(30.0);
        no_area.area = 0.0;
        let mut nan = tilted_disc(30.0);
        nan.centre.x = f64::NAN;
        cases.extend([in_plane, below, no_area, nan]);
        for disc in cases {
            for model in [DiscModel::PointSource, DiscModel::FiniteDisc] {
                assert_eq!(disc.maximum_on_plane(model, &plane), None, "{disc:?}");
                let (f, g) = disc.form_factor_with_gradient(model, &plane, DVec3::X);
                assert_eq!((f, g), (0.0, DVec3::ZERO));
            }
        }
    }

    #[test]
    fn gradient_is_in_the_plane_and_zero_at_the_peak() {
        let plane = ReceiverPlane {
            point: DVec3::new(0.0, 0.0, -0.5),
            normal: DVec3::new(0.1, -0.2, 1.0).normalize(),
        };
        let disc = tilted_disc(50.0);
        for model in [DiscModel::PointSource, DiscModel::FiniteDisc] {
            let peak = disc.maximum_on_plane(model, &plane).unwrap();
            let (f, g) = disc.form_factor_with_gradient(model, &plane, peak);
            assert!(g.length() < 1e-12 * f, "{model:?}: {g} at {peak}");
            let g = disc.form_factor_gradient(model, &plane, peak + DVec3::X);
            assert!(g.dot(plane.normal).abs() < 1e-15 * g.length());
        }
    }
}
