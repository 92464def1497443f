//! Per-camera and per-triangle setup for the rasterizer: sample positions,
//! homogeneous edge functions, near-plane clipping and screen bounds.
//!
//! Everything is expressed with rays through the eye. A sample at
//! tangent-plane coordinates (x, y) looks along the world direction
//! r = x·right + y·up + forward (its forward component is 1, so the ray
//! parameter of a hit is its depth). For a triangle with vertices c_k taken
//! relative to the eye, the edge plane through the eye and edge k (opposite
//! vertex k) has normal m_k = c_{k+1} × c_{k+2}, and
//!
//!   w_k(r) = r · m_k,   D = c_0 · (c_1 × c_2) = n · (p_0 − eye).
//!
//! The ray hits the triangle's plane at depth t = D / Σ w_k, at barycentric
//! coordinates b_k = w_k / Σ w_k. Each w_k is affine in (x, y), so this is
//! exactly perspective-correct interpolation (attribute/w and 1/w affine in
//! screen space), and the sample lies inside the triangle and in front of the
//! eye exactly when every σ·w_k ≥ 0, σ = sign D.
//!
//! Coverage must be decided identically by the two triangles sharing an
//! edge, even for samples on the edge or at a shared vertex. The floating-point
//! e_k = σ·w_k settles it when |e_k| exceeds a rounding bound; otherwise the
//! sign of r · (c_a × c_b) is computed exactly (Shewchuk's adaptive
//! predicate), and an exact zero is broken by symbolic perturbation of the
//! sample towards +right, then −up (the top-left rule). Since
//! r · (c_b × c_a) = −r · (c_a × c_b) exactly, every sample of a mesh without
//! holes is covered exactly once: no cracks and no double coverage.
//!
//! # References
//!
//! - M. Olano, T. Greer, *Triangle scan conversion using 2D homogeneous
//!   coordinates*, Graphics Hardware 1997.
//! - J. Pineda, *A parallel algorithm for polygon rasterization*, SIGGRAPH 1988
//!   (edge functions and the top-left tie rule).
//! - J. R. Shewchuk, *Adaptive precision floating-point arithmetic and fast
//!   robust geometric predicates*, Discrete & Computational Geometry 18, 1997.
//! - H. Edelsbrunner, E. P. Mücke, *Simulation of simplicity*, ACM TOG 9, 1990.

use glam::DVec3;

use super::shaded_triangle::ShadedTriangle;
use crate::rgb::Rgb;
use crate::scene::{Camera, CameraFrame};

/// Near-plane distance relative to the eye's distance h from a triangle's plane.
///
/// A triangle is clipped at depth z_near = `NEAR_PLANE_RELATIVE` · h. Every
/// point of the plane lies at distance ≥ h from the eye, so at depth
/// ≥ h·cos θ when seen at angle θ off the view axis: the clip removes nothing
/// inside any frustum whose half-diagonal is below 89.9999°. It exists to keep
/// the projection of vertices behind or beside the eye finite: nothing is ever
/// projected through the eye.
pub(crate) const NEAR_PLANE_RELATIVE: f64 = 1e-6;

/// A back face's depth is taken this much farther (relatively) in the
/// z-test: a face and its back-to-back twin tie in depth up to rounding
/// (about 10⁻¹⁵), and the face seen from its front must win; a true back
/// face nearer by more than a millionth of its depth (5 µm at 5 m) still
/// hides what is behind it.
pub(crate) const BACK_FACE_DEPTH_BIAS: f64 = 1e-6;

/// The camera's sample grid: where each sample column and row looks.
pub(crate) struct View {
    /// The eye position.
    pub eye: DVec3,
    /// The camera frame (right, up, forward).
    pub frame: CameraFrame,
    /// Sample columns: image width × samples per axis.
    pub columns: u32,
    /// Sample rows: image height × samples per axis.
    pub rows: u32,
    /// Tangent-plane x of each sample column, left to right.
    pub x_of_column: Vec<f64>,
    /// Tangent-plane y of each sample row, top to bottom.
    pub y_of_row: Vec<f64>,
    /// tan(vfov/2) · aspect: tangent-plane x at the image's right border.
    half_width: f64,
    /// tan(vfov/2): tangent-plane y at the image's top border.
    half_height: f64,
    /// Bound on |x| + |y| + 1 over the sample grid, for rounding bounds.
    extent: f64,
}

