//! The element hierarchy of adaptive meshing: every element of the starting
//! mesh is the root of a quadtree, and an element that needs more detail is
//! split into four children through its edge midpoints (and, for a quad, its
//! centre).
//!
//! The leaves are the mesh's elements. A neighbour split more finely than an
//! element leaves *hanging* vertices on the element's edges (T-vertices);
//! the mesh records every split edge's midpoint so that the renderer and the
//! probes triangulate each element through its hanging vertices, and no
//! crack or shading seam opens along the edge (see
//! [`Mesh::element_triangles`]).
//!
//! # References
//! M. F. Cohen, D. P. Greenberg, D. S. Immel, P. J. Brock, "An Efficient
//! Radiosity Approach for Realistic Image Synthesis", IEEE CG&A 1986 (patches
//! and elements, adaptive element subdivision).

use glam::DVec3;
use slotmap::{SlotMap, new_key_type};

use super::patch::Cell;
use super::topology::{Element, Mesh};
use super::validate::area_tolerance;

new_key_type! {
    /// A node of the element hierarchy.
    pub struct ElementKey;
}

/// A node of the hierarchy: an element, and its children once split.
#[derive(Clone, Debug, PartialEq)]
pub struct ElementNode {
    /// The element's corners (3 or 4 vertex indices, counter-clockwise),
    /// its surface, patch and area.
    pub element: Element,
    /// The element it was split from; `None` for an element of the starting mesh.
    pub parent: Option<ElementKey>,
    /// Its four children once split.
    pub children: Option<[ElementKey; 4]>,
    /// Depth: 0 for the starting mesh.
    pub level: u32,
}

/// Quadtrees of elements over a mesh; the mesh's elements are the leaves.
#[derive(Clone, Debug, Default)]
pub struct ElementHierarchy {
    nodes: SlotMap<ElementKey, ElementNode>,
    roots: Vec<ElementKey>,
    /// The node of each mesh element, by element index.
    leaves: Vec<ElementKey>,
}

impl ElementHierarchy {
    /// A hierarchy whose roots are the mesh's elements.
    #[must_use]
    pub fn new(mesh: &Mesh) -> ElementHierarchy {
        let mut nodes = SlotMap::with_key();
        let roots: Vec<ElementKey> = mesh
            .elements
            .iter()
            .map(|&element| {
                nodes.insert(ElementNode {
                    element,
                    parent: None,
                    children: None,
                    level: 0,
                })
            })
            .collect();
        ElementHierarchy {
            nodes,
            leaves: roots.clone(),
            roots,
        }
    }

    /// The node of mesh element `index`.
    #[must_use]
    pub fn leaf(&self, index: usize) -> &ElementNode {
        &self.nodes[self.leaves[index]]
    }

    /// A node.
    #[must_use]
    pub fn node(&self, key: ElementKey) -> Option<&ElementNode> {
        self.nodes.get(key)
    }

    /// The roots: the elements of the starting mesh.
    #[must_use]
    pub fn roots(&self) -> &[ElementKey] {
        &self.roots
    }

    /// Nodes in the hierarchy, split or not.
    #[must_use]
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// True when the hierarchy has no element.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// Splits the given mesh elements into four children each, adding the
    /// edge midpoints (shared with neighbours through
    /// [`Mesh::edge_midpoints`]) and quad centres as vertices. The mesh's
    /// elements become the new leaves, in hierarchy order; patches keep
    /// their areas. Returns the vertices added, whose values the caller
    /// must compute.
    pub fn split(&mut self, mesh: &mut Mesh, elements: &[usize]) -> Vec<u32> {
        let first_new = mesh.vertices.len() as u32;
        let mut split = vec![false; mesh.elements.len()];
        for &e in elements {
            split[e] = true;
        }
        let mut leaves = Vec::with_capacity(self.leaves.len() + 3 * elements.len());
        for (index, &key) in self.leaves.iter().enumerate() {
            if !split[index] {
                leaves.push(key);
                continue;
            }
            let node = &self.nodes[key];
            let (element, level) = (node.element, node.level);
            let children = split_element(mesh, &element).map(|corners| {
                self.nodes.insert(ElementNode {
                    element: element_with(mesh, &element, &corners),
                    parent: Some(key),
                    children: None,
                    level: level + 1,
                })
            });
            self.nodes[key].children = Some(children);
            leaves.extend(children);
        }
        self.leaves = leaves;
        self.write_leaves(mesh);
        (first_new..mesh.vertices.len() as u32).collect()
    }

