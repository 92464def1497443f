//! The radial contour-level mesher.
//!
//! On a receiver lit by one dominant small emitter, the emitter's direct
//! radiosity B(x) is unimodal: it rises to a single maximum, the centre c,
//! and every ray from c crosses each of its contours once. The mesher puts
//! vertices where D rays from c cross K chosen levels B_1 > … > B_K, found by
//! Newton's method with the analytic directional derivative ∇B·u, so that
//! element edges follow the iso-radiosity contours and the piecewise-linear
//! interpolation is exact along them.
//!
//! The mesh knows nothing of light: it meshes the level sets of any unimodal
//! scalar field on a polygon, given as a value-and-gradient function in the
//! polygon's plane coordinates. The solver builds that field and hands it
//! down.
//!
//! # References
//! P. Arquès, V. Biri, S. Derpierre, "A new formulation of differential
//! radiosity and a rendering application", WSCG 2005, §4.

use glam::DVec2;
use std::f64::consts::TAU;

use super::constrained::{PlaneTriangulation, triangulate_constrained};
use super::contour_levels::{LevelRule, choose_levels};
use super::contour_rays::{Ray, segment_ray_crossing};
use super::scalar_field::ScalarField;
use crate::scene::{distance_to_boundary, polygon_contains};

/// Size and orientation of a contour mesh. In a scene file:
/// `[mesh.contour]` with `directions` and `levels`.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct ContourSettings {
    /// D: rays from the centre, spread uniformly in angle.
    pub directions: usize,
    /// K: contour levels between the maximum and the polygon's minimum
    /// (with `max_relative_error`, the fewest: more are added where the
    /// field needs them).
    pub levels: usize,
    /// The relative interpolation error the layout aims for, everywhere on
    /// the receiver (0.01): levels are added until linear interpolation
    /// along every ray errs by about this fraction of the local value, and
    /// contour pieces are split (with a new ray through the middle) until
    /// the field at a piece's midpoint is within it of the level. This is
    /// what a tone-mapped picture shows in its dim parts. 0 lays out
    /// exactly `directions` × `levels`, spaced for the least RMS error (the
    /// seed's fixed layouts, as `isorad compare` sweeps them).
    pub max_relative_error: f64,
    /// Angle of the first ray, radians, in plane coordinates (the solver
    /// aligns it with the emitter's tilt so the mesh is symmetric with the
    /// light). Not read from files (`serde(skip)`): the solver sets it for
    /// every receiver, so a value written there would have no effect.
    #[serde(skip)]
    pub orientation: f64,
}

impl Default for ContourSettings {
    /// At least 16 directions × 8 levels, refined to a relative error of
    /// 1 %. (The seed paper recommends 20 × 5; at about the same vertex
    /// count, a fixed 16 × 8 halves the RMS error on the seed's case, but
    /// leaves the dim periphery 10–20 % off.)
    fn default() -> Self {
        ContourSettings {
            directions: 16,
            levels: 8,
            max_relative_error: 0.01,
            orientation: 0.0,
        }
    }
}

/// Where a contour mesh's vertices go, before triangulation.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ContourLayout {
    /// The field's maximum.
    pub centre: DVec2,
    /// The levels, decreasing.
    pub levels: Vec<f64>,
    /// Points to triangulate (the outline is added by the triangulation).
    pub points: Vec<DVec2>,
    /// Segments the triangulation must keep as edges: pieces of contours.
    pub constraints: Vec<[DVec2; 2]>,
    /// For each point of `points`, the level it lies on, if any.
    pub point_levels: Vec<Option<usize>>,
    /// Newton iterations spent placing vertices on levels.
    pub newton_iterations: usize,
    /// Vertices placed on levels by Newton's method.
    pub newton_solves: usize,
    /// Vertices added on and beside shadow boundaries.
    pub shadow_points: usize,
    /// The points where half the light is hidden (penumbrae's middles).
    pub shadow_boundary: Vec<DVec2>,
    /// The ring vertices by level, with the angle of their ray (`None`: the
    /// level is not reached inside the polygon in that direction). Used to
    /// find shadow boundaries along rings and rays.
    rings: Vec<Vec<(f64, Option<DVec2>)>>,
}

