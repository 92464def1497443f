//! Contour lines of a value grid by marching squares, joined into
//! polylines so that each can be drawn and labelled as one line.
//!
//! The grid is row-major: the value at (column, row) is
//! `values[row * columns + column]`, and a point of the result is in grid
//! coordinates, (fractional column, fractional row). Each cell between four
//! neighbouring points is classified by which corners are at or above the
//! level (v ≥ level); a side whose ends differ is crossed where the linear
//! interpolation of its ends equals the level,
//!
//! t = (level − v₀) / (v₁ − v₀), point = p₀ + t (p₁ − p₀),
//!
//! and the crossings are joined by one segment per cell, or two in a saddle
//! (two opposite corners above). A saddle is resolved by the mean of the
//! four corners, the value at the cell's centre: when it is at or above the
//! level the two corners above are connected through the centre, otherwise
//! the two below are. Cells with a non-finite corner (NaN: no data) are
//! skipped, so a line stops at the edge of a hole.
//!
//! A crossing belongs to the grid side it lies on, not to a cell, so the two
//! cells beside a side compute the same point and their segments join
//! exactly; a crossing on a grid point (a value equal to the level) belongs
//! to that point. Lines through such points may branch; they are then cut
//! into several polylines there.
//!
//! # References
//! - W. E. Lorensen, H. E. Cline, "Marching Cubes: A High Resolution 3D
//!   Surface Construction Algorithm", SIGGRAPH 1987 (its 2D case, marching
//!   squares, and the ambiguity of saddle cells).

use std::collections::HashMap;

use glam::DVec2;

/// Where a crossing lies: on the side from grid point (column, row) to its
/// right or upper neighbour, or on a grid point itself.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Crossing {
    /// The side from (column, row) to (column + 1, row).
    Horizontal(usize, usize),
    /// The side from (column, row) to (column, row + 1).
    Vertical(usize, usize),
    /// The grid point (column, row), whose value equals the level.
    Point(usize, usize),
}

/// The grid and the level being contoured.
struct Field<'a> {
    values: &'a [f64],
    columns: usize,
    level: f64,
}

impl Field<'_> {
    /// The value at (column, row).
    fn value(&self, column: usize, row: usize) -> f64 {
        self.values[row * self.columns + column]
    }

    /// The crossing of the level on the side from `from` to `to` (grid
    /// points, `to` the right or upper neighbour), with its position: on a
    /// grid point when the interpolation lands on one.
    fn crossing(&self, from: GridPoint, to: GridPoint) -> (Crossing, DVec2) {
        let (a, b) = (
            self.value(from.column, from.row),
            self.value(to.column, to.row),
        );
        let t = (self.level - a) / (b - a);
        let at = |p: GridPoint| DVec2::new(p.column as f64, p.row as f64);
        if t <= 0.0 {
            return (Crossing::Point(from.column, from.row), at(from));
        }
        if t >= 1.0 {
            return (Crossing::Point(to.column, to.row), at(to));
        }
        let side = if to.row == from.row {
            Crossing::Horizontal(from.column, from.row)
        } else {
            Crossing::Vertical(from.column, from.row)
        };
        (side, at(from).lerp(at(to), t))
    }
}

/// A point of the grid, by column and row.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct GridPoint {
    column: usize,
    row: usize,
}

/// The contour of `level` over a `columns` × `rows` grid of `values`
/// (row-major, `values[row * columns + column]`; NaN or infinite = no
/// data), as polylines in grid coordinates (x = column, y = row).
///
/// A closed polyline repeats its first point at its end; an open one ends
/// where the contour leaves the grid or reaches a cell without data. Points
/// are linear interpolations along the grid's sides (see the module notes);
/// saddle cells are resolved by the mean of their corners. The order of the
/// polylines and of their points is deterministic.
///
/// Returns no polyline when the level is not finite, when `values` holds
/// fewer than `columns · rows` values, or when no cell is crossed.
#[must_use]
pub fn contour_polylines(
    values: &[f64],
    columns: usize,
    rows: usize,
    level: f64,
) -> Vec<Vec<DVec2>> {
    let enough = columns
        .checked_mul(rows)
        .is_some_and(|count| count <= values.len());
    if !level.is_finite() || !enough || columns < 2 || rows < 2 {
        return Vec::new();
    }
    let field = Field {
        values,
        columns,
        level,
    };
    let (segments, positions) = cell_segments(&field, rows);
    join_segments(&segments, &positions)
}

