//! The contour mesher's levels: how many, and where between the field's top
//! and bottom, for an even interpolation error along the rays.

use glam::DVec2;

use super::contour_rays::Ray;
use super::scalar_field::ScalarField;
use crate::scene::polygon_contains;

/// How the levels are spaced along the rays.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum LevelRule {
    /// K levels for the least RMS error over the polygon.
    LeastSquares,
    /// As many levels as keep linear interpolation along every ray within
    /// this fraction of the local value (at least K).
    RelativeError(f64),
}

/// Below this fraction of the top, the relative-error rule treats the field
/// as this fraction of the top: a receiver's light that ends at a
/// luminaire's horizon need not be meshed to a relative error of nothing.
pub(crate) const RELATIVE_FLOOR: f64 = 1e-3;

/// The most levels the relative-error rule adds.
const MAX_LEVELS: usize = 64;

/// Chooses levels between the field's top and bottom over the polygon,
/// spaced equally in a measure S(t) = ∫ ρ(t) dt along each ray: each ray
/// gives S as a function of B, their average (normalised to [0, 1] per
/// ray) is inverted at k/(K + 1), k = 1…K.
///
/// Linear interpolation over a radial step h of a function with curvature
/// B'' errs by about h² |B''| / 8.
///
/// - [`LevelRule::LeastSquares`]: the ring at distance t from the centre
///   covers an area ∝ t h, so its share of the squared error is
///   ∝ t h⁵ B''²; minimising the sum for K rings equalises t h⁵ B''², that
///   is, ρ = (t B''²)^(1/5). On the seed's case (a small disc over a
///   10 × 10 plane, flat or tilted 30°) this halves the RMS error of 20 × 5
///   meshes against equal steps of ∫ √|B''| dt; but it leaves the dim
///   periphery, which weighs nothing in the RMS, with rings metres apart.
/// - [`LevelRule::RelativeError`] ε: a step h errs by ε of the local value
///   where h = √(8 ε B / |B''|), so ρ = √(|B''| / (8 ε B)) and S(end) is
///   the number of steps the ray needs. K is the largest S(end) over the
///   rays (at least the K asked for, at most 64): the periphery, where B is
///   small but so is its curvature, gets its share of rings, which is what
///   a tone-mapped picture needs. B is floored at 10⁻³ of the top. So that
///   the RMS error stays low too, ρ is the larger of this density and the
///   least-squares one scaled to the same total along the ray: the bright
///   core gets the rings the RMS error wants, and nowhere gets fewer than
///   the relative error needs.
pub(super) fn choose_levels(
    outline: &[DVec2],
    field: &ScalarField,
    centre: DVec2,
    rays: &[Ray],
    count: usize,
    rule: LevelRule,
) -> Vec<f64> {
    let top = if polygon_contains(outline, centre) {
        field(centre).0
    } else {
        boundary_extreme(outline, field, true)
    };
    let bottom = boundary_extreme(outline, field, false).max(0.0);
    if top.is_nan() || top <= bottom {
        return Vec::new();
    }
    // Per ray: S(end), and the normalised S at each sample, with B.
    let measured: Vec<(f64, Vec<(f64, f64)>)> = rays
        .iter()
        .filter_map(|ray| match rule {
            LevelRule::LeastSquares => level_measure(ray, &least_squares_density),
            LevelRule::RelativeError(target) => {
                let relative = |_: f64, value: f64, curvature: f64| {
                    (curvature / (8.0 * target * value.max(RELATIVE_FLOOR * top))).sqrt()
                };
                // ρ = max(ρ_rel, ρ_L² scaled to the same total).
                let steps = level_measure(ray, &relative)?.0;
                let scale = steps / level_measure(ray, &least_squares_density)?.0;
                let both = |t: f64, value: f64, curvature: f64| {
                    relative(t, value, curvature)
                        .max(scale * least_squares_density(t, value, curvature))
                };
                level_measure(ray, &both)
            }
        })
        .collect();
    let count = match rule {
        LevelRule::LeastSquares => count,
        LevelRule::RelativeError(_) => {
            let steps = measured.iter().map(|m| m.0).fold(0.0, f64::max);
            let needed = (steps.ceil() as usize).saturating_sub(1);
            needed.clamp(count, MAX_LEVELS.max(count))
        }
    };
    let profiles: Vec<&Vec<(f64, f64)>> = measured.iter().map(|m| &m.1).collect();
    // s̄(B): the mean over rays of the share of S above level B.
    let mean_share = |level: f64| {
        let shares = profiles.iter().map(|profile| {
            match profile
                .windows(2)
                .find(|w| w[0].1 >= level && w[1].1 < level)
            {
                Some(w) => w[0].0 + (w[1].0 - w[0].0) * (w[0].1 - level) / (w[0].1 - w[1].1),
                None => 1.0,
            }
        });
        shares.sum::<f64>() / profiles.len().max(1) as f64
    };
    (1..=count)
        .map(|k| {
            let target = k as f64 / (count + 1) as f64;
            if profiles.is_empty() {
                return top + (bottom - top) * target;
            }
            // Bisection on the level: s̄ decreases as the level rises.
            let (mut high, mut low) = (top, bottom);
            for _ in 0..60 {
                let mid = 0.5 * (high + low);
                if mean_share(mid) < target {
                    high = mid
                } else {
                    low = mid
                }
            }
            0.5 * (high + low)
        })
        .collect()
}

/// The least-squares rule's density ρ = (t B''²)^(1/5) at distance t.
fn least_squares_density(t: f64, _value: f64, curvature: f64) -> f64 {
    (t * curvature * curvature).powf(0.2)
}

/// A ray's level measure S = ∫ ρ dt, with ρ = `density(t, B, |B''|)` from
/// finite differences of the sampled values: S(end), and (S(t)/S(end), B(t))
/// at its samples. None if flat.
fn level_measure(
    ray: &Ray,
    density: &dyn Fn(f64, f64, f64) -> f64,
) -> Option<(f64, Vec<(f64, f64)>)> {
    let s = &ray.samples;
    if s.len() < 3 {
        return None;
    }
    let mut measure = vec![0.0; s.len()];
    for i in 1..s.len() {
        let j = i.clamp(1, s.len() - 2);
        let h = s[j + 1].0 - s[j].0;
        let curvature = ((s[j + 1].1 - 2.0 * s[j].1 + s[j - 1].1) / (h * h)).abs();
        let rho = density(s[i].0, s[i].1, curvature);
        measure[i] =
            measure[i - 1] + if rho.is_finite() { rho } else { 0.0 } * (s[i].0 - s[i - 1].0);
    }
    let total = *measure.last()?;
    (total > 0.0).then(|| {
        let profile = measure
            .iter()
            .zip(s)
            .map(|(m, &(_, b))| (m / total, b))
            .collect();
        (total, profile)
    })
}

/// The largest (or smallest) value of the field on the polygon's boundary,
/// from samples along each edge.
fn boundary_extreme(outline: &[DVec2], field: &ScalarField, largest: bool) -> f64 {
    let mut best = if largest {
        f64::NEG_INFINITY
    } else {
        f64::INFINITY
    };
    for k in 0..outline.len() {
        let (a, b) = (outline[k], outline[(k + 1) % outline.len()]);
        for i in 0..32 {
            let value = field(a.lerp(b, i as f64 / 32.0)).0;
            best = if largest {
                best.max(value)
            } else {
                best.min(value)
            };
        }
    }
    best
}
