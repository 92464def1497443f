//! Shooting patches and their stratified subdivision into cells.

use glam::DVec3;

use crate::scene::SurfaceId;

/// A convex planar cell: a triangle or a quadrilateral, counter-clockwise.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cell {
    /// Corners; for a triangle the fourth repeats the third.
    pub corners: [DVec3; 4],
    /// True for a triangle.
    pub is_triangle: bool,
    /// Area.
    pub area: f64,
}

impl Cell {
    /// A triangular cell.
    #[must_use]
    pub fn triangle(a: DVec3, b: DVec3, c: DVec3) -> Cell {
        Cell {
            corners: [a, b, c, c],
            is_triangle: true,
            area: 0.5 * (b - a).cross(c - a).length(),
        }
    }

    /// A quadrilateral cell (planar, convex).
    #[must_use]
    pub fn quad(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> Cell {
        Cell {
            corners: [a, b, c, d],
            is_triangle: false,
            area: 0.5 * (c - a).cross(d - b).length(),
        }
    }

    /// The unit normal of its plane, counter-clockwise corners facing it
    /// (zero for a degenerate cell).
    #[must_use]
    pub fn normal(&self) -> DVec3 {
        let [a, b, c, d] = self.corners;
        if self.is_triangle {
            (b - a).cross(c - a).normalize_or_zero()
        } else {
            (c - a).cross(d - b).normalize_or_zero()
        }
    }

    /// The corners as a polygon (3 or 4 points).
    #[must_use]
    pub fn polygon(&self) -> &[DVec3] {
        if self.is_triangle {
            &self.corners[..3]
        } else {
            &self.corners
        }
    }

    /// Centroid of the corners.
    #[must_use]
    pub fn centre(&self) -> DVec3 {
        let p = self.polygon();
        p.iter().copied().sum::<DVec3>() / p.len() as f64
    }

    /// A point of the cell for parameters (s, t) ∈ [0, 1]²: bilinear for a
    /// quad; for a triangle the square is folded onto it, which keeps a
    /// uniform (s, t) uniform in area.
    // Inlined where it is called: out of line, it returns the point
    // through memory, and the shots' strata loop may load it back across
    // two stores, which the processor cannot forward: a stall in the
    // solve's hottest loop.
    #[must_use]
    #[inline]
    pub fn point(&self, s: f64, t: f64) -> DVec3 {
        let [a, b, c, d] = self.corners;
        if self.is_triangle {
            let (s, t) = if s + t > 1.0 {
                (1.0 - s, 1.0 - t)
            } else {
                (s, t)
            };
            a + (b - a) * s + (c - a) * t
        } else {
            let bottom = a.lerp(b, s);
            let top = d.lerp(c, s);
            bottom.lerp(top, t)
        }
    }

    /// Splits the cell into `m²` cells of a regular lattice: an m × m
    /// bilinear grid of a quad, or the m² sub-triangles of a triangle (all of
    /// equal area). Used to stratify samples over a shooting patch.
    pub fn subdivide(&self, m: usize, out: &mut Vec<Cell>) {
        out.clear();
        let m = m.max(1);
        let step = 1.0 / m as f64;
        if self.is_triangle {
            let [a, b, c, _] = self.corners;
            let lattice =
                |i: usize, j: usize| a + (b - a) * (i as f64 * step) + (c - a) * (j as f64 * step);
            for j in 0..m {
                for i in 0..m - j {
                    out.push(Cell::triangle(
                        lattice(i, j),
                        lattice(i + 1, j),
                        lattice(i, j + 1),
                    ));
                    if i + j + 2 <= m {
                        out.push(Cell::triangle(
                            lattice(i + 1, j),
                            lattice(i + 1, j + 1),
                            lattice(i, j + 1),
                        ));
                    }
                }
            }
        } else {
            let grid = |i: usize, j: usize| self.point(i as f64 * step, j as f64 * step);
            for j in 0..m {
                for i in 0..m {
                    out.push(Cell::quad(
                        grid(i, j),
                        grid(i + 1, j),
                        grid(i + 1, j + 1),
                        grid(i, j + 1),
                    ));
                }
            }
        }
    }
}

/// A shooting patch: a convex cell of one surface, made of the elements that
/// receive on it. Patches shoot; elements receive (Cohen et al. 1986).
#[derive(Clone, Debug, PartialEq)]
pub struct Patch {
    /// The surface it lies on.
    pub surface: SurfaceId,
    /// Its shape, over which shots are sampled.
    pub cell: Cell,
    /// Indices of its elements in [`crate::mesh::Mesh::elements`].
    pub elements: Vec<u32>,
    /// The area of its elements: the cell's area, less any part hidden
    /// under an object standing on it. Power is radiosity times this area.
    pub area: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subdivision_preserves_area() {
        let tri = Cell::triangle(
            DVec3::ZERO,
            DVec3::new(3.0, 0.0, 0.0),
            DVec3::new(1.0, 2.0, 0.0),
        );
        let quad = Cell::quad(
            DVec3::ZERO,
            DVec3::new(4.0, 0.0, 0.0),
            DVec3::new(3.0, 2.0, 0.0),
            DVec3::new(0.5, 1.5, 0.0),
        );
        let mut cells = Vec::new();
        for cell in [tri, quad] {
            for m in 1..6 {
                cell.subdivide(m, &mut cells);
                assert_eq!(cells.len(), m * m);
                let sum: f64 = cells.iter().map(|c| c.area).sum();
                assert!((sum - cell.area).abs() < 1e-12 * cell.area, "m={m}");
            }
        }
    }
}
