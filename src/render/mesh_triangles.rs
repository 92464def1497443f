//! Turning a solved mesh into triangles with vertex radiance.

use super::rasterizer::ShadedTriangle;
use crate::mesh::Mesh;
use crate::scene::Rgb;

/// The triangles of a mesh with per-vertex radiance L = B/π, from the
/// radiosity B (W/m²) of each mesh vertex.
///
/// A quadrilateral element is split along the diagonal whose two end
/// vertices have the closer radiosities: splitting across a bright corner
/// instead would draw a visible diagonal streak in Gouraud shading.
#[must_use]
pub fn mesh_triangles(mesh: &Mesh, radiosity: &[Rgb]) -> Vec<ShadedTriangle> {
    let radiance = |v: u32| radiosity[v as usize] / std::f64::consts::PI;
    let position = |v: u32| mesh.vertices[v as usize].position;
    let triangle = |a: u32, b: u32, c: u32| ShadedTriangle {
        positions: [position(a), position(b), position(c)],
        radiance: [radiance(a), radiance(b), radiance(c)],
    };
    let mut triangles = Vec::with_capacity(2 * mesh.elements.len());
    for element in &mesh.elements {
        let (split, count) = element.triangles(radiosity_gap(radiosity));
        for &[a, b, c] in &split[..count] {
            triangles.push(triangle(a, b, c));
        }
    }
    triangles
}

/// How much the radiosities of two vertices differ, summed over channels:
/// the measure by which [`crate::Element::triangles`] picks a quad's diagonal.
/// The renderer, the probes and the exporters all split with it.
pub(crate) fn radiosity_gap(radiosity: &[Rgb]) -> impl Fn(u32, u32) -> f64 + Copy + '_ {
    |p: u32, q: u32| {
        (radiosity[p as usize] - radiosity[q as usize])
            .abs()
            .element_sum()
    }
}