impl View {
    /// The sample grid of `camera` with `samples_per_axis`² samples per pixel,
    /// or `None` when the camera cannot form an image (non-finite frame,
    /// field of view outside (0°, 180°), zero size, a sample count beyond u32).
    ///
    /// Sample column X (of W·s) looks at u = (X + 0.5)/(W·s),
    /// x = (2u − 1)·tan(vfov/2)·W/H; row Y looks at v = (Y + 0.5)/(H·s),
    /// y = (1 − 2v)·tan(vfov/2). With s = 1 these are the pixel centres.
    pub fn new(camera: &Camera, samples_per_axis: u32) -> Option<View> {
        // Reject what cannot form an image.
        let frame = camera.frame();
        let frame_finite = [frame.right, frame.up, frame.forward, camera.position]
            .iter()
            .all(|v| v.is_finite());
        let vfov_ok = camera.vfov_deg > 0.0 && camera.vfov_deg < 180.0;
        if !frame_finite || !vfov_ok || camera.width == 0 || camera.height == 0 {
            return None;
        }
        // Image-plane extent at unit depth.
        let half_height = (0.5 * camera.vfov_deg.to_radians()).tan();
        let half_width = half_height * f64::from(camera.width) / f64::from(camera.height);
        let columns = camera.width.checked_mul(samples_per_axis)?;
        let rows = camera.height.checked_mul(samples_per_axis)?;
        // Tangent-plane coordinates of the sample grid.
        let x_of_column = (0..columns)
            .map(|x| (2.0 * ((f64::from(x) + 0.5) / f64::from(columns)) - 1.0) * half_width)
            .collect();
        let y_of_row = (0..rows)
            .map(|y| (1.0 - 2.0 * ((f64::from(y) + 0.5) / f64::from(rows))) * half_height)
            .collect();
        Some(View {
            eye: camera.position,
            frame,
            columns,
            rows,
            x_of_column,
            y_of_row,
            half_width,
            half_height,
            extent: half_width + half_height + 1.0,
        })
    }

    /// The direction of the sample ray at tangent-plane (x, y):
    /// r = x·right + y·up + forward, always rounded the same way.
    #[inline]
    pub fn ray(&self, x: f64, y: f64) -> DVec3 {
        x * self.frame.right + y * self.frame.up + self.frame.forward
    }

    /// The (fractional) sample column looking at tangent-plane x.
    pub fn column_of(&self, x: f64) -> f64 {
        0.5 * (x / self.half_width + 1.0) * f64::from(self.columns) - 0.5
    }

    /// The (fractional) sample row looking at tangent-plane y.
    pub fn row_of(&self, y: f64) -> f64 {
        0.5 * (1.0 - y / self.half_height) * f64::from(self.rows) - 0.5
    }
}

/// One edge function e(x, y) = a·x + b·y + c, signed so that the inside is e ≥ 0.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Edge {
    /// Coefficient of tangent-plane x: σ·(right · m).
    pub a: f64,
    /// Coefficient of tangent-plane y: σ·(up · m).
    pub b: f64,
    /// Constant: σ·(forward · m).
    pub c: f64,
    /// Bound on the rounding error of e at any sample: when |e| is below it,
    /// the sign is computed exactly.
    pub tolerance: f64,
}

