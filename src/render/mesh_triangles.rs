//! Turning a solved mesh into triangles with vertex radiance.

use super::rasterizer::ShadedTriangle;
use crate::mesh::Mesh;
use crate::scene::Rgb;

/// The triangles of a mesh with per-vertex radiance L = B/π, from the
/// radiosity B (W/m²) of each mesh vertex.
///
/// A quadrilateral element is split along the diagonal whose two end
/// vertices have the closer radiosities: splitting across a bright corner
/// instead would draw a visible diagonal streak in Gouraud shading. An
/// element with hanging vertices on its edges (a finer neighbour's) is
/// triangulated through them, so the image has no T-junction cracks.
#[must_use]
pub fn mesh_triangles(mesh: &Mesh, radiosity: &[Rgb]) -> Vec<ShadedTriangle> {
    let radiance = |v: u32| radiosity[v as usize] / std::f64::consts::PI;
    let position = |v: u32| mesh.vertices[v as usize].position;
    triangle_indices(mesh, radiosity)
        .into_iter()
        .map(|[a, b, c]| ShadedTriangle {
            positions: [position(a), position(b), position(c)],
            radiance: [radiance(a), radiance(b), radiance(c)],
        })
        .collect()
}

/// The mesh's triangles as triples of vertex indices, counter-clockwise seen
/// from the front, in element order: each element split as
/// [`mesh_triangles`] splits it (a quad along the diagonal of closer
/// radiosities). The one triangulation the renderer draws and the exporters
/// write.
pub(crate) fn triangle_indices(mesh: &Mesh, radiosity: &[Rgb]) -> Vec<[u32; 3]> {
    let gap = |p: u32, q: u32| {
        (radiosity[p as usize] - radiosity[q as usize])
            .abs()
            .element_sum()
    };
    let mut triangles = Vec::with_capacity(2 * mesh.elements.len());
    let mut split = Vec::new();
    for element in &mesh.elements {
        mesh.element_triangles(element, gap, &mut split);
        triangles.extend_from_slice(&split);
    }
    triangles
}
