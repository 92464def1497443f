//! Polygon geometry for loaders: best-fit planes, projection, and the
//! clean-up that turns a raw face into planar [`Surface`]s.
//!
//! A face read from a file is a list of 3D points. Radiosity needs planar
//! polygons, so each face is
//! - cleaned of consecutive repeated vertices;
//! - **skipped** when fewer than three distinct vertices remain, its area
//!   is below [`DEGENERATE_AREA_RATIO`] × diameter², or two of its edges
//!   cross (a bow-tie: no side is its front), or its outline touches itself
//!   and goes twice round some of its area;
//! - **split into triangles** when its outline touches itself but covers
//!   its area once (a keyhole, or loops meeting at a vertex);
//! - **projected** onto its best-fit plane when nearly planar (every vertex
//!   within [`PLANARITY_TOLERANCE`] × diameter of the plane: measured scenes
//!   such as the Cornell box have walls a millimetre off plane);
//! - **split into triangles** (ear clipping in the best-fit plane) otherwise.
//!
//! Skips and splits come back with a warning naming the object.

use glam::{DVec2, DVec3};

use super::plane_polygon::distance_to_segment;
use super::triangulate::{signed_area_2d, triangulate_polygon};
use crate::scene::surface::{PlaneFrame, Surface, newell_normal};

/// Largest distance of a vertex from the best-fit plane, as a fraction of the
/// polygon's diameter, for the polygon to count as planar (1 %).
pub const PLANARITY_TOLERANCE: f64 = 0.01;

/// Smallest area, as a fraction of the squared diameter, for a polygon not
/// to count as degenerate.
pub const DEGENERATE_AREA_RATIO: f64 = 1e-12;

/// Relative distance under which consecutive vertices count as repeated.
const DUPLICATE_RATIO: f64 = 1e-10;

/// The best-fit plane of a 3D polygon and how far the polygon is from it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PolygonPlane {
    /// Plane frame: origin at the vertex centroid, normal along Newell's
    /// normal (so the polygon is counter-clockwise in (u, v)).
    pub frame: PlaneFrame,
    /// Area of the polygon projected on the plane, |N_newell| / 2.
    pub area: f64,
    /// Largest distance of a vertex from the plane.
    pub max_deviation: f64,
    /// Largest distance between two vertices.
    pub diameter: f64,
}

/// The best-fit plane of a polygon: through the vertex centroid
/// c = (1/n) Σ p_i, with Newell's normal N = Σ p_i × p_{i+1} (normalised).
///
/// For a non-planar polygon this is the plane of its "vector area"; the
/// polygon's projection onto it has area |N| / 2. Returns `None` for fewer
/// than three vertices, a non-finite coordinate or a zero normal.
///
/// # References
/// Sutherland, Sproull, Schumacker (1974), Newell's method; Tampieri,
/// "Newell's Method for Computing the Plane Equation of a Polygon",
/// *Graphics Gems III* (1992).
#[must_use]
pub fn best_fit_plane(vertices: &[DVec3]) -> Option<PolygonPlane> {
    if vertices.len() < 3 || vertices.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let twice_area_normal = newell_normal(vertices);
    let length = twice_area_normal.length();
    if !length.is_finite() || length <= 0.0 {
        return None;
    }
    let centroid = vertices.iter().copied().sum::<DVec3>() / vertices.len() as f64;
    let frame = PlaneFrame::new(centroid, twice_area_normal / length);
    let max_deviation = vertices
        .iter()
        .map(|&p| frame.height(p).abs())
        .fold(0.0, f64::max);
    Some(PolygonPlane {
        frame,
        area: 0.5 * length,
        max_deviation,
        diameter: polygon_diameter(vertices),
    })
}

/// The largest distance between two vertices, max |p_i − p_j| (O(n²)).
#[must_use]
pub fn polygon_diameter(vertices: &[DVec3]) -> f64 {
    let mut diameter_squared: f64 = 0.0;
    for (i, a) in vertices.iter().enumerate() {
        for b in &vertices[i + 1..] {
            diameter_squared = diameter_squared.max(a.distance_squared(*b));
        }
    }
    diameter_squared.sqrt()
}

/// Orthogonal projection of points onto a plane: p − ((p − o)·n) n.
#[must_use]
pub fn project_onto_plane(vertices: &[DVec3], frame: &PlaneFrame) -> Vec<DVec3> {
    vertices
        .iter()
        .map(|&p| p - frame.normal * frame.height(p))
        .collect()
}

