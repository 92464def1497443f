//! Where a surface's boundary vertices gather: a hair inside the surface,
//! or, on a surface one element across, at the element's Gauss points.
//!
//! The work is a surface's own: an element's edge is a boundary edge when
//! no other element uses it, and elements only use their own surface's
//! vertices ([`Mesh::validate`]). So each surface's elements are read on
//! their own, surfaces in parallel, their edges counted by sorting rather
//! than in one table of every edge of the mesh, whose serial passes would
//! take a large share of a building's meshing.

use glam::DVec3;
use rayon::prelude::*;
use std::collections::HashMap;
use std::ops::Range;

use crate::mesh::data::topology::{Element, Mesh};
use crate::scene::SurfaceId;

/// (1 − 1/√3)/2: the lower two-point Gauss–Legendre abscissa on [0, 1].
const GAUSS_ABSCISSA: f64 = 0.211_324_865_405_187_1;

/// Surfaces whose boundary moves are found in parallel before they are
/// applied.
const INSET_BATCH: usize = 16_384;

/// What one surface's boundary does to one of its vertices: the sum of the
/// inward normals of its boundary edges, and its Gauss-point offset.
type VertexMove = (u32, DVec3, DVec3);

impl Mesh {
    /// Moves every vertex on a surface's boundary (on an edge used by only
    /// one element) by `distance` towards the interior, into
    /// [`crate::mesh::MeshVertex::receiver_position`]; where a surface is
    /// one element across, further, to that element's Gauss points, so that
    /// its shading shows the element's mean light rather than its edges'.
    ///
    /// The direction is the sum of the inward normals of the vertex's
    /// boundary edges: elements are counter-clockwise, so the interior lies
    /// to the left of each edge, along normal × edge. (Averaging directions
    /// to element centres instead would point into the hole at a reflex
    /// corner, such as the floor around a block's corner.)
    ///
    /// Surfaces are read apart: an edge two surfaces' elements share
    /// (which [`Mesh::validate`] refuses: a vertex belongs to one surface)
    /// is a boundary edge of each, and such a vertex takes the sum of
    /// each surface's move.
    pub fn inset_boundary_receivers(&mut self, distance: f64) {
        self.inset_boundary_receivers_by(&|_| distance);
    }

    /// [`Mesh::inset_boundary_receivers`] with each surface's own
    /// `distance(surface)`: a building's rooms each by their own size.
    pub fn inset_boundary_receivers_by(&mut self, distance: &(dyn Fn(SurfaceId) -> f64 + Sync)) {
        for vertex in &mut self.vertices {
            vertex.set_receiver_position(vertex.position);
        }
        // A batch of surfaces at a time, each vertex moved as its surface's
        // are found: no list of every vertex's move (for a million quads,
        // two such lists held 860 MB at the end of meshing).
        for batch in self.elements_by_surface().chunks(INSET_BATCH) {
            let moves: Vec<Vec<VertexMove>> = batch
                .par_iter()
                .map(|ranges| self.boundary_moves(ranges))
                .collect();
            for (v, direction, offset) in moves.into_iter().flatten() {
                let vertex = &mut self.vertices[v as usize];
                let inward = direction.normalize_or_zero() * distance(vertex.surface);
                let moved = vertex.receiver_position() + inward + offset;
                vertex.set_receiver_position(moved);
            }
        }
    }

    /// The elements of each surface, as runs of consecutive indices (one
    /// run a surface in a mesh that [`Mesh::append`] built surface by
    /// surface), in the order the surfaces first appear.
    fn elements_by_surface(&self) -> Vec<Vec<Range<usize>>> {
        let mut groups: Vec<Vec<Range<usize>>> = Vec::new();
        let mut group_of = HashMap::new();
        let mut start = 0;
        for end in 1..=self.elements.len() {
            let surface = self.elements[start].surface;
            if end < self.elements.len() && self.elements[end].surface == surface {
                continue;
            }
            let group = *group_of.entry(surface).or_insert_with(|| {
                groups.push(Vec::new());
                groups.len() - 1
            });
            groups[group].push(start..end);
            start = end;
        }
        groups
    }

