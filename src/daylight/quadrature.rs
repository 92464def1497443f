//! Numerical integration for the sky: globally adaptive Gauss–Kronrod on an
//! interval, and integrals over the directions above one or two planes
//! through the origin, in polar coordinates about a chosen pole.
//!
//! # The rule
//!
//! Each segment [a, b] is integrated by the 15-point Kronrod rule K15; the
//! 7-point Gauss rule G7 on the same nodes gives the error estimate, scaled
//! as QUADPACK's `qk15` does: with ρ = ∫ |f − mean| on the Kronrod nodes,
//! err = ρ · min(1, (200 |K15 − G7| / ρ)^1.5), since K15 is far more exact
//! than G7 on smooth integrands, and err ≥ 50 ε ∫ |f|, the rounding floor.
//! The segment with the largest estimate is bisected until the estimates
//! sum to at most max(absolute, relative · |total|).
//!
//! # On the sphere
//!
//! About a unit pole p with orthonormal u, v, a direction is
//! ω(χ, ψ) = cos χ p + sin χ (cos ψ u + sin ψ v), dω = sin χ dχ dψ. For a
//! plane normal m, m·ω = A cos χ + B sin χ = R cos(χ − δ) with A = m·p,
//! B = m·(cos ψ u + sin ψ v), δ = atan2(B, A): on the half great circle
//! χ ∈ [0, π] the directions in front of the plane form one arc, and the
//! intersection of two such arcs is one arc. The integrand is smooth in χ
//! along each arc when the pole sits on its one sharp feature (the sun of a
//! circumsolar peak e^(−3χ)); what remains (kinks where the active plane
//! changes, a cusp elsewhere) is left to the adaptive bisection in ψ.
//!
//! # References
//! - R. Piessens, E. de Doncker-Kapenga, C. W. Überhuber, D. K. Kahaner,
//!   *QUADPACK: A Subroutine Package for Automatic Integration*, Springer
//!   1983 (the K15/G7 nodes and weights of `qk15`).
//! - A. S. Kronrod, *Nodes and Weights of Quadrature Formulas*, 1965.

use glam::DVec3;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// The Kronrod nodes on [−1, 1] (their negatives too), from the outermost
/// inwards; the odd indices (1, 3, 5) and the centre are Gauss's 7 nodes.
const KRONROD_NODES: [f64; 8] = [
    0.991_455_371_120_812_6,
    0.949_107_912_342_758_5,
    0.864_864_423_359_769_1,
    0.741_531_185_599_394_4,
    0.586_087_235_467_691_1,
    0.405_845_151_377_397_2,
    0.207_784_955_007_898_5,
    0.0,
];

/// The Kronrod weights of [`KRONROD_NODES`].
const KRONROD_WEIGHTS: [f64; 8] = [
    0.022_935_322_010_529_22,
    0.063_092_092_629_978_55,
    0.104_790_010_322_250_18,
    0.140_653_259_715_525_92,
    0.169_004_726_639_267_9,
    0.190_350_578_064_785_4,
    0.204_432_940_075_298_9,
    0.209_482_141_084_727_83,
];

/// The Gauss weights of the nodes 1, 3, 5 and of the centre.
const GAUSS_WEIGHTS: [f64; 4] = [
    0.129_484_966_168_869_7,
    0.279_705_391_489_276_7,
    0.381_830_050_505_118_9,
    0.417_959_183_673_469_4,
];

/// When an adaptive integral may stop: when the error estimates sum to at
/// most max(`absolute`, `relative` · |integral|), or after `max_segments`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Tolerance {
    /// Absolute error allowed, in the integrand's unit times the variable's.
    pub absolute: f64,
    /// Error allowed relative to the integral.
    pub relative: f64,
    /// Most segments the interval is cut into.
    pub max_segments: usize,
}

/// One segment of an adaptive integral with its K15 value and error estimate.
#[derive(Clone, Copy, Debug)]
struct Segment {
    start: f64,
    end: f64,
    integral: f64,
    error: f64,
}