/// Every cell's segments, as pairs of crossings, and each crossing's
/// position.
fn cell_segments(
    field: &Field,
    rows: usize,
) -> (Vec<(Crossing, Crossing)>, HashMap<Crossing, DVec2>) {
    let mut segments = Vec::new();
    let mut positions = HashMap::new();
    for row in 0..rows - 1 {
        for column in 0..field.columns - 1 {
            // Corners counter-clockwise from the lower left.
            let corners = [
                (column, row),
                (column + 1, row),
                (column + 1, row + 1),
                (column, row + 1),
            ]
            .map(|(column, row)| GridPoint { column, row });
            let values = corners.map(|p| field.value(p.column, p.row));
            if values.iter().any(|v| !v.is_finite()) {
                continue;
            }
            let above = values.map(|v| v >= field.level);

            // Sides counter-clockwise from the bottom: (from, to) with `to`
            // the right or upper neighbour, and the corners they join.
            let sides = [(0, 1), (1, 2), (3, 2), (0, 3)];
            let crossed: Vec<usize> = (0..4)
                .filter(|&s| above[sides[s].0] != above[sides[s].1])
                .collect();
            let mut crossing = |side: usize| {
                let (from, to) = sides[side];
                let (key, point) = field.crossing(corners[from], corners[to]);
                positions.insert(key, point);
                key
            };

            // One segment, or two in a saddle, paired by the centre's mean.
            let pairs: Vec<(usize, usize)> = match crossed.as_slice() {
                [a, b] => vec![(*a, *b)],
                [_, _, _, _] => {
                    let centre_above = values.iter().sum::<f64>() / 4.0 >= field.level;
                    // Sides 0-1 and 2-3 cut off corners 1 and 3; sides 0-3
                    // and 1-2 cut off corners 0 and 2. Cut off the corners
                    // that differ from the centre.
                    if above[0] == centre_above {
                        vec![(0, 1), (2, 3)]
                    } else {
                        vec![(0, 3), (1, 2)]
                    }
                }
                _ => Vec::new(),
            };
            for (a, b) in pairs {
                let (start, end) = (crossing(a), crossing(b));
                if start != end {
                    segments.push((start, end));
                }
            }
        }
    }
    (segments, positions)
}