    /// The moves of the boundary vertices of one surface's elements (`ranges`
    /// of element indices): each vertex's summed inward normals and its
    /// Gauss-point offset ([`gauss_offsets`]).
    fn boundary_moves(&self, ranges: &[Range<usize>]) -> Vec<VertexMove> {
        let elements: Vec<&Element> = ranges
            .iter()
            .flat_map(|range| &self.elements[range.clone()])
            .collect();
        let boundary = boundary_edges(&elements);
        let mut moves: HashMap<u32, (DVec3, DVec3)> = HashMap::new();
        for (element, &edges) in elements.iter().zip(&boundary) {
            if edges == 0 {
                continue;
            }
            let c = element.corners();
            let p = |k: usize| self.vertices[c[k] as usize].position;
            let normal = (p(1) - p(0)).cross(p(2) - p(0)).normalize_or_zero();
            for k in 0..c.len() {
                if edges & (1 << k) != 0 {
                    let edge = p((k + 1) % c.len()) - p(k);
                    let left = normal.cross(edge).normalize_or_zero();
                    moves.entry(c[k]).or_default().0 += left;
                    moves.entry(c[(k + 1) % c.len()]).or_default().0 += left;
                }
            }
        }
        for (v, offset) in self.gauss_offsets(&elements, &boundary) {
            moves.entry(v).or_default().1 = offset;
        }
        moves
            .into_iter()
            .map(|(v, (direction, offset))| (v, direction, offset))
            .collect()
    }

    /// Per vertex of `elements` that moves, how far it gathers off its
    /// position because its surface is only one element across: a quad
    /// whose two opposite edges both lie on the boundary (a book's spine, a
    /// table leg) moves those edges' vertices across it to the two-point
    /// Gauss–Legendre abscissae (1 ∓ 1/√3)/2 of its width, and a triangle
    /// that is a whole surface moves each corner to the three-point rule's
    /// point (2/3, 1/6, 1/6). `boundary` holds each element's boundary
    /// edges ([`boundary_edges`]).
    ///
    /// Gouraud shading of such an element shows the mean of its corners'
    /// values; gathered at the corners themselves, that mean is the field's
    /// along the boundary only, where the neighbours standing beside a thin
    /// face shade it most (the shelved books' spines came out 10–20 % dark).
    /// At the Gauss points, the mean of the corners is the Gauss rule's
    /// estimate of the element's mean, exact for a cubic across the width.
    /// Where two elements on a side agree on a direction, a vertex takes
    /// their mean; offsets across different directions add.
    ///
    /// # References
    /// G. Strang, G. Fix, "An Analysis of the Finite Element Method", 1973,
    /// ch. 4.3 (numerical integration).
    fn gauss_offsets(&self, elements: &[&Element], boundary: &[u8]) -> Vec<(u32, DVec3)> {
        // Per vertex: the offsets found, each with how many elements gave it.
        let mut found: HashMap<u32, Vec<(DVec3, u32)>> = HashMap::new();
        let mut add = |v: u32, offset: DVec3| {
            let offsets = found.entry(v).or_default();
            let direction = offset.normalize_or_zero();
            match offsets
                .iter_mut()
                .find(|(o, _)| o.normalize_or_zero().dot(direction) > 0.99)
            {
                Some((sum, count)) => {
                    *sum += offset;
                    *count += 1;
                }
                None => offsets.push((offset, 1)),
            }
        };
        for (element, &edges) in elements.iter().zip(boundary) {
            let c = element.corners();
            let p = |k: usize| self.vertices[c[k] as usize].position;
            let is_boundary = |k: usize| edges & (1 << (k % c.len())) != 0;
            if element.is_triangle() {
                if (0..3).all(is_boundary) {
                    for (k, &corner) in c.iter().enumerate() {
                        add(corner, (p((k + 1) % 3) + p((k + 2) % 3) - 2.0 * p(k)) / 6.0);
                    }
                }
                continue;
            }
            let normal = (p(1) - p(0)).cross(p(2) - p(0)).normalize_or_zero();
            for k in 0..4 {
                if !(is_boundary(k) && is_boundary(k + 2)) {
                    continue;
                }
                let edge = p((k + 1) % 4) - p(k);
                let left = normal.cross(edge).normalize_or_zero();
                let width = element.area / edge.length().max(f64::MIN_POSITIVE);
                let offset = left * (GAUSS_ABSCISSA * width);
                if offset.is_finite() {
                    add(c[k], offset);
                    add(c[(k + 1) % 4], offset);
                }
            }
        }
        found
            .into_iter()
            .map(|(v, found)| {
                let offset = found
                    .iter()
                    .map(|&(sum, count)| sum / f64::from(count))
                    .sum();
                (v, offset)
            })
            .collect()
    }
}

