//! The mesh-size guard: a mesh is counted before it is made, and refused
//! when it would exceed [`MeshSettings::max_elements`].

use super::scene_mesh::{MeshKind, MeshSettings};
use crate::error::{Error, Result};
use crate::mesh::estimate_square_elements;
use crate::scene::Scene;

impl MeshSettings {
    /// The default of [`MeshSettings::max_elements`]: five million elements,
    /// about a gigabyte for mesh and solver together and hours of solving
    /// on a small machine; the Cornell box at default settings has 4 000.
    pub const DEFAULT_MAX_ELEMENTS: usize = 5_000_000;

    /// The elements [`super::mesh_scene`] would make at most: the square
    /// grid's count, plus for the contour mesher two triangles per
    /// direction and level on every receiver that might qualify.
    #[must_use]
    pub fn estimate_elements(&self, scene: &Scene) -> f64 {
        let square = estimate_square_elements(scene, &self.square_for(scene));
        let contour = match self.kind {
            // Adaptive meshing starts from the square grid; its splits stop
            // at `refinement.max_vertices`.
            MeshKind::Square | MeshKind::Adaptive => 0.0,
            MeshKind::Contour => {
                let receivers = scene
                    .surfaces
                    .iter()
                    .filter(|s| !scene.material_of(s).is_emitter())
                    .count();
                2.0 * self.contour.directions as f64 * self.contour.levels as f64 * receivers as f64
            }
        };
        square + contour
    }

    /// Refuses settings that would mesh `scene` into more than
    /// [`MeshSettings::max_elements`] elements, with an error that says how
    /// to ask for fewer or allow more. [`crate::Solver::new`] calls it before
    /// meshing; call it before [`super::mesh_scene`] when meshing yourself.
    pub fn check_budget(&self, scene: &Scene) -> Result<()> {
        let estimate = self.estimate_elements(scene);
        if estimate <= self.max_elements as f64 {
            return Ok(());
        }
        Err(Error::MeshTooLarge {
            estimate,
            limit: self.max_elements,
            max_edge: self.square_for(scene).max_edge,
            diagonal: scene.diagonal(),
        })
    }
}
