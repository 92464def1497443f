//! Looking at a solution: its shaded triangles, for a program's own viewer,
//! and its image in memory. The one place where a solution meets the
//! renderer, which itself knows only triangles.

mod exact_sun;
mod pixel_rays;
mod sky;

use crate::mesh::{Element, Mesh};
use crate::render::{Image, RenderSettings, ShadedTriangle, rasterize};
use crate::rgb::Rgb;
use crate::scene::Camera;
use crate::solver::Solution;

impl Solution<'_> {
    /// The rendered triangles: the mesh's elements (quads split along the
    /// diagonal with the closer radiosities) with per-vertex radiance
    /// L = B/π, W/(m²·sr). What [`Solution::render`] draws.
    #[must_use]
    pub fn triangles(&self) -> Vec<ShadedTriangle> {
        let radiosity = |v: u32| self.radiosity_at(v as usize);
        shaded(self.mesh, &radiosity, self.triangle_indices())
    }

    /// The same triangles as vertex-index triples into the mesh's vertices
    /// (counter-clockwise seen from the front), for writers and viewers
    /// that keep the vertices shared: the exporters, `isorad view`. A
    /// quad's diagonal follows the radiosity, so the triples may change as
    /// the solve goes on.
    #[must_use]
    pub fn triangle_indices(&self) -> Vec<[u32; 3]> {
        triangle_indices_of(self.mesh, &|v| self.radiosity_at(v as usize), |_| true)
    }

    /// The triangles an image from `camera` can show, as
    /// [`Solution::triangle_indices`]: all of them, or, where the camera
    /// stands inside a closed zone (a room whose light does not leave it,
    /// see `meshing/zones/`), that zone's elements' alone: its walls hide
    /// the rest. A floor of 16 closed offices then triangulates and draws
    /// one office for a view from inside it, not all sixteen rooms in the
    /// view's frustum.
    pub(crate) fn triangle_indices_seen_from(&self, camera: &Camera) -> Vec<[u32; 3]> {
        match self.zones.zip(self.camera_zone(camera)) {
            Some((zones, zone)) => {
                let radiosity = |v: u32| self.radiosity_at(v as usize);
                triangle_indices_of(self.mesh, &radiosity, |element| {
                    zones.of(element.surface) == zone
                })
            }
            None => self.triangle_indices(),
        }
    }

    /// The closed zone `camera` stands in ([`ZoneLabels::enclosing`]).
    fn camera_zone(&self, camera: &Camera) -> Option<usize> {
        self.zones?
            .enclosing(self.scene, self.visibility, camera.position)
    }

    /// [`Solution::triangles`] less those `camera` cannot see because it
    /// stands inside a closed room that hides them: what
    /// [`Solution::render`] draws, for a viewer of its own.
    #[must_use]
    pub fn triangles_seen_from(&self, camera: &Camera) -> Vec<ShadedTriangle> {
        let radiosity = |v: u32| self.radiosity_at(v as usize);
        shaded(
            self.mesh,
            &radiosity,
            self.triangle_indices_seen_from(camera),
        )
    }

    /// Renders the irradiance H (W/m²) the solution holds at each mesh
    /// vertex through `camera`, interpolated as [`Solution::render`]
    /// interpolates radiance and split along the same diagonals: a picture
    /// of the light arriving on every visible surface (× 179 lm/W for lux).
    #[must_use]
    pub fn render_irradiance(&self, camera: &Camera, settings: &RenderSettings) -> Image {
        let position = |v: u32| self.mesh.vertices[v as usize].position;
        let irradiance = |v: u32| self.irradiance_at(v as usize);
        let triangles: Vec<ShadedTriangle> = self
            .triangle_indices_seen_from(camera)
            .into_iter()
            .map(|[a, b, c]| ShadedTriangle {
                positions: [position(a), position(b), position(c)],
                radiance: [irradiance(a), irradiance(b), irradiance(c)],
            })
            .collect();
        rasterize(&triangles, camera, settings)
    }

    /// Renders the solution through `camera` into an image of linear
    /// radiance that the caller owns; write it with [`crate::write_exr`] or
    /// [`crate::write_png`]. Under daylight, the sky and the ground are
    /// seen where no surface is, and through glazing, attenuated
    /// (`view/sky.rs`).
    #[must_use]
    pub fn render(&self, camera: &Camera, settings: &RenderSettings) -> Image {
        let Some(source) = self.daylight else {
            return rasterize(&self.triangles_seen_from(camera), camera, settings);
        };
        let radiosity = |v: u32| self.radiosity_at(v as usize);
        let indices = self.triangle_indices_seen_from(camera);
        let triangles = shaded(self.mesh, &radiosity, indices.clone());
        let image = self.render_daylit(&triangles, camera, settings, source.daylight());
        self.with_exact_sun(image, &indices, camera, settings, source)
    }
}

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
    let radiosity = |v: u32| radiosity[v as usize];
    shaded(
        mesh,
        &radiosity,
        triangle_indices_of(mesh, &radiosity, |_| true),
    )
}

/// Triangles given as vertex-index triples, with their vertices' positions
/// and radiance L = B/π, from each vertex's `radiosity`.
fn shaded(
    mesh: &Mesh,
    radiosity: &dyn Fn(u32) -> Rgb,
    triangles: Vec<[u32; 3]>,
) -> Vec<ShadedTriangle> {
    let radiance = |v: u32| radiosity(v) / std::f64::consts::PI;
    let position = |v: u32| mesh.vertices[v as usize].position;
    triangles
        .into_iter()
        .map(|[a, b, c]| ShadedTriangle {
            positions: [position(a), position(b), position(c)],
            radiance: [radiance(a), radiance(b), radiance(c)],
        })
        .collect()
}

/// The triangles of the elements `keep` selects as triples of vertex
/// indices, counter-clockwise seen from the front, in element order: each
/// element split as [`mesh_triangles`] splits it (a quad along the diagonal
/// of closer radiosities, from each vertex's `radiosity`). The one
/// triangulation the renderer draws and the exporters write.
fn triangle_indices_of(
    mesh: &Mesh,
    radiosity: &dyn Fn(u32) -> Rgb,
    keep: impl Fn(&Element) -> bool,
) -> Vec<[u32; 3]> {
    let gap = |p: u32, q: u32| (radiosity(p) - radiosity(q)).abs().element_sum();
    let mut triangles = Vec::with_capacity(2 * mesh.elements.len());
    let mut split = Vec::new();
    for element in mesh.elements.iter().filter(|element| keep(element)) {
        mesh.element_triangles(element, gap, &mut split);
        triangles.extend_from_slice(&split);
    }
    triangles
}
