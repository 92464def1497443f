//! The level-line contour mesher: a contour layout of any field, with as
//! many peaks as it has.
//!
//! The radial contour-level mesher needs one maximum from which every ray
//! crosses each contour once. Under several luminaires the total direct
//! light has several peaks and saddles between them, so no ray family
//! covers it. Here the contours are found as curves instead: the field is
//! sampled on a coarse lattice over the polygon, marching squares gives
//! each level's lines ([`contour_polylines`]), every line point is moved
//! onto the exact level by Newton steps along the gradient,
//!
//! p ← p − (B(p) − L) ∇B / |∇B|²,
//!
//! and each line is resampled so that the chord between two of its points
//! stays within the relative error ε of the level at its middle. The lines
//! become constraint edges: element edges follow the contours, as in the
//! radial layout, and the peaks (the lattice's local maxima, climbed by
//! gradient ascent) become vertices.
//!
//! The levels come from the field itself. Linear interpolation across a
//! step h along the gradient errs by about h² |B_nn| / 8, B_nn the second
//! derivative along the gradient, so a relative error ε allows
//! h = √(8 ε B / |B_nn|) and a value step Δ = |∇B| h (at least 4 ε B, the
//! drop across h at a peak, and at most B / 2). Walking down from the top,
//! each level is the previous one less the smallest Δ of the lattice points
//! between them.
//!
//! # References
//! - P. Arquès, V. Biri, S. Derpierre, "A new formulation of differential
//!   radiosity and a rendering application", WSCG 2005, §4 (vertices on
//!   iso-radiosity contours, found with the analytic gradient).
//! - W. E. Lorensen, H. E. Cline, "Marching Cubes", SIGGRAPH 1987 (its 2D
//!   case).

use glam::DVec2;

use super::contour::{ContourLayout, ContourSettings, boundary_crossings, scale_of};
use super::contour_levels::RELATIVE_FLOOR;
use super::contour_lines::contour_polylines;
use super::scalar_field::ScalarField;
use crate::scene::{distance_to_boundary, polygon_contains};

/// Lattice cells along the polygon's longer side.
const LATTICE_CELLS: usize = 64;

/// The most levels a layout gets.
const MAX_LEVELS: usize = 96;

/// How many times a piece of a line may be halved.
const MAX_PIECE_SPLITS: usize = 4;

/// The relative error aimed for when the settings ask for none (a fixed
/// layout has no meaning without one ray family).
const DEFAULT_ERROR: f64 = 0.01;

/// Lays out contour lines of `field` on the polygon `outline` (plane
/// coordinates, counter-clockwise) for the relative error
/// `settings.max_relative_error` (1 % if it is 0), as the module notes
/// describe. `extra_constraints` (a luminaire's horizon) are kept as edges.
/// Where no line comes near, lattice points are added: wherever the field
/// curves more than the lines between its levels can follow (around peaks
/// and saddles, and across plateaus between levels), as densely as the
/// relative error needs in every direction, and nowhere sparser than
/// `spacing`, so that a region the direct light leaves flat keeps vertices
/// for the indirect light. None when the lines would need more than
/// `max_points` points (the work stops there).
#[must_use]
pub fn level_line_layout(
    outline: &[DVec2],
    field: &ScalarField,
    settings: &ContourSettings,
    extra_constraints: &[[DVec2; 2]],
    spacing: f64,
    max_points: usize,
) -> Option<ContourLayout> {
    let target = if settings.max_relative_error > 0.0 {
        settings.max_relative_error
    } else {
        DEFAULT_ERROR
    };
    let mut layout = ContourLayout::default();
    let Some(lattice) = Lattice::sample(outline, field) else {
        return Some(layout);
    };
    let inside = |p: DVec2| {
        polygon_contains(outline, p)
            || distance_to_boundary(outline, p) <= 1e-12 * scale_of(outline)
    };
    // The peaks, climbed from the lattice's local maxima.
    let peaks: Vec<DVec2> = lattice
        .local_maxima(&inside)
        .into_iter()
        .map(|p| climb(field, p, lattice.step))
        .filter(|&p| inside(p))
        .collect();
    let top = peaks
        .iter()
        .map(|&p| field(p).0)
        .chain(lattice.inside_values(&inside))
        .fold(f64::NEG_INFINITY, f64::max);
    if !(top.is_finite() && top > 0.0) {
        return Some(layout);
    }
    layout.centre = peaks.first().copied().unwrap_or(outline[0]);
    for &p in &peaks {
        layout.push(p, None);
    }
    layout.levels = lattice.levels(&inside, top, target);
    for (k, &level) in layout.levels.clone().iter().enumerate() {
        let lines = contour_polylines(&lattice.values, lattice.columns, lattice.rows, level);
        for line in lines {
            let line: Vec<DVec2> = line.iter().map(|&g| lattice.to_plane(g)).collect();
            let line = Line {
                field,
                level,
                target,
                step: lattice.step,
            }
            .traced(&line, &mut layout);
            for &p in &line {
                if inside(p) {
                    layout.push(p, Some(k));
                }
            }
            for pair in line.windows(2) {
                if inside(pair[0]) && inside(pair[1]) && inside(pair[0].lerp(pair[1], 0.5)) {
                    layout.constraints.push([pair[0], pair[1]]);
                }
            }
        }
        for p in boundary_crossings(outline, field, level) {
            layout.push(p, Some(k));
        }
        if layout.points.len() > max_points {
            return None;
        }
    }
    layout.add_straight_constraints(extra_constraints, &inside, 4.0 * lattice.step);
    let spacings = lattice.spacings(&inside, RELATIVE_FLOOR * top, target, spacing);
    layout.fill_gaps(&lattice, &spacings);
    split_flat_triangles(&mut layout, outline, field, target, RELATIVE_FLOOR * top);
    (layout.points.len() <= max_points).then_some(layout)
}