/// Lays out a contour mesh of `field` on the polygon `outline` (plane
/// coordinates, counter-clockwise), around `centre`, the field's maximum
/// (which may lie outside the polygon).
///
/// The levels are chosen for even interpolation error (see
/// `choose_levels`); each vertex X_{k,d} solves B(c + t u_d) = B_k by
/// safeguarded Newton; vertices outside the polygon are dropped, and where a
/// level meets the polygon's boundary the crossing becomes a vertex, so
/// levels not reached in some directions and non-convex polygons are
/// handled. `extra_constraints` (such as the line where a tilted emitter's
/// plane cuts the receiver's, beyond which its light ends) are kept as
/// edges, with vertices along them.
#[must_use]
pub fn contour_layout(
    outline: &[DVec2],
    field: &ScalarField,
    centre: DVec2,
    settings: &ContourSettings,
    extra_constraints: &[[DVec2; 2]],
) -> ContourLayout {
    let directions = settings.directions.max(3);
    let rays: Vec<Ray> = (0..directions)
        .map(|d| {
            Ray::new(
                outline,
                centre,
                settings.orientation + TAU * d as f64 / directions as f64,
                field,
            )
        })
        .collect();
    let rule = if settings.max_relative_error > 0.0 {
        LevelRule::RelativeError(settings.max_relative_error)
    } else {
        LevelRule::LeastSquares
    };
    let levels = choose_levels(outline, field, centre, &rays, settings.levels.max(1), rule);
    let mut layout = ContourLayout {
        centre,
        levels: levels.clone(),
        ..ContourLayout::default()
    };
    let inside = |p: DVec2| {
        polygon_contains(outline, p)
            || distance_to_boundary(outline, p) <= 1e-12 * scale_of(outline)
    };
    if inside(centre) {
        layout.push(centre, None);
    }
    // Ring vertices: each level along each ray, and with a relative-error
    // target, along more rays where a contour bends between two of them.
    for (k, &level) in levels.iter().enumerate() {
        let mut ring: Vec<(f64, Option<DVec2>)> = rays
            .iter()
            .map(|ray| {
                let vertex = ray.solve(field, level).map(|(t, iterations)| {
                    layout.newton_iterations += iterations;
                    layout.newton_solves += 1;
                    ray.at(t)
                });
                (ray.angle, vertex.filter(|&p| inside(p)))
            })
            .collect();
        if let LevelRule::RelativeError(target) = rule {
            let pieces = RingPieces {
                outline,
                field,
                centre,
                inside: &inside,
                level,
                target,
            };
            ring = pieces.split(&ring, &mut layout);
        }
        for &(_, vertex) in &ring {
            if let Some(p) = vertex {
                layout.push(p, Some(k));
            }
        }
        // Consecutive ring vertices inside the polygon: a piece of contour.
        for d in 0..ring.len() {
            if let (Some(a), Some(b)) = (ring[d].1, ring[(d + 1) % ring.len()].1)
                && inside(a.lerp(b, 0.5))
            {
                layout.constraints.push([a, b]);
            }
        }
        layout.rings.push(ring);
    }
    // Where rays leave the polygon, and where levels cross its edges.
    for ray in &rays {
        if let Some(t) = ray.exit {
            layout.push(ray.at(t), None);
        }
    }
    for (k, &level) in levels.iter().enumerate() {
        for p in boundary_crossings(outline, field, level) {
            layout.push(p, Some(k));
        }
    }
    layout.add_constraint_lines(outline, extra_constraints, &rays);
    layout
}

impl ContourLayout {
    pub(crate) fn push(&mut self, p: DVec2, level: Option<usize>) {
        self.points.push(p);
        self.point_levels.push(level);
    }

    /// Adds segments to keep as edges, clipped to the polygon, with vertices
    /// where they cross the rays (so elements stay shaped like the rest).
    fn add_constraint_lines(&mut self, outline: &[DVec2], lines: &[[DVec2; 2]], rays: &[Ray]) {
        for &[a, b] in lines {
            let mut cuts: Vec<f64> = vec![0.0, 1.0];
            cuts.extend(
                rays.iter()
                    .filter_map(|ray| segment_ray_crossing(a, b, ray)),
            );
            cuts.sort_by(f64::total_cmp);
            let points: Vec<DVec2> = cuts.iter().map(|&t| a.lerp(b, t)).collect();
            for pair in points.windows(2) {
                let middle = pair[0].lerp(pair[1], 0.5);
                if polygon_contains(outline, middle) {
                    self.constraints.push([pair[0], pair[1]]);
                }
            }
            for p in points {
                if polygon_contains(outline, p) {
                    self.push(p, None);
                }
            }
        }
    }

