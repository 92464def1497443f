//! What the rasterizer draws: triangles with radiance at their vertices.

use glam::DVec3;

use crate::rgb::Rgb;

/// A triangle with a radiance value at each vertex, W/(m²·sr).
///
/// One-sided: the front is the side from which p0, p1, p2 appear
/// counter-clockwise, the side the normal n = (p1 − p0) × (p2 − p0) points to.
/// Seen from the back (n · (eye − p0) ≤ 0) the triangle is drawn black but
/// still hides what lies behind it, like a one-sided surface in pbrt or
/// Mitsuba.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadedTriangle {
    /// Vertex positions, world space.
    pub positions: [DVec3; 3],
    /// Radiance at each vertex, W/(m²·sr), linear RGB.
    pub radiance: [Rgb; 3],
}
