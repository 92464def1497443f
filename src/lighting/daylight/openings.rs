//! Openings: the holes in a model through which the sky is seen, found in
//! its geometry, since a model says nothing of them (an OBJ writes a wall
//! with a window as the pieces around it).
//!
//! In each large plane of the model (and each face of its bounding box),
//! the plane's own surfaces cover parts of it, and every other surface
//! that ends at the plane draws its edge there (a floor's edge at the foot
//! of a wall, the walls' edges around a missing façade). A region of the plane
//! that neither covers and that these lines and surfaces close in on every
//! side is an opening: a hole in a roof or a wall, a door down to the
//! floor, a whole missing wall. Each is found on a raster of the plane
//! (cells of 1/384 of its extent, flooded from outside), then given as the
//! rectangle around it, its sides moved onto the model's own vertices
//! nearby, so that a rectangular hole's rectangle is exact.
//!
//! The rectangle is where daylight is sampled from, not a surface: a ray
//! through a part of it the model covers is blocked there. An opening the
//! raster misses is not lost either: the sky it shows is gathered by
//! hemisphere rays ([`super::direct`]), more noisily.

use glam::{DVec2, DVec3};

use crate::scene::geometry::Box3;
use crate::scene::{PlaneFrame, Scene, polygon_contains};

use super::plane_groups::{PlaneGroup, frame_along, plane_groups};

/// The most planes searched for openings (the largest).
const MAX_PLANES: usize = 256;
/// Raster cells along a plane's longer side.
const CELLS: f64 = 384.0;

/// An opening: a planar rectangle the sky may be seen through.
#[derive(Clone, Debug, PartialEq)]
pub struct Opening {
    /// The rectangle's corners, counter-clockwise about `normal`.
    pub corners: [DVec3; 4],
    /// Its plane's unit normal (either side: light passes both ways).
    pub normal: DVec3,
}

/// The openings of `scene`, in a deterministic order.
#[must_use]
pub fn find_openings(scene: &Scene) -> Vec<Opening> {
    let diagonal = scene.diagonal();
    if diagonal <= 0.0 {
        return Vec::new();
    }
    let tolerance = 1e-6 * diagonal;
    let smallest = (diagonal / 50.0).powi(2);
    let mut planes: Vec<PlaneGroup> = plane_groups(scene, tolerance)
        .into_iter()
        .filter(|g| g.area >= smallest)
        .take(MAX_PLANES)
        .collect();
    // The bounding box's faces, where no surface lies in them already.
    let bounds = scene.bounds();
    for face in box_faces(bounds) {
        let taken = planes.iter().any(|g| {
            g.frame.normal.dot(face.normal).abs() > 1.0 - 1e-8
                && g.frame.height(face.origin).abs() <= tolerance
        });
        if !taken {
            planes.push(PlaneGroup {
                frame: face,
                surfaces: Vec::new(),
                area: 0.0,
            });
        }
    }
    let mut openings = Vec::new();
    for plane in &planes {
        openings.extend(plane_openings(scene, plane, tolerance));
    }
    openings
}

/// The six faces of `bounds` as frames (normals along the axes).
fn box_faces(bounds: Box3) -> Vec<PlaneFrame> {
    let mut faces = Vec::new();
    for (axis, along) in [
        (DVec3::X, DVec3::Y),
        (DVec3::Y, DVec3::X),
        (DVec3::Z, DVec3::X),
    ] {
        for corner in [bounds.min, bounds.max] {
            faces.push(frame_along(axis * axis.dot(corner), axis, along));
        }
    }
    faces
}

/// A segment in plane coordinates.
#[derive(Clone, Copy, Debug)]
struct Segment {
    a: DVec2,
    b: DVec2,
}

/// Where the other surfaces end at `plane`: their edges lying in it.
fn lines_on_plane(scene: &Scene, plane: &PlaneGroup, tolerance: f64) -> Vec<Segment> {
    let frame = &plane.frame;
    let mut lines = Vec::new();
    for (id, surface) in scene.surfaces_with_ids() {
        if plane.surfaces.binary_search(&id).is_ok()
            || surface.normal().dot(frame.normal).abs() > 1.0 - 1e-9
        {
            continue;
        }
        let b = surface.bounds();
        let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
        for corner in 0..8 {
            let pick = |bit: usize, lo: f64, hi: f64| if corner >> bit & 1 == 0 { lo } else { hi };
            let p = DVec3::new(
                pick(0, b.min.x, b.max.x),
                pick(1, b.min.y, b.max.y),
                pick(2, b.min.z, b.max.z),
            );
            let h = frame.height(p);
            low = low.min(h);
            high = high.max(h);
        }
        if low > tolerance || high < -tolerance {
            continue;
        }
        edges_in_plane(surface.vertices(), frame, tolerance, &mut lines);
    }
    lines
}

