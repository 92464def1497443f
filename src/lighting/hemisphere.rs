//! Cosine-weighted directions on the hemisphere about a normal: the rays
//! that find the closed zones and those of the ambient term.

use glam::DVec3;

use super::sample_stream::SampleStream;

/// A cosine-weighted direction about the unit `normal` (Malley's method:
/// a uniform point of the unit disc lifted onto the hemisphere).
pub(crate) fn cosine_direction(normal: DVec3, random: &mut SampleStream) -> DVec3 {
    cosine_direction_at(normal, random.next_f64(), random.next_f64())
}

/// The cosine-weighted direction about the unit `normal` of the unit
/// square's point (u₁, u₂): radius √u₁ and angle 2π u₂ on the disc, lifted.
/// Strata of the square are strata of the projected solid angle.
pub(crate) fn cosine_direction_at(normal: DVec3, u1: f64, u2: f64) -> DVec3 {
    let (radius, angle) = (u1.sqrt(), std::f64::consts::TAU * u2);
    let tangent = normal.any_orthonormal_vector();
    let bitangent = normal.cross(tangent);
    (tangent * (radius * angle.cos())
        + bitangent * (radius * angle.sin())
        + normal * (1.0 - u1).max(0.0).sqrt())
    .normalize()
}
