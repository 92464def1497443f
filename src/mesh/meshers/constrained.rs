//! Constrained Delaunay triangulation of a planar region (spade).

use std::collections::HashMap;

use glam::DVec2;
use spade::handles::FixedVertexHandle;
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

use crate::scene::{distance_to_boundary, polygon_contains};

/// A triangulation in plane coordinates: points and counter-clockwise
/// triangles indexing them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlaneTriangulation {
    /// Vertex positions.
    pub points: Vec<DVec2>,
    /// Triangles, counter-clockwise.
    pub triangles: Vec<[usize; 3]>,
}

/// Triangulates the inside of `outline` (a simple polygon) with every one of
/// `points` as a vertex and every segment of `constraints` (and the
/// outline's edges) as a chain of triangle edges, by spade's constrained
/// Delaunay triangulation. Constraints that cross are split where they
/// cross. Points outside the outline are ignored, and so is input spade
/// rejects (non-finite or absurdly large coordinates).
///
/// # References
/// L. P. Chew, "Constrained Delaunay Triangulations", Algorithmica 1989;
/// the spade crate.
#[must_use]
pub fn triangulate_constrained(
    outline: &[DVec2],
    points: &[DVec2],
    constraints: &[[DVec2; 2]],
) -> PlaneTriangulation {
    let mut cdt = Cdt::new();
    // Points a rounding error apart (a layout point and a patch corner
    // computed two ways) become one: two vertices there would leave a crack.
    let mut snap = Snapper::new(
        outline
            .iter()
            .chain(points)
            .chain(constraints.iter().flatten()),
    );
    let outline: Vec<DVec2> = outline.iter().map(|&p| snap.point(p)).collect();
    let points: Vec<DVec2> = points.iter().map(|&p| snap.point(p)).collect();
    let constraints: Vec<[DVec2; 2]> = constraints
        .iter()
        .map(|s| s.map(|p| snap.point(p)))
        .collect();
    let outline_edges: Vec<[DVec2; 2]> = (0..outline.len())
        .map(|k| [outline[k], outline[(k + 1) % outline.len()]])
        .collect();
    // Where segments cross, a vertex of our own: spade's splitting of
    // crossing constraints is not robust to nearly coincident crossings.
    let crossings: Vec<DVec2> = segment_crossings(&outline_edges, &constraints)
        .into_iter()
        .map(|p| snap.point(p))
        .collect();
    // Every point, then every constraint as a chain through the points lying
    // on it: a point a rounding error off a constraint's line must not be
    // left on one side of it in a sliver.
    let unit = UnitFrame::new(outline.iter().chain(&points));
    let vertices = insert_vertices(
        &mut cdt,
        &unit,
        outline
            .iter()
            .chain(&points)
            .chain(constraints.iter().flatten())
            .chain(&crossings),
    );
    add_constraint_chains(
        &mut cdt,
        &vertices,
        &unit,
        outline_edges.iter().chain(&constraints),
    );
    // A vertex spade made where constraints cross, a rounding error from a
    // vertex already there, is that vertex (else the mesh has a crack).
    let (points, faces) = welded_faces(&cdt, &mut snap, &unit);
    // A needle (two corners a rounding error apart, beyond the snapping
    // distance: crossings of nearly parallel segments) is one point there.
    // Left out instead, it would leave a crack between its long sides.
    let merged = collapse_needles(&points, &faces, &outline);
    // Keep the faces whose centroid lies inside the outline.
    let triangles = faces
        .into_iter()
        .map(|face| face.map(|k| merged[k]))
        .filter(|&[a, b, c]| a != b && b != c && c != a)
        .filter(|&[a, b, c]| {
            let (pa, pb, pc) = (points[a], points[b], points[c]);
            !is_sliver(pa, pb, pc) && polygon_contains(&outline, (pa + pb + pc) / 3.0)
        })
        .collect();
    PlaneTriangulation { points, triangles }
}

/// The constrained triangulation being built, in unit coordinates.
type Cdt = ConstrainedDelaunayTriangulation<Point2<f64>>;