/// The edges of `polygon` lying in `frame`'s plane, appended to `lines`:
/// where a surface ends at the plane (a floor at the foot of a wall). A
/// surface that passes through the plane draws nothing: the walls a desk's
/// top plane cuts do not close it in.
fn edges_in_plane(polygon: &[DVec3], frame: &PlaneFrame, tolerance: f64, lines: &mut Vec<Segment>) {
    for (k, &a) in polygon.iter().enumerate() {
        let b = polygon[(k + 1) % polygon.len()];
        if frame.height(a).abs() <= tolerance && frame.height(b).abs() <= tolerance {
            lines.push(Segment {
                a: frame.to_plane(a),
                b: frame.to_plane(b),
            });
        }
    }
}

/// The raster of one plane: which cells are covered or drawn across.
struct Raster {
    origin: DVec2,
    cell: f64,
    nx: usize,
    ny: usize,
    blocked: Vec<bool>,
}

impl Raster {
    fn centre(&self, i: usize, j: usize) -> DVec2 {
        self.origin + DVec2::new(i as f64 + 0.5, j as f64 + 0.5) * self.cell
    }

    fn cell_of(&self, p: DVec2) -> (f64, f64) {
        let q = (p - self.origin) / self.cell;
        (q.x, q.y)
    }

    /// Marks every cell the segment ab passes through (a supercover walk
    /// in small steps: a quarter cell).
    fn draw(&mut self, a: DVec2, b: DVec2) {
        let steps = ((b - a).length() / self.cell * 4.0).ceil().max(1.0) as usize;
        for s in 0..=steps {
            let (x, y) = self.cell_of(a.lerp(b, s as f64 / steps as f64));
            self.mark(x, y);
        }
    }

    fn mark(&mut self, x: f64, y: f64) {
        if x >= 0.0 && y >= 0.0 && (x as usize) < self.nx && (y as usize) < self.ny {
            let index = y as usize * self.nx + x as usize;
            self.blocked[index] = true;
        }
    }

    /// Marks the cells whose centres lie inside `polygon`, and those its
    /// edges cross.
    fn fill(&mut self, polygon: &[DVec2]) {
        let (lo, hi) = polygon.iter().fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(lo, hi), &p| (lo.min(p), hi.max(p)),
        );
        let (x0, y0) = self.cell_of(lo);
        let (x1, y1) = self.cell_of(hi);
        let clamp_x = |v: f64| (v.max(0.0) as usize).min(self.nx - 1);
        let clamp_y = |v: f64| (v.max(0.0) as usize).min(self.ny - 1);
        for j in clamp_y(y0)..=clamp_y(y1) {
            for i in clamp_x(x0)..=clamp_x(x1) {
                if polygon_contains(polygon, self.centre(i, j)) {
                    self.blocked[j * self.nx + i] = true;
                }
            }
        }
        for k in 0..polygon.len() {
            self.draw(polygon[k], polygon[(k + 1) % polygon.len()]);
        }
    }
}

/// The openings in one plane.
fn plane_openings(scene: &Scene, plane: &PlaneGroup, tolerance: f64) -> Vec<Opening> {
    let polygons = plane.polygons(scene);
    let lines = lines_on_plane(scene, plane, tolerance);
    let points = || {
        polygons
            .iter()
            .flatten()
            .copied()
            .chain(lines.iter().flat_map(|s| [s.a, s.b]))
    };
    let (lo, hi) = points().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(p), hi.max(p)),
    );
    let extent = hi - lo;
    if !(extent.x > tolerance && extent.y > tolerance) {
        return Vec::new();
    }
    let cell = extent.max_element() / CELLS;
    let nx = (extent.x / cell).ceil() as usize + 4;
    let ny = (extent.y / cell).ceil() as usize + 4;
    let mut raster = Raster {
        origin: lo - DVec2::splat(2.0 * cell),
        cell,
        nx,
        ny,
        blocked: vec![false; nx * ny],
    };
    for polygon in &polygons {
        raster.fill(polygon);
    }
    for line in &lines {
        raster.draw(line.a, line.b);
    }
    let regions = enclosed_regions(&raster);
    let snap_to: Vec<DVec2> = points().collect();
    regions
        .into_iter()
        .map(|region| rectangle(&raster, region, &snap_to, &plane.frame))
        .collect()
}