/// Joins segments that share a crossing into polylines: first walks from
/// every end that closes no loop (a crossing on an odd number of segments),
/// then round the loops left.
fn join_segments(
    segments: &[(Crossing, Crossing)],
    positions: &HashMap<Crossing, DVec2>,
) -> Vec<Vec<DVec2>> {
    let mut touching: HashMap<Crossing, Vec<usize>> = HashMap::new();
    for (index, &(start, end)) in segments.iter().enumerate() {
        touching.entry(start).or_default().push(index);
        touching.entry(end).or_default().push(index);
    }
    let is_end = |key: &Crossing| touching.get(key).is_some_and(|s| s.len() % 2 == 1);
    let mut used = vec![false; segments.len()];
    let mut polylines = Vec::new();

    // Open lines from their ends, in the order of the segments, then loops.
    let ends = segments
        .iter()
        .flat_map(|&(start, end)| [start, end])
        .filter(is_end);
    let loops = segments.iter().map(|&(start, _)| start);
    for start in ends.collect::<Vec<_>>().into_iter().chain(loops) {
        let mut current = start;
        let mut line = Vec::new();
        while let Some(&next_segment) = touching
            .get(&current)
            .and_then(|list| list.iter().find(|&&s| !used[s]))
        {
            used[next_segment] = true;
            if line.is_empty() {
                line.push(positions[&current]);
            }
            let (a, b) = segments[next_segment];
            current = if a == current { b } else { a };
            line.push(positions[&current]);
        }
        if line.len() >= 2 {
            polylines.push(line);
        }
    }
    polylines
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A `columns` × `rows` grid of `f(column, row)`.
    fn grid(columns: usize, rows: usize, f: impl Fn(f64, f64) -> f64) -> Vec<f64> {
        (0..rows)
            .flat_map(|r| (0..columns).map(move |c| (c, r)))
            .map(|(c, r)| f(c as f64, r as f64))
            .collect()
    }

    #[test]
    fn a_radial_field_gives_one_closed_circle() {
        let centre = DVec2::new(10.3, 9.7);
        let radius = 6.0;
        let values = grid(21, 20, |c, r| DVec2::new(c, r).distance(centre));
        let lines = contour_polylines(&values, 21, 20, radius);
        assert_eq!(lines.len(), 1);
        let circle = &lines[0];
        assert_eq!(circle.first(), circle.last(), "the circle is closed");
        // One crossing per grid side crossed: about 4 per unit of diameter.
        assert!(circle.len() > 40, "{} points", circle.len());
        // Along a side the distance d has d'' ≤ 1/d, so the chord of unit
        // sides is off by at most 1/(8 d) ≈ 0.025 near d = 5, and inside:
        // the distance is convex.
        for point in circle {
            let error = radius - point.distance(centre);
            assert!((-1e-12..0.03).contains(&error), "{point}: off by {error}");
        }
        // It goes all the way round.
        let angles: Vec<f64> = circle
            .iter()
            .map(|p| (*p - centre).y.atan2((*p - centre).x))
            .collect();
        let turned: f64 = angles
            .windows(2)
            .map(|w| {
                let d = w[1] - w[0];
                (d + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
            })
            .sum();
        assert!((turned.abs() - std::f64::consts::TAU).abs() < 1e-9);
    }

    #[test]
    fn a_ramp_gives_one_straight_open_line() {
        // f = column + 0.5 row; the level 4.2 crosses it as a straight line.
        let values = grid(10, 8, |c, r| c + 0.5 * r);
        let lines = contour_polylines(&values, 10, 8, 4.2);
        assert_eq!(lines.len(), 1);
        let line = &lines[0];
        assert_ne!(line.first(), line.last());
        for point in line {
            assert!((point.x + 0.5 * point.y - 4.2).abs() < 1e-12, "{point}");
        }
        // From the bottom row to the top row.
        let rows: Vec<f64> = line.iter().map(|p| p.y).collect();
        let (low, high) = (
            rows.iter().copied().fold(f64::MAX, f64::min),
            rows.iter().copied().fold(f64::MIN, f64::max),
        );
        assert_eq!((low, high), (0.0, 7.0));
    }

    #[test]
    fn a_hole_without_data_cuts_the_line() {
        // f = column, level 4.5: a vertical line x = 4.5, through the cells
        // beside the missing point (4, 5).
        let mut values = grid(10, 10, |c, _| c);
        values[5 * 10 + 4] = f64::NAN;
        let lines = contour_polylines(&values, 10, 10, 4.5);
        assert_eq!(lines.len(), 2);
        for point in lines.iter().flatten() {
            assert!((point.x - 4.5).abs() < 1e-12);
            assert!(point.y <= 4.0 || point.y >= 6.0, "{point} in the hole");
        }
    }

    #[test]
    fn a_level_outside_the_values_gives_nothing() {
        let values = grid(5, 5, |c, r| c * r);
        assert!(contour_polylines(&values, 5, 5, 17.0).is_empty());
        assert!(contour_polylines(&values, 5, 5, -1.0).is_empty());
        assert!(contour_polylines(&values, 5, 5, f64::NAN).is_empty());
    }

    #[test]
    fn degenerate_grids_give_nothing() {
        assert!(contour_polylines(&[], 0, 0, 1.0).is_empty());
        assert!(contour_polylines(&[1.0, 2.0], 2, 2, 1.5).is_empty());
        assert!(contour_polylines(&[1.0, 2.0], 2, 1, 1.5).is_empty());
        assert!(contour_polylines(&[1.0; 4], usize::MAX, 2, 1.0).is_empty());
    }

    #[test]
    fn a_saddle_is_resolved_by_the_centre() {
        // Corners 0 and 2 above (value 1), 1 and 3 below (value 0).
        let values = [1.0, 0.0, 0.0, 1.0];
        // Centre 0.5 ≥ 0.4: the upper corners connect, the lower ones are
        // cut off: segments round corners 1 (lower right) and 3 (upper left).
        let lines = contour_polylines(&values, 2, 2, 0.4);
        assert_eq!(lines.len(), 2);
        for line in &lines {
            let mid = 0.5 * (line[0] + line[1]);
            assert!(
                mid.distance(DVec2::new(1.0, 0.0)) < 0.7
                    || mid.distance(DVec2::new(0.0, 1.0)) < 0.7
            );
        }
        // Centre 0.5 < 0.6: the corners above are cut off.
        let lines = contour_polylines(&values, 2, 2, 0.6);
        assert_eq!(lines.len(), 2);
        for line in &lines {
            let mid = 0.5 * (line[0] + line[1]);
            assert!(mid.distance(DVec2::ZERO) < 0.7 || mid.distance(DVec2::ONE) < 0.7);
        }
    }

    #[test]
    fn a_line_through_grid_points_stays_whole() {
        // f = column; the level 3 runs through the grid points of column 3.
        let values = grid(6, 6, |c, _| c);
        let lines = contour_polylines(&values, 6, 6, 3.0);
        assert_eq!(lines.len(), 1);
        assert!(lines[0].iter().all(|p| p.x == 3.0));
    }
}