    /// Adds vertices on shadow boundaries. `visible` is the fraction of the
    /// light visible from a point. Along every ring and every ray (each
    /// sampled at 8 points, so a thin shadow between two vertices is not
    /// missed), wherever the fraction crosses 5 %, 50 % or 95 %, bisection
    /// finds the crossing and it becomes a vertex: the penumbra's outer edge,
    /// middle and inner edge, so the shadow keeps its shape without a fine
    /// grid. The 50 % crossings are also listed in `shadow_boundary`.
    pub fn refine_shadows(&mut self, visible: &(dyn Fn(DVec2) -> f64 + Sync)) {
        const SAMPLES: usize = 8;
        const THRESHOLDS: [f64; 3] = [0.05, 0.5, 0.95];
        let mut edges: Vec<[DVec2; 2]> = Vec::new();
        for ring in &self.rings {
            for j in 0..ring.len() {
                if let (Some(a), Some(b)) = (ring[j].1, ring[(j + 1) % ring.len()].1) {
                    edges.push([a, b]);
                }
            }
        }
        // Radially: each ring vertex to the nearest in angle on the ring inside it.
        for k in 0..self.rings.len() {
            for &(angle, vertex) in &self.rings[k] {
                let Some(b) = vertex else { continue };
                let inner = if k == 0 {
                    Some(self.centre)
                } else {
                    self.rings[k - 1]
                        .iter()
                        .min_by(|x, y| angle_gap(x.0, angle).total_cmp(&angle_gap(y.0, angle)))
                        .and_then(|x| x.1)
                };
                if let Some(a) = inner {
                    edges.push([a, b]);
                }
            }
        }
        for [a, b] in edges {
            let fractions: Vec<f64> = (0..=SAMPLES)
                .map(|i| visible(a.lerp(b, i as f64 / SAMPLES as f64)))
                .collect();
            let mut added: Vec<f64> = Vec::new();
            for i in 0..SAMPLES {
                for threshold in THRESHOLDS {
                    let (f0, f1) = (fractions[i] - threshold, fractions[i + 1] - threshold);
                    if (f0 > 0.0) == (f1 > 0.0) {
                        continue;
                    }
                    // Bisection on the sub-interval, to 10⁻⁵ of the edge.
                    let (mut lo, mut hi) =
                        (i as f64 / SAMPLES as f64, (i + 1) as f64 / SAMPLES as f64);
                    while hi - lo > 1e-5 {
                        let mid = 0.5 * (lo + hi);
                        if (visible(a.lerp(b, mid)) - threshold > 0.0) == (f0 > 0.0) {
                            lo = mid
                        } else {
                            hi = mid
                        }
                    }
                    let t = 0.5 * (lo + hi);
                    if added.iter().any(|&u| (u - t).abs() < 1e-3) {
                        continue;
                    }
                    added.push(t);
                    self.push(a.lerp(b, t), None);
                    self.shadow_points += 1;
                    if threshold == 0.5 {
                        self.shadow_boundary.push(a.lerp(b, t));
                    }
                }
            }
        }
    }

    /// Adds shadow boundaries (already clipped to the polygon) as edges, with
    /// vertices along them about `spacing` apart, as the assembled mesh
    /// takes them (`SurfaceGuides::boundaries`): a layout measured on its
    /// own then has the edges the renderer's mesh has.
    pub fn add_boundaries(&mut self, boundaries: &[[DVec2; 2]], spacing: f64) {
        for &[a, b] in boundaries {
            let n = (a.distance(b) / spacing).ceil().clamp(1.0, 4096.0) as usize;
            for k in 0..=n {
                self.push(a.lerp(b, k as f64 / n as f64), None);
            }
            self.constraints.push([a, b]);
        }
    }

    /// Triangulates the layout inside `outline` (spade's constrained
    /// Delaunay triangulation, contour pieces as constraint edges).
    #[must_use]
    pub fn triangulate(&self, outline: &[DVec2]) -> PlaneTriangulation {
        triangulate_constrained(outline, &self.points, &self.constraints)
    }
}

/// The absolute difference of two angles, in [0, π].
fn angle_gap(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(TAU);
    d.min(TAU - d)
}

/// How many times a contour piece between two rays may be halved (16
/// pieces at most where there was one).
const MAX_PIECE_SPLITS: usize = 4;

/// A point of a ring where the ray at `angle` from the centre crosses it.
#[derive(Clone, Copy, Debug, PartialEq)]
struct RayPoint {
    angle: f64,
    point: DVec2,
}

