//! The mesh's invariants, checked by [`Mesh::validate`], and the tolerance
//! on areas computed two ways that it and the element hierarchy allow.

use glam::DVec3;
use std::collections::HashMap;

use super::topology::Mesh;
use crate::mesh::meshers::constrained::CHAIN_DISTANCE;

impl Mesh {
    /// Checks the mesh's invariants: indices in range, elements on one
    /// surface with positive area, each element listed by exactly its patch,
    /// each patch's area the sum of its elements' and no more than its
    /// cell's, and the elements of each surface covering no more than
    /// `surface_areas` (all of it unless something stands on the surface),
    /// to a relative 1e-9, plus what the rounding of coordinates far from
    /// the origin and the bend a constrained triangulation may give a
    /// cell's edges can add along its boundary. Returns a description of
    /// the first violation.
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
                .get_mut(element.surface.index())
                .ok_or(format!("element {index}: surface out of range"))? += element.area;
        }
        // Each surface's size: the diagonal of its vertices' bounding box.
        let mut bounds = vec![(DVec3::INFINITY, DVec3::NEG_INFINITY); surface_areas.len()];
        for vertex in &self.vertices {
            if let Some((low, high)) = bounds.get_mut(vertex.surface.index()) {
                (*low, *high) = (low.min(vertex.position), high.max(vertex.position));
            }
        }
        let extents: Vec<f64> = bounds
            .iter()
            .map(|(low, high)| {
                if low.x <= high.x {
                    low.distance(*high)
                } else {
                    0.0
                }
            })
            .collect();
        // Its elements may cover more than its area by the bend of its
        // outline's constraints and the rounding of its coordinates, each
        // times the length of its boundary (the edges one element uses).
        let boundaries = self.boundary_lengths(surface_areas.len());
        for (surface, (&sum, &area)) in area_sum.iter().zip(surface_areas).enumerate() {
            let (low, high) = bounds[surface];
            let reach = if low.x <= high.x {
                low.abs().max(high.abs()).max_element()
            } else {
                0.0
            };
            let slack = (2.0 * CHAIN_DISTANCE * extents[surface] + 1000.0 * f64::EPSILON * reach)
                * boundaries[surface];
            if sum > area * (1.0 + 1e-9) + slack {
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
            // A constrained triangulation's cell edges may bend by
            // CHAIN_DISTANCE of the surface's size (twice: unit coordinates).
            let cell = patch.cell.polygon();
            let extent = extents.get(patch.surface.index()).copied().unwrap_or(0.0);
            let bend = 2.0 * CHAIN_DISTANCE * extent * perimeter(cell);
            let tolerance = area_tolerance(cell, patch.cell.area) + bend / patch.cell.area;
            if (covered - patch.area).abs() > tolerance * patch.area
                || patch.area > patch.cell.area * (1.0 + tolerance)
            {
                return Err(format!(
                    "patch {index}: elements cover {covered}, patch area is {}, cell area {}",
                    patch.area, patch.cell.area
                ));
            }
        }
        Ok(())
    }

    /// How many elements use each undirected edge (a, b), a < b, between
    /// corners: 1 on the mesh's boundary, 2 inside.
    fn edge_uses(&self) -> HashMap<(u32, u32), u32> {
        let mut uses: HashMap<(u32, u32), u32> = HashMap::new();
        for element in &self.elements {
            let c = element.corners();
            for k in 0..c.len() {
                let (a, b) = (c[k], c[(k + 1) % c.len()]);
                *uses.entry((a.min(b), a.max(b))).or_default() += 1;
            }
        }
        uses
    }

    /// Per surface (of `surfaces`), the total length of the element edges
    /// used by exactly one element: its mesh's boundary.
    fn boundary_lengths(&self, surfaces: usize) -> Vec<f64> {
        let mut lengths = vec![0.0; surfaces];
        for (&(a, b), &count) in &self.edge_uses() {
            let (Some(va), Some(vb)) =
                (self.vertices.get(a as usize), self.vertices.get(b as usize))
            else {
                continue;
            };
            if let (1, Some(length)) = (count, lengths.get_mut(va.surface.index())) {
                *length += va.position.distance(vb.position);
            }
        }
        lengths
    }
}

/// Relative tolerance on areas computed two ways over a cell of `area` with
/// corners `polygon`: 10⁻⁹, plus the rounding of coordinates as far from the
/// origin as the cell's farthest corner, r: each corner is off by up to
/// ε·r, which moves the area by about ε·r times the perimeter P, allowed a
/// thousand times over: 10⁻⁹ + 1000 ε·r·P/A.
pub(crate) fn area_tolerance(polygon: &[DVec3], area: f64) -> f64 {
    let reach = polygon
        .iter()
        .map(|p| p.abs().max_element())
        .fold(0.0, f64::max);
    if area > 0.0 {
        1e-9 + 1000.0 * f64::EPSILON * reach * perimeter(polygon) / area
    } else {
        1e-9
    }
}

/// The perimeter of a closed polygon.
fn perimeter(polygon: &[DVec3]) -> f64 {
    (0..polygon.len())
        .map(|k| polygon[k].distance(polygon[(k + 1) % polygon.len()]))
        .sum()
}