/// A region of cells, by its inclusive cell bounds.
#[derive(Clone, Copy, Debug)]
struct CellBox {
    i0: usize,
    j0: usize,
    i1: usize,
    j1: usize,
}

/// The open cells that no path of open cells joins to the raster's edge,
/// grouped into 4-connected regions, each by its bounds.
fn enclosed_regions(raster: &Raster) -> Vec<CellBox> {
    let (nx, ny) = (raster.nx, raster.ny);
    // 0: open, not yet reached; 1: blocked or reached from outside; 2: in a region.
    let mut state: Vec<u8> = raster.blocked.iter().map(|&b| u8::from(b)).collect();
    let mut stack: Vec<usize> = Vec::new();
    let neighbours = |c: usize| {
        let (i, j) = (c % nx, c / nx);
        [
            (i > 0).then(|| c - 1),
            (i + 1 < nx).then(|| c + 1),
            (j > 0).then(|| c - nx),
            (j + 1 < ny).then(|| c + nx),
        ]
    };
    let flood = |seed: usize, mark: u8, state: &mut Vec<u8>, stack: &mut Vec<usize>| {
        let mut bounds = CellBox {
            i0: usize::MAX,
            j0: usize::MAX,
            i1: 0,
            j1: 0,
        };
        state[seed] = mark;
        stack.push(seed);
        while let Some(c) = stack.pop() {
            let (i, j) = (c % nx, c / nx);
            bounds = CellBox {
                i0: bounds.i0.min(i),
                j0: bounds.j0.min(j),
                i1: bounds.i1.max(i),
                j1: bounds.j1.max(j),
            };
            for n in neighbours(c).into_iter().flatten() {
                if state[n] == 0 {
                    state[n] = mark;
                    stack.push(n);
                }
            }
        }
        bounds
    };
    for c in 0..nx * ny {
        let (i, j) = (c % nx, c / nx);
        let edge = i == 0 || j == 0 || i + 1 == nx || j + 1 == ny;
        if edge && state[c] == 0 {
            flood(c, 1, &mut state, &mut stack);
        }
    }
    let mut regions = Vec::new();
    for c in 0..nx * ny {
        if state[c] == 0 {
            regions.push(flood(c, 2, &mut state, &mut stack));
        }
    }
    regions
}

