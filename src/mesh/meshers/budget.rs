//! How many elements a mesh will have, counted before meshing, so that an
//! absurd request (an element edge of a nanometre on a room) is refused up
//! front instead of exhausting memory.

use super::square::{SquareMeshSettings, convex_quad, lattice_size, quad_grid_size};
use crate::error::{Error, Result};
use crate::scene::Scene;

/// The number of elements [`crate::mesh::mesh_square`] makes of `scene` with
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

/// The most elements the contour meshers add to `scene`'s receivers, given
/// the square grid's `square_elements`: a layout keeps at most
/// `max_grid_ratio` times its receiver's grid points plus
/// `extra_points` (the solver drops a larger one for the grid), and each
/// point makes about two triangles.
#[must_use]
pub fn estimate_contour_elements(
    scene: &Scene,
    square_elements: f64,
    max_grid_ratio: f64,
    extra_points: f64,
) -> f64 {
    let receivers = scene
        .surfaces
        .iter()
        .filter(|s| !scene.material_of(s).is_emitter())
        .count();
    2.0 * (max_grid_ratio * square_elements + extra_points * receivers as f64)
}

/// Refuses a mesh of `estimate` elements when that is more than `limit`,
/// with an error that says how long the elements would be
/// (`square.max_edge`) against the scene's size, so the user can ask for
/// fewer or allow more.
pub fn check_element_budget(
    scene: &Scene,
    estimate: f64,
    limit: usize,
    square: &SquareMeshSettings,
) -> Result<()> {
    if estimate <= limit as f64 {
        return Ok(());
    }
    Err(Error::MeshTooLarge {
        estimate,
        limit,
        max_edge: square.max_edge,
        diagonal: scene.diagonal(),
    })
}