/// Rounds of [`split_flat_triangles`].
const FLAT_TRIANGLE_ROUNDS: usize = 2;

/// Adds the centroid of every triangle of the layout's triangulation whose
/// linear interpolation misses the field there by more than `target` of its
/// value (or of `floor`, in the dark), for a few rounds. Such a triangle
/// has its corners on one level line, or on two lines across a ridge or a
/// saddle between lamps, and lies flat over a field that bulges between
/// them: the long slivers between six ceiling lights' level lines erred by
/// 5 % of the floor's brightest light where a square grid errs by 0.5 %.
fn split_flat_triangles(
    layout: &mut ContourLayout,
    outline: &[DVec2],
    field: &ScalarField,
    target: f64,
    floor: f64,
) {
    for _ in 0..FLAT_TRIANGLE_ROUNDS {
        let mesh = layout.triangulate(outline);
        let values: Vec<f64> = mesh.points.iter().map(|&p| field(p).0).collect();
        let centroids: Vec<DVec2> = mesh
            .triangles
            .iter()
            .filter_map(|&[a, b, c]| {
                let centre = (mesh.points[a] + mesh.points[b] + mesh.points[c]) / 3.0;
                let interpolated = (values[a] + values[b] + values[c]) / 3.0;
                let exact = field(centre).0;
                ((exact - interpolated).abs() > target * exact.max(floor)).then_some(centre)
            })
            .collect();
        if centroids.is_empty() {
            return;
        }
        for p in centroids {
            layout.push(p, None);
        }
    }
}

impl ContourLayout {
    /// Adds segments as edges, cut into pieces at most `piece` long, those
    /// inside the polygon kept.
    fn add_straight_constraints(
        &mut self,
        lines: &[[DVec2; 2]],
        inside: &dyn Fn(DVec2) -> bool,
        piece: f64,
    ) {
        for &[a, b] in lines {
            let n = (a.distance(b) / piece).ceil().clamp(1.0, 4096.0) as usize;
            let points: Vec<DVec2> = (0..=n).map(|k| a.lerp(b, k as f64 / n as f64)).collect();
            for pair in points.windows(2) {
                if inside(pair[0]) && inside(pair[1]) {
                    self.constraints.push([pair[0], pair[1]]);
                }
            }
            for p in points {
                if inside(p) {
                    self.push(p, None);
                }
            }
        }
    }