/// Inserts `points` (plane coordinates) into `cdt` in `unit` coordinates:
/// returns each one spade accepted, in unit coordinates, with its handle.
fn insert_vertices<'a>(
    cdt: &mut Cdt,
    unit: &UnitFrame,
    points: impl Iterator<Item = &'a DVec2>,
) -> Vec<(DVec2, FixedVertexHandle)> {
    let mut vertices = Vec::new();
    for &p in points {
        let q = unit.to_unit(p);
        if let Ok(handle) = cdt.insert(Point2::new(q.x, q.y)) {
            vertices.push((q, handle));
        }
    }
    vertices
}

/// Adds each of `segments` (plane coordinates) to `cdt` as a chain of
/// constraint edges through the `vertices` lying on it, within
/// [`CHAIN_DISTANCE`], in order along it.
fn add_constraint_chains<'a>(
    cdt: &mut Cdt,
    vertices: &[(DVec2, FixedVertexHandle)],
    unit: &UnitFrame,
    segments: impl Iterator<Item = &'a [DVec2; 2]>,
) {
    let scale = vertices
        .iter()
        .map(|(p, _)| p.abs().max_element())
        .fold(0.0, f64::max);
    for &[a, b] in segments {
        let (a, b) = (unit.to_unit(a), unit.to_unit(b));
        let length_squared = (b - a).length_squared();
        if length_squared.is_nan() || length_squared <= 0.0 {
            continue;
        }
        // The points on the segment, in order along it.
        let mut chain: Vec<(f64, _)> = vertices
            .iter()
            .filter_map(|&(p, handle)| {
                let t = (p - a).dot(b - a) / length_squared;
                let off = (p - a).perp_dot(b - a).abs() / length_squared.sqrt();
                ((-1e-12..=1.0 + 1e-12).contains(&t) && off <= CHAIN_DISTANCE * scale)
                    .then_some((t, handle))
            })
            .collect();
        chain.sort_by(|x, y| x.0.total_cmp(&y.0));
        chain.dedup_by_key(|(_, handle)| *handle);
        // Crossings are vertices already; a piece that would still cross
        // an earlier constraint (by a rounding error) is left out.
        for pair in chain.windows(2) {
            if cdt.can_add_constraint(pair[0].1, pair[1].1) {
                cdt.add_constraint(pair[0].1, pair[1].1);
            }
        }
    }
}

/// The vertices and inner faces of `cdt`, back in plane coordinates, with
/// each vertex snapped and those at one position welded into one.
fn welded_faces(cdt: &Cdt, snap: &mut Snapper, unit: &UnitFrame) -> (Vec<DVec2>, Vec<[usize; 3]>) {
    let mut points: Vec<DVec2> = Vec::new();
    let mut by_position: HashMap<[u64; 2], usize> = HashMap::new();
    let remap: Vec<usize> = cdt
        .vertices()
        .map(|v| {
            let p = snap.point(unit.to_plane(DVec2::new(v.position().x, v.position().y)));
            *by_position
                .entry([p.x.to_bits(), p.y.to_bits()])
                .or_insert_with(|| {
                    points.push(p);
                    points.len() - 1
                })
        })
        .collect();
    let faces: Vec<[usize; 3]> = cdt
        .inner_faces()
        .map(|face| face.vertices().map(|v| remap[v.fix().index()]))
        .collect();
    (points, faces)
}

/// Whether a triangle is too thin to keep: twice its area at most 10⁻¹²
/// of its longest side from `a` squared (or clockwise).
fn is_sliver(a: DVec2, b: DVec2, c: DVec2) -> bool {
    let twice_area = (b - a).perp_dot(c - a);
    let scale = (b - a).length_squared().max((c - a).length_squared());
    twice_area.is_nan() || twice_area <= 1e-12 * scale
}

/// Length of a needle's shortest side, relative to its longest, under
/// which its two nearest corners are taken as one.
const NEEDLE_RATIO: f64 = 1e-6;

