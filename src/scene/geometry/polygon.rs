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
use super::repair::RepairKind;
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
    /// The kind of repair or skip, when there was one.
    pub repair: Option<RepairKind>,
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
    let skipped = |kind: RepairKind, why: String| CleanedPolygon {
        surfaces: Vec::new(),
        warning: Some(format!("object `{object}`: face skipped: {why}")),
        repair: Some(kind),
    };
    if vertices.iter().any(|v| !v.is_finite()) {
        return skipped(
            RepairKind::NonFinite,
            "it has a non-finite coordinate".into(),
        );
    }
    // Drop repeated vertices, relative to the face's size.
    let raw_diameter = polygon_diameter(vertices);
    let distinct = remove_spikes(
        remove_repeated_vertices(vertices, DUPLICATE_RATIO * raw_diameter),
        DUPLICATE_RATIO * raw_diameter,
    );
    if distinct.len() < 3 {
        return skipped(
            RepairKind::TooFewVertices,
            format!("it has {} distinct vertices, fewer than 3", distinct.len()),
        );
    }
    // Degenerate: no plane, or an area negligible against the diameter².
    let plane = match best_fit_plane(&distinct) {
        Some(p) if p.area >= DEGENERATE_AREA_RATIO * p.diameter * p.diameter => p,
        _ => return skipped(RepairKind::ZeroArea, "its area is zero".into()),
    };
    // Self-intersecting (a bow-tie): no side is its front, no area its own.
    let plane_points: Vec<DVec2> = distinct.iter().map(|&p| plane.frame.to_plane(p)).collect();
    if let Some((a, b)) = first_crossing(&plane_points) {
        return skipped(
            RepairKind::EdgesCross,
            format!(
                "its edges cross each other (edge {} and edge {} of {}): \
             a face must be a simple polygon, its vertices in order around it",
                a + 1,
                b + 1,
                plane_points.len()
            ),
        );
    }
    let planar = plane.max_deviation <= PLANARITY_TOLERANCE * plane.diameter;
    // Touching itself (a keyhole's bridge, or loops meeting at a vertex):
    // split into triangles when it covers its area once, else skip.
    if let Some(touch) = first_touch(&plane_points) {
        let outline = Outline {
            distinct: &distinct,
            plane: &plane,
            plane_points: &plane_points,
            planar,
        };
        return split_touching(object, material, &outline, touch.0, touch.1);
    }
    // Nearly planar: project onto the best-fit plane.
    if planar {
        let projected = project_onto_plane(&distinct, &plane.frame);
        return match Surface::new(object, material, projected) {
            Some(s) => CleanedPolygon {
                surfaces: vec![s.with_occluder(distinct)],
                warning: None,
                repair: None,
            },
            None => skipped(RepairKind::ZeroArea, "its area is zero".into()),
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
        repair: Some(RepairKind::NotPlanar),
    }
}

/// A face's outline as [`clean_polygon`] found it: its distinct vertices,
/// their best-fit plane, their plane coordinates, and whether they lie
/// within the tolerance of that plane.
struct Outline<'a> {
    distinct: &'a [DVec3],
    plane: &'a PolygonPlane,
    plane_points: &'a [DVec2],
    planar: bool,
}

/// A face whose outline touches itself (its `vertex` on its `edge`): split into
/// triangles when they cover its area once, else skipped.
fn split_touching(
    object: &str,
    material: usize,
    outline: &Outline<'_>,
    vertex: usize,
    edge: usize,
) -> CleanedPolygon {
    let touch = format!(
        "its outline touches itself (vertex {} lies on edge {} of {})",
        vertex + 1,
        edge + 1,
        outline.plane_points.len()
    );
    let triangles = triangulate_polygon(outline.plane_points);
    if !covers_once(outline.plane_points, &triangles) {
        return CleanedPolygon {
            surfaces: Vec::new(),
            warning: Some(format!(
                "object `{object}`: face skipped: {touch} and covers some of its area \
                 twice: a face must be a simple polygon, its vertices in order around it"
            )),
            repair: Some(RepairKind::CoversTwice),
        };
    }
    let corners = if outline.planar {
        project_onto_plane(outline.distinct, &outline.plane.frame)
    } else {
        outline.distinct.to_vec()
    };
    let surfaces = surfaces_of_triangles(object, material, &corners, &triangles);
    let warning = format!(
        "object `{object}`: {touch}; split into {} triangles",
        surfaces.len()
    );
    CleanedPolygon {
        surfaces,
        warning: Some(warning),
        repair: Some(RepairKind::TouchesItself),
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
mod tests;
