//! How many elements a mesh will have, counted before meshing, so that an
//! absurd request (an element edge of a nanometre on a room) is refused up
//! front instead of exhausting memory.

use super::square::{SquareMeshSettings, convex_quad, lattice_size, quad_grid_size};
use crate::scene::Scene;

/// The number of elements [`super::mesh_square`] makes of `scene` with
/// `settings`, before contact lines are meshed in (which adds a few along
/// each line) and hidden elements dropped: the same grid and lattice sizes,
/// without building them. Costs one triangulation per non-quad surface.
#[must_use]
pub fn estimate_square_elements(scene: &Scene, settings: &SquareMeshSettings) -> f64 {
    scene
        .surfaces
        .iter()
        .map(|surface| match convex_quad(surface) {
            Some(corners) => {
                let (cols, rows) = quad_grid_size(corners, settings);
                cols as f64 * rows as f64
            }
            None => {
                let (triangles, n, _) = lattice_size(surface, settings);
                triangles.len() as f64 * (n as f64).powi(2)
            }
        })
        .sum()
}
