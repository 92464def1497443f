//! The gradient of Lambert's point-to-polygon form factor with respect to the
//! receiving point (Arvo's irradiance Jacobian, for a fixed normal).

use super::form_factor::with_clipped;
use glam::DVec3;
use std::f64::consts::PI;

/// Edges seen from the point under a sine smaller than this (the point on the
/// edge's line, or at a vertex) contribute nothing.
const DEGENERATE_SINE: f64 = 1e-12;

/// Gradient of the exact, unoccluded form factor F of
/// [`polygon_form_factor`](super::polygon_form_factor) with respect to moving
/// the receiving `point`, its unit `normal` held fixed.
///
/// Lambert's formula is a sum over the edges e = (A, B) of the polygon clipped
/// to the receiver's front half-space, F = (1/2π) |Σ_e γ_e n·u_e|. With
/// a = A − p, b = B − p, L = |B − A|, the edge direction ê = (B − A)/L, the
/// unit normal of the plane through p and the edge u = a×b/|a×b|, the
/// subtended angle γ = atan2(|a×b|, a·b), the distance from p to the edge's
/// line δ = |a×b|/L, the unit vector from p towards that line ŵ = ê×u, and
/// t_a = a·ê, t_b = b·ê (so γ = atan(t_b/δ) − atan(t_a/δ)):
///
/// ```text
///   ∇γ = −ê δ (1/|b|² − 1/|a|²) + ŵ (t_b/|b|² − t_a/|a|²)
///   ∇u = ŵ uᵀ / δ          (so ∇(n·u) = (n·ŵ) u / δ)
///   ∇F = ± (1/2π) Σ_e [ (n·u_e) ∇γ_e + γ_e (n·ŵ_e) u_e / δ_e ]
/// ```
///
/// the sign being that of the sum inside |…|. With the vector irradiance
/// Φ = (1/2π) Σ_e γ_e u_e (so F = |n·Φ|) this is ∇F = ± Jᵀn, where
/// J = ∂Φ/∂p is Arvo's irradiance Jacobian of an unoccluded polygon, whose
/// per-edge terms are written here in each edge's own frame.
///
/// The result is the full 3-D gradient: moving the point along the normal
/// moves its plane too. The gradient within the receiver's plane is
/// g − (g·n) n.
///
/// **Clipping.** A source partly behind the receiver's plane is clipped to
/// n·(x − p) ≥ 0 first, and the clip vertices are treated as fixed, though
/// they move with p. They contribute nothing: F is the integral of
/// cosθ_r cosθ_s/(π r²) over the clipped region, and by Reynolds' transport
/// theorem moving its boundary adds the integrand on the moving part, the
/// clip segment, times its normal velocity; on the clip segment, which lies
/// in the receiver's plane, cosθ_r = 0. (The tests check this against
/// finite differences of the clipped F.)
///
/// **Degenerate input.** Edges seen under a sine below 10⁻¹² (the point on
/// the edge's line or at one of its vertices) are skipped, as in F itself,
/// and so is any edge term that overflows; the result is always finite. Near
/// a source edge lying in the receiver's plane the true gradient grows like
/// log(1/distance), and so does the returned one. A polygon wholly behind
/// the receiver gives the zero vector.
///
/// # References
/// J. Arvo, "The Irradiance Jacobian for Partially Occluded Polyhedral
/// Sources", SIGGRAPH 1994, §3–4. N. Holzschuch, F. Sillion, "Accurate
/// Computation of the Radiosity Gradient with Constant and Linear Emitters",
/// Eurographics Rendering Workshop 1995.
#[must_use]
pub fn polygon_form_factor_gradient(point: DVec3, normal: DVec3, polygon: &[DVec3]) -> DVec3 {
    polygon_form_factor_with_gradient(point, normal, polygon).1
}

/// The form factor F of [`polygon_form_factor`](super::polygon_form_factor)
/// and its gradient [`polygon_form_factor_gradient`] together, sharing the
/// clipping and the per-edge work. See those functions for the formulas and
/// the treatment of degenerate input.
///
/// # References
/// J. Arvo, "The Irradiance Jacobian for Partially Occluded Polyhedral
/// Sources", SIGGRAPH 1994.
#[must_use]
pub fn polygon_form_factor_with_gradient(
    point: DVec3,
    normal: DVec3,
    polygon: &[DVec3],
) -> (f64, DVec3) {
    with_clipped(point, normal, polygon, |clipped| {
        // Fewer than three vertices in front: no light, no change.
        if clipped.len() < 3 {
            return (0.0, DVec3::ZERO);
        }
        // Sum Lambert's edge terms and their gradients.
        let mut sum = 0.0;
        let mut gradient = DVec3::ZERO;
        for i in 0..clipped.len() {
            let a = clipped[i] - point;
            let b = clipped[(i + 1) % clipped.len()] - point;
            if let Some((term, term_gradient)) = edge_term(a, b, normal) {
                sum += term;
                gradient += term_gradient;
            }
        }
        // F = |sum|/2π: the gradient takes the sum's sign.
        let sign = if sum < 0.0 { -1.0 } else { 1.0 };
        let value = (sum.abs() / (2.0 * PI)).min(1.0);
        (value, gradient * (sign / (2.0 * PI)))
    })
}