    /// Adds lattice points where no layout point is near: a point whose
    /// own spacing h (from `spacings`) has no layout point within 0.7 h is
    /// added, the finest spacings first.
    fn fill_gaps(&mut self, lattice: &Lattice, spacings: &[(DVec2, f64)]) {
        let step = lattice.step;
        let mut buckets: std::collections::HashMap<glam::IVec2, Vec<DVec2>> =
            std::collections::HashMap::new();
        let bucket = |p: DVec2| ((p - lattice.origin) / step).floor().as_ivec2();
        for &p in &self.points {
            buckets.entry(bucket(p)).or_default().push(p);
        }
        let mut order: Vec<&(DVec2, f64)> = spacings.iter().collect();
        order.sort_by(|a, b| a.1.total_cmp(&b.1));
        for &(p, h) in order {
            let radius = 0.7 * h;
            let widest = lattice.columns.max(lattice.rows) as f64;
            let reach = (radius / step).ceil().min(widest) as i32;
            let centre = bucket(p);
            let near = (-reach..=reach).any(|dx| {
                (-reach..=reach).any(|dy| {
                    buckets
                        .get(&(centre + glam::IVec2::new(dx, dy)))
                        .is_some_and(|points| points.iter().any(|q| q.distance(p) < radius))
                })
            });
            if !near {
                buckets.entry(centre).or_default().push(p);
                self.push(p, None);
            }
        }
    }
}

/// The field sampled on a regular lattice over the polygon's bounds.
struct Lattice {
    origin: DVec2,
    step: f64,
    columns: usize,
    rows: usize,
    /// Row-major values.
    values: Vec<f64>,
    /// Row-major gradients.
    gradients: Vec<DVec2>,
}

impl Lattice {
    fn sample(outline: &[DVec2], field: &ScalarField) -> Option<Lattice> {
        let (low, high) = bounds(outline);
        let size = high - low;
        let step = size.max_element() / LATTICE_CELLS as f64;
        if !(step > 0.0 && step.is_finite()) {
            return None;
        }
        // One cell of margin, so that lines close around the outline.
        let origin = low - DVec2::splat(step);
        let columns = (size.x / step).ceil() as usize + 3;
        let rows = (size.y / step).ceil() as usize + 3;
        let mut values = Vec::with_capacity(columns * rows);
        let mut gradients = Vec::with_capacity(columns * rows);
        for row in 0..rows {
            for column in 0..columns {
                let (value, gradient) =
                    field(origin + DVec2::new(column as f64, row as f64) * step);
                values.push(if value.is_finite() { value } else { f64::NAN });
                gradients.push(gradient);
            }
        }
        Some(Lattice {
            origin,
            step,
            columns,
            rows,
            values,
            gradients,
        })
    }

    fn to_plane(&self, grid: DVec2) -> DVec2 {
        self.origin + grid * self.step
    }

    fn point(&self, column: usize, row: usize) -> DVec2 {
        self.to_plane(DVec2::new(column as f64, row as f64))
    }

