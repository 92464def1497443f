//! The mesh: vertices that receive light, elements that interpolate it, and
//! patches that shoot it.

use glam::DVec3;
use std::collections::HashMap;

use super::patch::Patch;

/// A mesh vertex. It belongs to one surface; neighbouring surfaces do not
/// share vertices (their normals and materials differ).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshVertex {
    /// Position on the surface.
    pub position: DVec3,
    /// Where the vertex gathers light: its position, moved a hair into the
    /// surface's interior when it lies on the surface's boundary. Radiosity
    /// on a boundary is the limit from inside the polygon; exactly on an edge
    /// shared with a perpendicular wall, that wall would be seen edge-on.
    pub receiver_position: DVec3,
    /// Index of the surface.
    pub surface: u32,
}

/// A mesh element: a triangle or a quadrilateral of vertices, counter-clockwise
/// seen from the surface's front.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Element {
    /// Vertex indices; a triangle repeats its third vertex.
    pub vertices: [u32; 4],
    /// True for a triangle.
    pub is_triangle: bool,
    /// Index of the surface.
    pub surface: u32,
    /// Index of the patch it belongs to.
    pub patch: u32,
    /// Area.
    pub area: f64,
}

impl Element {
    /// The element's vertex indices (3 or 4).
    #[must_use]
    pub fn corners(&self) -> &[u32] {
        if self.is_triangle {
            &self.vertices[..3]
        } else {
            &self.vertices
        }
    }

    /// The element as triangles, counter-clockwise. A quad is split along
    /// the diagonal whose end vertices differ least by `gap`: with vertex
    /// values, this avoids Gouraud's streak across a bright corner. The
    /// renderer and the probes split the same way, so they agree.
    #[must_use]
    pub fn triangles(&self, gap: impl Fn(u32, u32) -> f64) -> ([[u32; 3]; 2], usize) {
        let [a, b, c, d] = self.vertices;
        if self.is_triangle {
            ([[a, b, c], [a, b, c]], 1)
        } else if gap(a, c) <= gap(b, d) {
            ([[a, b, c], [a, c, d]], 2)
        } else {
            ([[a, b, d], [b, c, d]], 2)
        }
    }
}

/// A mesh of a whole scene.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Receiving vertices.
    pub vertices: Vec<MeshVertex>,
    /// Interpolating elements.
    pub elements: Vec<Element>,
    /// Shooting patches, each made of elements.
    pub patches: Vec<Patch>,
}

impl Mesh {
    /// Moves every vertex on a surface's boundary (on an edge used by only
    /// one element) by `distance` towards the interior, into
    /// [`MeshVertex::receiver_position`].
    pub fn inset_boundary_receivers(&mut self, distance: f64) {
        // Count the elements using each undirected edge.
        let mut edge_uses: HashMap<(u32, u32), u32> = HashMap::new();
        for element in &self.elements {
            let c = element.corners();
            for k in 0..c.len() {
                let (a, b) = (c[k], c[(k + 1) % c.len()]);
                *edge_uses.entry((a.min(b), a.max(b))).or_default() += 1;
            }
        }
        // Sum, per boundary vertex, the inward directions of its elements.
        let mut inward = vec![DVec3::ZERO; self.vertices.len()];
        for element in &self.elements {
            let c = element.corners();
            let centre = c
                .iter()
                .map(|&v| self.vertices[v as usize].position)
                .sum::<DVec3>()
                / c.len() as f64;
            for k in 0..c.len() {
                let (a, b) = (c[k], c[(k + 1) % c.len()]);
                if edge_uses[&(a.min(b), a.max(b))] == 1 {
                    for v in [a, b] {
                        let p = self.vertices[v as usize].position;
                        inward[v as usize] += (centre - p).normalize_or_zero();
                    }
                }
            }
        }
        for (vertex, direction) in self.vertices.iter_mut().zip(inward) {
            vertex.receiver_position = vertex.position + direction.normalize_or_zero() * distance;
        }
    }

    /// Checks the mesh's invariants: indices in range, elements on one
    /// surface with positive area, each element listed by exactly its patch,
    /// and the elements of each surface tiling `surface_areas` to a relative
    /// 1e-9. Returns a description of the first violation.
    pub fn validate(&self, surface_areas: &[f64]) -> Result<(), String> {
        let mut area_sum = vec![0.0; surface_areas.len()];
        for (index, element) in self.elements.iter().enumerate() {
            for &v in element.corners() {
                let vertex = self
                    .vertices
                    .get(v as usize)
                    .ok_or(format!("element {index}: vertex {v} out of range"))?;
                if vertex.surface != element.surface {
                    return Err(format!(
                        "element {index}: vertex {v} lies on another surface"
                    ));
                }
            }
            if element.area.is_nan() || element.area <= 0.0 {
                return Err(format!(
                    "element {index}: area {} is not positive",
                    element.area
                ));
            }
            let patch = self
                .patches
                .get(element.patch as usize)
                .ok_or(format!("element {index}: patch out of range"))?;
            if !patch.elements.contains(&(index as u32)) {
                return Err(format!("element {index}: its patch does not list it"));
            }
            *area_sum
                .get_mut(element.surface as usize)
                .ok_or(format!("element {index}: surface out of range"))? += element.area;
        }
        for (surface, (&sum, &area)) in area_sum.iter().zip(surface_areas).enumerate() {
            if (sum - area).abs() > 1e-9 * area {
                return Err(format!(
                    "surface {surface}: elements cover {sum}, surface area is {area}"
                ));
            }
        }
        for (index, patch) in self.patches.iter().enumerate() {
            let covered: f64 = patch
                .elements
                .iter()
                .map(|&e| self.elements[e as usize].area)
                .sum();
            if (covered - patch.cell.area).abs() > 1e-9 * patch.cell.area {
                return Err(format!(
                    "patch {index}: elements cover {covered}, patch area is {}",
                    patch.cell.area
                ));
            }
        }
        Ok(())
    }
}
