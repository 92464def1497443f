//! The mesh: vertices that receive light, elements that interpolate it, and
//! patches that shoot it.

use glam::DVec3;
use std::collections::HashMap;
use std::iter::Sum;
use std::ops::Div;

use super::patch::{Cell, Patch};
use crate::scene::SurfaceId;

/// A mesh vertex. It belongs to one surface; neighbouring surfaces do not
/// share vertices (their normals and materials differ).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshVertex {
    /// Position on the surface.
    pub position: DVec3,
    /// Where the vertex gathers light, from its position
    /// ([`MeshVertex::receiver_position`]), in `f32`: 40 bytes a vertex
    /// instead of 56.
    receiver_offset: [f32; 3],
    /// The surface it lies on.
    pub surface: SurfaceId,
}

impl MeshVertex {
    /// A vertex on `surface` that gathers light at its own position.
    #[must_use]
    pub fn new(position: DVec3, surface: SurfaceId) -> MeshVertex {
        MeshVertex {
            position,
            receiver_offset: [0.0; 3],
            surface,
        }
    }

    /// Where the vertex gathers light: its position, moved a hair into the
    /// surface's interior when it lies on the surface's boundary. Radiosity
    /// on a boundary is the limit from inside the polygon; exactly on an
    /// edge shared with a perpendicular wall, that wall would be seen
    /// edge-on. On a surface only one element across, it moves to the
    /// element's Gauss points instead (see [`Mesh::inset_boundary_receivers`]).
    #[must_use]
    pub fn receiver_position(&self) -> DVec3 {
        self.position + self.receiver_offset()
    }

    /// How far the vertex gathers from its position
    /// ([`MeshVertex::receiver_position`] − `position`): zero but on a
    /// surface's boundary.
    #[must_use]
    pub fn receiver_offset(&self) -> DVec3 {
        let [x, y, z] = self.receiver_offset.map(f64::from);
        DVec3::new(x, y, z)
    }

    /// Moves where the vertex gathers light to `receiver`. The offset from
    /// its position is kept in `f32`: rounded by 6 · 10⁻⁸ of its length
    /// (for an inset of a millimetre, 10⁻¹⁰ m).
    pub fn set_receiver_position(&mut self, receiver: DVec3) {
        self.receiver_offset = (receiver - self.position).as_vec3().to_array();
    }
}

/// A mesh element: a triangle or a quadrilateral of vertices, counter-clockwise
/// seen from the surface's front. 32 bytes: a building's mesh holds tens
/// of millions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Element {
    /// Vertex indices; a triangle repeats its third vertex, and a
    /// quadrilateral's four differ ([`Element::is_triangle`]).
    pub vertices: [u32; 4],
    /// The surface it lies on.
    pub surface: SurfaceId,
    /// Index of the patch it belongs to.
    pub patch: u32,
    /// Area.
    pub area: f64,
}

impl Element {
    /// True for a triangle: its fourth vertex repeats its third.
    #[must_use]
    pub fn is_triangle(&self) -> bool {
        self.vertices[3] == self.vertices[2]
    }

    /// The element's vertex indices (3 or 4).
    #[must_use]
    pub fn corners(&self) -> &[u32] {
        if self.is_triangle() {
            &self.vertices[..3]
        } else {
            &self.vertices
        }
    }

    /// The mean of a per-vertex value over the element's corners,
    /// (Σ value(v)) / n summed in corner order: element averages of vertex
    /// radiosity, irradiance, form factors or positions.
    #[must_use]
    pub fn corner_mean<T>(&self, value: impl Fn(u32) -> T) -> T
    where
        T: Sum + Div<f64, Output = T>,
    {
        let corners = self.corners();
        corners.iter().map(|&v| value(v)).sum::<T>() / corners.len() as f64
    }