/// Removes consecutive repeated vertices (including the last against the
/// first): those closer than `tolerance`.
#[must_use]
pub fn remove_repeated_vertices(vertices: &[DVec3], tolerance: f64) -> Vec<DVec3> {
    let mut kept: Vec<DVec3> = Vec::with_capacity(vertices.len());
    for &p in vertices {
        if kept.last().is_none_or(|q| q.distance(p) > tolerance) {
            kept.push(p);
        }
    }
    while kept.len() > 1 && kept[0].distance(kept[kept.len() - 1]) <= tolerance {
        kept.pop();
    }
    kept
}

/// Removes spikes: a vertex where the outline turns straight back on itself
/// (the edges before and after it antiparallel), such as `b` in `a b a c d`.
/// A spike encloses no area, but it makes the outline touch itself, and the
/// triangulation of such an outline may cover more than the polygon. Repeats
/// left behind (`a a`) are merged, until no spike is left. An outline that
/// would be left with fewer than three vertices (it is all spike: a line) is
/// returned as it came, for the area check to refuse.
fn remove_spikes(vertices: Vec<DVec3>, tolerance: f64) -> Vec<DVec3> {
    let mut kept = vertices.clone();
    loop {
        let n = kept.len();
        if n < 3 {
            return vertices;
        }
        let spike = (0..n).find(|&i| {
            let (prev, v, next) = (kept[(i + n - 1) % n], kept[i], kept[(i + 1) % n]);
            let (a, b) = (v - prev, next - v);
            a.cross(b).length() <= 1e-9 * a.length() * b.length() && a.dot(b) < 0.0
        });
        let Some(i) = spike else {
            return kept;
        };
        kept.remove(i);
        kept = remove_repeated_vertices(&kept, tolerance);
    }
}

/// What [`clean_polygon`] made of a raw face.
#[derive(Clone, Debug, PartialEq)]
pub struct CleanedPolygon {
    /// Zero (skipped), one (planar) or several (split) planar surfaces.
    pub surfaces: Vec<Surface>,
    /// What was repaired or skipped, naming the object; `None` when the face
    /// was used as it is (or projected by less than the tolerance).
    pub warning: Option<String>,
}

/// Turns a raw face into planar surfaces named `object` with `material`.
///
/// The face's vertices are counter-clockwise seen from its front. Repeated
/// consecutive vertices are dropped; a face with fewer than three distinct
/// vertices or area < [`DEGENERATE_AREA_RATIO`] · d² (d its diameter) is
/// skipped; a face within [`PLANARITY_TOLERANCE`] · d of its best-fit plane
/// is projected onto it; any other face is split into triangles by ear
/// clipping in that plane, each triangle keeping the original vertices (a
/// triangle is always planar). Skips and splits carry a warning.
#[must_use]
pub fn clean_polygon(object: &str, material: usize, vertices: &[DVec3]) -> CleanedPolygon {
    let skipped = |why: String| CleanedPolygon {
        surfaces: Vec::new(),
        warning: Some(format!("object `{object}`: face skipped: {why}")),
    };
    if vertices.iter().any(|v| !v.is_finite()) {
        return skipped("it has a non-finite coordinate".into());
    }
    // Drop repeated vertices, relative to the face's size.
    let raw_diameter = polygon_diameter(vertices);
    let distinct = remove_spikes(
        remove_repeated_vertices(vertices, DUPLICATE_RATIO * raw_diameter),
        DUPLICATE_RATIO * raw_diameter,
    );
    if distinct.len() < 3 {
        return skipped(format!(
            "it has {} distinct vertices, fewer than 3",
            distinct.len()
        ));
    }
    // Degenerate: no plane, or an area negligible against the diameter².
    let plane = match best_fit_plane(&distinct) {
        Some(p) if p.area >= DEGENERATE_AREA_RATIO * p.diameter * p.diameter => p,
        _ => return skipped("its area is zero".into()),
    };
    // Self-intersecting (a bow-tie): no side is its front, no area its own.
    let plane_points: Vec<DVec2> = distinct.iter().map(|&p| plane.frame.to_plane(p)).collect();
    if let Some((a, b)) = first_crossing(&plane_points) {
        return skipped(format!(
            "its edges cross each other (edge {} and edge {} of {}): \
             a face must be a simple polygon, its vertices in order around it",
            a + 1,
            b + 1,
            plane_points.len()
        ));
    }
    let planar = plane.max_deviation <= PLANARITY_TOLERANCE * plane.diameter;
    // Touching itself (a keyhole's bridge, or loops meeting at a vertex):
    // split into triangles when it covers its area once, else skip.
    if let Some((vertex, edge)) = first_touch(&plane_points) {
        let touch = format!(
            "its outline touches itself (vertex {} lies on edge {} of {})",
            vertex + 1,
            edge + 1,
            plane_points.len()
        );
        let triangles = triangulate_polygon(&plane_points);
        if !covers_once(&plane_points, &triangles) {
            return skipped(format!(
                "{touch} and covers some of its area twice: a face must be a simple \
                 polygon, its vertices in order around it"
            ));
        }
        let corners = if planar {
            project_onto_plane(&distinct, &plane.frame)
        } else {
            distinct.clone()
        };
        let surfaces = surfaces_of_triangles(object, material, &corners, &triangles);
        let warning = format!(
            "object `{object}`: {touch}; split into {} triangles",
            surfaces.len()
        );
        return CleanedPolygon {
            surfaces,
            warning: Some(warning),
        };
    }
    // Nearly planar: project onto the best-fit plane.
    if planar {
        let projected = project_onto_plane(&distinct, &plane.frame);
        return match Surface::new(object, material, projected) {
            Some(s) => CleanedPolygon {
                surfaces: vec![s.with_occluder(distinct)],
                warning: None,
            },
            None => skipped("its area is zero".into()),
        };
    }
    // Clearly non-planar: ear-clip in the best-fit plane.
    let surfaces = split_into_triangles(object, material, &distinct, &plane.frame);
    let warning = format!(
        "object `{object}`: face is not planar (a vertex lies {:.3} off its best-fit plane, \
         {:.1} % of its size); split into {} triangles",
        plane.max_deviation,
        100.0 * plane.max_deviation / plane.diameter,
        surfaces.len()
    );
    CleanedPolygon {
        surfaces,
        warning: Some(warning),
    }
}

