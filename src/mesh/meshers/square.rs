//! The square (uniform) mesher: the baseline the contour mesher is compared
//! against.
//!
//! A convex quadrilateral is cut into a G × H bilinear grid of quad elements
//! (N × N when asked, otherwise as many as keep every element edge under the
//! maximum edge length). Triangles, n-gons and non-convex quads are
//! triangulated, and every triangle is cut into the n² sub-triangles of a
//! regular lattice, with one n per surface so that the triangles' shared edges
//! are split at the same points: the subdivision is conforming, and adjacent
//! elements of one surface share their vertices.
//!
//! Elements are grouped into shooting patches: blocks of the grid (or coarse
//! lattice triangles) no longer than the patch edge length.

use glam::DVec3;
use std::collections::HashMap;

use crate::mesh::data::patch::Cell;
use crate::mesh::data::topology::Mesh;
use crate::scene::{Scene, Surface, SurfaceId};

/// Settings of the square mesher.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct SquareMeshSettings {
    /// Longest element edge, in scene units.
    pub max_edge: f64,
    /// N for an N × N grid on every quad (and N divisions of every triangle
    /// edge), instead of `max_edge`.
    pub elements_per_side: Option<usize>,
    /// Longest shooting-patch edge, in scene units.
    pub patch_max_edge: f64,
}

impl SquareMeshSettings {
    /// Defaults scaled to a scene: elements of 1/40 and patches of 1/8 of its
    /// bounding diagonal.
    #[must_use]
    pub fn for_scene(scene: &Scene) -> SquareMeshSettings {
        let diagonal = scene.diagonal();
        SquareMeshSettings {
            max_edge: diagonal / 40.0,
            elements_per_side: None,
            patch_max_edge: diagonal / 8.0,
        }
    }
}

/// One surface's square grid of elements in patch blocks. A quad one
/// element across gets a row of element edges across it through each of
/// `marks` on its long sides (see [`rows_through_marks`]).
pub(crate) fn square_grid(
    surface: &Surface,
    id: SurfaceId,
    settings: &SquareMeshSettings,
    marks: &[DVec3],
) -> Mesh {
    let mut grid = Mesh::default();
    let mut builder = SurfaceBuilder::new(&mut grid, id);
    match convex_quad(surface) {
        Some(corners) => builder.quad_grid(corners, settings, marks),
        None => builder.triangle_lattices(surface, settings),
    }
    grid
}

/// The grid lines `lines` (parameters in [0, 1], ascending) across a quad
/// one element wide, with a line added at each of `marks` lying on one of
/// its two long `sides` (each from parameter 0 to 1), at the mark's
/// parameter along it: the light across a thin face (a book's spine)
/// changes where a neighbour standing beside it ends, within millimetres,
/// which an element as tall as the face draws as a straight line. A mark
/// within [`MARK_MERGE`] of a line's spacing of an existing line moves
/// nothing.
fn rows_through_marks(
    mut lines: Vec<f64>,
    sides: [(DVec3, DVec3); 2],
    marks: &[DVec3],
) -> Vec<f64> {
    let spacing = 1.0 / (lines.len() - 1) as f64;
    for &mark in marks {
        for (from, to) in sides {
            let side = to - from;
            let t = (mark - from).dot(side) / side.length_squared().max(f64::MIN_POSITIVE);
            let off = (mark - from - side * t).length();
            if off > 1e-6 * side.length() || !(0.0..=1.0).contains(&t) {
                continue;
            }
            if lines.iter().all(|&l| (l - t).abs() > MARK_MERGE * spacing) {
                lines.push(t);
            }
        }
    }
    lines.sort_by(f64::total_cmp);
    lines
}

/// How close to an existing grid line, as a fraction of the lines'
/// spacing, a mark adds no line of its own ([`rows_through_marks`]).
const MARK_MERGE: f64 = 0.1;