/// One edge's γ n·u and its gradient with respect to the point, from the
/// edge's end points relative to the point; `None` for a degenerate edge.
fn edge_term(a: DVec3, b: DVec3, normal: DVec3) -> Option<(f64, DVec3)> {
    // The plane through the point and the edge, and the angle it subtends.
    let cross = a.cross(b);
    let cross_length = cross.length();
    let (a2, b2) = (a.length_squared(), b.length_squared());
    // (Written so that NaN input also counts as degenerate.)
    let seen = cross_length > DEGENERATE_SINE * (a2 * b2).sqrt();
    if !seen {
        return None;
    }
    let u = cross / cross_length;
    let gamma = cross_length.atan2(a.dot(b));
    // The edge frame: direction ê, distance δ to its line, unit ŵ towards it.
    let edge = b - a;
    let length = edge.length();
    let e = edge / length;
    let delta = cross_length / length;
    let w = e.cross(u);
    // ∇γ from γ = atan(t_b/δ) − atan(t_a/δ), with ∇t = −ê and ∇δ = −ŵ.
    let grad_gamma = -e * (delta * (1.0 / b2 - 1.0 / a2)) + w * (b.dot(e) / b2 - a.dot(e) / a2);
    // ∇(n·u) = (n·ŵ) u / δ: the plane turns about the edge as the point moves.
    let n_u = normal.dot(u);
    let term_gradient = grad_gamma * n_u + u * (gamma * normal.dot(w) / delta);
    let term = gamma * n_u;
    (term.is_finite() && term_gradient.is_finite()).then_some((term, term_gradient))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::radiometry::polygon_form_factor;

    fn square(height: f64) -> [DVec3; 4] {
        [
            DVec3::new(-1.0, -1.0, height),
            DVec3::new(1.0, -1.0, height),
            DVec3::new(1.0, 1.0, height),
            DVec3::new(-1.0, 1.0, height),
        ]
    }

    #[test]
    fn a_polygon_in_the_receivers_plane_gives_no_value_and_no_gradient() {
        // A point inside a square of its own plane, facing either way.
        let polygon = square(0.0);
        for normal in [DVec3::Z, DVec3::NEG_Z] {
            let got =
                polygon_form_factor_with_gradient(DVec3::new(0.2, -0.3, 0.0), normal, &polygon);
            assert_eq!(got, (0.0, DVec3::ZERO));
        }
    }

    #[test]
    fn value_matches_polygon_form_factor() {
        let polygon = square(1.5);
        for p in [
            DVec3::ZERO,
            DVec3::new(0.7, -2.0, 0.3),
            DVec3::new(3.0, 1.0, -1.0),
        ] {
            let n = DVec3::new(0.2, 0.1, 1.0).normalize();
            let (f, _) = polygon_form_factor_with_gradient(p, n, &polygon);
            assert!((f - polygon_form_factor(p, n, &polygon)).abs() < 1e-15);
        }
    }

    #[test]
    fn gradient_vanishes_under_the_centre_of_a_parallel_square() {
        let g = polygon_form_factor_gradient(DVec3::ZERO, DVec3::Z, &square(1.0));
        // Symmetry in x and y; moving up towards the square increases F.
        assert!(g.x.abs() < 1e-15 && g.y.abs() < 1e-15 && g.z > 0.0, "{g}");
    }

    #[test]
    fn degenerate_input_gives_zero_or_finite_values() {
        let wall = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 1.0),
            DVec3::new(0.0, 0.0, 1.0),
        ];
        // On a vertex, on an edge, on an edge's line, just off an edge.
        for p in [
            DVec3::ZERO,
            DVec3::new(0.5, 0.0, 0.0),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.5, 1e-300, 0.0),
            DVec3::new(0.5, 1e-9, 0.0),
        ] {
            let (f, g) = polygon_form_factor_with_gradient(p, DVec3::Y, &wall);
            assert!(f.is_finite() && g.is_finite(), "{p}: {f} {g}");
        }
        // A NaN vertex: its edges are skipped.
        let mut broken = wall;
        broken[2].x = f64::NAN;
        let (f, g) =
            polygon_form_factor_with_gradient(DVec3::new(0.5, -1.0, 0.5), DVec3::Y, &broken);
        assert!(f.is_finite() && g.is_finite(), "{f} {g}");
        // Empty, too short, wholly behind the receiver, repeated vertices.
        let behind = square(-1.0);
        let repeated = [DVec3::Z; 3];
        for polygon in [&[][..], &wall[..2], &behind[..], &repeated[..]] {
            let (f, g) = polygon_form_factor_with_gradient(DVec3::ZERO, DVec3::Z, polygon);
            assert_eq!((f, g), (0.0, DVec3::ZERO));
        }
    }
}