/// The first pair of non-adjacent edges (edge k runs from vertex k to
/// k + 1) that properly cross, each passing strictly through the other's
/// line. Edges that only touch or overlap (a keyhole's bridge) do not count.
/// O(n²) with a bounding-box test first.
#[must_use]
pub fn first_crossing(points: &[DVec2]) -> Option<(usize, usize)> {
    let n = points.len();
    if n < 4 {
        return None;
    }
    let scale = points
        .iter()
        .map(|p| p.abs().max_element())
        .fold(0.0, f64::max);
    let eps = 1e-12 * scale * scale;
    let edge = |k: usize| (points[k], points[(k + 1) % n]);
    let side = |a: DVec2, b: DVec2, p: DVec2| {
        let cross = (b - a).perp_dot(p - a);
        if cross > eps {
            1
        } else if cross < -eps {
            -1
        } else {
            0
        }
    };
    for i in 0..n {
        let (a, b) = edge(i);
        let (low, high) = (a.min(b), a.max(b));
        // Edges i + 1 and i − 1 share a vertex with edge i.
        for j in i + 2..n {
            if i == 0 && j == n - 1 {
                continue;
            }
            let (c, d) = edge(j);
            if c.max(d).cmplt(low).any() || c.min(d).cmpgt(high).any() {
                continue;
            }
            if side(a, b, c) * side(a, b, d) < 0 && side(c, d, a) * side(c, d, b) < 0 {
                return Some((i, j));
            }
        }
    }
    None
}

/// Triangulates a non-planar polygon in the plane `frame` (where it is
/// counter-clockwise) and makes a surface of each non-degenerate triangle.
fn split_into_triangles(
    object: &str,
    material: usize,
    vertices: &[DVec3],
    frame: &PlaneFrame,
) -> Vec<Surface> {
    let plane_points: Vec<DVec2> = vertices.iter().map(|&p| frame.to_plane(p)).collect();
    let triangles = triangulate_polygon(&plane_points);
    surfaces_of_triangles(object, material, vertices, &triangles)
}

/// A surface of each non-degenerate triangle (index triples into `corners`).
fn surfaces_of_triangles(
    object: &str,
    material: usize,
    corners: &[DVec3],
    triangles: &[[usize; 3]],
) -> Vec<Surface> {
    triangles
        .iter()
        .filter_map(|&[a, b, c]| {
            Surface::new(object, material, vec![corners[a], corners[b], corners[c]])
        })
        .collect()
}