    /// Replaces the mesh's elements with the leaves, and rebuilds each
    /// patch's element list (its area is unchanged: the children tile it).
    fn write_leaves(&self, mesh: &mut Mesh) {
        mesh.elements = self.leaves.iter().map(|&k| self.nodes[k].element).collect();
        for patch in &mut mesh.patches {
            patch.elements.clear();
        }
        for (index, element) in mesh.elements.iter().enumerate() {
            mesh.patches[element.patch as usize]
                .elements
                .push(index as u32);
        }
    }

    /// Checks the hierarchy against its mesh: the mesh's elements are
    /// exactly the leaves; every split node has four children one level
    /// deeper whose areas sum to its own, on its surface and patch; every
    /// recorded edge midpoint lies halfway along its edge. Then checks the
    /// mesh itself ([`Mesh::validate`]). Returns the first violation.
    pub fn validate(&self, mesh: &Mesh, surface_areas: &[f64]) -> Result<(), String> {
        if self.leaves.len() != mesh.elements.len() {
            return Err(format!(
                "{} leaves but {} mesh elements",
                self.leaves.len(),
                mesh.elements.len()
            ));
        }
        for (index, &key) in self.leaves.iter().enumerate() {
            let node = self
                .nodes
                .get(key)
                .ok_or(format!("element {index}: no node"))?;
            if node.children.is_some() {
                return Err(format!("element {index}: its node is split"));
            }
            if node.element != mesh.elements[index] {
                return Err(format!("element {index}: differs from its node"));
            }
        }
        for (key, node) in &self.nodes {
            let Some(children) = node.children else {
                continue;
            };
            let mut area = 0.0;
            for child in children {
                let c = self
                    .nodes
                    .get(child)
                    .ok_or(format!("{key:?}: child missing"))?;
                if c.parent != Some(key) || c.level != node.level + 1 {
                    return Err(format!(
                        "{key:?}: child {child:?} has the wrong parent or level"
                    ));
                }
                if c.element.surface != node.element.surface
                    || c.element.patch != node.element.patch
                {
                    return Err(format!(
                        "{key:?}: child {child:?} on another surface or patch"
                    ));
                }
                area += c.element.area;
            }
            let corners: Vec<DVec3> = node
                .element
                .corners()
                .iter()
                .filter_map(|&v| mesh.vertices.get(v as usize).map(|v| v.position))
                .collect();
            let tolerance = area_tolerance(&corners, node.element.area);
            if (area - node.element.area).abs() > tolerance * node.element.area {
                return Err(format!(
                    "{key:?}: children cover {area}, the element {}",
                    node.element.area
                ));
            }
        }
        for (&(a, b), &m) in &mesh.edge_midpoints {
            let p = |v: u32| -> Result<DVec3, String> {
                mesh.vertices
                    .get(v as usize)
                    .map(|v| v.position)
                    .ok_or(format!("edge ({a}, {b}): vertex {v} out of range"))
            };
            let halfway = 0.5 * (p(a)? + p(b)?);
            if p(m)?.distance(halfway) > 1e-9 * p(a)?.distance(p(b)?) {
                return Err(format!("edge ({a}, {b}): midpoint {m} is not halfway"));
            }
        }
        mesh.validate(surface_areas)
    }
}