    /// The element as triangles, counter-clockwise. A quad is split along
    /// the diagonal whose end vertices differ least by `gap`: with vertex
    /// values, this avoids Gouraud's streak across a bright corner. The
    /// renderer and the probes split the same way, so they agree.
    #[must_use]
    pub fn triangles(&self, gap: impl Fn(u32, u32) -> f64) -> ([[u32; 3]; 2], usize) {
        let [a, b, c, d] = self.vertices;
        if self.is_triangle() {
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
    /// The vertex halfway along each split edge, by the edge's end vertices
    /// (smaller index first): where adaptive refinement split an element,
    /// and so where a coarser neighbour has a hanging vertex. Empty for a
    /// mesh that was never refined.
    pub edge_midpoints: HashMap<(u32, u32), u32>,
}

impl Mesh {
    /// Adds a vertex on a surface; it gathers at its own position until
    /// [`Mesh::inset_boundary_receivers`] moves boundary vertices.
    pub fn add_vertex(&mut self, position: DVec3, surface: SurfaceId) -> u32 {
        self.vertices.push(MeshVertex::new(position, surface));
        (self.vertices.len() - 1) as u32
    }

    /// The longest edge of any patch: the mesher's patch edge
    /// (`patch_max_edge`), or shorter where no surface is that large.
    #[must_use]
    pub fn longest_patch_edge(&self) -> f64 {
        let longest = |polygon: &[DVec3]| {
            let edges = polygon.iter().zip(polygon.iter().cycle().skip(1));
            edges.map(|(a, b)| a.distance(*b)).fold(0.0, f64::max)
        };
        self.patches
            .iter()
            .map(|patch| longest(patch.cell.polygon()))
            .fold(0.0, f64::max)
    }

    /// Adds an empty patch of a surface.
    pub fn add_patch(&mut self, surface: SurfaceId, cell: Cell) -> u32 {
        self.patches.push(Patch {
            surface,
            cell,
            elements: Vec::new(),
            area: 0.0,
        });
        (self.patches.len() - 1) as u32
    }

    /// The shape of an element of this mesh, from its corners' positions.
    #[must_use]
    pub fn element_cell(&self, element: &Element) -> Cell {
        let p = |k: usize| self.vertices[element.vertices[k] as usize].position;
        if element.is_triangle() {
            Cell::triangle(p(0), p(1), p(2))
        } else {
            Cell::quad(p(0), p(1), p(2), p(3))
        }
    }

    /// Adds a triangle or quad element (3 or 4 vertex indices,
    /// counter-clockwise) to a patch of its surface.
    pub fn add_element(&mut self, corners: &[u32], patch: u32) -> u32 {
        // Four corners of which the last two are one make a triangle.
        let corners = match corners {
            [a, b, c, d] if c == d => &[*a, *b, *c][..],
            corners => corners,
        };
        let p = |k: usize| self.vertices[corners[k] as usize].position;
        let cell = if corners.len() == 3 {
            Cell::triangle(p(0), p(1), p(2))
        } else {
            Cell::quad(p(0), p(1), p(2), p(3))
        };
        let mut vertices = [corners[0], corners[1], corners[2], corners[2]];
        if corners.len() == 4 {
            vertices[3] = corners[3];
        }
        let index = self.elements.len() as u32;
        let owner = &mut self.patches[patch as usize];
        self.elements.push(Element {
            vertices,
            surface: owner.surface,
            patch,
            area: cell.area,
        });
        owner.elements.push(index);
        owner.area += cell.area;
        index
    }

    /// Appends another mesh, re-indexing its vertices, elements and patches.
    pub fn append(&mut self, other: Mesh) {
        let (vertex_base, element_base, patch_base) = (
            self.vertices.len() as u32,
            self.elements.len() as u32,
            self.patches.len() as u32,
        );
        self.vertices.extend(other.vertices);
        self.edge_midpoints.extend(
            other
                .edge_midpoints
                .into_iter()
                .map(|((a, b), m)| ((a + vertex_base, b + vertex_base), m + vertex_base)),
        );
        self.elements
            .extend(other.elements.into_iter().map(|mut e| {
                e.vertices = e.vertices.map(|v| v + vertex_base);
                e.patch += patch_base;
                e
            }));
        self.patches.extend(other.patches.into_iter().map(|mut p| {
            p.elements.iter_mut().for_each(|e| *e += element_base);
            p
        }));
    }

    /// Gives back the room its vertex, element, patch and midpoint lists
    /// grew into beyond what they hold: a list that doubles as it grows
    /// holds up to twice its contents, and a building's mesh is most of its
    /// solve's memory. Each patch's short list of elements is made anew at
    /// its size, the lists one after another in the patches' order: made
    /// surface by surface on several threads, they lay scattered through
    /// memory, and a shot that reads its zone's patches' lists one by one
    /// ran 3–4 % slower over 64 offices.
    pub fn shrink_to_fit(&mut self) {
        self.vertices.shrink_to_fit();
        self.elements.shrink_to_fit();
        self.patches.shrink_to_fit();
        self.edge_midpoints.shrink_to_fit();
        let lists: Vec<Vec<u32>> = self.patches.iter().map(|p| p.elements.to_vec()).collect();
        for (patch, list) in self.patches.iter_mut().zip(lists) {
            patch.elements = list;
        }
    }

    /// Removes the elements for which `remove` holds, then patches left
    /// empty and vertices no element uses, re-indexing the rest: elements
    /// keep their order, patches are numbered in the order of their first
    /// element left and vertices in the order of their first use by one.
    /// Vertices keep their gathering points, and the midpoints of split
    /// edges whose three vertices stay are kept, renumbered.
    ///
    /// In place: a building's mesh is most of its memory, and a copy of it
    /// beside it would be the peak of its meshing.
    pub fn remove_elements(&mut self, remove: impl Fn(usize, &Element) -> bool) {
        let keep: Vec<bool> = self
            .elements
            .iter()
            .enumerate()
            .map(|(i, e)| !remove(i, e))
            .collect();
        let mut vertex_map = vec![u32::MAX; self.vertices.len()];
        let mut patch_map = vec![u32::MAX; self.patches.len()];
        let mut element_map = vec![u32::MAX; self.elements.len()];
        let (mut vertices, mut patches, mut elements) = (0, 0, 0);
        for (index, element) in self.elements.iter().enumerate() {
            if !keep[index] {
                continue;
            }
            element_map[index] = elements;
            elements += 1;
            let patch = &mut patch_map[element.patch as usize];
            if *patch == u32::MAX {
                *patch = patches;
                patches += 1;
            }
            for &v in element.corners() {
                if vertex_map[v as usize] == u32::MAX {
                    vertex_map[v as usize] = vertices;
                    vertices += 1;
                }
            }
        }
        let mut index = 0;
        self.elements.retain_mut(|element| {
            index += 1;
            if !keep[index - 1] {
                return false;
            }
            element.vertices = element.vertices.map(|v| vertex_map[v as usize]);
            element.patch = patch_map[element.patch as usize];
            true
        });
        for patch in &mut self.patches {
            patch.elements.retain(|&e| keep[e as usize]);
            patch.area = 0.0;
            for e in &mut patch.elements {
                *e = element_map[*e as usize];
                patch.area += self.elements[*e as usize].area;
            }
        }
        reorder_in_place(&mut self.vertices, vertex_map.clone());
        reorder_in_place(&mut self.patches, patch_map);
        self.edge_midpoints = std::mem::take(&mut self.edge_midpoints)
            .into_iter()
            .filter_map(|((a, b), m)| {
                let [a, b, m] = [a, b, m].map(|v| vertex_map[v as usize]);
                (a != u32::MAX && b != u32::MAX && m != u32::MAX)
                    .then_some(((a.min(b), a.max(b)), m))
            })
            .collect();
    }
}

/// Moves each item to its new index (`new_index[old]`, `u32::MAX` for an
/// item dropped; the kept items' new indices are 0, 1, … in some order),
/// in place, then drops the rest: each swap puts one item where it goes.
fn reorder_in_place<T>(items: &mut Vec<T>, mut new_index: Vec<u32>) {
    let kept = new_index.iter().filter(|&&k| k != u32::MAX).count();
    // The dropped items go after the kept ones, so that every index has
    // one item to take it.
    let mut next = kept as u32;
    for k in &mut new_index {
        if *k == u32::MAX {
            *k = next;
            next += 1;
        }
    }
    for i in 0..items.len() {
        while new_index[i] as usize != i {
            let j = new_index[i] as usize;
            items.swap(i, j);
            new_index.swap(i, j);
        }
    }
    items.truncate(kept);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A building's mesh holds tens of millions of each: an element is 32
    /// bytes and a vertex 40.
    #[test]
    fn elements_and_vertices_stay_small() {
        assert_eq!(std::mem::size_of::<Element>(), 32);
        assert_eq!(std::mem::size_of::<MeshVertex>(), 40);
    }

    /// A triangle repeats its third vertex; four corners whose last two
    /// are one make a triangle too, of the same area.
    #[test]
    fn an_element_is_a_triangle_when_its_third_vertex_repeats() {
        let mut mesh = Mesh::default();
        let surface = SurfaceId::new(0);
        let cell = Cell::quad(DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y);
        let patch = mesh.add_patch(surface, cell);
        for p in [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y] {
            mesh.add_vertex(p, surface);
        }
        let quad = mesh.add_element(&[0, 1, 2, 3], patch);
        let triangle = mesh.add_element(&[0, 1, 2], patch);
        let folded = mesh.add_element(&[0, 1, 2, 2], patch);
        let element = |e: u32| mesh.elements[e as usize];
        assert!(!element(quad).is_triangle());
        assert_eq!(element(quad).corners(), &[0, 1, 2, 3]);
        for e in [triangle, folded] {
            assert!(element(e).is_triangle());
            assert_eq!(element(e).corners(), &[0, 1, 2]);
            assert!((element(e).area - 0.5).abs() < 1e-15);
        }
        assert!((element(quad).area - 1.0).abs() < 1e-15);
    }

    /// A 6 × 6 grid of quads and triangles in 2 × 2 patches, its vertices
    /// made in an order that is not the elements' order of use, and a
    /// midpoint recorded on each row's first edge.
    fn grid_mesh() -> Mesh {
        let mut mesh = Mesh::default();
        let surface = SurfaceId::new(0);
        let n = 6;
        let at = |i: u32, j: u32| DVec3::new(f64::from(i), f64::from(j) * 1.5, 0.0);
        for j in (0..=n).rev() {
            for i in 0..=n {
                mesh.add_vertex(at(i, j), surface);
            }
        }
        let id = |i: u32, j: u32| (n - j) * (n + 1) + i;
        for pj in 0..n / 2 {
            for pi in 0..n / 2 {
                let (i0, j0) = (2 * pi, 2 * pj);
                let cell = Cell::quad(
                    at(i0, j0),
                    at(i0 + 2, j0),
                    at(i0 + 2, j0 + 2),
                    at(i0, j0 + 2),
                );
                let patch = mesh.add_patch(surface, cell);
                for (i, j) in [(i0, j0), (i0 + 1, j0), (i0, j0 + 1), (i0 + 1, j0 + 1)] {
                    let [a, b, c, d] = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
                    if (i + j) % 3 == 0 {
                        mesh.add_element(&[a, b, c], patch);
                        mesh.add_element(&[a, c, d], patch);
                    } else {
                        mesh.add_element(&[a, b, c, d], patch);
                    }
                }
            }
        }
        for j in 0..n {
            mesh.edge_midpoints.insert(
                (id(0, j).min(id(0, j + 1)), id(0, j).max(id(0, j + 1))),
                id(1, j),
            );
        }
        mesh
    }

    /// The mesh a fresh build of the kept elements, in their order, makes.
    fn built_anew(old: &Mesh, keep: &[bool]) -> Mesh {
        let mut mesh = Mesh::default();
        let mut vertex_map = vec![u32::MAX; old.vertices.len()];
        let mut patch_map = vec![u32::MAX; old.patches.len()];
        for (element, _) in old.elements.iter().zip(keep).filter(|(_, k)| **k) {
            let patch = element.patch as usize;
            if patch_map[patch] == u32::MAX {
                patch_map[patch] = mesh.add_patch(element.surface, old.patches[patch].cell);
            }
            let corners: Vec<u32> = element
                .corners()
                .iter()
                .map(|&v| {
                    if vertex_map[v as usize] == u32::MAX {
                        let vertex = old.vertices[v as usize];
                        vertex_map[v as usize] = mesh.add_vertex(vertex.position, vertex.surface);
                    }
                    vertex_map[v as usize]
                })
                .collect();
            mesh.add_element(&corners, patch_map[patch]);
        }
        mesh
    }

    /// Removing elements in place leaves what building the rest anew
    /// would: the same vertices, elements and patches in the same order,
    /// the patches' areas summed alike, empty patches and unused vertices
    /// gone; and the midpoints whose three vertices stay, renumbered.
    #[test]
    fn removing_elements_leaves_what_building_the_rest_anew_would() {
        let original = grid_mesh();
        // Every element of patch 4, and a scatter of others.
        let removed = |i: usize, e: &Element| e.patch == 4 || (i * 7) % 5 == 1;
        let keep: Vec<bool> = original
            .elements
            .iter()
            .enumerate()
            .map(|(i, e)| !removed(i, e))
            .collect();
        let expected = built_anew(&original, &keep);
        let mut mesh = original.clone();
        mesh.remove_elements(removed);
        assert_eq!(mesh.vertices, expected.vertices);
        assert_eq!(mesh.elements, expected.elements);
        assert_eq!(mesh.patches, expected.patches);
        assert_eq!(mesh.patches.len(), original.patches.len() - 1);
        assert!(mesh.vertices.len() < original.vertices.len());
        // A midpoint stays where its edge's ends and itself all do.
        assert!(!mesh.edge_midpoints.is_empty());
        for (&(a, b), &m) in &mesh.edge_midpoints {
            let p = |v: u32| mesh.vertices[v as usize].position;
            assert!(p(a).x == 0.0 && p(b).x == 0.0 && p(m).x == 1.0);
            assert!((p(a).y - p(b).y).abs() == 1.5 && p(m).y == p(a).y.min(p(b).y));
        }
        let kept_midpoints = original.edge_midpoints.iter().filter(|&(&(a, b), &m)| {
            [a, b, m].iter().all(|&v| {
                mesh.vertices
                    .iter()
                    .any(|w| w.position == original.vertices[v as usize].position)
            })
        });
        assert_eq!(mesh.edge_midpoints.len(), kept_midpoints.count());
    }

    /// Each item goes to its new index, the dropped ones away.
    #[test]
    fn items_are_reordered_in_place() {
        let mut items = vec!['a', 'b', 'c', 'd', 'e', 'f'];
        reorder_in_place(&mut items, vec![2, u32::MAX, 0, 3, u32::MAX, 1]);
        assert_eq!(items, ['c', 'f', 'a', 'd']);
    }
}