/// The rectangle around a region: its cells' bounds grown by the cell the
/// drawn edges took, each side moved onto the nearest model vertex within
/// two cells of it (where there is one).
fn rectangle(raster: &Raster, region: CellBox, snap_to: &[DVec2], frame: &PlaneFrame) -> Opening {
    let cell = raster.cell;
    let low = raster.origin + DVec2::new(region.i0 as f64, region.j0 as f64) * cell;
    let high = raster.origin + DVec2::new(region.i1 as f64 + 1.0, region.j1 as f64 + 1.0) * cell;
    let snap = |guess: f64, axis: usize| {
        snap_to
            .iter()
            .map(|p| p.to_array()[axis])
            .filter(|c| (c - guess).abs() <= 2.0 * cell)
            .min_by(|a, b| (a - guess).abs().total_cmp(&(b - guess).abs()))
            .unwrap_or(guess)
    };
    let x0 = snap(low.x - 0.5 * cell, 0);
    let x1 = snap(high.x + 0.5 * cell, 0);
    let y0 = snap(low.y - 0.5 * cell, 1);
    let y1 = snap(high.y + 0.5 * cell, 1);
    let corners = [
        DVec2::new(x0, y0),
        DVec2::new(x1, y0),
        DVec2::new(x1, y1),
        DVec2::new(x0, y1),
    ]
    .map(|p| frame.to_world(p));
    Opening {
        corners,
        normal: frame.normal,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rgb::Rgb;
    use crate::scene::{Material, Surface};

    /// A rectangle from `corner` along `a` and `b` (its front is a × b).
    fn rect(corner: DVec3, a: DVec3, b: DVec3) -> Vec<DVec3> {
        vec![corner, corner + a, corner + a + b, corner + b]
    }

    /// A 4 × 3 × 4 box facing inwards, without the faces `leave_out`
    /// names (0 floor, 1 ceiling, 2 north z = 0, 3 south z = 4, 4 west, 5
    /// east), with `extra` polygons.
    fn room(leave_out: &[usize], extra: Vec<Vec<DVec3>>) -> Scene {
        let (x, y, z) = (DVec3::X * 4.0, DVec3::Y * 3.0, DVec3::Z * 4.0);
        let faces = [
            rect(DVec3::ZERO, z, x),
            rect(y, x, z),
            rect(DVec3::ZERO, x, y),
            rect(z, y, x),
            rect(DVec3::ZERO, y, z),
            rect(x, z, y),
        ];
        let mut scene = Scene::default();
        scene
            .materials
            .push(Material::diffuse("m", Rgb::splat(0.5)));
        for (k, face) in faces.into_iter().enumerate() {
            if !leave_out.contains(&k) {
                scene.surfaces.push(Surface::new("f", 0, face).unwrap());
            }
        }
        for polygon in extra {
            scene.surfaces.push(Surface::new("x", 0, polygon).unwrap());
        }
        scene
    }

    fn close(a: DVec3, b: DVec3) -> bool {
        a.distance(b) < 1e-9
    }

    /// The opening's corners as a set, rounded.
    fn has_corners(opening: &Opening, want: [DVec3; 4]) -> bool {
        want.iter()
            .all(|w| opening.corners.iter().any(|c| close(*c, *w)))
    }

    #[test]
    fn a_closed_room_with_furniture_has_no_opening() {
        let desk = rect(DVec3::new(1.0, 0.75, 1.0), DVec3::Z, DVec3::X * 1.5);
        assert!(find_openings(&room(&[], vec![desk])).is_empty());
    }

    #[test]
    fn a_window_written_as_four_pieces_is_found_exactly() {
        // The south wall z = 4 around a hole x 1…3, y 0.9…2.1, in pieces
        // whose edges meet in T-junctions.
        let piece = |x0: f64, x1: f64, y0: f64, y1: f64| {
            rect(
                DVec3::new(x0, y0, 4.0),
                DVec3::Y * (y1 - y0),
                DVec3::X * (x1 - x0),
            )
        };
        let wall = vec![
            piece(0.0, 4.0, 0.0, 0.9),
            piece(0.0, 4.0, 2.1, 3.0),
            piece(0.0, 1.0, 0.9, 2.1),
            piece(3.0, 4.0, 0.9, 2.1),
        ];
        let openings = find_openings(&room(&[3], wall));
        assert_eq!(openings.len(), 1, "{openings:?}");
        let want =
            [(1.0, 0.9), (3.0, 0.9), (3.0, 2.1), (1.0, 2.1)].map(|(x, y)| DVec3::new(x, y, 4.0));
        assert!(has_corners(&openings[0], want), "{:?}", openings[0]);
        assert!(openings[0].normal.dot(DVec3::Z).abs() > 1.0 - 1e-12);
    }

    #[test]
    fn a_door_down_to_the_floor_is_found() {
        // The north wall z = 0 with a door x 1.5…2.5 up to 2.1: the floor's
        // edge closes the notch.
        let piece = |x0: f64, x1: f64, y0: f64, y1: f64| {
            rect(
                DVec3::new(x0, y0, 0.0),
                DVec3::X * (x1 - x0),
                DVec3::Y * (y1 - y0),
            )
        };
        let wall = vec![
            piece(0.0, 1.5, 0.0, 3.0),
            piece(2.5, 4.0, 0.0, 3.0),
            piece(1.5, 2.5, 2.1, 3.0),
        ];
        let openings = find_openings(&room(&[2], wall));
        assert_eq!(openings.len(), 1, "{openings:?}");
        let want =
            [(1.5, 0.0), (2.5, 0.0), (2.5, 2.1), (1.5, 2.1)].map(|(x, y)| DVec3::new(x, y, 0.0));
        assert!(has_corners(&openings[0], want), "{:?}", openings[0]);
    }

    #[test]
    fn a_missing_facade_is_found() {
        let openings = find_openings(&room(&[5], Vec::new()));
        assert_eq!(openings.len(), 1, "{openings:?}");
        let want =
            [(0.0, 0.0), (4.0, 0.0), (4.0, 3.0), (0.0, 3.0)].map(|(z, y)| DVec3::new(4.0, y, z));
        assert!(has_corners(&openings[0], want), "{:?}", openings[0]);
    }
}