/// The first vertex of the outline lying on an edge that does not end at
/// it (within 10⁻⁹ of the outline's size), as (vertex, edge), edge k
/// running from vertex k to k + 1. Such an outline touches itself without
/// crossing: a keyhole's bridge, a vertex visited twice, or a lobe folded
/// back onto the rest. O(n²) with a bounding-box test first.
#[must_use]
pub fn first_touch(points: &[DVec2]) -> Option<(usize, usize)> {
    let n = points.len();
    if n < 4 {
        return None;
    }
    let (low, high) = points.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    let tolerance = 1e-9 * (high - low).length();
    for j in 0..n {
        let (a, b) = (points[j], points[(j + 1) % n]);
        let (box_low, box_high) = (a.min(b) - tolerance, a.max(b) + tolerance);
        for (k, &p) in points.iter().enumerate() {
            if k == j || k == (j + 1) % n || p.cmplt(box_low).any() || p.cmpgt(box_high).any() {
                continue;
            }
            if distance_to_segment(p, a, b) <= tolerance {
                return Some((k, j));
            }
        }
    }
    None
}

/// Whether the triangles tile the counter-clockwise outline `points` once:
/// each triangle counter-clockwise with winding number 1 at its centroid,
/// and their areas summing to the outline's signed (shoelace) area, which
/// counts area the outline goes round twice twice.
fn covers_once(points: &[DVec2], triangles: &[[usize; 3]]) -> bool {
    let mut sum = 0.0;
    for &[a, b, c] in triangles {
        let (a, b, c) = (points[a], points[b], points[c]);
        let area = 0.5 * (b - a).perp_dot(c - a);
        if area <= 0.0 || winding_number(points, (a + b + c) / 3.0) != 1 {
            return false;
        }
        sum += area;
    }
    let area = signed_area_2d(points);
    (sum - area).abs() <= 1e-9 * area.abs()
}