/// For each point, the point it is merged into. The two corners of the
/// shortest side of each sliver inside `outline`, when that side is under
/// [`NEEDLE_RATIO`] of its longest, become one: the corner nearer the
/// outline (the lower-numbered on a tie), so that the outline does not
/// move in. A needle's area is below a rounding error of its neighbours',
/// and merging its short side leaves them sharing their long sides. A merge
/// that would turn one of the moved corner's other triangles inside out is
/// not made.
fn collapse_needles(points: &[DVec2], faces: &[[usize; 3]], outline: &[DVec2]) -> Vec<usize> {
    fn root(merged: &[usize], mut k: usize) -> usize {
        while merged[k] != k {
            k = merged[k];
        }
        k
    }
    let centroid = |[a, b, c]: [usize; 3]| (points[a] + points[b] + points[c]) / 3.0;
    let needles: Vec<(usize, usize)> = faces
        .iter()
        .filter(|&&[a, b, c]| is_sliver(points[a], points[b], points[c]))
        .filter(|&&face| polygon_contains(outline, centroid(face)))
        .filter_map(|&[a, b, c]| {
            let sides =
                [(a, b), (b, c), (c, a)].map(|(i, j)| (points[i].distance(points[j]), i, j));
            let longest = sides.iter().map(|s| s.0).fold(0.0, f64::max);
            let (shortest, i, j) = sides.into_iter().min_by(|x, y| x.0.total_cmp(&y.0))?;
            (shortest <= NEEDLE_RATIO * longest).then_some((i, j))
        })
        .collect();
    let mut merged: Vec<usize> = (0..points.len()).collect();
    if needles.is_empty() {
        return merged;
    }
    let mut faces_of: Vec<Vec<usize>> = vec![Vec::new(); points.len()];
    for (f, face) in faces.iter().enumerate() {
        for &k in face {
            faces_of[k].push(f);
        }
    }
    let from_boundary = |k: usize| distance_to_boundary(outline, points[k]);
    for (i, j) in needles {
        let (ri, rj) = (root(&merged, i), root(&merged, j));
        if ri == rj {
            continue;
        }
        let (keep, gone) = match from_boundary(ri)
            .total_cmp(&from_boundary(rj))
            .then(ri.cmp(&rj))
        {
            std::cmp::Ordering::Greater => (rj, ri),
            _ => (ri, rj),
        };
        // Every triangle of the moved points' that stays a triangle must
        // keep its winding.
        let at = |k: usize| match root(&merged, k) {
            r if r == gone => points[keep],
            r => points[r],
        };
        let folds = (0..points.len())
            .filter(|&k| root(&merged, k) == gone)
            .flat_map(|k| &faces_of[k])
            .any(|&f| {
                let [a, b, c] = faces[f];
                let before = [a, b, c].map(|k| points[root(&merged, k)]);
                let after = [at(a), at(b), at(c)];
                let twice_area = |[p, q, r]: [DVec2; 3]| (q - p).perp_dot(r - p);
                let collapsed = [a, b, c].iter().any(|&k| root(&merged, k) == keep);
                !collapsed && twice_area(before) > 0.0 && twice_area(after) <= 0.0
            });
        if !folds {
            merged[gone] = keep;
        }
    }
    (0..points.len()).map(|k| root(&merged, k)).collect()
}

/// Distance, relative to the largest unit coordinate (at most the input's
/// size), within which a point counts as lying on a constraint, which then
/// runs through it: a rounding error must not leave a point on the wrong
/// side of a constraint in a sliver. A constraint may so bend by up to this
/// fraction of the polygon's size, and the area on either side change by
/// that times its length ([`Mesh::validate`](crate::mesh::Mesh::validate) allows
/// for it).
pub(crate) const CHAIN_DISTANCE: f64 = 1e-9;

/// Coordinates in which the triangulation is built: centred on the input's
/// bounding box and scaled by a power of two to about unit size, with any
/// coordinate under spade's smallest (1.8e-43) flushed to zero. Spade
/// refuses such coordinates, and a polygon a few 10⁻³² across has vertices
/// a rounding error from its frame's axes that would fall out.
struct UnitFrame {
    centre: DVec2,
    unit: f64,
}

