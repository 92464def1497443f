//! Points of a mesh cell by their coordinates (s, t) and back: values
//! interpolated at the corners, the inverse of [`Cell::point`], and the
//! cell's point nearest another.

use glam::{DVec2, DVec3};

use crate::mesh::Cell;
use crate::rgb::Rgb;

/// Values at an element's corners at coordinates (s, t) of its cell
/// ([`Cell::point`]): linear over a triangle (the fourth value unused),
/// bilinear over a quad.
pub(crate) fn interpolated([a, b, c, d]: [Rgb; 4], is_triangle: bool, st: DVec2) -> Rgb {
    let (s, t) = (st.x, st.y);
    if is_triangle {
        a * (1.0 - s - t) + b * s + c * t
    } else {
        a * ((1.0 - s) * (1.0 - t)) + b * (s * (1.0 - t)) + c * (s * t) + d * ((1.0 - s) * t)
    }
}

/// The coordinates (s, t) of y in a cell, inverting [`Cell::point`]
/// (Gauss–Newton on the bilinear map; one step is exact for a triangle
/// and for a parallelogram, whose map is affine: the square grid's
/// elements and patches); `None` when y lies outside.
pub(crate) fn cell_coordinates(cell: &Cell, y: DVec3) -> Option<(f64, f64)> {
    const INSIDE: f64 = 1e-9;
    let [a, b, c, d] = cell.corners;
    let (mut s, mut t) = if cell.is_triangle {
        (0.0, 0.0)
    } else {
        (0.5, 0.5)
    };
    let steps = if is_affine(cell) { 1 } else { 8 };
    for _ in 0..steps {
        let (du, dv) = if cell.is_triangle {
            (b - a, c - a)
        } else {
            (
                (b - a) * (1.0 - t) + (c - d) * t,
                (d - a) * (1.0 - s) + (c - b) * s,
            )
        };
        let r = y - cell.point(s, t);
        let (uu, uv, vv) = (du.dot(du), du.dot(dv), dv.dot(dv));
        let det = uu * vv - uv * uv;
        if det.abs() <= f64::MIN_POSITIVE {
            return None;
        }
        let (ru, rv) = (du.dot(r), dv.dot(r));
        let (ds, dt) = ((vv * ru - uv * rv) / det, (uu * rv - uv * ru) / det);
        s += ds;
        t += dt;
        // Converged.
        if ds.abs().max(dt.abs()) < 1e-12 {
            break;
        }
    }
    let inside = if cell.is_triangle {
        s >= -INSIDE && t >= -INSIDE && s + t <= 1.0 + INSIDE
    } else {
        (-INSIDE..=1.0 + INSIDE).contains(&s) && (-INSIDE..=1.0 + INSIDE).contains(&t)
    };
    inside.then_some((s.clamp(0.0, 1.0), t.clamp(0.0, 1.0)))
}

/// Whether a cell's map ([`Cell::point`]) is affine: a triangle, or a
/// quad whose bilinear twist a − b + c − d (the s·t term) vanishes, to
/// 10⁻¹² of its diagonals and the rounding of its corners' coordinates: a
/// parallelogram.
fn is_affine(cell: &Cell) -> bool {
    let [a, b, c, d] = cell.corners;
    let size = (c - a).length().max((d - b).length());
    let magnitude = [a, b, c, d]
        .map(|p| p.abs().max_element())
        .into_iter()
        .fold(0.0, f64::max);
    let tolerance = 1e-12 * size + 16.0 * f64::EPSILON * magnitude;
    cell.is_triangle || (a - b + c - d).length() <= tolerance
}

/// The point of a convex cell nearest y: y's foot on the cell's plane if
/// that lies inside, else the nearest point of its edges.
pub(crate) fn nearest_point_of(cell: &Cell, y: DVec3) -> DVec3 {
    if let Some((s, t)) = cell_coordinates(cell, y) {
        let [a, b, c, _] = cell.corners;
        return if cell.is_triangle {
            a + (b - a) * s + (c - a) * t
        } else {
            cell.point(s, t)
        };
    }
    let polygon = cell.polygon();
    let mut best = (f64::INFINITY, polygon[0]);
    for (k, &p) in polygon.iter().enumerate() {
        let q = polygon[(k + 1) % polygon.len()];
        let edge = q - p;
        let along = (y - p).dot(edge) / edge.length_squared();
        let nearest = p + edge
            * if along.is_finite() {
                along.clamp(0.0, 1.0)
            } else {
                0.0
            };
        let d = (y - nearest).length_squared();
        if d < best.0 {
            best = (d, nearest);
        }
    }
    best.1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coordinates_invert_the_cell_map() {
        let quad = Cell::quad(
            DVec3::ZERO,
            DVec3::new(4.0, 0.0, 0.0),
            DVec3::new(3.0, 2.0, 0.0),
            DVec3::new(0.5, 1.5, 0.0),
        );
        let tri = Cell::triangle(
            DVec3::ZERO,
            DVec3::new(3.0, 0.0, 0.0),
            DVec3::new(1.0, 2.0, 0.0),
        );
        // A slanted parallelogram in space: its map is affine, one step;
        // the trapezoid above is not.
        let (a, u, v) = (
            DVec3::new(1.0, -2.0, 0.5),
            DVec3::new(0.3, 0.1, 0.2),
            DVec3::new(-0.1, 0.25, 0.05),
        );
        let parallelogram = Cell::quad(a, a + u, a + u + v, a + v);
        for (cell, s, t) in [
            (quad, 0.3, 0.8),
            (tri, 0.2, 0.5),
            (parallelogram, 0.9, 0.15),
        ] {
            let (s2, t2) = cell_coordinates(&cell, cell.point(s, t)).unwrap();
            assert!((s2 - s).abs() < 1e-12 && (t2 - t).abs() < 1e-12);
        }
        assert!(is_affine(&parallelogram) && is_affine(&tri) && !is_affine(&quad));
        // Far from the origin, a small parallelogram is still one.
        let far = DVec3::splat(1000.0);
        let small = Cell::quad(far, far + u * 0.01, far + (u + v) * 0.01, far + v * 0.01);
        assert!(is_affine(&small));
        assert!(cell_coordinates(&quad, DVec3::new(5.0, 1.0, 0.0)).is_none());
    }
}