/// How many times the closed outline `points` winds counter-clockwise round
/// p (Sunday's crossing rule: upward edges with p on their left count +1,
/// downward edges with p on their right −1).
fn winding_number(points: &[DVec2], p: DVec2) -> i32 {
    let n = points.len();
    (0..n)
        .map(|k| {
            let (a, b) = (points[k], points[(k + 1) % n]);
            let left = (b - a).perp_dot(p - a);
            if a.y <= p.y && b.y > p.y && left > 0.0 {
                1
            } else if a.y > p.y && b.y <= p.y && left < 0.0 {
                -1
            } else {
                0
            }
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64, z: f64) -> DVec3 {
        DVec3::new(x, y, z)
    }

    #[test]
    fn plane_of_a_tilted_square() {
        let square = [v(0., 0., 0.), v(2., 0., 0.), v(2., 2., 1.), v(0., 2., 1.)];
        let plane = best_fit_plane(&square).unwrap();
        assert!(plane.max_deviation < 1e-12);
        assert!((plane.area - 2.0 * 5f64.sqrt()).abs() < 1e-12);
        assert!((plane.diameter - 3.0).abs() < 1e-12);
        let n = plane.frame.normal;
        assert!((n - v(0., -1., 2.).normalize()).length() < 1e-12);
    }

    #[test]
    fn projection_lands_on_the_plane() {
        let quad = [v(0., 0., 0.), v(1., 0., 0.1), v(1., 1., 0.), v(0., 1., 0.1)];
        let plane = best_fit_plane(&quad).unwrap();
        assert!((plane.max_deviation - 0.05).abs() < 1e-12);
        for p in project_onto_plane(&quad, &plane.frame) {
            assert!(plane.frame.height(p).abs() < 1e-12);
        }
    }

    #[test]
    fn nearly_planar_face_is_projected_silently() {
        let quad = [
            v(0., 0., 0.),
            v(10., 0., 0.05),
            v(10., 10., 0.),
            v(0., 10., 0.05),
        ];
        let cleaned = clean_polygon("wall", 3, &quad);
        assert_eq!(cleaned.surfaces.len(), 1);
        assert!(cleaned.warning.is_none());
        assert_eq!(cleaned.surfaces[0].material, 3);
        assert!((cleaned.surfaces[0].area() - 100.0).abs() < 0.01);
    }

    #[test]
    fn non_planar_face_is_split_with_warning() {
        let quad = [v(0., 0., 0.), v(1., 0., 0.), v(1., 1., 0.3), v(0., 1., 0.)];
        let cleaned = clean_polygon("bent", 0, &quad);
        assert_eq!(cleaned.surfaces.len(), 2);
        let warning = cleaned.warning.unwrap();
        assert!(warning.contains("`bent`") && warning.contains("2 triangles"));
        for s in &cleaned.surfaces {
            assert!(s.normal().z > 0.9, "triangles keep the face's front side");
        }
    }

    #[test]
    fn repeated_and_degenerate_faces() {
        let repeated = [
            v(0., 0., 0.),
            v(0., 0., 0.),
            v(1., 0., 0.),
            v(0., 1., 0.),
            v(0., 0., 0.),
        ];
        let cleaned = clean_polygon("r", 0, &repeated);
        assert_eq!(cleaned.surfaces[0].vertices().len(), 3);
        assert!(cleaned.warning.is_none());
        let two = [v(0., 0., 0.), v(1., 0., 0.), v(1., 0., 0.)];
        let cleaned = clean_polygon("two", 0, &two);
        assert!(cleaned.surfaces.is_empty());
        assert!(cleaned.warning.unwrap().contains("`two`"));
        let line = [v(0., 0., 0.), v(1., 0., 0.), v(2., 0., 0.)];
        let cleaned = clean_polygon("line", 0, &line);
        assert!(cleaned.surfaces.is_empty());
        assert!(cleaned.warning.unwrap().contains("area is zero"));
    }

    fn flat(points: &[(f64, f64)]) -> Vec<DVec3> {
        points.iter().map(|&(x, y)| v(x, y, 0.)).collect()
    }

    fn total_area(cleaned: &CleanedPolygon) -> f64 {
        cleaned.surfaces.iter().map(Surface::area).sum()
    }

    #[test]
    fn keyhole_is_split_into_triangles_covering_it_once() {
        // A 10 × 10 square with a 4 × 4 hole, joined by a bridge along y = 5.
        let keyhole = flat(&[
            (0., 0.),
            (10., 0.),
            (10., 10.),
            (0., 10.),
            (0., 5.),
            (3., 5.),
            (3., 7.),
            (7., 7.),
            (7., 3.),
            (3., 3.),
            (3., 5.),
            (0., 5.),
        ]);
        let cleaned = clean_polygon("slab", 0, &keyhole);
        assert!((total_area(&cleaned) - 84.0).abs() < 1e-9, "{cleaned:?}");
        let warning = cleaned.warning.unwrap();
        assert!(warning.contains("`slab`") && warning.contains("touches itself"));
        assert!(cleaned.surfaces.iter().all(|s| s.normal().z > 0.99));
    }

    #[test]
    fn two_squares_meeting_at_a_corner_are_kept() {
        let pinched = flat(&[
            (0., 0.),
            (1., 0.),
            (1., 1.),
            (2., 1.),
            (2., 2.),
            (1., 2.),
            (1., 1.),
            (0., 1.),
        ]);
        let cleaned = clean_polygon("pinched", 0, &pinched);
        assert!((total_area(&cleaned) - 2.0).abs() < 1e-12, "{cleaned:?}");
    }

    #[test]
    fn outline_going_twice_round_some_area_is_skipped() {
        // A triangle lobe folded back inside a 10 × 5 rectangle, touching
        // it at (0, 0) and (5, 0) without crossing (found by fuzzing: the
        // meshers covered 40 of its 60 units of shoelace area).
        let folded = flat(&[
            (0., 0.),
            (5., 0.),
            (10., 4.),
            (0., 0.),
            (5., 0.),
            (10., 0.),
            (10., 5.),
            (0., 5.),
            (0., 0.),
            (5.04, 0.),
        ]);
        let cleaned = clean_polygon("folded", 0, &folded);
        assert!(cleaned.surfaces.is_empty(), "{cleaned:?}");
        let warning = cleaned.warning.unwrap();
        assert!(warning.contains("touches itself") && warning.contains("twice"));
    }

    #[test]
    fn simple_outlines_do_not_touch() {
        let l_shape = [(0., 0.), (2., 0.), (2., 1.), (1., 1.), (1., 2.), (0., 2.)];
        let points: Vec<DVec2> = l_shape.iter().map(|&(x, y)| DVec2::new(x, y)).collect();
        assert_eq!(first_touch(&points), None);
        let cleaned = clean_polygon("l", 0, &flat(&l_shape));
        assert_eq!(cleaned.surfaces.len(), 1);
        assert!(cleaned.warning.is_none());
    }
}