/// K15 of `f` over [start, end] and QUADPACK's error estimate: with
/// ρ = ∫ |f − mean| by the Kronrod weights, err = ρ min(1, (200 |K15 −
/// G7| / ρ)^1.5), and at least 50 ε ∫ |f| (see the module docs).
fn gauss_kronrod(f: &mut impl FnMut(f64) -> f64, start: f64, end: f64) -> Segment {
    let centre = 0.5 * (start + end);
    let half = 0.5 * (end - start);
    let mid = f(centre);
    let mut values = [[0.0; 2]; 7];
    let mut kronrod = KRONROD_WEIGHTS[7] * mid;
    let mut gauss = GAUSS_WEIGHTS[3] * mid;
    let mut absolute = KRONROD_WEIGHTS[7] * mid.abs();
    for (i, (&node, &weight)) in KRONROD_NODES
        .iter()
        .zip(&KRONROD_WEIGHTS)
        .take(7)
        .enumerate()
    {
        values[i] = [f(centre - half * node), f(centre + half * node)];
        let pair = values[i][0] + values[i][1];
        kronrod += weight * pair;
        absolute += weight * (values[i][0].abs() + values[i][1].abs());
        if i % 2 == 1 {
            gauss += GAUSS_WEIGHTS[i / 2] * pair;
        }
    }
    // The spread about the mean, ∫ |f − K/(b − a)| on the Kronrod nodes.
    let mean = 0.5 * kronrod;
    let spread = KRONROD_WEIGHTS[7] * (mid - mean).abs()
        + KRONROD_WEIGHTS
            .iter()
            .zip(&values)
            .map(|(w, v)| w * ((v[0] - mean).abs() + (v[1] - mean).abs()))
            .sum::<f64>();
    let (spread, absolute, raw) = (
        spread * half.abs(),
        absolute * half.abs(),
        ((kronrod - gauss) * half).abs(),
    );
    let mut error = raw;
    if spread != 0.0 && raw != 0.0 {
        error = spread * (200.0 * raw / spread).powf(1.5).min(1.0);
    }
    error = error.max(50.0 * f64::EPSILON * absolute);
    Segment {
        start,
        end,
        integral: kronrod * half,
        error,
    }
}

/// ∫ f over [breaks[0], breaks[last]], starting from the segments between
/// consecutive `breaks` and bisecting the worst until `tolerance` is met.
/// Fewer than two breaks give 0.
pub(crate) fn integrate_pieces(
    mut f: impl FnMut(f64) -> f64,
    breaks: &[f64],
    tolerance: Tolerance,
) -> f64 {
    let mut segments: Vec<Segment> = breaks
        .windows(2)
        .map(|w| gauss_kronrod(&mut f, w[0], w[1]))
        .collect();
    loop {
        let total: f64 = segments.iter().map(|s| s.integral).sum();
        let error: f64 = segments.iter().map(|s| s.error).sum();
        let allowed = tolerance.absolute.max(tolerance.relative * total.abs());
        if error.is_nan() || error <= allowed || segments.len() >= tolerance.max_segments {
            return total;
        }
        // Bisect the segment with the largest error estimate.
        let worst = segments
            .iter()
            .enumerate()
            .max_by(|x, y| x.1.error.total_cmp(&y.1.error))
            .map_or(0, |(i, _)| i);
        let segment = segments.swap_remove(worst);
        let mid = 0.5 * (segment.start + segment.end);
        if mid <= segment.start || mid >= segment.end {
            // Too narrow to cut: keep its value and stop asking for more.
            segments.push(Segment {
                error: 0.0,
                ..segment
            });
            continue;
        }
        segments.push(gauss_kronrod(&mut f, segment.start, mid));
        segments.push(gauss_kronrod(&mut f, mid, segment.end));
    }
}

/// ∫ f over [start, end] to `tolerance` (see [`integrate_pieces`]).
pub(crate) fn integrate(
    f: impl FnMut(f64) -> f64,
    start: f64,
    end: f64,
    tolerance: Tolerance,
) -> f64 {
    integrate_pieces(f, &[start, end], tolerance)
}

/// A polar frame on the sphere: the pole and two unit vectors across it.
#[derive(Clone, Copy, Debug)]
struct PolarFrame {
    pole: DVec3,
    u: DVec3,
    v: DVec3,
}

impl PolarFrame {
    fn new(pole: DVec3) -> PolarFrame {
        let (u, v) = pole.any_orthonormal_pair();
        PolarFrame { pole, u, v }
    }

    /// The unit direction across the pole at angle ψ.
    fn across(&self, psi: f64) -> DVec3 {
        self.u * psi.cos() + self.v * psi.sin()
    }
}

/// The arc [lo, hi] of χ ∈ [0, π] on the half great circle from the pole
/// towards `across` where m·ω ≥ 0 (m·ω = R cos(χ − δ)); None when empty.
fn arc_in_front(plane: DVec3, pole: DVec3, across: DVec3) -> Option<ArcLimits> {
    let (a, b) = (plane.dot(pole), plane.dot(across));
    if a == 0.0 && b == 0.0 {
        return None;
    }
    let delta = b.atan2(a);
    let arc = if delta.abs() <= FRAC_PI_2 {
        ArcLimits {
            lo: 0.0,
            hi: delta + FRAC_PI_2,
        }
    } else if delta > 0.0 {
        ArcLimits {
            lo: delta - FRAC_PI_2,
            hi: PI,
        }
    } else {
        ArcLimits {
            lo: delta + 1.5 * PI,
            hi: PI,
        }
    };
    (arc.hi > arc.lo).then_some(arc)
}

/// Limits of χ along one half great circle.
#[derive(Clone, Copy, Debug, PartialEq)]
struct ArcLimits {
    lo: f64,
    hi: f64,
}