impl UnitFrame {
    fn new<'a>(points: impl Iterator<Item = &'a DVec2>) -> UnitFrame {
        let (low, high) = points.filter(|p| p.is_finite()).fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(lo, hi), &p| (lo.min(p), hi.max(p)),
        );
        let size = (high - low).max_element();
        if !(size.is_finite() && size > 0.0) {
            return UnitFrame {
                centre: DVec2::ZERO,
                unit: 1.0,
            };
        }
        UnitFrame {
            centre: 0.5 * (low + high),
            unit: 2f64.powi(size.log2().ceil() as i32),
        }
    }

    fn to_unit(&self, p: DVec2) -> DVec2 {
        let q = (p - self.centre) / self.unit;
        let flush = |x: f64| {
            if x.abs() < spade::MIN_ALLOWED_VALUE {
                0.0
            } else {
                x
            }
        };
        DVec2::new(flush(q.x), flush(q.y))
    }

    fn to_plane(&self, q: DVec2) -> DVec2 {
        q * self.unit + self.centre
    }
}

/// The points where two segments cross properly (each passing strictly
/// through the other), over every pair of `outline` edges and
/// `constraints` (outline edges against each other excepted: the outline is
/// simple). O(n²), pairs with disjoint bounding boxes skipped.
fn segment_crossings(outline: &[[DVec2; 2]], constraints: &[[DVec2; 2]]) -> Vec<DVec2> {
    let segments: Vec<[DVec2; 2]> = outline.iter().chain(constraints).copied().collect();
    let mut crossings = Vec::new();
    for (i, &[a, b]) in segments.iter().enumerate() {
        let (low, high) = (a.min(b), a.max(b));
        for &[c, d] in &segments[(i + 1).max(outline.len())..] {
            if c.max(d).cmplt(low).any() || c.min(d).cmpgt(high).any() {
                continue;
            }
            let denominator = (b - a).perp_dot(d - c);
            if denominator == 0.0 || !denominator.is_finite() {
                continue;
            }
            let t = (c - a).perp_dot(d - c) / denominator;
            let u = (c - a).perp_dot(b - a) / denominator;
            if t > 0.0 && t < 1.0 && u > 0.0 && u < 1.0 {
                crossings.push(a + (b - a) * t);
            }
        }
    }
    crossings
}

/// Merges points closer than [`SNAP_DISTANCE`] × their largest coordinate:
/// each point maps to the first point met within that distance.
struct Snapper {
    cell: f64,
    cells: HashMap<(i64, i64), Vec<DVec2>>,
}

/// Distance, relative to the largest coordinate, under which points merge:
/// a million rounding errors of coordinates a thousand polygon sizes from
/// the origin, far below any mesh feature.
const SNAP_DISTANCE: f64 = 1e-10;