/// Per element, bit k set where its edge from corner k to corner k + 1 is
/// used by no other of `elements`: the edges counted by sorting them by
/// their ends.
fn boundary_edges(elements: &[&Element]) -> Vec<u8> {
    let mut edges: Vec<(u64, u32)> = elements
        .iter()
        .enumerate()
        .flat_map(|(i, element)| {
            let c = element.corners();
            (0..c.len()).map(move |k| {
                let (a, b) = (c[k], c[(k + 1) % c.len()]);
                let key = (u64::from(a.min(b)) << 32) | u64::from(a.max(b));
                // Element i's edge k, in one u32 (a surface of 2³⁰
                // elements would take 16 GiB of the mesh's alone).
                (key, ((i as u32) << 2) | k as u32)
            })
        })
        .collect();
    edges.sort_unstable_by_key(|&(key, _)| key);
    let mut boundary = vec![0u8; elements.len()];
    for run in edges.chunk_by(|a, b| a.0 == b.0) {
        if let [(_, slot)] = run {
            boundary[(slot >> 2) as usize] |= 1 << (slot & 3);
        }
    }
    boundary
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Cell;

    /// A unit quad at x offset `x` of surface `surface`, in a patch of its own.
    fn add_quad(mesh: &mut Mesh, surface: usize, x: f64) {
        let surface = SurfaceId::new(surface);
        let corners = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
            .map(|(a, b)| DVec3::new(x + a, b, 0.0));
        let v = corners.map(|c| mesh.add_vertex(c, surface));
        let patch = mesh.add_patch(
            surface,
            Cell::quad(corners[0], corners[1], corners[2], corners[3]),
        );
        mesh.add_element(&v, patch);
    }

    #[test]
    fn a_surface_split_over_runs_of_elements_is_read_as_one() {
        const INSET: f64 = 0.01;
        // Surface 0 is two quads side by side whose shared edge is inside
        // it; surface 1's quad lies between them in the element list.
        let mut mesh = Mesh::default();
        add_quad(&mut mesh, 0, 0.0);
        add_quad(&mut mesh, 1, 5.0);
        add_quad(&mut mesh, 0, 1.0);
        // The second quad's corners at x = 1 repeat the first's: join them.
        for element in &mut mesh.elements[2..] {
            element.vertices[0] = 1;
            element.vertices[3] = 2;
        }
        mesh.inset_boundary_receivers(INSET);
        let at = |v: usize| mesh.vertices[v].receiver_position();
        // Within the rounding of the offsets, kept in f32.
        let close = |v: usize, expected: DVec3| at(v).distance(expected) < 1e-7;
        // Corner (0, 0): inward along the diagonal, and to the Gauss point
        // across the strip's height only (the edge at x = 1 is not a
        // boundary, so the quad is not one element wide along x).
        let expected =
            DVec3::new(1.0, 1.0, 0.0).normalize() * INSET + DVec3::new(0.0, GAUSS_ABSCISSA, 0.0);
        assert!(close(0, expected), "{}", at(0));
        // Surface 1's lone quad is one element across both ways.
        let lone = DVec3::new(5.0, 0.0, 0.0)
            + DVec3::new(1.0, 1.0, 0.0).normalize() * INSET
            + DVec3::new(GAUSS_ABSCISSA, GAUSS_ABSCISSA, 0.0);
        assert!(close(4, lone), "{}", at(4));
        // The shared corner (1, 0) moves up only.
        let shared = DVec3::new(1.0, INSET + GAUSS_ABSCISSA, 0.0);
        assert!(close(1, shared), "{}", at(1));
    }
}