/// The corners of the four children of an element: a triangle's corner
/// triangles and middle triangle, or a quad's four quads around its centre.
fn split_element(mesh: &mut Mesh, element: &Element) -> [[u32; 4]; 4] {
    let c = element.corners();
    let n = c.len();
    let mid: Vec<u32> = (0..n)
        .map(|k| mesh.midpoint(c[k], c[(k + 1) % n]))
        .collect();
    if element.is_triangle() {
        let (a, b, d) = (c[0], c[1], c[2]);
        let (ab, bd, da) = (mid[0], mid[1], mid[2]);
        [
            [a, ab, da, da],
            [ab, b, bd, bd],
            [da, bd, d, d],
            [ab, bd, da, da],
        ]
    } else {
        let position = c
            .iter()
            .map(|&v| mesh.vertices[v as usize].position)
            .sum::<DVec3>()
            / 4.0;
        let offset = c.iter().map(|&v| receiver_offset(mesh, v)).sum::<DVec3>() / 4.0;
        let centre = mesh.add_vertex(position, element.surface);
        mesh.vertices[centre as usize].set_receiver_position(position + offset);
        let (a, b, d, e) = (c[0], c[1], c[2], c[3]);
        let (ab, bd, de, ea) = (mid[0], mid[1], mid[2], mid[3]);
        [
            [a, ab, centre, ea],
            [ab, b, bd, centre],
            [centre, bd, d, de],
            [ea, centre, de, e],
        ]
    }
}

/// How far a vertex's receiver position is moved off its position.
fn receiver_offset(mesh: &Mesh, v: u32) -> DVec3 {
    mesh.vertices[v as usize].receiver_offset()
}

/// A child element of `parent` with the given corners (a triangle repeats
/// its third).
fn element_with(mesh: &Mesh, parent: &Element, corners: &[u32; 4]) -> Element {
    let p = |k: usize| mesh.vertices[corners[k] as usize].position;
    let cell = if parent.is_triangle() {
        Cell::triangle(p(0), p(1), p(2))
    } else {
        Cell::quad(p(0), p(1), p(2), p(3))
    };
    debug_assert_eq!(corners[3] == corners[2], parent.is_triangle());
    Element {
        vertices: *corners,
        surface: parent.surface,
        patch: parent.patch,
        area: cell.area,
    }
}

impl Mesh {
    /// The vertex halfway along edge (a, b), added (and recorded in
    /// [`Mesh::edge_midpoints`]) the first time it is asked for. Its
    /// receiver position moves off the edge as its ends' do on average, so
    /// a midpoint of a boundary edge also gathers just inside the surface.
    pub fn midpoint(&mut self, a: u32, b: u32) -> u32 {
        let key = (a.min(b), a.max(b));
        if let Some(&m) = self.edge_midpoints.get(&key) {
            return m;
        }
        let position =
            0.5 * (self.vertices[a as usize].position + self.vertices[b as usize].position);
        let offset = 0.5 * (receiver_offset(self, a) + receiver_offset(self, b));
        let surface = self.vertices[a as usize].surface;
        let m = self.add_vertex(position, surface);
        self.vertices[m as usize].set_receiver_position(position + offset);
        self.edge_midpoints.insert(key, m);
        m
    }

    /// The element's boundary, counter-clockwise: its corners with the
    /// hanging vertices of finer neighbours inserted along each edge.
    #[must_use]
    pub fn element_outline(&self, element: &Element) -> Vec<u32> {
        let corners = element.corners();
        let mut outline = Vec::with_capacity(2 * corners.len());
        for k in 0..corners.len() {
            self.push_edge(corners[k], corners[(k + 1) % corners.len()], &mut outline);
        }
        outline
    }

    /// Pushes edge (a, b)'s vertices from a up to, not including, b.
    fn push_edge(&self, a: u32, b: u32, out: &mut Vec<u32>) {
        match self.edge_midpoints.get(&(a.min(b), a.max(b))) {
            Some(&m) => {
                self.push_edge(a, m, out);
                self.push_edge(m, b, out);
            }
            None => out.push(a),
        }
    }

