//! A probe read on the mesh ([`crate::ProbeMode::Mesh`]): the
//! piecewise-linear value the renderer shows, interpolated on the
//! triangle under the point, with its in-plane gradient.

use glam::{DVec2, DVec3};

use crate::rgb::Rgb;
use crate::scene::{SurfaceId, distance_to_segment};
use crate::solver::reading::solution::{Probe, Solution};

impl Solution<'_> {
    /// The mesh's piecewise-linear value at a point of a surface, split into
    /// triangles as the renderer splits it. A point that no element covers
    /// lies where meshing dropped the surface as hidden (under a block
    /// standing on it, behind a book a millimetre away,
    /// `mesh/assembly/contacts.rs`): no light reaches it, and the renderer shows
    /// none of it, so it gets no irradiance and only its own emission.
    pub(super) fn interpolate(&self, position: DVec3, surface: SurfaceId) -> Probe {
        let normal = self.scene.surface(surface).normal();
        let frame = self.scene.surface(surface).frame();
        let at = frame.to_plane(position);
        let hidden = Probe {
            position,
            surface,
            irradiance: Rgb::ZERO,
            standard_error: Rgb::ZERO,
            radiosity: self
                .scene
                .material_of(self.scene.surface(surface))
                .emitted_radiosity(),
            gradient: [DVec3::ZERO; 3],
        };
        let radiosity = |v: u32| self.radiosity_at(v as usize);
        let gap = |p: u32, q: u32| (radiosity(p) - radiosity(q)).abs().element_sum();
        let mut best: Option<(f64, [u32; 3], [f64; 3])> = None;
        let mut split = Vec::new();
        for element in self.mesh.elements.iter().filter(|e| e.surface == surface) {
            self.mesh.element_triangles(element, gap, &mut split);
            for &triangle in &split {
                let [a, b, c] = triangle.map(|v| self.mesh.vertices[v as usize].position);
                let weights = barycentric(position, a, b, c, normal);
                // How far outside the triangle (0 inside).
                let corners = [a, b, c].map(|q| frame.to_plane(q));
                let outside = distance_outside_triangle(at, corners, weights);
                if best.is_none_or(|(o, _, _)| outside < o) {
                    best = Some((outside, triangle, weights));
                }
            }
        }
        // Farther from every element than a point may be from its surface
        // (`Solution::locate`'s tolerance): in a dropped part.
        let covered = 1e-4 * self.scene.diagonal();
        let Some((_, triangle, weights)) = best.filter(|&(outside, _, _)| outside <= covered)
        else {
            return hidden;
        };
        let weights = weights.map(|w| w.max(0.0));
        let total: f64 = weights.iter().sum();
        let value = |at: &dyn Fn(u32) -> Rgb| {
            (0..3)
                .map(|k| at(triangle[k]) * (weights[k] / total))
                .sum::<Rgb>()
        };
        let [a, b, c] = triangle.map(|v| self.mesh.vertices[v as usize].position);
        let gradients = barycentric_gradients(a, b, c, normal);
        let gradient = [0, 1, 2].map(|channel| {
            (0..3)
                .map(|k| gradients[k] * radiosity(triangle[k]).to_array()[channel])
                .sum()
        });
        Probe {
            position,
            surface,
            irradiance: value(&|v| self.irradiance_at(v as usize)),
            standard_error: Rgb::ZERO,
            radiosity: value(&radiosity),
            gradient,
        }
    }
}

/// The distance from `p` to the triangle `corners` (plane coordinates), 0
/// inside it, given `p`'s barycentric `weights` there: the distance to the
/// nearest of its sides when a weight is negative. Infinite for weights a
/// degenerate triangle leaves undefined: it covers nothing.
fn distance_outside_triangle(p: DVec2, corners: [DVec2; 3], weights: [f64; 3]) -> f64 {
    if !weights.iter().all(|w| w.is_finite()) {
        return f64::INFINITY;
    }
    if weights.iter().all(|&w| w >= 0.0) {
        return 0.0;
    }
    (0..3)
        .map(|k| distance_to_segment(p, corners[k], corners[(k + 1) % 3]))
        .fold(f64::INFINITY, f64::min)
}

/// Barycentric weights of `p` (projected onto the triangle's plane) in the
/// triangle (a, b, c) whose front normal is `normal`.
fn barycentric(p: DVec3, a: DVec3, b: DVec3, c: DVec3, normal: DVec3) -> [f64; 3] {
    let twice_area = (b - a).cross(c - a).dot(normal);
    if twice_area.abs() <= f64::MIN_POSITIVE {
        return [-f64::INFINITY; 3];
    }
    let wa = (c - b).cross(p - b).dot(normal) / twice_area;
    let wb = (a - c).cross(p - c).dot(normal) / twice_area;
    [wa, wb, 1.0 - wa - wb]
}

/// Gradients of the barycentric coordinates of a counter-clockwise triangle:
/// ∇λ_a = n × (c − b) / (2A), and cyclically.
fn barycentric_gradients(a: DVec3, b: DVec3, c: DVec3, normal: DVec3) -> [DVec3; 3] {
    let twice_area = (b - a).cross(c - a).dot(normal);
    if twice_area.abs() <= f64::MIN_POSITIVE {
        return [DVec3::ZERO; 3];
    }
    [
        normal.cross(c - b) / twice_area,
        normal.cross(a - c) / twice_area,
        normal.cross(b - a) / twice_area,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    const SLIVER: [DVec2; 3] = [
        DVec2::new(0.0, 0.0),
        DVec2::new(1.0, 0.0),
        DVec2::new(1.0, 0.01),
    ];

    /// The weights of `p` in the sliver, through the 3-D barycentric.
    fn weights(p: DVec2) -> [f64; 3] {
        let lift = |q: DVec2| DVec3::new(q.x, q.y, 0.0);
        let [a, b, c] = SLIVER.map(lift);
        barycentric(lift(p), a, b, c, DVec3::Z)
    }

    #[test]
    fn the_distance_outside_a_triangle_is_to_its_nearest_side() {
        let inside = DVec2::new(0.9, 0.005);
        assert_eq!(
            distance_outside_triangle(inside, SLIVER, weights(inside)),
            0.0
        );
        // Beyond the sharp corner at the origin: a unit from it, where the
        // sides' lines are a hundredth away.
        let beyond = DVec2::new(-1.0, 0.005);
        let d = distance_outside_triangle(beyond, SLIVER, weights(beyond));
        assert!((d - 1.0).abs() < 1e-4, "{d}");
        let below = DVec2::new(0.5, -0.25);
        let d = distance_outside_triangle(below, SLIVER, weights(below));
        assert!((d - 0.25).abs() < 1e-12, "{d}");
    }

    #[test]
    fn a_degenerate_triangle_covers_nothing() {
        let flat = [DVec2::ZERO, DVec2::X, 2.0 * DVec2::X];
        let lift = |q: DVec2| DVec3::new(q.x, q.y, 0.0);
        let [a, b, c] = flat.map(lift);
        let p = DVec2::new(0.5, 0.0);
        let w = barycentric(lift(p), a, b, c, DVec3::Z);
        assert_eq!(distance_outside_triangle(p, flat, w), f64::INFINITY);
    }
}