    fn inside_values<'a>(
        &'a self,
        inside: &'a dyn Fn(DVec2) -> bool,
    ) -> impl Iterator<Item = f64> + 'a {
        (0..self.rows).flat_map(move |row| {
            (0..self.columns)
                .filter(move |&column| inside(self.point(column, row)))
                .map(move |column| self.values[row * self.columns + column])
                .filter(|v| v.is_finite())
        })
    }

    /// Lattice points inside the polygon above all eight neighbours.
    fn local_maxima(&self, inside: &dyn Fn(DVec2) -> bool) -> Vec<DVec2> {
        let mut maxima = Vec::new();
        for row in 1..self.rows - 1 {
            for column in 1..self.columns - 1 {
                let value = self.values[row * self.columns + column];
                let highest = (0..9).filter(|&k| k != 4).all(|k| {
                    let (c, r) = (column + k % 3 - 1, row + k / 3 - 1);
                    value > self.values[r * self.columns + c]
                });
                let p = self.point(column, row);
                if highest && value > 0.0 && inside(p) {
                    maxima.push(p);
                }
            }
        }
        maxima
    }

    /// The Hessian at a lattice point, by central differences of the
    /// gradients (one-sided at the lattice's edge): its columns ∂∇B/∂x and
    /// ∂∇B/∂y.
    fn hessian(&self, column: usize, row: usize) -> (DVec2, DVec2) {
        let at = |c: usize, r: usize| r * self.columns + c;
        let (c0, c1) = (column.saturating_sub(1), (column + 1).min(self.columns - 1));
        let (r0, r1) = (row.saturating_sub(1), (row + 1).min(self.rows - 1));
        let dx = (self.gradients[at(c1, row)] - self.gradients[at(c0, row)])
            / ((c1 - c0) as f64 * self.step);
        let dy = (self.gradients[at(column, r1)] - self.gradients[at(column, r0)])
            / ((r1 - r0) as f64 * self.step);
        (dx, dy)
    }

    /// The value step Δ at a lattice point allowed by the relative error
    /// `target` (module notes), or None outside the polygon.
    fn allowed_step(
        &self,
        column: usize,
        row: usize,
        floor: f64,
        target: f64,
    ) -> Option<(f64, f64)> {
        let at = |c: usize, r: usize| r * self.columns + c;
        let value = self.values[at(column, row)];
        let gradient = self.gradients[at(column, row)];
        if !value.is_finite() || !gradient.is_finite() {
            return None;
        }
        let (dx, dy) = self.hessian(column, row);
        let slope = gradient.length();
        let curvature = if slope > 0.0 {
            let n = gradient / slope;
            (n.x * (dx.x * n.x + dy.x * n.y) + n.y * (dx.y * n.x + dy.y * n.y)).abs()
        } else {
            0.5 * (dx.x.abs() + dy.y.abs())
        };
        let base = value.max(floor);
        let h = (8.0 * target * base / curvature.max(f64::MIN_POSITIVE)).sqrt();
        let step = (slope * h).max(4.0 * target * base).min(0.5 * base);
        step.is_finite().then_some((value, step))
    }

    /// Each lattice point inside the polygon with the spacing the relative
    /// error allows in every direction, h = √(8 ε B / |λ|max), λ the
    /// Hessian's eigenvalues, clamped to [lattice step, `widest`].
    fn spacings(
        &self,
        inside: &dyn Fn(DVec2) -> bool,
        floor: f64,
        target: f64,
        widest: f64,
    ) -> Vec<(DVec2, f64)> {
        let at = |c: usize, r: usize| r * self.columns + c;
        let mut spacings = Vec::new();
        for row in 0..self.rows {
            for column in 0..self.columns {
                let p = self.point(column, row);
                let value = self.values[at(column, row)];
                if !inside(p) || !value.is_finite() {
                    continue;
                }
                let (dx, dy) = self.hessian(column, row);
                // The largest |eigenvalue| of the symmetrised Hessian.
                let (a, b, d) = (dx.x, 0.5 * (dx.y + dy.x), dy.y);
                let largest = 0.5 * (a + d).abs() + (0.25 * (a - d) * (a - d) + b * b).sqrt();
                let h = (8.0 * target * value.max(floor) / largest.max(f64::MIN_POSITIVE)).sqrt();
                if h.is_finite() {
                    spacings.push((p, h.clamp(self.step, widest.max(self.step))));
                }
            }
        }
        spacings
    }

    /// The levels, decreasing from `top`: each the previous less the smallest
    /// allowed step of the lattice points inside the polygon between them,
    /// down to the smallest value inside (or 10⁻³ of the top).
    fn levels(&self, inside: &dyn Fn(DVec2) -> bool, top: f64, target: f64) -> Vec<f64> {
        let floor = RELATIVE_FLOOR * top;
        let mut steps: Vec<(f64, f64)> = (0..self.rows)
            .flat_map(|row| (0..self.columns).map(move |column| (column, row)))
            .filter(|&(column, row)| inside(self.point(column, row)))
            .filter_map(|(column, row)| self.allowed_step(column, row, floor, target))
            .collect();
        if steps.is_empty() {
            return Vec::new();
        }
        steps.sort_by(|a, b| b.0.total_cmp(&a.0));
        let bottom = steps.last().map_or(0.0, |s| s.0).max(floor);
        let mut levels = Vec::new();
        let mut level = top;
        while levels.len() < MAX_LEVELS {
            // The nearest point at or below the level starts the step; the
            // points within it may shorten it.
            let first = steps.partition_point(|s| s.0 > level);
            let Some(&(_, start)) = steps.get(first) else {
                break;
            };
            let mut step = start;
            for _ in 0..4 {
                let smallest = steps[first..]
                    .iter()
                    .take_while(|s| s.0 >= level - step)
                    .map(|s| s.1)
                    .fold(step, f64::min);
                if smallest >= step {
                    break;
                }
                step = smallest;
            }
            level -= step;
            if level <= bottom {
                break;
            }
            levels.push(level);
        }
        levels
    }
}