/// ∫ g(ω) dω over the unit directions ω in front of every plane of
/// `planes` (unit normals, m·ω ≥ 0), in polar coordinates about the unit
/// `pole`, to about `relative` of the result (see the module docs).
pub(crate) fn integrate_in_front_of(
    pole: DVec3,
    planes: &[DVec3],
    relative: f64,
    g: impl Fn(DVec3) -> f64,
) -> f64 {
    let frame = PolarFrame::new(pole);
    let breaks: Vec<f64> = (0..=16).map(|i| TAU * f64::from(i) / 16.0).collect();
    // A coarse first pass sets the scale of the inner integrals' tolerance.
    let coarse = Tolerance {
        absolute: 0.0,
        relative,
        max_segments: 1,
    };
    let rough = integrate_pieces(
        |psi| along_arc(&frame, planes, psi, coarse, &g),
        &breaks,
        Tolerance {
            max_segments: breaks.len() - 1,
            ..coarse
        },
    );
    let inner = Tolerance {
        absolute: 0.1 * relative * rough.abs() / TAU,
        relative,
        max_segments: 100,
    };
    let outer = Tolerance {
        absolute: 0.0,
        relative,
        max_segments: 600,
    };
    integrate_pieces(
        |psi| along_arc(&frame, planes, psi, inner, &g),
        &breaks,
        outer,
    )
}

/// ∫ g(ω(χ, ψ)) sin χ dχ over the arc of χ in front of every plane.
fn along_arc(
    frame: &PolarFrame,
    planes: &[DVec3],
    psi: f64,
    tolerance: Tolerance,
    g: &impl Fn(DVec3) -> f64,
) -> f64 {
    let across = frame.across(psi);
    let mut arc = ArcLimits { lo: 0.0, hi: PI };
    for &plane in planes {
        let Some(limits) = arc_in_front(plane, frame.pole, across) else {
            return 0.0;
        };
        arc = ArcLimits {
            lo: arc.lo.max(limits.lo),
            hi: arc.hi.min(limits.hi),
        };
    }
    if arc.hi <= arc.lo {
        return 0.0;
    }
    let integrand = |chi: f64| {
        let (sin, cos) = chi.sin_cos();
        g(frame.pole * cos + across * sin) * sin
    };
    integrate(integrand, arc.lo, arc.hi, tolerance)
}

#[cfg(test)]
mod tests {
    use super::*;

    const TIGHT: Tolerance = Tolerance {
        absolute: 0.0,
        relative: 1e-13,
        max_segments: 200,
    };

    #[test]
    fn kronrod_is_exact_for_degree_22_and_gauss_for_13() {
        // ∫₀¹ x^k dx = 1/(k + 1); one segment, no bisection.
        for k in 0..=22 {
            let segment = gauss_kronrod(&mut |x: f64| x.powi(k), 0.0, 1.0);
            let exact = 1.0 / f64::from(k + 1);
            assert!(
                (segment.integral - exact).abs() < 1e-15,
                "K15, x^{k}: {}",
                segment.integral
            );
            if k <= 13 {
                assert!(
                    segment.error < 1e-13,
                    "G7 should be exact for x^{k}: {}",
                    segment.error
                );
            }
        }
    }

    #[test]
    fn adaptive_handles_a_kink_and_a_peak() {
        // ∫₋₁² |x| dx = 5/2; ∫₀^π e^(−3x) dx = (1 − e^(−3π))/3.
        let kink = integrate(f64::abs, -1.0, 2.0, TIGHT);
        assert!((kink - 2.5).abs() < 1e-12, "{kink}");
        let peak = integrate(|x: f64| (-3.0 * x).exp(), 0.0, PI, TIGHT);
        assert!(
            (peak - (1.0 - (-3.0 * PI).exp()) / 3.0).abs() < 1e-14,
            "{peak}"
        );
    }

    #[test]
    fn a_degenerate_interval_integrates_to_zero() {
        assert_eq!(integrate(|_| 1.0, 1.0, 1.0, TIGHT), 0.0);
        assert_eq!(integrate_pieces(|_| 1.0, &[1.0], TIGHT), 0.0);
    }

    #[test]
    fn solid_angles_and_projected_solid_angles_of_hemispheres() {
        let up = DVec3::Z;
        let tilted = DVec3::new(0.3, -0.5, 0.4).normalize();
        for pole in [up, tilted, -up, DVec3::X] {
            // The whole sphere, a hemisphere, and a lune between two planes.
            let sphere = integrate_in_front_of(pole, &[], 1e-12, |_| 1.0);
            assert!((sphere - 4.0 * PI).abs() < 1e-10, "{sphere}");
            let hemisphere = integrate_in_front_of(pole, &[up], 1e-12, |_| 1.0);
            assert!((hemisphere - TAU).abs() < 1e-10, "{hemisphere}");
            let projected = integrate_in_front_of(pole, &[up], 1e-12, |w| w.z);
            assert!((projected - PI).abs() < 1e-10, "{projected}");
            // Two planes at angle α between their normals bound a lune of
            // solid angle 2(π − α).
            let alpha = up.angle_between(tilted);
            let lune = integrate_in_front_of(pole, &[up, tilted], 1e-12, |_| 1.0);
            assert!(
                (lune - 2.0 * (PI - alpha)).abs() < 1e-9,
                "{lune} vs {}",
                2.0 * (PI - alpha)
            );
        }
    }
}