    /// The triangles that render element `element`, counter-clockwise.
    ///
    /// Without hanging vertices a quad is split along the diagonal whose end
    /// vertices differ least by `gap` (see [`Element::triangles`]). With
    /// them, the convex outline is cut ear by ear, never through a hanging
    /// vertex, so every hanging vertex is a corner of this element's
    /// triangles as of its neighbour's: the rendered mesh is conforming.
    pub fn element_triangles(
        &self,
        element: &Element,
        gap: impl Fn(u32, u32) -> f64,
        out: &mut Vec<[u32; 3]>,
    ) {
        out.clear();
        if self.edge_midpoints.is_empty() {
            let (split, count) = element.triangles(gap);
            out.extend_from_slice(&split[..count]);
            return;
        }
        let outline = self.element_outline(element);
        if outline.len() == element.corners().len() {
            let (split, count) = element.triangles(gap);
            out.extend_from_slice(&split[..count]);
            return;
        }
        let position = |v: u32| self.vertices[v as usize].position;
        triangulate_convex_outline(&outline, &position, out);
    }
}

/// Cuts a convex polygon whose edges may carry extra collinear vertices into
/// triangles using only its vertices, each triangle of positive area.
///
/// Ears are cut at strict corners only, and never so that the rest would be
/// flat: after cutting corner i the rest still has three non-collinear
/// vertices. Such a corner exists whenever the outline is not a plain
/// triangle: a quad's other three corners stay non-collinear, and of a
/// triangle's corners only one whose two edges are both bare can leave a flat
/// rest.
fn triangulate_convex_outline(
    outline: &[u32],
    position: &dyn Fn(u32) -> DVec3,
    out: &mut Vec<[u32; 3]>,
) {
    let mut ring: Vec<u32> = outline.to_vec();
    let twice_area = |a: u32, b: u32, c: u32| {
        (position(b) - position(a))
            .cross(position(c) - position(a))
            .length()
    };
    let scale = |ring: &[u32]| {
        ring.iter()
            .map(|&v| position(v).distance_squared(position(ring[0])))
            .fold(0.0, f64::max)
    };
    let flat = 1e-12 * scale(&ring);
    while ring.len() > 3 {
        let n = ring.len();
        let corner =
            |i: usize| twice_area(ring[(i + n - 1) % n], ring[i], ring[(i + 1) % n]) > flat;
        let rest_is_flat = |i: usize| {
            let rest: Vec<u32> = (1..n).map(|k| ring[(i + k) % n]).collect();
            let (first, last) = (rest[0], rest[rest.len() - 1]);
            rest.iter().all(|&v| twice_area(first, last, v) <= flat)
        };
        // Among the corners that may be cut, the one with the best-shaped
        // ear: the largest area over its longest edge squared.
        let quality = |i: usize| {
            let (a, b, c) = (ring[(i + n - 1) % n], ring[i], ring[(i + 1) % n]);
            let longest = [(a, b), (b, c), (c, a)]
                .iter()
                .map(|&(p, q)| position(p).distance_squared(position(q)))
                .fold(0.0, f64::max);
            twice_area(a, b, c) / longest.max(f64::MIN_POSITIVE)
        };
        let Some(ear) = (0..n)
            .filter(|&i| corner(i) && !rest_is_flat(i))
            .max_by(|&i, &j| quality(i).total_cmp(&quality(j)))
        else {
            break;
        };
        out.push([ring[(ear + n - 1) % n], ring[ear], ring[(ear + 1) % n]]);
        ring.remove(ear);
    }
    if ring.len() == 3 && twice_area(ring[0], ring[1], ring[2]) > flat {
        out.push([ring[0], ring[1], ring[2]]);
    }
}