/// A triangle ready to rasterize.
#[derive(Clone, Debug)]
pub(crate) struct Setup {
    /// Edge functions, edge k opposite vertex k.
    pub edges: [Edge; 3],
    /// |D| = |n · (p_0 − eye)|: the depth of a covered sample is |D| / Σ e_k.
    pub volume: f64,
    /// Samples nearer than this depth are clipped away.
    pub z_near: f64,
    /// Vertex radiance as drawn: zero when the triangle is seen from its back.
    pub radiance: [Rgb; 3],
    /// What a covered sample's depth is multiplied by for the z-test: 1 for
    /// a triangle seen from its front, 1 + [`BACK_FACE_DEPTH_BIAS`] from
    /// its back, so that of two faces back to back (a shade or a panel
    /// modelled as a face each way) the one facing the eye is drawn.
    pub depth_scale: f64,
    /// Vertices relative to the eye, for exact coverage decisions.
    vertices: [DVec3; 3],
    /// σ = sign D, orienting the edge functions.
    sigma: f64,
    /// Inclusive sample-column range that may be covered.
    pub columns: (u32, u32),
    /// Inclusive sample-row range that may be covered.
    pub rows: (u32, u32),
}

impl Setup {
    /// Sets up `triangle` for `view`, or `None` when it cannot cover a sample:
    /// non-finite data, zero area, seen edge-on, entirely behind the near
    /// plane, or outside the image.
    pub fn new(triangle: &ShadedTriangle, view: &View) -> Option<Setup> {
        // Reject non-finite input.
        let finite = triangle.positions.iter().all(|p| p.is_finite())
            && triangle.radiance.iter().all(|l| l.is_finite());
        if !finite {
            return None;
        }
        // Vertices relative to the eye, and the edge planes through the eye.
        let c = triangle.positions.map(|p| p - view.eye);
        let m = [c[1].cross(c[2]), c[2].cross(c[0]), c[0].cross(c[1])];
        // D = c0 · (c1 × c2) = n · (p0 − eye): zero when seen edge-on or degenerate.
        let volume = c[0].dot(m[0]);
        let normal = (c[1] - c[0]).cross(c[2] - c[0]);
        let normal_length = normal.length();
        let has_plane = volume != 0.0 && volume.is_finite() && normal_length > 0.0;
        if !has_plane {
            return None;
        }
        // Orient every edge function so that the inside is positive.
        let sigma = volume.signum();
        let edges = [0, 1, 2].map(|k| edge(m[k] * sigma, c[(k + 1) % 3], c[(k + 2) % 3], view));
        let finite_edge = |e: &Edge| [e.a, e.b, e.c, e.tolerance].iter().all(|v| v.is_finite());
        if !edges.iter().all(finite_edge) {
            return None;
        }
        // One-sided: the front (n · (eye − p0) > 0, i.e. D < 0) carries the
        // radiance, the back is black.
        let (radiance, depth_scale) = if volume < 0.0 {
            (triangle.radiance, 1.0)
        } else {
            ([Rgb::ZERO; 3], 1.0 + BACK_FACE_DEPTH_BIAS)
        };
        // Near plane relative to the eye's distance h = |D|/|n| from the plane.
        let z_near = NEAR_PLANE_RELATIVE * volume.abs() / normal_length;
        let (columns, rows) = screen_bounds(&c, view, z_near)?;
        Some(Setup {
            edges,
            volume: volume.abs(),
            z_near,
            radiance,
            depth_scale,
            vertices: c,
            sigma,
            columns,
            rows,
        })
    }
}

impl Setup {
    /// The edge functions e_k = a_k·x + (b_k·y + c_k) at the sample at
    /// tangent-plane (x, y), with row parts `partial` = b_k·y + c_k, when the
    /// sample is inside the triangle; `None` otherwise.
    ///
    /// Evaluated in exactly this order so that a neighbour sharing an edge,
    /// whose coefficients are the exact negatives, gets the exact negative;
    /// near zero the decision is exact (see the module documentation).
    #[inline]
    pub fn covers(&self, x: f64, y: f64, partial: [f64; 3], view: &View) -> Option<[f64; 3]> {
        let mut e = [0.0; 3];
        for k in 0..3 {
            e[k] = self.edges[k].a * x + partial[k];
            let inside = if e[k].abs() > self.edges[k].tolerance {
                e[k] > 0.0
            } else {
                self.exactly_inside(k, view.ray(x, y), view)
            };
            if !inside {
                return None;
            }
        }
        Some(e)
    }