impl Snapper {
    fn new<'a>(points: impl Iterator<Item = &'a DVec2>) -> Snapper {
        let scale = points
            .filter(|p| p.is_finite())
            .map(|p| p.abs().max_element())
            .fold(0.0, f64::max);
        Snapper {
            cell: SNAP_DISTANCE * scale,
            cells: HashMap::new(),
        }
    }

    /// The representative of `p`: an earlier point within the snapping
    /// distance, or `p` itself.
    fn point(&mut self, p: DVec2) -> DVec2 {
        if !(p.is_finite() && self.cell > 0.0) {
            return p;
        }
        let key = (
            (p.x / self.cell).floor() as i64,
            (p.y / self.cell).floor() as i64,
        );
        for dx in -1..=1 {
            for dy in -1..=1 {
                let near = self.cells.get(&(key.0 + dx, key.1 + dy));
                if let Some(&q) = near.and_then(|c| c.iter().find(|q| q.distance(p) <= self.cell)) {
                    return q;
                }
            }
        }
        self.cells.entry(key).or_default().push(p);
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::geometry::plane_polygon::L_SHAPE;

    fn area(t: &PlaneTriangulation) -> f64 {
        t.triangles
            .iter()
            .map(|&[a, b, c]| 0.5 * (t.points[b] - t.points[a]).perp_dot(t.points[c] - t.points[a]))
            .sum()
    }

    #[test]
    fn an_l_shape_with_a_crossing_constraint() {
        let l = L_SHAPE;
        let points = [
            DVec2::new(0.5, 0.5),
            DVec2::new(1.5, 0.5),
            DVec2::new(0.5, 1.5),
        ];
        let constraints = [
            [DVec2::new(0.2, 0.1), DVec2::new(1.8, 0.9)],
            [DVec2::new(0.2, 0.9), DVec2::new(1.8, 0.1)],
        ];
        let t = triangulate_constrained(&l, &points, &constraints);
        assert!((area(&t) - 3.0).abs() < 1e-12, "{}", area(&t));
        assert!(t.triangles.iter().all(|&[a, b, c]| {
            (t.points[b] - t.points[a]).perp_dot(t.points[c] - t.points[a]) > 0.0
        }));
        // The crossing point of the two constraints is a vertex.
        assert!(
            t.points
                .iter()
                .any(|p| p.distance(DVec2::new(1.0, 0.5)) < 1e-12)
        );
    }

    /// A box about every test point.
    const AROUND: [DVec2; 4] = [
        DVec2::new(-1.0, -1.0),
        DVec2::new(3.0, -1.0),
        DVec2::new(3.0, 3.0),
        DVec2::new(-1.0, 3.0),
    ];

    #[test]
    fn a_needle_s_short_side_is_one_point_and_a_cap_keeps_its_corners() {
        // 0–1–2: a needle along the x axis, its short side 1–2 10⁻⁹ long,
        // corner 2 the nearer the outline (below).
        // 3–4–5: a cap, corner 5 a rounding error off the middle of 3–4.
        // 0–1–6: a fair triangle.
        let points = [
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 1e-16),
            DVec2::new(1.0 + 1e-9, -1e-9),
            DVec2::new(0.0, 2.0),
            DVec2::new(1.0, 2.0),
            DVec2::new(0.5, 2.0 + 1e-14),
            DVec2::new(0.5, 1.0),
        ];
        let faces = [[0, 1, 2], [3, 4, 5], [0, 1, 6]];
        let merged = collapse_needles(&points, &faces, &AROUND);
        assert_eq!(merged, [0, 2, 2, 3, 4, 5, 6]);
        assert!(is_sliver(points[0], points[1], points[2]));
        assert!(is_sliver(points[3], points[4], points[5]));
        assert!(!is_sliver(points[0], points[1], points[6]));
        // Outside the outline, a needle is left as it is (it is dropped).
        let far = [
            DVec2::new(10.0, 10.0),
            DVec2::new(10.0, 11.0),
            DVec2::new(11.0, 10.0),
        ];
        assert_eq!(
            collapse_needles(&points, &faces, &far),
            [0, 1, 2, 3, 4, 5, 6]
        );
    }

    /// A merge that would turn a small triangle at the moved corner inside
    /// out is not made.
    #[test]
    fn a_needle_is_left_where_merging_would_fold_a_neighbour() {
        let points = [
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 1e-16),
            DVec2::new(1.0 + 1e-9, -1e-9),
            DVec2::new(1.0 - 1e-9, -0.5e-9),
            DVec2::new(1.0 + 2e-9, -0.5e-9),
        ];
        // 1–3–4 lies above 3–4's line; corner 1 moved onto 2 falls below.
        assert!(!is_sliver(points[1], points[3], points[4]));
        let merged = collapse_needles(&points, &[[0, 1, 2], [1, 3, 4]], &AROUND);
        assert_eq!(merged, [0, 1, 2, 3, 4]);
        // Without that neighbour, the needle closes.
        assert_eq!(
            collapse_needles(&points, &[[0, 1, 2]], &AROUND),
            [0, 2, 2, 3, 4]
        );
    }
}