/// One level's contour pieces, split where they stray from the contour.
struct RingPieces<'a> {
    outline: &'a [DVec2],
    field: &'a ScalarField<'a>,
    centre: DVec2,
    inside: &'a dyn Fn(DVec2) -> bool,
    level: f64,
    /// The relative error a piece's midpoint may have.
    target: f64,
}

impl RingPieces<'_> {
    /// The ring with vertices added, in order of angle: a piece between two
    /// consecutive vertices whose midpoint's value differs from the level by
    /// more than `target` × level (the chord cuts across the contour, and
    /// the interpolation there is off by that much) gets a vertex where the
    /// ray at the middle angle meets the level, and each half is checked
    /// again.
    fn split(
        &self,
        ring: &[(f64, Option<DVec2>)],
        layout: &mut ContourLayout,
    ) -> Vec<(f64, Option<DVec2>)> {
        let mut refined = Vec::with_capacity(ring.len());
        for d in 0..ring.len() {
            let (angle, vertex) = ring[d];
            refined.push((angle, vertex));
            let (mut next_angle, next) = ring[(d + 1) % ring.len()];
            if next_angle <= angle {
                next_angle += TAU;
            }
            if let (Some(a), Some(b)) = (vertex, next) {
                self.split_piece(
                    RayPoint { angle, point: a },
                    RayPoint {
                        angle: next_angle,
                        point: b,
                    },
                    0,
                    &mut refined,
                    layout,
                );
            }
        }
        refined
    }

    fn split_piece(
        &self,
        from: RayPoint,
        to: RayPoint,
        depth: usize,
        refined: &mut Vec<(f64, Option<DVec2>)>,
        layout: &mut ContourLayout,
    ) {
        let (angle_a, a) = (from.angle, from.point);
        let (angle_b, b) = (to.angle, to.point);
        let middle = a.lerp(b, 0.5);
        if depth >= MAX_PIECE_SPLITS || !(self.inside)(middle) {
            return;
        }
        let value = (self.field)(middle).0;
        if !value.is_finite() || (value - self.level).abs() <= self.target * self.level {
            return;
        }
        let angle = 0.5 * (angle_a + angle_b);
        // The level crosses the middle ray near its neighbours' distances:
        // a few samples there bracket it, the whole ray if they do not.
        let (ta, tb) = (a.distance(self.centre), b.distance(self.centre));
        let span = 0.5 * ta.min(tb)..1.5 * ta.max(tb);
        let near = Ray::sampled(self.outline, self.centre, angle, self.field, span, 8);
        let Some((t, iterations)) = near.solve(self.field, self.level).or_else(|| {
            Ray::new(self.outline, self.centre, angle, self.field).solve(self.field, self.level)
        }) else {
            return;
        };
        let ray = near;
        layout.newton_iterations += iterations;
        layout.newton_solves += 1;
        let p = ray.at(t);
        if !(self.inside)(p) {
            return;
        }
        let middle = RayPoint { angle, point: p };
        self.split_piece(from, middle, depth + 1, refined, layout);
        refined.push((angle, Some(p)));
        self.split_piece(middle, to, depth + 1, refined, layout);
    }
}

/// Points where the field crosses `level` on the polygon's edges: sign
/// changes between samples, refined by bisection.
pub(crate) fn boundary_crossings(outline: &[DVec2], field: &ScalarField, level: f64) -> Vec<DVec2> {
    const SAMPLES: usize = 64;
    let mut crossings = Vec::new();
    for k in 0..outline.len() {
        let (a, b) = (outline[k], outline[(k + 1) % outline.len()]);
        let value = |s: f64| field(a.lerp(b, s)).0 - level;
        for i in 0..SAMPLES {
            let (mut lo, mut hi) = (i as f64 / SAMPLES as f64, (i + 1) as f64 / SAMPLES as f64);
            let (f_lo, f_hi) = (value(lo), value(hi));
            if (f_lo > 0.0) == (f_hi > 0.0) || f_hi == 0.0 {
                continue;
            }
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if (value(mid) > 0.0) == (f_lo > 0.0) {
                    lo = mid
                } else {
                    hi = mid
                }
            }
            crossings.push(a.lerp(b, 0.5 * (lo + hi)));
        }
    }
    crossings
}

pub(crate) fn scale_of(outline: &[DVec2]) -> f64 {
    outline
        .iter()
        .map(|p| p.abs().max_element())
        .fold(f64::MIN_POSITIVE, f64::max)
}