    /// The row parts b_k·y + c_k of the edge functions at tangent-plane y.
    #[inline]
    pub fn row_parts(&self, y: f64) -> [f64; 3] {
        self.edges.map(|e| e.b * y + e.c)
    }

    /// Whether ray `r` is on the inner side of edge k, decided exactly:
    /// the sign of σ·det(r + δ·right − δ²·up, c_a, c_b) for an infinitesimal
    /// δ > 0 (simulation of simplicity), i.e. of the first non-zero of
    /// det(r, c_a, c_b), det(right, c_a, c_b), −det(up, c_a, c_b).
    #[cold]
    fn exactly_inside(&self, k: usize, r: DVec3, view: &View) -> bool {
        let (a, b) = (self.vertices[(k + 1) % 3], self.vertices[(k + 2) % 3]);
        let perturbed = [(r, 1.0), (view.frame.right, 1.0), (view.frame.up, -1.0)];
        for (direction, sign) in perturbed {
            let det = exact_triple_product_sign(direction, a, b);
            if det != 0.0 {
                return self.sigma * sign * det > 0.0;
            }
        }
        // c_a ∥ c_b: a degenerate edge covers nothing.
        false
    }
}

/// The exact sign (−1, 0 or 1) of d · (a × b) = det[d; a; b].
///
/// `robust::orient3d(pa, pb, pc, pd)` is det[pa − pd; pb − pd; pc − pd],
/// exact for finite inputs without overflow or underflow.
fn exact_triple_product_sign(d: DVec3, a: DVec3, b: DVec3) -> f64 {
    let coord = |v: DVec3| robust::Coord3D {
        x: v.x,
        y: v.y,
        z: v.z,
    };
    let det = robust::orient3d(coord(d), coord(a), coord(b), coord(DVec3::ZERO));
    if det > 0.0 {
        1.0
    } else if det < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// The edge function of the edge plane through the eye and the edge from
/// `from` to `to` (relative to the eye), whose σ-signed normal is `m`.
///
/// The rounding bound 128·ε·‖from‖₁‖to‖₁·(|x| + |y| + 1) generously covers
/// the cross product, the three dot products, the evaluation, and the
/// rounding of the sample direction r that the exact test uses.
fn edge(m: DVec3, from: DVec3, to: DVec3, view: &View) -> Edge {
    let frame = view.frame;
    let scale = from.abs().element_sum() * to.abs().element_sum() * view.extent;
    Edge {
        a: frame.right.dot(m),
        b: frame.up.dot(m),
        c: frame.forward.dot(m),
        tolerance: 128.0 * f64::EPSILON * scale,
    }
}

/// Inclusive sample column and row ranges covering the triangle (vertices
/// `c` relative to the eye) once clipped to depth ≥ `z_near`, with one
/// sample of margin; `None` when nothing is left on screen.
fn screen_bounds(c: &[DVec3; 3], view: &View, z_near: f64) -> Option<((u32, u32), (u32, u32))> {
    // Camera space: (right, up, forward) components, the last being depth.
    let frame = view.frame;
    let camera = c.map(|v| DVec3::new(frame.right.dot(v), frame.up.dot(v), frame.forward.dot(v)));
    // Clip the triangle against depth ≥ z_near (Sutherland–Hodgman, one plane).
    let mut clipped = [DVec3::ZERO; 4];
    let mut count = 0;
    for (k, &current) in camera.iter().enumerate() {
        let next = camera[(k + 1) % 3];
        if current.z >= z_near {
            clipped[count] = current;
            count += 1;
        }
        if (current.z >= z_near) != (next.z >= z_near) {
            let t = (z_near - current.z) / (next.z - current.z);
            let mut crossing = current + (next - current) * t;
            crossing.z = z_near;
            clipped[count] = crossing;
            count += 1;
        }
    }
    // Project what is left and bound it in sample units.
    let (mut column_min, mut column_max) = (f64::INFINITY, f64::NEG_INFINITY);
    let (mut row_min, mut row_max) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in &clipped[..count] {
        let column = view.column_of(v.x / v.z);
        let row = view.row_of(v.y / v.z);
        column_min = column_min.min(column);
        column_max = column_max.max(column);
        row_min = row_min.min(row);
        row_max = row_max.max(row);
    }
    let columns = clamp_range(column_min, column_max, view.columns)?;
    let rows = clamp_range(row_min, row_max, view.rows)?;
    Some((columns, rows))
}

/// The integer range [floor(lo) − 1, ceil(hi) + 1] ∩ [0, count − 1], or
/// `None` when empty. A NaN bound leaves its side unbounded (never narrower).
pub(crate) fn clamp_range(lo: f64, hi: f64, count: u32) -> Option<(u32, u32)> {
    let last = f64::from(count) - 1.0;
    let lo = (lo.floor() - 1.0).max(0.0);
    let hi = (hi.ceil() + 1.0).min(last);
    // `as` saturates; both bounds are within [0, count − 1] here.
    (lo <= hi).then_some((lo as u32, hi as u32))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> Camera {
        Camera {
            position: DVec3::ZERO,
            look_at: DVec3::Z,
            up: DVec3::Y,
            vfov_deg: 90.0,
            width: 4,
            height: 2,
        }
    }

    #[test]
    fn sample_grid_is_symmetric_and_inverts() {
        let view = View::new(&camera(), 1).expect("valid camera");
        // Aspect 2, tan 45° = 1: columns at ±0.25, ±0.75 of the half-width 2.
        let close = |got: &[f64], expected: &[f64]| {
            got.iter().zip(expected).all(|(g, e)| (g - e).abs() < 1e-15)
        };
        assert!(close(&view.x_of_column, &[-1.5, -0.5, 0.5, 1.5]));
        assert!(close(&view.y_of_row, &[0.5, -0.5]));
        for (k, &x) in view.x_of_column.iter().enumerate() {
            assert!((view.column_of(x) - k as f64).abs() < 1e-12);
        }
        for (k, &y) in view.y_of_row.iter().enumerate() {
            assert!((view.row_of(y) - k as f64).abs() < 1e-12);
        }
    }

    #[test]
    fn degenerate_cameras_are_rejected() {
        let mut bad = camera();
        bad.look_at = bad.position;
        assert!(View::new(&bad, 1).is_none());
        let mut bad = camera();
        bad.vfov_deg = 180.0;
        assert!(View::new(&bad, 1).is_none());
        let mut bad = camera();
        bad.width = 0;
        assert!(View::new(&bad, 1).is_none());
    }

    #[test]
    fn exact_triple_product_has_the_sign_of_the_determinant() {
        assert_eq!(exact_triple_product_sign(DVec3::X, DVec3::Y, DVec3::Z), 1.0);
        assert_eq!(
            exact_triple_product_sign(DVec3::X, DVec3::Z, DVec3::Y),
            -1.0
        );
        assert_eq!(exact_triple_product_sign(DVec3::X, DVec3::X, DVec3::Z), 0.0);
        // Plain f64 rounds this to 0: (1e-30, 1, 0) · ((1, 0, 1e15) × (0, 0, 1)) = −1.
        let d = DVec3::new(1e-30, 1.0, 0.0);
        assert_eq!(
            exact_triple_product_sign(d, DVec3::new(1.0, 0.0, 1e15), DVec3::Z),
            -1.0
        );
    }

    #[test]
    fn clamp_range_handles_nan_and_infinity() {
        assert_eq!(
            clamp_range(f64::NEG_INFINITY, f64::INFINITY, 10),
            Some((0, 9))
        );
        assert_eq!(clamp_range(f64::NAN, 3.0, 10), Some((0, 4)));
        assert_eq!(clamp_range(12.0, 15.0, 10), None);
        assert_eq!(clamp_range(2.2, 2.7, 10), Some((1, 4)));
    }
}