/// The corners of a surface that is a strictly convex quadrilateral.
pub(crate) fn convex_quad(surface: &Surface) -> Option<[DVec3; 4]> {
    let points = surface.plane_vertices();
    if points.len() != 4 {
        return None;
    }
    let convex = (0..4).all(|k| {
        let (a, b, c) = (points[k], points[(k + 1) % 4], points[(k + 2) % 4]);
        (b - a).perp_dot(c - b) > 0.0
    });
    let v = surface.vertices();
    convex.then(|| [v[0], v[1], v[2], v[3]])
}

/// Number of divisions of a length under a maximum step (at least 1, at most
/// 4096 so that absurd settings cannot exhaust memory).
pub(crate) fn divisions(length: f64, max_step: f64) -> usize {
    let n = (length / max_step).ceil();
    if n.is_finite() {
        n.clamp(1.0, 4096.0) as usize
    } else {
        1
    }
}

/// The longest edge lengths of a quad along its u (a→b, d→c) and v
/// (a→d, b→c) directions.
fn quad_lengths([a, b, c, d]: [DVec3; 4]) -> (f64, f64) {
    (
        (b - a).length().max((c - d).length()),
        (d - a).length().max((c - b).length()),
    )
}

/// Columns and rows of a convex quad's grid.
pub(crate) fn quad_grid_size(corners: [DVec3; 4], settings: &SquareMeshSettings) -> (usize, usize) {
    let (length_u, length_v) = quad_lengths(corners);
    match settings.elements_per_side {
        Some(n) => (n.clamp(1, 4096), n.clamp(1, 4096)),
        None => (
            divisions(length_u, settings.max_edge),
            divisions(length_v, settings.max_edge),
        ),
    }
}

/// A surface's triangles with the divisions n of its lattice and of a
/// patch block (see [`lattice_divisions`]).
pub(crate) fn lattice_size(
    surface: &Surface,
    settings: &SquareMeshSettings,
) -> (Vec<[usize; 3]>, usize, usize) {
    let points = surface.vertices();
    let triangles = surface.triangles();
    let longest = triangles
        .iter()
        .flat_map(|t| (0..3).map(move |k| (points[t[k]] - points[t[(k + 1) % 3]]).length()))
        .fold(0.0, f64::max);
    let (n, block) = lattice_divisions(surface, triangles.len(), longest, settings);
    (triangles, n, block)
}

/// Most elements a lattice may spend per element of the ideal count
/// (the surface's area over that of an equilateral triangle of edge
/// `max_edge`): a polygon of many thin triangles (a 10 000-gon's fan)
/// gets a coarser lattice rather than thousands of slivers per triangle.
const LATTICE_SLACK: f64 = 16.0;

/// Divisions n of every triangle edge of a surface's lattice, and divisions
/// per patch block, for `triangles` triangles whose longest edge is
/// `longest`. One n for the whole surface keeps the lattice conforming.
fn lattice_divisions(
    surface: &Surface,
    triangles: usize,
    longest: f64,
    settings: &SquareMeshSettings,
) -> (usize, usize) {
    let cap = match settings.elements_per_side {
        Some(_) => usize::MAX,
        None => {
            let ideal = surface.area() / (settings.max_edge.powi(2) * 3f64.sqrt() / 4.0);
            let t = triangles.max(1) as f64;
            let n = ((LATTICE_SLACK * ideal + t) / t).sqrt().floor();
            if n.is_finite() {
                n.max(1.0) as usize
            } else {
                usize::MAX
            }
        }
    };
    let patch_divisions = divisions(longest, settings.patch_max_edge).min(cap);
    let element_divisions = settings
        .elements_per_side
        .map_or_else(
            || divisions(longest, settings.max_edge),
            |n| n.clamp(1, 4096),
        )
        .min(cap);
    let block = element_divisions.div_ceil(patch_divisions);
    (block * patch_divisions, block)
}

/// Where a lattice vertex sits, so that points shared by two triangles of one
/// surface are created once.
#[derive(Clone, Copy, Debug, Hash, PartialEq, Eq)]
enum LatticeKey {
    Corner(usize),
    /// On the polygon edge or diagonal (lo, hi), `step` divisions from lo.
    Edge(usize, usize, usize),
    Interior(usize, usize, usize),
}

