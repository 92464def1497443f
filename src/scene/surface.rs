//! A planar, one-sided polygon with its material: the unit of geometry.

use crate::scene::geometry::Box3;
use glam::{DVec2, DVec3};

use super::geometry::triangulate_polygon;

/// An orthonormal frame on a surface's plane: `origin` on the plane, `u` and
/// `v` spanning it, `normal = u × v` the front side's normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneFrame {
    /// A point on the plane.
    pub origin: DVec3,
    /// First in-plane axis (unit).
    pub u: DVec3,
    /// Second in-plane axis (unit), `normal × u`.
    pub v: DVec3,
    /// Unit normal of the front side.
    pub normal: DVec3,
}

impl PlaneFrame {
    /// A frame with the given origin and unit normal; `u` is chosen stably.
    #[must_use]
    pub fn new(origin: DVec3, normal: DVec3) -> PlaneFrame {
        let u = normal.any_orthonormal_vector();
        let v = normal.cross(u);
        PlaneFrame {
            origin,
            u,
            v,
            normal,
        }
    }

    /// Plane coordinates of a world point (its projection onto the plane).
    #[must_use]
    pub fn to_plane(&self, world: DVec3) -> DVec2 {
        let d = world - self.origin;
        DVec2::new(d.dot(self.u), d.dot(self.v))
    }

    /// World position of plane coordinates.
    #[must_use]
    pub fn to_world(&self, plane: DVec2) -> DVec3 {
        self.origin + self.u * plane.x + self.v * plane.y
    }

    /// Signed distance of a world point from the plane (positive in front).
    #[must_use]
    pub fn height(&self, world: DVec3) -> f64 {
        (world - self.origin).dot(self.normal)
    }
}

/// A planar polygon, counter-clockwise seen from its front (the OBJ
/// convention), with one material. Surfaces are one-sided: they emit and
/// reflect only on the front, but block light from both sides.
#[derive(Clone, Debug, PartialEq)]
pub struct Surface {
    /// The name of the object (or group) it came from, for messages.
    pub name: String,
    /// Index into [`crate::Scene::materials`].
    pub material: usize,
    vertices: Vec<DVec3>,
    /// The polygon as the file gave it, before projection onto its plane.
    occluder: Option<Vec<DVec3>>,
    frame: PlaneFrame,
    area: f64,
}

impl Surface {
    /// A surface from the vertices of a planar polygon (counter-clockwise seen
    /// from the front). The normal is Newell's; vertices are assumed to lie on
    /// one plane already (the loaders project nearly planar polygons first).
    ///
    /// Returns `None` when the polygon has fewer than three vertices, a
    /// non-finite coordinate or zero area.
    #[must_use]
    pub fn new(name: impl Into<String>, material: usize, vertices: Vec<DVec3>) -> Option<Surface> {
        if vertices.len() < 3 || vertices.iter().any(|v| !v.is_finite()) {
            return None;
        }
        let twice_area_normal = newell_normal(&vertices);
        let area = 0.5 * twice_area_normal.length();
        if !area.is_finite() || area <= 0.0 {
            return None;
        }
        let normal = twice_area_normal / (2.0 * area);
        let centroid = vertices.iter().copied().sum::<DVec3>() / vertices.len() as f64;
        Some(Surface {
            name: name.into(),
            material,
            vertices,
            occluder: None,
            frame: PlaneFrame::new(centroid, normal),
            area,
        })
    }

    /// Keeps `original`, the polygon as its file gave it (same vertex count
    /// and order, before projection onto its best-fit plane), as the shape
    /// that blocks light. Neighbouring faces share their edges with the
    /// original, not with the projection: shadow rays tested against the
    /// original shapes neither leak through nor stop short at the joins.
    /// Ignored when the vertex counts differ.
    #[must_use]
    pub fn with_occluder(mut self, original: Vec<DVec3>) -> Surface {
        if original.len() == self.vertices.len() && original != self.vertices {
            self.occluder = Some(original);
        }
        self
    }

