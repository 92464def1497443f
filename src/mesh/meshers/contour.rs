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
use crate::scene::{distance_to_boundary, polygon_contains};

/// A scalar field on a plane: its value and gradient at a point.
pub type ScalarField<'a> = dyn Fn(DVec2) -> (f64, DVec2) + Sync + 'a;

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

/// Samples per ray for the level rule and for bracketing.
const RAY_SAMPLES: usize = 96;

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
                self.split_piece((angle, a), (next_angle, b), 0, &mut refined, layout);
            }
        }
        refined
    }

    fn split_piece(
        &self,
        (angle_a, a): (f64, DVec2),
        (angle_b, b): (f64, DVec2),
        depth: usize,
        refined: &mut Vec<(f64, Option<DVec2>)>,
        layout: &mut ContourLayout,
    ) {
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
        let span = (0.5 * ta.min(tb), 1.5 * ta.max(tb));
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
        self.split_piece((angle_a, a), (angle, p), depth + 1, refined, layout);
        refined.push((angle, Some(p)));
        self.split_piece((angle, p), (angle_b, b), depth + 1, refined, layout);
    }
}

/// A ray from the centre, sampled, with its extent over the polygon.
struct Ray {
    origin: DVec2,
    angle: f64,
    direction: DVec2,
    /// Where the ray last leaves the polygon (None: it never meets it).
    exit: Option<f64>,
    /// Where it first enters, when the centre is outside.
    entry: f64,
    /// (t, B) samples from 0 to the exit.
    samples: Vec<(f64, f64)>,
}

impl Ray {
    fn new(outline: &[DVec2], origin: DVec2, angle: f64, field: &ScalarField) -> Ray {
        Ray::sampled(
            outline,
            origin,
            angle,
            field,
            (0.0, f64::INFINITY),
            RAY_SAMPLES,
        )
    }

    /// A ray sampled at `count` + 1 points over `span` (clipped to where it
    /// leaves the polygon): a whole ray, or the stretch where a level is
    /// expected to cross.
    fn sampled(
        outline: &[DVec2],
        origin: DVec2,
        angle: f64,
        field: &ScalarField,
        span: (f64, f64),
        count: usize,
    ) -> Ray {
        let direction = DVec2::new(angle.cos(), angle.sin());
        let crossings = ray_polygon_crossings(outline, origin, direction);
        let exit = crossings
            .iter()
            .copied()
            .fold(None, |m: Option<f64>, t| Some(m.map_or(t, |m| m.max(t))));
        let entry = if polygon_contains(outline, origin) {
            0.0
        } else {
            crossings.iter().copied().fold(f64::INFINITY, f64::min)
        };
        let samples = exit
            .map(|end| {
                let (start, stop) = (span.0.clamp(0.0, end), span.1.min(end));
                (0..=count)
                    .map(|i| start + (stop - start) * i as f64 / count as f64)
                    .map(|t| (t, field(origin + direction * t).0))
                    .collect()
            })
            .unwrap_or_default();
        Ray {
            origin,
            angle,
            direction,
            exit,
            entry,
            samples,
        }
    }

    fn at(&self, t: f64) -> DVec2 {
        self.origin + self.direction * t
    }

    /// Solves B(c + t u) = level for t in (0, exit] by Newton's method on
    /// f(t) = B − level with f'(t) = ∇B·u, safeguarded by the bracket the
    /// samples give (a bisection step whenever Newton leaves it). Returns t
    /// and the iterations taken, or None when the level is not crossed.
    fn solve(&self, field: &ScalarField, level: f64) -> Option<(f64, usize)> {
        // Bracket: the first sample interval where B drops through the level.
        let k = self
            .samples
            .windows(2)
            .position(|w| w[0].1 >= level && w[1].1 < level)?;
        let (mut lo, mut hi) = (self.samples[k].0, self.samples[k + 1].0);
        let (b_lo, b_hi) = (self.samples[k].1, self.samples[k + 1].1);
        let mut t = lo + (hi - lo) * (b_lo - level) / (b_lo - b_hi);
        let tolerance = 1e-9 * level.abs().max(f64::MIN_POSITIVE);
        for iteration in 1..=60 {
            let (value, gradient) = field(self.at(t));
            let f = value - level;
            if f.abs() <= tolerance {
                return Some((t, iteration));
            }
            if f > 0.0 {
                lo = t
            } else {
                hi = t
            }
            let slope = gradient.dot(self.direction);
            let newton = t - f / slope;
            t = if slope.is_finite() && slope != 0.0 && newton > lo && newton < hi {
                newton
            } else {
                0.5 * (lo + hi)
            };
            if hi - lo <= 1e-15 * hi.abs().max(1.0) {
                return Some((t, iteration));
            }
        }
        Some((t, 60))
    }
}

/// How the levels are spaced along the rays.
#[derive(Clone, Copy, Debug, PartialEq)]
enum LevelRule {
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
fn choose_levels(
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

/// Parameters t ≥ 0 where the ray origin + t·direction crosses the polygon's edges.
fn ray_polygon_crossings(outline: &[DVec2], origin: DVec2, direction: DVec2) -> Vec<f64> {
    let mut crossings = Vec::new();
    for k in 0..outline.len() {
        let (p, q) = (outline[k], outline[(k + 1) % outline.len()]);
        let denominator = direction.perp_dot(q - p);
        if denominator.abs() <= f64::MIN_POSITIVE {
            continue;
        }
        let t = (p - origin).perp_dot(q - p) / denominator;
        let s = (p - origin).perp_dot(direction) / denominator;
        if t >= 0.0 && (0.0..=1.0).contains(&s) {
            crossings.push(t);
        }
    }
    crossings
}

/// Parameter along a→b where the segment crosses a ray, if it does strictly inside.
fn segment_ray_crossing(a: DVec2, b: DVec2, ray: &Ray) -> Option<f64> {
    let denominator = ray.direction.perp_dot(b - a);
    if denominator.abs() <= f64::MIN_POSITIVE {
        return None;
    }
    let t = (a - ray.origin).perp_dot(b - a) / denominator;
    let s = (a - ray.origin).perp_dot(ray.direction) / denominator;
    (t > ray.entry && s > 0.0 && s < 1.0).then_some(s)
}

pub(crate) fn scale_of(outline: &[DVec2]) -> f64 {
    outline
        .iter()
        .map(|p| p.abs().max_element())
        .fold(f64::MIN_POSITIVE, f64::max)
}