struct SurfaceBuilder<'a> {
    mesh: &'a mut Mesh,
    surface: SurfaceId,
}

impl<'a> SurfaceBuilder<'a> {
    fn new(mesh: &'a mut Mesh, surface: SurfaceId) -> Self {
        SurfaceBuilder { mesh, surface }
    }

    fn add_vertex(&mut self, position: DVec3) -> u32 {
        self.mesh.add_vertex(position, self.surface)
    }

    fn add_patch(&mut self, cell: Cell) -> u32 {
        self.mesh.add_patch(self.surface, cell)
    }

    fn add_element(&mut self, corners: &[u32], patch: u32) {
        self.mesh.add_element(corners, patch);
    }

    /// A G × H bilinear grid of quads over a convex quad, in patch blocks,
    /// with rows through `marks` where it is one element across.
    fn quad_grid(&mut self, corners: [DVec3; 4], settings: &SquareMeshSettings, marks: &[DVec3]) {
        let [a, b, c, d] = corners;
        let (length_u, length_v) = quad_lengths(corners);
        let (cols, rows) = quad_grid_size(corners, settings);
        let uniform = |n: usize| (0..=n).map(|k| k as f64 / n as f64).collect::<Vec<f64>>();
        let (mut us, mut vs) = (uniform(cols), uniform(rows));
        if cols == 1 {
            vs = rows_through_marks(vs, [(a, d), (b, c)], marks);
        }
        if rows == 1 {
            us = rows_through_marks(us, [(a, b), (d, c)], marks);
        }
        let (cols, rows) = (us.len() - 1, vs.len() - 1);
        let quad = Cell::quad(a, b, c, d);
        let at = |i: usize, j: usize| quad.point(us[i], vs[j]);
        // Grid vertices, row by row.
        let first = self.mesh.vertices.len() as u32;
        for j in 0..=rows {
            for i in 0..=cols {
                self.add_vertex(at(i, j));
            }
        }
        let id = |i: usize, j: usize| first + (j * (cols + 1) + i) as u32;
        // Patch blocks of about `patch_max_edge`.
        let block_u = cols.div_ceil(divisions(length_u, settings.patch_max_edge));
        let block_v = rows.div_ceil(divisions(length_v, settings.patch_max_edge));
        for j0 in (0..rows).step_by(block_v) {
            for i0 in (0..cols).step_by(block_u) {
                let (i1, j1) = ((i0 + block_u).min(cols), (j0 + block_v).min(rows));
                let patch =
                    self.add_patch(Cell::quad(at(i0, j0), at(i1, j0), at(i1, j1), at(i0, j1)));
                for j in j0..j1 {
                    for i in i0..i1 {
                        self.add_element(
                            &[id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)],
                            patch,
                        );
                    }
                }
            }
        }
    }

    /// Triangulates the surface and cuts every triangle into an n × n lattice.
    fn triangle_lattices(&mut self, surface: &Surface, settings: &SquareMeshSettings) {
        let points = surface.vertices();
        let (triangles, n, block) = lattice_size(surface, settings);
        let mut ids: HashMap<LatticeKey, u32> = HashMap::new();
        for (t, &corners) in triangles.iter().enumerate() {
            self.lattice(points, corners, t, n, block, &mut ids);
        }
    }

    /// One triangle's lattice of n divisions, grouped into coarse triangles
    /// of `block` divisions as patches.
    fn lattice(
        &mut self,
        points: &[DVec3],
        corners: [usize; 3],
        t: usize,
        n: usize,
        block: usize,
        ids: &mut HashMap<LatticeKey, u32>,
    ) {
        let mut vertex = |builder: &mut Self, i: usize, j: usize| {
            let (key, position) = lattice_point(points, corners, t, n, i, j);
            *ids.entry(key)
                .or_insert_with(|| builder.add_vertex(position))
        };
        let coarse = n / block;
        let at = |i: usize, j: usize| lattice_point(points, corners, t, n, i, j).1;
        // Coarse triangles: patches, "up" ones then "down" ones per lattice cell.
        let mut patch_of = HashMap::new();
        for jc in 0..coarse {
            for ic in 0..coarse - jc {
                let (i, j) = (ic * block, jc * block);
                let up =
                    self.add_patch(Cell::triangle(at(i, j), at(i + block, j), at(i, j + block)));
                patch_of.insert((ic, jc, true), up);
                if ic + jc + 2 <= coarse {
                    let down = self.add_patch(Cell::triangle(
                        at(i + block, j),
                        at(i + block, j + block),
                        at(i, j + block),
                    ));
                    patch_of.insert((ic, jc, false), down);
                }
            }
        }
        // Fine triangles, each assigned to the coarse triangle holding its centroid.
        for j in 0..n {
            for i in 0..n - j {
                let (ic, jc, ri, rj) = (i / block, j / block, i % block, j % block);
                let up = [
                    vertex(self, i, j),
                    vertex(self, i + 1, j),
                    vertex(self, i, j + 1),
                ];
                self.add_element(&up, patch_of[&(ic, jc, ri + rj < block)]);
                if i + j + 2 <= n {
                    let down = [
                        vertex(self, i + 1, j),
                        vertex(self, i + 1, j + 1),
                        vertex(self, i, j + 1),
                    ];
                    self.add_element(&down, patch_of[&(ic, jc, ri + rj + 2 <= block)]);
                }
            }
        }
    }
}

