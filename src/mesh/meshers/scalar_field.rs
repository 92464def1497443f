//! The field the contour and level-line meshers follow, handed down by the
//! solver: the mesh knows nothing of light.

use glam::DVec2;

/// A scalar field on a plane: its value and gradient at a point.
pub type ScalarField<'a> = dyn Fn(DVec2) -> (f64, DVec2) + Sync + 'a;
