//! Looking at a solution: its shaded triangles, for a program's own viewer,
//! and its image in memory.

use super::image::Image;
use super::mesh_triangles::{mesh_triangles, triangle_indices};
use super::rasterizer::{RenderSettings, ShadedTriangle, rasterize};
use crate::scene::Camera;
use crate::solver::Solution;

impl Solution<'_> {
    /// The rendered triangles: the mesh's elements (quads split along the
    /// diagonal with the closer radiosities) with per-vertex radiance
    /// L = B/π, W/(m²·sr). What [`Solution::render`] draws.
    #[must_use]
    pub fn triangles(&self) -> Vec<ShadedTriangle> {
        mesh_triangles(self.mesh, &self.radiosity)
    }

    /// The same triangles as vertex-index triples into the mesh's vertices,
    /// for writers that keep the vertices shared (the exporters).
    pub(crate) fn triangle_indices(&self) -> Vec<[u32; 3]> {
        triangle_indices(self.mesh, &self.radiosity)
    }

    /// Renders the solution through `camera` into an image of linear
    /// radiance that the caller owns; write it with [`crate::write_exr`] or
    /// [`crate::write_png`].
    #[must_use]
    pub fn render(&self, camera: &Camera, settings: &RenderSettings) -> Image {
        rasterize(&self.triangles(), camera, settings)
    }
}
