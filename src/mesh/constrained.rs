//! Constrained Delaunay triangulation of a planar region (spade).

use glam::DVec2;
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

use crate::scene::polygon_contains;

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
    let mut cdt: ConstrainedDelaunayTriangulation<Point2<f64>> =
        ConstrainedDelaunayTriangulation::new();
    // Every point, then every constraint as a chain through the points lying
    // on it: a point a rounding error off a constraint's line must not be
    // left on one side of it in a sliver.
    let mut vertices: Vec<(DVec2, _)> = Vec::new();
    for &p in outline
        .iter()
        .chain(points)
        .chain(constraints.iter().flatten())
    {
        if let Ok(handle) = cdt.insert(Point2::new(p.x, p.y)) {
            vertices.push((p, handle));
        }
    }
    let scale = vertices
        .iter()
        .map(|(p, _)| p.abs().max_element())
        .fold(0.0, f64::max);
    let outline_edges = (0..outline.len()).map(|k| [outline[k], outline[(k + 1) % outline.len()]]);
    for [a, b] in outline_edges.chain(constraints.iter().copied()) {
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
                ((-1e-12..=1.0 + 1e-12).contains(&t) && off <= 1e-9 * scale).then_some((t, handle))
            })
            .collect();
        chain.sort_by(|x, y| x.0.total_cmp(&y.0));
        chain.dedup_by_key(|(_, handle)| *handle);
        for pair in chain.windows(2) {
            cdt.add_constraint_and_split(pair[0].1, pair[1].1, |p| p);
        }
    }
    // Keep the faces whose centroid lies inside the outline.
    let points: Vec<DVec2> = cdt
        .vertices()
        .map(|v| DVec2::new(v.position().x, v.position().y))
        .collect();
    let triangles = cdt
        .inner_faces()
        .map(|face| face.vertices().map(|v| v.fix().index()))
        .filter(|&[a, b, c]| {
            let (pa, pb, pc) = (points[a], points[b], points[c]);
            let twice_area = (pb - pa).perp_dot(pc - pa);
            let scale = (pb - pa).length_squared().max((pc - pa).length_squared());
            twice_area > 1e-12 * scale && polygon_contains(outline, (pa + pb + pc) / 3.0)
        })
        .collect();
    PlaneTriangulation { points, triangles }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(t: &PlaneTriangulation) -> f64 {
        t.triangles
            .iter()
            .map(|&[a, b, c]| 0.5 * (t.points[b] - t.points[a]).perp_dot(t.points[c] - t.points[a]))
            .sum()
    }

    #[test]
    fn an_l_shape_with_a_crossing_constraint() {
        let l = [
            (0.0, 0.0),
            (2.0, 0.0),
            (2.0, 1.0),
            (1.0, 1.0),
            (1.0, 2.0),
            (0.0, 2.0),
        ]
        .map(|(x, y)| DVec2::new(x, y));
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
}