    /// The polygon that blocks light: the original vertices of a face that
    /// was projected onto its plane, otherwise [`Surface::vertices`].
    #[must_use]
    pub fn occluder_vertices(&self) -> &[DVec3] {
        self.occluder.as_deref().unwrap_or(&self.vertices)
    }

    /// How far the projection moved the file's vertices: the largest
    /// distance between [`Surface::occluder_vertices`] and
    /// [`Surface::vertices`] (zero for a face that was planar).
    #[must_use]
    pub fn projection_offset(&self) -> f64 {
        self.occluder_vertices()
            .iter()
            .zip(&self.vertices)
            .map(|(a, b)| a.distance(*b))
            .fold(0.0, f64::max)
    }

    /// The polygon's vertices, counter-clockwise seen from the front.
    #[must_use]
    pub fn vertices(&self) -> &[DVec3] {
        &self.vertices
    }

    /// The polygon's axis-aligned bounding box.
    #[must_use]
    pub fn bounds(&self) -> Box3 {
        let low = self
            .vertices
            .iter()
            .copied()
            .fold(DVec3::INFINITY, DVec3::min);
        let high = self
            .vertices
            .iter()
            .copied()
            .fold(DVec3::NEG_INFINITY, DVec3::max);
        Box3::new(low, high)
    }

    /// Unit normal of the front side.
    #[must_use]
    pub fn normal(&self) -> DVec3 {
        self.frame.normal
    }

    /// The surface's plane frame (origin at the vertex centroid).
    #[must_use]
    pub fn frame(&self) -> &PlaneFrame {
        &self.frame
    }

    /// Area, in the square of the scene's length unit.
    #[must_use]
    pub fn area(&self) -> f64 {
        self.area
    }

    /// A triangulation of the polygon, as index triples into
    /// [`Surface::vertices`], counter-clockwise like the polygon: a fan for
    /// a convex polygon, ear clipping for a concave one (a fan from a
    /// vertex that does not see the whole polygon would cover area outside
    /// it).
    #[must_use]
    pub fn triangles(&self) -> Vec<[usize; 3]> {
        let fan = || {
            (1..self.vertices.len() - 1)
                .map(|i| [0, i, i + 1])
                .collect()
        };
        let points = self.plane_vertices();
        if is_convex(&points) {
            return fan();
        }
        let triangles = triangulate_polygon(&points);
        if triangles.is_empty() {
            fan()
        } else {
            triangles
        }
    }

    /// The polygon's vertices in plane coordinates (counter-clockwise).
    #[must_use]
    pub fn plane_vertices(&self) -> Vec<DVec2> {
        self.vertices
            .iter()
            .map(|&p| self.frame.to_plane(p))
            .collect()
    }
}

/// Newell's normal: a vector along the polygon's normal whose length is twice
/// its area. Robust for nearly planar and non-convex polygons.
///
/// # References
/// Sutherland, Sproull, Schumacker, "A Characterization of Ten Hidden-Surface
/// Algorithms" (1974), crediting M. Newell.
#[must_use]
pub fn newell_normal(vertices: &[DVec3]) -> DVec3 {
    let Some(&base) = vertices.first() else {
        return DVec3::ZERO;
    };
    let n = vertices.len();
    let mut normal = DVec3::ZERO;
    for i in 0..n {
        // Relative to the first vertex, so far-from-origin polygons keep precision.
        let a = vertices[i] - base;
        let b = vertices[(i + 1) % n] - base;
        normal += a.cross(b);
    }
    normal
}

/// True when every corner of a counter-clockwise polygon turns strictly
/// left: a fan from any vertex then stays inside it and has no zero-area
/// triangle (a straight corner, a vertex on an edge, would give one; ear
/// clipping skips it).
fn is_convex(points: &[DVec2]) -> bool {
    let n = points.len();
    (0..n).all(|k| {
        let (a, b, c) = (points[k], points[(k + 1) % n], points[(k + 2) % n]);
        (b - a).perp_dot(c - b) > 0.0
    })
}