/// Key and position of lattice point (i, j) of triangle `t` with polygon
/// corners (c0, c1, c2): barycentric weights ((n − i − j), i, j) / n. Points on
/// the triangle's sides are computed from the side's end points in a fixed
/// order, so both triangles sharing a side get bit-identical positions.
fn lattice_point(
    points: &[DVec3],
    corners: [usize; 3],
    t: usize,
    n: usize,
    i: usize,
    j: usize,
) -> (LatticeKey, DVec3) {
    let [c0, c1, c2] = corners;
    let on_side = |from: usize, to: usize, step: usize| {
        let (lo, hi, step) = if from < to {
            (from, to, step)
        } else {
            (to, from, n - step)
        };
        let position = points[lo].lerp(points[hi], step as f64 / n as f64);
        (LatticeKey::Edge(lo, hi, step), position)
    };
    match (i, j) {
        (0, 0) => (LatticeKey::Corner(c0), points[c0]),
        (i, 0) if i == n => (LatticeKey::Corner(c1), points[c1]),
        (0, j) if j == n => (LatticeKey::Corner(c2), points[c2]),
        (i, 0) => on_side(c0, c1, i),
        (0, j) => on_side(c0, c2, j),
        (i, j) if i + j == n => on_side(c1, c2, j),
        (i, j) => {
            let (a, b, c) = (points[c0], points[c1], points[c2]);
            let position = a + (b - a) * (i as f64 / n as f64) + (c - a) * (j as f64 / n as f64);
            (LatticeKey::Interior(t, i, j), position)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A mark on either long side adds its row; one on neither, or next to
    /// a row already there, adds none.
    #[test]
    fn marks_on_a_long_side_add_rows() {
        let (a, b, c, d) = (
            DVec3::ZERO,
            DVec3::new(0.06, 0.0, 0.0),
            DVec3::new(0.06, 0.28, 0.0),
            DVec3::new(0.0, 0.28, 0.0),
        );
        let rows = vec![0.0, 0.5, 1.0];
        let marks = [
            DVec3::new(0.06, 0.07, 0.0), // right side, a quarter up
            DVec3::new(0.0, 0.21, 0.0),  // left side, three quarters up
            DVec3::new(0.0, 0.141, 0.0), // beside the middle row
            DVec3::new(0.03, 0.1, 0.0),  // inside, on neither side
        ];
        let lines = rows_through_marks(rows, [(a, d), (b, c)], &marks);
        let expected = [0.0, 0.25, 0.5, 0.75, 1.0];
        assert_eq!(lines.len(), expected.len(), "{lines:?}");
        for (l, e) in lines.iter().zip(expected) {
            assert!((l - e).abs() < 1e-12, "{lines:?}");
        }
    }
}