/// One level's line being traced onto the exact contour.
struct Line<'a> {
    field: &'a ScalarField<'a>,
    level: f64,
    target: f64,
    step: f64,
}

impl Line<'_> {
    /// The polyline with its points moved onto the level, pieces whose
    /// midpoint strays by more than the target split, and runs of points
    /// that a chord follows within half the target merged.
    fn traced(&self, line: &[DVec2], layout: &mut ContourLayout) -> Vec<DVec2> {
        let on: Vec<DVec2> = line.iter().map(|&p| self.onto(p, layout)).collect();
        let mut refined = Vec::with_capacity(on.len());
        for pair in on.windows(2) {
            refined.push(pair[0]);
            self.split(pair[0], pair[1], 0, &mut refined, layout);
        }
        refined.extend(on.last());
        self.merged(&refined)
    }

    fn strays(&self, p: DVec2, tolerance: f64) -> bool {
        let value = (self.field)(p).0;
        !value.is_finite() || (value - self.level).abs() > tolerance * self.level
    }

    fn split(
        &self,
        a: DVec2,
        b: DVec2,
        depth: usize,
        refined: &mut Vec<DVec2>,
        layout: &mut ContourLayout,
    ) {
        let middle = a.lerp(b, 0.5);
        if depth >= MAX_PIECE_SPLITS || !self.strays(middle, self.target) {
            return;
        }
        let p = self.onto(middle, layout);
        self.split(a, p, depth + 1, refined, layout);
        refined.push(p);
        self.split(p, b, depth + 1, refined, layout);
    }

    /// Greedily drops points that the chord over them follows: from each
    /// kept point, the farthest next point (at most 16 on) whose chord's
    /// quarter points all lie within half the target of the level.
    fn merged(&self, points: &[DVec2]) -> Vec<DVec2> {
        if points.len() < 3 {
            return points.to_vec();
        }
        let mut kept = vec![points[0]];
        let mut i = 0;
        while i + 1 < points.len() {
            let mut j = i + 1;
            while j + 1 < points.len() && j + 1 - i <= 16 {
                let (a, b) = (points[i], points[j + 1]);
                let follows = [0.25, 0.5, 0.75]
                    .iter()
                    .all(|&t| !self.strays(a.lerp(b, t), 0.5 * self.target));
                if !follows {
                    break;
                }
                j += 1;
            }
            kept.push(points[j]);
            i = j;
        }
        kept
    }

    /// Newton steps along the gradient onto the level, each at most a
    /// lattice step long.
    fn onto(&self, start: DVec2, layout: &mut ContourLayout) -> DVec2 {
        let mut p = start;
        for iteration in 1..=8 {
            let (value, gradient) = (self.field)(p);
            let f = value - self.level;
            layout.newton_iterations += 1;
            if f.abs() <= 1e-9 * self.level || iteration == 8 {
                break;
            }
            let squared = gradient.length_squared();
            if !(squared > 0.0 && squared.is_finite()) {
                break;
            }
            let mut delta = -gradient * (f / squared);
            let length = delta.length();
            if !length.is_finite() {
                break;
            }
            if length > self.step {
                delta *= self.step / length;
            }
            p += delta;
        }
        layout.newton_solves += 1;
        if start.distance(p) <= 2.0 * self.step {
            p
        } else {
            start
        }
    }
}

/// Gradient ascent from `start`, steps at most `step` long, halved when the
/// value would fall.
fn climb(field: &ScalarField, start: DVec2, step: f64) -> DVec2 {
    let mut p = start;
    let mut value = field(p).0;
    let mut length = step;
    for _ in 0..64 {
        let gradient = field(p).1;
        let norm = gradient.length();
        if !(norm > 0.0 && norm.is_finite()) || length < 1e-6 * step {
            break;
        }
        let candidate = p + gradient / norm * length;
        let next = field(candidate).0;
        if next > value {
            (p, value) = (candidate, next);
        } else {
            length *= 0.5;
        }
    }
    p
}

/// The polygon's bounding box.
fn bounds(outline: &[DVec2]) -> (DVec2, DVec2) {
    outline.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(low, high), &p| (low.min(p), high.max(p)),
    )
}
